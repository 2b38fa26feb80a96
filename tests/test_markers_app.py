"""Markers in the real window (under Xvfb): analysis outputs of a C3D are never drawn nor used
by the automatic alignment; marker-map messages."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.markers.alignment import auto_alignment
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
        spheres = scene.parts["markers"]  # every marker has its sphere; the missing ones are not drawn
        assert spheres.mesh.n_points == 42 and int(spheres.drawn.sum()) == int(shown.sum()) > 30
        np.testing.assert_array_equal(spheres.drawn, shown)
        np.testing.assert_allclose(spheres.mesh.points[shown], overlay.positions[frame][shown], atol=1e-4)
    # the automatic alignment is the one of the markers alone
    resampled = cmu.resampled(state.motion.frame_rate)
    alone = auto_alignment(
        resampled.positions, resampled.labels, state.snapshot.positions, state.motion.names, cmu.units
    )
    np.testing.assert_allclose(overlay.alignment.transform.rotation, alone.transform.rotation, atol=1e-9)
    np.testing.assert_allclose(
        overlay.alignment.transform.translation, alone.transform.translation, rtol=1e-6, atol=1e-6
    )
    assert overlay.alignment.transform.scale == pytest.approx(alone.transform.scale, rel=1e-9)


def test_pelvis_frames_on_the_cmu_bvh_and_a_message_when_the_map_cannot_apply(qtbot, tmp_path):
    from gmr_studio.app.model import pelvis_recovery
    from gmr_studio.app.model.state import Snapshot, StudioState
    from gmr_studio.core.formats import load_gmr
    from gmr_studio.core.markers import read_markers
    from tests.test_markers_pelvis_guess import write_rig

    markers = read_markers(shared_path("cmu/subject01/01_01.c3d"))
    messages: list[str] = []
    state = StudioState()
    state.message.connect(messages.append)
    state.open_document(Snapshot.of(load_gmr(shared_path("cmu/subject01/01_01.bvh"))), None)
    state.set_markers(markers)
    assert pelvis_recovery.recover_pelvis_frames(state, quiet=True)
    assert state.pelvis is not None and int(state.pelvis.source.valid.sum()) == 2751  # computed samples kept
    assert "marker map 'cmu' (Hips, LeftUpLeg, RightUpLeg) (fitted on LFWT, RFWT, LBWT)" in messages[-1]
    # a skeleton no joint map pairs with CMU's: said, even though the recovery is quiet
    rig = write_rig(tmp_path / "rig.bvh", root="pelvis", left="l_hip", right="r_hip", back="belly")
    state.open_document(Snapshot.of(rig), None)
    state.set_markers(markers)
    messages.clear()
    assert not pelvis_recovery.recover_pelvis_frames(state, quiet=True)
    assert state.pelvis is None
    assert messages and "marker map 'cmu' fits these markers but cannot apply to this skeleton" in messages[-1]
    assert "does not pair them with this skeleton's joints" in messages[-1]


def test_computed_samples_are_counted_in_the_inspector_and_the_layers_dock(qtbot, studio):
    """CMU 01_01.c3d over its BVH: the inspector gives the share of samples the capture
    software computed (0.74%) and says so beside the selected marker at a frame where it is
    computed (STRN, 103 such frames), not where it is measured; the same file as a marker
    layer shows the share in the Layers dock."""
    c3d = shared_path("cmu/subject01/01_01.c3d")
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"), c3d)
    state = studio.state
    overlay = state.marker_overlay
    assert overlay.computed.shape == overlay.positions.shape[:2]
    # on the BVH's clock (120.005 Hz): a sample between a computed one and another is computed
    assert int(overlay.markers.computed.sum()) == 859 <= int(overlay.computed.sum()) <= 2 * 859
    assert "42 from 01_01.c3d, 120 Hz, mm; 0.74% computed by the capture software" in studio.inspector.text()
    strn = overlay.markers.index("STRN")
    state.select_marker(strn)
    computed, measured = np.flatnonzero(overlay.computed[:, strn])[0], 10
    assert not overlay.computed[measured, strn]
    state.set_frame(int(computed))
    assert "(computed by the capture software)" in studio.inspector.text()
    state.set_frame(measured)
    assert "Marker STRN" in studio.inspector.text() and "(computed by" not in studio.inspector.text()
    studio.layers.add_markers(overlay.markers, c3d)
    table = studio.layers_panel.table
    names = [table.item(r, 2).text() for r in range(table.rowCount()) if table.item(r, 2) is not None]
    assert "01_01.c3d (markers, 0.74% computed)" in names
