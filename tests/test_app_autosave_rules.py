"""The autosaver's rules, edit by edit, on a state without a window (issue 24): a copy at
every 10th edit (not only the first 10th), the old copy removed when the copy's path
changes, the recovery list newest first with times that differ."""

from __future__ import annotations

import json

import pytest
from PyQt6 import sip

from gmr_studio.app.crash import crash_log_path
from gmr_studio.app.model import commands
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.app.reliability import recovery
from gmr_studio.app.reliability.autosave import Autosaver
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr

pytestmark = pytest.mark.gui  # a QApplication (signals, timers)


@pytest.fixture
def saver(qtbot, tmp_path, monkeypatch):
    """An autosaver writing to tmp_path/recovery, of a state holding the demo walk, whose
    timer never fires during a test (only the every-10th rule writes). Nothing may reach the
    crash log (the worker logs what fails there instead of raising)."""
    monkeypatch.setenv("GMR_STUDIO_CONFIG", str(tmp_path / "config"))
    state = StudioState()
    state.open_document(Snapshot.of(load_gmr(demo_folder() / MOTION_FILE)), demo_folder() / MOTION_FILE)
    autosaver = Autosaver(state, interval_ms=3_600_000, every=10, folder=tmp_path / "recovery")
    yield autosaver
    autosaver.shutdown()
    assert not crash_log_path().exists(), crash_log_path().read_text()


def edit(state: StudioState, k: int) -> None:
    """Edit ``k`` (1-based): odd edits split the tree at ltibia, even ones join it back (the
    document stays modified: the history is not back at its clean index)."""
    joint = state.motion.joint_index("ltibia")
    assert commands.split_here(state, joint) if k % 2 else commands.join_to_parent(state, joint)


def test_a_copy_is_written_at_once_at_every_tenth_edit_not_only_the_first(saver):
    # planted bug: ``edits == every`` instead of ``edits % every == 0`` (only the 10th saves)
    state = saver.state
    written: list[int] = []
    saver.written.connect(lambda path: written.append(saver.edits))
    at_each: list[int] = []
    for k in range(1, 36):
        edit(state, k)
        saver.wait()
        at_each.append(len(written))
    assert written == [10, 20, 30]
    assert at_each == [k // 10 for k in range(1, 36)]  # at the 10th, 20th and 30th edit, at once
    record = recovery.read_record(saver.current)
    assert record.edits == 30 and record.original == (demo_folder() / MOTION_FILE).resolve()


def test_the_old_copy_is_removed_when_the_copy_moves(saver, tmp_path):
    # planted bug: a new copy written beside the old one when the recovery path changes
    state = saver.state
    folder = tmp_path / "recovery"
    # the document was restored from a copy named otherwise (e.g. renamed by hand)
    old = recovery.write_recovery(state.motion, folder / "walk (old copy).gmr", state.path, 4)
    saver.adopt(old)
    assert saver.current == old.path and saver.edits == 4
    edit(state, 1)
    saver.save_now()
    saver.wait()
    new_path = recovery.recovery_path(state.path, folder)
    assert new_path != old.path and saver.current == new_path
    assert sorted(p.name for p in folder.iterdir()) == [new_path.name]  # one copy, the new one
    assert recovery.read_record(new_path).edits == 5


def restamp(path, when: str) -> None:
    """Give a recovery file another ``saved_at`` (its record line, as the writer formats it)."""
    lines = path.read_text().splitlines(keepends=True)
    fields = json.loads(lines[1][len(recovery.MARKER) :])
    fields["saved_at"] = when
    lines[1] = recovery.MARKER + json.dumps(fields, ensure_ascii=True) + "\n"
    path.write_text("".join(lines))


def test_recoveries_are_listed_newest_first(tmp_path):
    # planted bug: the list sorted oldest first (the dialog would offer the oldest copy first)
    motion = load_gmr(demo_folder() / MOTION_FILE)
    folder = tmp_path / "recovery"
    # names in the opposite order of the times, so the folder's order cannot pass for it
    stamps = {"a.gmr": "2026-11-20T09:00:00", "b.gmr": "2026-11-26T08:30:05", "c.gmr": "2026-11-26T08:30:04"}
    for name, when in stamps.items():
        record = recovery.write_recovery(motion, folder / name, None, 1)
        restamp(record.path, when)
    listed = recovery.list_recoveries(folder, include_live=True)
    assert [r.path.name for r in listed] == ["b.gmr", "c.gmr", "a.gmr"]
    assert [r.saved_at for r in listed] == sorted(stamps.values(), reverse=True)


def test_the_documented_defaults_and_keyword_only_options(qtbot, tmp_path):
    # planted bugs: another interval or count than docs/reliability.md says; options positional
    state = StudioState()
    autosaver = Autosaver(state=state, parent=None, folder=tmp_path)
    try:
        assert autosaver.timer.interval() == 30_000 and autosaver.every == 10  # "within 30 s", "every 10th"
    finally:
        autosaver.shutdown()
    with pytest.raises(TypeError):
        Autosaver(state, None, 1000)


def test_a_clean_document_gets_no_copy(saver):
    # planted bug: a copy written when the document has no unsaved edits
    saver.save_now()
    saver.wait()
    assert saver.current is None and not (saver.folder.exists() and any(saver.folder.iterdir()))


def test_shutting_down_finishes_the_copy_asked_for(saver):
    # planted bug: the worker stopped without waiting (the window closes on a half-written copy)
    edit(saver.state, 1)
    saver.save_now()
    saver.shutdown()
    record = recovery.read_record(saver.current)  # on disk, complete, as soon as shutdown returns
    assert record is not None and record.edits == 1
    assert load_gmr(saver.current).n_frames == saver.state.motion.n_frames


def test_a_copy_that_cannot_be_written_is_logged_not_raised(qtbot, tmp_path, monkeypatch):
    # planted bug: the worker's failure raised (the window's wait/close would raise it)
    monkeypatch.setenv("GMR_STUDIO_CONFIG", str(tmp_path / "config"))
    (tmp_path / "a-file").write_text("not a folder")
    state = StudioState()
    state.open_document(Snapshot.of(load_gmr(demo_folder() / MOTION_FILE)), demo_folder() / MOTION_FILE)
    autosaver = Autosaver(state, interval_ms=3_600_000, folder=tmp_path / "a-file" / "recovery")
    written: list[str] = []
    autosaver.written.connect(written.append)
    try:
        edit(state, 1)
        autosaver.save_now()
        autosaver.wait()  # returns: the failure is logged, not raised
    finally:
        autosaver.shutdown()
    assert written == [] and "Autosave (write" in crash_log_path().read_text()


def test_a_removal_waits_for_the_write_before_it(saver, monkeypatch):
    # planted bug: two worker threads (a removal overtakes a slow write, the copy stays behind)
    import time

    original = recovery.write_recovery

    def slow_write(*args):
        time.sleep(0.3)  # a big motion
        return original(*args)

    monkeypatch.setattr(recovery, "write_recovery", slow_write)
    edit(saver.state, 1)
    saver.save_now()
    path = saver.current
    saver.discard()  # asked after the write: done after it
    saver.wait()
    assert path is not None and not path.exists()


def test_nothing_is_written_or_removed_after_shutdown(saver):
    # planted bug: the closed flag not set (a late edit or discard hits the stopped worker)
    edit(saver.state, 1)
    saver.shutdown()
    saver.save_now()  # a late timer or edit while the window closes: ignored, no error
    saver.discard()
    assert not (saver.folder.exists() and any(saver.folder.iterdir()))


def test_a_copy_already_gone_is_removed_quietly(saver):
    # planted bug: a removal of a missing copy fails (and lands in the crash log)
    edit(saver.state, 1)
    saver.save_now()
    saver.wait()
    saver.current.unlink()  # discarded by hand, or by the recovery dialog of another window
    saver.discard()
    saver.wait()  # the fixture checks that nothing reached the crash log
    assert saver.current is None


def test_an_edit_signal_from_a_stack_being_deleted_is_ignored(saver):
    # seen in CI under load: a closing window's undo stack moved its index as it was deleted,
    # and the slot asked the deleted stack whether the document was modified
    edit(saver.state, 1)
    sip.delete(saver.state.undo_stack)
    edits = saver.edits
    # the slot itself, called as the dying stack called it: a deleted stack cannot emit its
    # signal from a test, and closing a window races with its deletion
    saver._on_edited(0)  # no RuntimeError: nothing counted
    assert saver.edits == edits
