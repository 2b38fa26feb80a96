"""The app's BVH export when the exporter fails unexpectedly: the message is shown, the crash
log gets the traceback, nothing is written and the document is as it was."""

from __future__ import annotations

import pytest

import gmr_studio.core.formats.bvh_export as export_module
from gmr_studio.app.model import commands
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

crash_folder = app_fixtures.crash_folder  # the fixture: the crash log's folder, emptied per test


@pytest.mark.parametrize("per_tree", [False, True])
def test_an_export_that_raises_is_reported_and_changes_nothing(
    qtbot, studio, crash_folder, monkeypatch, tmp_path, per_tree
):
    open_file(studio, demo_folder() / MOTION_FILE)
    assert commands.split_here(studio.state, 5)
    before, count, modified = studio.state.snapshot, studio.state.undo_stack.count(), studio.state.modified
    motion = studio.state.motion

    def broken(*args, **kwargs):
        raise RuntimeError("simulated bug in the exporter")

    monkeypatch.setattr(export_module, "bvh_export_trees" if per_tree else "bvh_export", broken)
    target = tmp_path / "out" / "walk.bvh"
    target.parent.mkdir()
    assert studio.exports.export_bvh(target, per_tree=per_tree) is False
    message = studio.status.text()
    assert f"Exporting {target} failed unexpectedly: RuntimeError: simulated bug in the exporter" in message
    assert "Your document is unchanged" in message
    log = (crash_folder / "crash.log").read_text()
    assert "Traceback" in log and "simulated bug in the exporter" in log and "Exporting" in log
    assert list(target.parent.iterdir()) == []
    assert studio.state.snapshot is before and studio.state.motion is motion
    assert studio.state.undo_stack.count() == count and studio.state.modified == modified
    monkeypatch.undo()  # the exporter works again: so does the export, from the same document
    assert studio.exports.export_bvh(target, per_tree=per_tree) is True
    assert any(target.parent.iterdir())
