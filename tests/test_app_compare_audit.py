"""Tools > Audit round trips: the table of paths, failing rows in red, a row selects its joint."""

from __future__ import annotations

import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.dialogs import audit_dialog
from gmr_studio.core.compare.audit import AuditPath
from tests.app_fixtures import open_file, studio  # noqa: F401 (fixture)
from tests.conftest import shared_path

pytestmark = pytest.mark.gui

SMALL_BVH = "bvh/cmu_cgspeed_npybvh_example_75f.bvh"


def _dialog(window) -> audit_dialog.AuditDialog:
    window.audit_action.trigger()
    QApplication.processEvents()
    return window.audit_dialog


def test_audit_of_the_open_document(studio, qtbot):  # noqa: F811
    open_file(studio, shared_path(SMALL_BVH))
    menus = [a.text().replace("&", "") for a in studio.menuBar().actions()]
    assert menus.index("Tools") == menus.index("Help") - 1
    dialog = _dialog(studio)
    qtbot.waitExposed(dialog)
    assert dialog.table.rowCount() == len(dialog.paths) >= 7
    assert all(p.ok for p in dialog.paths)
    assert dialog.summary.text().startswith(f"{len(dialog.paths)} of {len(dialog.paths)} paths")
    names = [dialog.table.item(r, 0).text() for r in range(dialog.table.rowCount())]
    assert "BVH written and read" in names and "split all / join all" in names
    # choosing a row selects its worst joint at its frame
    row = names.index("forest export after split all")
    dialog.table.selectRow(row)
    path = dialog.paths[row]
    assert studio.state.selected == studio.state.motion.joint_index(path.worst_joint)
    assert studio.state.frame == path.worst_frame
    dialog.close()


def test_a_failing_path_is_red_and_named(studio, qtbot, monkeypatch):  # noqa: F811
    open_file(studio, shared_path(SMALL_BVH))
    bad = AuditPath("lengths off", 1e-3, 1e-5, 1e-9, "Head", 7, failing_joints=("Head",))
    good = AuditPath("to GMR in memory", 0.0, 0.0, 1e-9, "Hips", 0)
    monkeypatch.setattr(audit_dialog, "audit_motion", lambda motion, source=None: [good, bad])
    dialog = _dialog(studio)
    qtbot.waitExposed(dialog)
    assert "1 of 2 paths" in dialog.summary.text() and "failing: lengths off" in dialog.summary.text()
    assert dialog.table.item(1, 4).text() == "FAIL" and dialog.table.item(0, 4).text() == "ok"
    dialog.table.clearSelection()
    image = dialog.table.viewport().grab().toImage()
    rect = dialog.table.visualItemRect(dialog.table.item(1, 4))
    ok_rect = dialog.table.visualItemRect(dialog.table.item(0, 4))

    def reddish(r) -> int:
        count = 0
        for x in range(r.left(), r.right()):
            for y in range(r.top(), r.bottom()):
                c = image.pixelColor(x, y)
                count += c.red() > 150 and c.green() < 110 and c.blue() < 110
        return count

    assert reddish(rect) > 5 and reddish(ok_rect) == 0  # the FAIL text is drawn red, ok is not
    dialog.table.selectRow(1)
    assert studio.state.selected == studio.state.motion.joint_index("Head") and studio.state.frame == 7
    dialog.close()
