"""The app never loses work: unexpected failures in edits, saves, loads and slots are
caught, logged to the crash log, shown, and leave the document and history as they were."""

from __future__ import annotations

import sys
import threading

import pytest
from PyQt6.QtCore import QObject, QTimer, pyqtSignal

from gmr_studio.app import crash
from gmr_studio.app.model import commands
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

crash_folder = app_fixtures.crash_folder  # the fixture: the crash log's folder, emptied per test


def log_text(folder) -> str:
    return (folder / "crash.log").read_text()


def test_an_edit_that_fails_unexpectedly_changes_nothing(qtbot, studio, crash_folder, monkeypatch):
    open_file(studio, demo_folder() / MOTION_FILE)
    commands.split_here(studio.state, 5)
    before, count = studio.state.snapshot, studio.state.undo_stack.count()

    def broken(motion, joint, threads=None):
        raise RuntimeError("simulated bug in shift root")

    monkeypatch.setattr(commands, "shift_root_edit", broken)
    assert commands.shift_root_to(studio.state, 3) is False
    assert studio.state.snapshot is before and studio.state.undo_stack.count() == count
    assert "failed unexpectedly: RuntimeError: simulated bug in shift root" in studio.status.text()
    assert "Your document is unchanged" in studio.status.text()
    assert "Traceback" in log_text(crash_folder) and "simulated bug in shift root" in log_text(crash_folder)
    studio.state.undo_stack.undo()  # the history still works
    assert studio.state.undo_stack.count() == count and studio.state.snapshot is not before


def test_running_out_of_memory_while_caching_an_edit_changes_nothing(qtbot, studio, crash_folder, monkeypatch):
    open_file(studio, demo_folder() / MOTION_FILE)
    before = studio.state.snapshot

    def no_memory(motion):
        raise MemoryError("simulated: the forward kinematics cache does not fit")

    monkeypatch.setattr(commands.Snapshot, "of", staticmethod(no_memory))
    monkeypatch.setattr(commands.Snapshot, "of_edit", staticmethod(lambda before, edited: no_memory(edited.motion)))
    assert commands.split_everything(studio.state) is False
    assert studio.state.snapshot is before and studio.state.undo_stack.count() == 0
    assert "MemoryError" in log_text(crash_folder)


def test_a_save_that_fails_midway_keeps_the_old_file_and_the_edits(qtbot, studio, crash_folder, monkeypatch, tmp_path):
    import gmr_studio.core.formats.textmotion as textmotion

    open_file(studio, demo_folder() / MOTION_FILE)
    target = tmp_path / "walk.gmr"
    assert studio.files.save_to(target)
    old = target.read_bytes()
    commands.split_everything(studio.state)
    assert studio.state.modified

    def broken(values, digits):
        raise RuntimeError("simulated failure while formatting frames")

    monkeypatch.setattr(textmotion, "format_frames", broken)
    assert studio.files.save_to(target) is False
    assert target.read_bytes() == old and studio.state.modified
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".gmr") == ["walk.gmr"]
    assert "Saving" in studio.status.text() and "RuntimeError" in log_text(crash_folder)


def test_a_loader_that_fails_unexpectedly_keeps_the_document(qtbot, studio, crash_folder, monkeypatch):
    from gmr_studio.app.model import loading

    open_file(studio, demo_folder() / MOTION_FILE)
    before = studio.state.snapshot

    def broken(path):
        raise MemoryError("simulated: the file does not fit")

    monkeypatch.setattr(loading, "load_snapshot", broken)
    studio.files.open_path(str(demo_folder() / MOTION_FILE), ask=False, wait=True)
    assert studio.state.snapshot is before
    assert "MemoryError" in log_text(crash_folder)


class _Emitter(QObject):
    fire = pyqtSignal()


def test_an_exception_escaping_a_slot_is_logged_and_survived(qtbot, studio, crash_folder):
    saved_hooks = sys.excepthook, threading.excepthook
    crash.install_hooks(studio.report_problem)
    try:
        open_file(studio, demo_folder() / MOTION_FILE)
        before = studio.state.snapshot
        emitter = _Emitter()

        def slot():
            raise ValueError("simulated bug in a slot")

        emitter.fire.connect(slot)
        QTimer.singleShot(0, emitter.fire.emit)
        qtbot.waitUntil(lambda: (crash_folder / "crash.log").exists(), timeout=3000)
        assert "simulated bug in a slot" in log_text(crash_folder)
        assert "failed unexpectedly" in studio.status.text()
        assert studio.state.snapshot is before and studio.isVisible()
        worker = threading.Thread(target=lambda: 1 / 0, name="worker")
        worker.start()
        worker.join()
        assert "ZeroDivisionError" in log_text(crash_folder)
    finally:
        sys.excepthook, threading.excepthook = saved_hooks


def test_the_crash_log_stays_bounded(crash_folder, monkeypatch):
    monkeypatch.setattr(crash, "LOG_LIMIT", 2000)
    for i in range(50):
        crash.log_exception(f"case {i}", RuntimeError("x" * 100))
    size = (crash_folder / "crash.log").stat().st_size
    assert size < 4000 and "case 49" in log_text(crash_folder)
