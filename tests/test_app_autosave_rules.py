"""The autosaver's rules, edit by edit, on a state without a window (issue 24): a copy at
every 10th edit (not only the first 10th), the old copy removed when the copy's path
changes, the recovery list newest first with times that differ."""

from __future__ import annotations

import json

import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.app.reliability import recovery
from gmr_studio.app.reliability.autosave import Autosaver
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr

pytestmark = pytest.mark.gui  # a QApplication (signals, timers)


@pytest.fixture
def saver(qtbot, tmp_path):
    """An autosaver writing to tmp_path/recovery, of a state holding the demo walk, whose
    timer never fires during a test (only the every-10th rule writes)."""
    state = StudioState()
    state.open_document(Snapshot.of(load_gmr(demo_folder() / MOTION_FILE)), demo_folder() / MOTION_FILE)
    autosaver = Autosaver(state, interval_ms=3_600_000, every=10, folder=tmp_path / "recovery")
    yield autosaver
    autosaver.shutdown()


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
