"""Tools > Audit round trips: a failing path's joints are ringed in red in the view."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.dialogs import audit_dialog
from gmr_studio.core.compare.audit import AuditPath
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
pytestmark = pytest.mark.gui

SMALL_BVH = "bvh/cmu_cgspeed_npybvh_example_75f.bvh"


def _red(image: np.ndarray) -> int:
    pixels = image.astype(int)
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return int(((r > 120) & (r > g + 60) & (r > b + 60)).sum())


def test_failing_joints_are_highlighted(studio, qtbot, monkeypatch):
    open_file(studio, shared_path(SMALL_BVH))
    motion = studio.state.motion
    failing = (motion.names[5], motion.names[9], "NotInTheMotion")
    bad = AuditPath("lengths off", 1e-3, 1e-5, 1e-9, motion.names[9], 7, failing_joints=failing)
    good = AuditPath("to GMR in memory", 0.0, 0.0, 1e-9, motion.names[0], 0)
    monkeypatch.setattr(audit_dialog, "audit_motion", lambda motion, source=None: [good, bad])
    before = screen_image(studio)
    studio.audit_action.trigger()
    QApplication.processEvents()
    dialog = studio.audit_dialog
    qtbot.waitExposed(dialog)
    dialog.table.selectRow(0)
    assert dialog.highlight.part is None  # a passing path rings nothing
    dialog.table.selectRow(1)
    highlight = dialog.highlight
    assert highlight.joints.tolist() == [5, 9]
    np.testing.assert_array_equal(highlight.part.mesh.points, studio.state.snapshot.positions[7, [5, 9]])
    ringed = screen_image(studio)
    assert _red(ringed) > _red(before) + 30
    studio.state.set_frame(40)  # it follows the frame
    np.testing.assert_array_equal(highlight.part.mesh.points, studio.state.snapshot.positions[40, [5, 9]])
    dialog.close()
    QApplication.processEvents()
    assert highlight.part is None
    studio.state.set_frame(7)
    assert _red(screen_image(studio)) < _red(ringed) - 30
