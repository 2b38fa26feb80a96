"""Markers in the real window (under Xvfb): analysis outputs of a C3D are never drawn nor used
by the automatic alignment; marker-map messages."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.alignment import auto_alignment
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path
from tests.test_markers_c3d_outputs import write_with_outputs

pytestmark = pytest.mark.gui
studio = app_fixtures.studio  # the fixture: a main window that must not leak


def test_the_window_draws_and_aligns_only_markers(qtbot, studio, tmp_path):
    cmu, _, _ = write_with_outputs(tmp_path / "gait.c3d")
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"), tmp_path / "gait.c3d")
    state, scene = studio.state, studio.view.scene
    overlay = state.marker_overlay
    assert overlay.markers.labels == cmu.labels and overlay.positions.shape[1] == 42
    for frame in (0, 60):
        state.set_frame(frame)
        shown = np.isfinite(overlay.positions[frame]).all(axis=1)
        assert scene.parts["markers"].mesh.n_points == int(shown.sum()) > 30
        np.testing.assert_allclose(scene.parts["markers"].mesh.points, overlay.positions[frame][shown], atol=1e-4)
    # the automatic alignment is the one of the markers alone
    resampled = cmu.resampled(state.motion.frame_rate)
    alone = auto_alignment(
        resampled.positions, resampled.labels, state.snapshot.positions, state.motion.names, cmu.units
    )
    np.testing.assert_allclose(overlay.alignment.rotation, alone.rotation, atol=1e-9)
    np.testing.assert_allclose(overlay.alignment.offset, alone.offset, rtol=1e-6, atol=1e-6)
    assert overlay.alignment.scale == pytest.approx(alone.scale, rel=1e-9)
