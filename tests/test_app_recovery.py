"""Autosave and recovery: unsaved edits survive SIGKILL and come back exactly.

The crash test runs the real app in a subprocess (``--test-edits N``, a test-only flag,
makes N edits after opening, as a user would), kills it with SIGKILL once the recovery
copy is on disk, lists it with ``gmr-studio --recover``, and restores it in a window. The
restored positions are compared with positions computed independently: the same splits
applied by the core to the original file, forward kinematics on the result.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from PyQt6.QtCore import QTimer

from gmr_studio.app.dialogs.recovery_dialog import RecoveryDialog, item_text, offer_recovery, restore
from gmr_studio.app.model import commands
from gmr_studio.app.reliability import recovery
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.edits.operations import split
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import forward_kinematics
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.test_app_autosave_rules import restamp

pytestmark = pytest.mark.gui
STUDIO = [sys.executable, "-m", "gmr_studio.app.main"]
#: restored positions against independent FK, relative to the motion's size (measured ~3e-15:
#: the GMR text holds Euler angles to 15 digits)
RESTORE_TOLERANCE = 1e-12


@pytest.fixture(autouse=True)
def data_home(tmp_path, monkeypatch):
    """XDG folders in tmp_path: the app's data folder (recovery files), config and crash log."""
    for name in ("XDG_DATA_HOME", "XDG_CONFIG_HOME"):
        monkeypatch.setenv(name, str(tmp_path / name.lower()))
    monkeypatch.setenv("GMR_STUDIO_CONFIG", str(tmp_path / "config"))
    return tmp_path / "xdg_data_home" / "GMR Studio" / "recovery"


studio = app_fixtures.studio  # (after data_home: autouse fixtures come first)


def wait_for(condition, timeout: float = 60.0) -> None:
    end = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < end, "timed out"
        time.sleep(0.05)


def expected_motion(path, joints: list[str]):
    """The file split at the named joints, by the core alone; its names and world positions."""
    motion = load_gmr(path)
    for name in joints:
        motion = split(motion, motion.names.index(name))
    return motion.names, forward_kinematics(motion)[0]


def size_of(positions: np.ndarray) -> float:
    return float(np.ptp(positions.reshape(-1, 3), axis=0).max())


def test_the_folder_is_the_app_data_folder_under_xdg(data_home):
    assert recovery.recovery_folder() == data_home
    walk = demo_folder() / MOTION_FILE
    named = recovery.recovery_path(walk)
    assert named.parent == data_home and named.name.startswith("walk.") and named.suffix == ".gmr"
    assert recovery.recovery_path(walk) == named and recovery.recovery_path(walk.with_name("x.gmr")) != named
    assert recovery.recovery_path(None).name == "untitled.gmr"


def test_a_killed_app_leaves_its_edits_to_restore(qtbot, data_home, tmp_path):
    walk = demo_folder() / MOTION_FILE
    app = subprocess.Popen(
        [*STUDIO, str(walk), "--test-edits", "10"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        wait_for(lambda: any(r.edits == 10 for r in recovery.list_recoveries(data_home, include_live=True)))
        os.kill(app.pid, signal.SIGKILL)
        app.wait(timeout=30)
    finally:
        if app.poll() is None:
            app.kill()
            app.wait()
    assert app.returncode == -signal.SIGKILL
    printed = app.stdout.read()
    assert "made 10 edits: split at " in printed
    split_at = printed.split("split at ")[1].split()[0].split(",")

    listed = subprocess.run([*STUDIO, "--recover"], capture_output=True, text=True, timeout=60)
    assert listed.returncode == 0, listed.stderr
    lines = [line for line in listed.stdout.splitlines() if "walk.gmr" in line]
    assert len(lines) == 1 and "10 edits" in lines[0] and str(walk.resolve()) in lines[0]
    assert "in use" not in lines[0]

    (record,) = recovery.list_recoveries(data_home)
    assert record.original == walk.resolve() and record.edits == 10 and record.path.parent == data_home
    assert record.pid == app.pid
    _restore_into_window(qtbot, tmp_path, record, *expected_motion(walk, split_at))


def _restore_into_window(qtbot, tmp_path, record, names: list[str], expected: np.ndarray) -> None:
    from PyQt6.QtCore import QSettings

    window = app_fixtures.MainWindow(settings=QSettings(str(tmp_path / "s.ini"), QSettings.Format.IniFormat))
    window.files.quiet = True
    window.show()
    qtbot.waitExposed(window)
    try:
        QTimer.singleShot(0, lambda: _click_restore(window))
        assert offer_recovery(window, record.path.parent)
        state = window.state
        assert state.path == record.original and state.modified
        assert window.windowTitle().startswith("walk.gmr")
        assert len(state.motion.roots) == 11 and sorted(state.motion.names) == sorted(names)
        assert not any("recovery" in c for c in state.motion.comments)
        order = [names.index(name) for name in state.motion.names]  # the file lists joints tree by tree
        scale = size_of(expected)
        assert np.abs(state.positions - expected[:, order]).max() <= RESTORE_TOLERANCE * scale
        assert record.path.exists() and window.autosave.current == record.path
        assert window.autosave.edits == 10
        commands.join_everything(state)  # the 11th edit is counted on top of the recovered ten
        assert window.autosave.edits == 11
        save_to = tmp_path / "walk-edited.gmr"
        assert window.files.save_to(save_to)
        window.autosave.wait()
        assert not record.path.exists()  # a clean save removes the copy
    finally:
        window.state.undo_stack.setClean()
        window.close()
        window.deleteLater()


def _click_restore(window) -> None:
    dialog = window.findChild(RecoveryDialog)
    assert dialog is not None and dialog.list.count() == 1
    dialog.restore_button.click()


def test_the_first_edit_is_saved_within_the_interval_then_every_tenth_at_once(qtbot, studio, data_home):
    open_file(studio, demo_folder() / MOTION_FILE)
    saver = studio.autosave
    saver.timer.setInterval(300)
    written: list[str] = []
    saver.written.connect(written.append)
    commands.split_here(studio.state, 3)
    assert saver.timer.isActive() and not written  # not at once: within the interval
    qtbot.waitUntil(lambda: len(written) == 1, timeout=5000)
    (record,) = recovery.list_recoveries(data_home, include_live=True)
    assert record.edits == 1 and record.original == (demo_folder() / MOTION_FILE).resolve()
    assert record.pid == os.getpid() and recovery.list_recoveries(data_home) == []  # ours: not offered

    saver.timer.setInterval(3_600_000)  # from now on only the tenth edit writes
    assert commands.split_here(studio.state, 5)  # edit 2
    for _ in range(3):  # edits 3..8: undo and redo count (they change the document)
        studio.state.undo_stack.undo()
        studio.state.undo_stack.redo()
    assert commands.split_here(studio.state, 7)  # edit 9
    assert saver.edits == 9 and len(written) == 1 and saver.timer.isActive()
    assert commands.split_here(studio.state, 9)  # edit 10: written at once
    saver.wait()
    assert len(written) == 2 and recovery.read_record(record.path).edits == 10
    restored = load_gmr(record.path)
    motion = studio.state.motion
    assert {restored.names[r] for r in restored.roots} == {motion.names[r] for r in motion.roots}
    assert len(motion.roots) == 5 and sorted(restored.names) == sorted(motion.names)
    for edit in range(11, 21):  # every 10th edit, not only the first tenth: the 20th writes too
        (studio.state.undo_stack.undo if edit % 2 else studio.state.undo_stack.redo)()
        saver.wait()
        assert saver.edits == edit and len(written) == (3 if edit == 20 else 2)
    assert recovery.read_record(record.path).edits == 20


def test_undo_back_to_the_file_and_a_clean_close_remove_the_copy(qtbot, studio, data_home, monkeypatch):
    open_file(studio, demo_folder() / MOTION_FILE)
    commands.split_here(studio.state, 3)
    studio.autosave.save_now()
    studio.autosave.wait()
    path = studio.autosave.current
    assert path is not None and path.exists()
    studio.state.undo_stack.undo()  # the document is its file again
    studio.autosave.wait()
    assert not path.exists() and studio.autosave.current is None
    commands.split_here(studio.state, 3)
    studio.autosave.save_now()
    studio.autosave.wait()
    assert path.exists()
    from PyQt6.QtWidgets import QMessageBox

    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.StandardButton.Discard)
    studio.close()  # the user drops the edits: the copy goes with them
    assert not path.exists()


def test_the_dialog_lists_name_time_edits_and_discards(qtbot, studio, data_home, tmp_path):
    motion = load_gmr(demo_folder() / MOTION_FILE)
    first = recovery.write_recovery(motion, data_home / "a.gmr", tmp_path / "first.bvh", 3)
    second = recovery.write_recovery(motion, data_home / "b.gmr", None, 1)
    (data_home / "not-a-recovery.gmr").write_text("GMR 1\n")
    # a minute apart (the records keep whole seconds), the newer one in the later-sorted file
    restamp(first.path, "2026-11-26T09:59:00")
    restamp(second.path, "2026-11-26T10:00:00")
    first, second = recovery.read_record(first.path), recovery.read_record(second.path)
    records = recovery.list_recoveries(data_home, include_live=True)
    assert [r.path for r in records] == [second.path, first.path]  # newest first
    dialog = RecoveryDialog(records, studio)
    qtbot.addWidget(dialog)
    texts = [dialog.list.item(i).text() for i in range(dialog.list.count())]
    assert texts == [item_text(second), item_text(first)]  # offered in that order
    assert any("first.bvh" in t and "3 edits" in t and first.saved_at.replace("T", " ") in t for t in texts)
    assert any("untitled motion" in t and "1 edit" in t for t in texts)
    assert item_text(first) in texts
    row = [r.path for r in dialog.records].index(first.path)
    dialog.list.setCurrentRow(row)
    dialog.discard_button.click()
    assert not first.path.exists() and second.path.exists() and dialog.list.count() == 1
    assert dialog.restored is None


def test_a_damaged_recovery_file_is_reported_and_kept(qtbot, studio, data_home):
    motion = load_gmr(demo_folder() / MOTION_FILE)
    record = recovery.write_recovery(motion, data_home / "cut.gmr", None, 2)
    text = record.path.read_text()
    record.path.write_text(text[: len(text) // 2])  # cut in the frames
    before = studio.state.snapshot
    with pytest.raises(Exception) as caught:
        restore(studio.state, studio.autosave, recovery.read_record(record.path))
    assert "cut.gmr" in str(caught.value)
    assert studio.state.snapshot is before and record.path.exists()
