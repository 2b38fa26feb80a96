"""Bad input in the window: every reader's refusal reaches the user as a dialog naming the
file, the line and what is wrong, whichever way the file came in, and the document open
with its unsaved edits stays exactly as it was.

The fuzz corpus (``core/fuzz``: every mutation category of every format, on the real files
of ``../shared/data``) goes through the window's open path (motions) or its add-markers
path (TRC, C3D); then one bad file goes through each other way in: the open dialog, a
drop, the recent-files menu, the command line's call, and the add-markers dialog.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from PyQt6.QtCore import QMimeData, QPointF, Qt, QUrl
from PyQt6.QtGui import QDropEvent
from PyQt6.QtWidgets import QFileDialog, QMessageBox

from gmr_studio.app.model import commands
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.fuzz.targets import all_targets
from gmr_studio.core.shared_data import shared_data_dir
from tests import app_fixtures
from tests.app_fixtures import open_file

pytestmark = pytest.mark.gui
studio = app_fixtures.studio
MARKER_FORMATS = {"trc", "c3d"}
TEXT_FORMATS = {"bvh", "gmr", "trc", "asf", "amc"}
#: tries per category to find a mutation the reader refuses (C3D: ~1 s a try; its header
#: counts and a cut inside the data are read from the parameters and what is left)
TRIES = {"c3d": 6}
#: formats whose cases come from their few smallest seed files (C3D: a child process per try)
SMALLEST_SEEDS = {"c3d": 3}
DEFAULT_TRIES = 12
#: formats whose categories are fed here, each its own test (C3D's reader runs ezc3d in a
#: child process at about 1 s a case)
FED_FORMATS = ("amc", "asf", "bvh", "gmr", "trc", "c3d")
#: categories each format must have explained at least (the rest may all still read)
EXPLAINED_AT_LEAST = {"c3d": 2}


@pytest.fixture
def dialogs(monkeypatch, tmp_path):
    """Error dialogs shown (text, details), recorded instead of blocking; no crash log."""
    monkeypatch.setenv("GMR_STUDIO_CONFIG", str(tmp_path / "config"))
    shown: list[tuple[str, str]] = []
    monkeypatch.setattr(QMessageBox, "exec", lambda box: shown.append((box.text(), box.detailedText())) or 0)
    return shown


@pytest.fixture
def edited(studio, dialogs):
    """The window with the demo open and two unsaved edits; dialogs are shown (not quiet)."""
    open_file(studio, demo_folder() / MOTION_FILE)
    commands.split_here(studio.state, 3)
    commands.split_here(studio.state, 9)
    studio.files.quiet = False
    return studio


def refused_case(target, category: str, number: int, folder: Path) -> tuple[bytes, str] | None:
    """A mutation of ``category`` that the core refuses: (bytes, seed label), or None."""
    seeds = target.seeds()
    if target.name in SMALLEST_SEEDS:  # slow readers: their smallest files in turn, so that the
        # cases stay the same (and quick) whatever files are added to the data folder
        seeds = sorted(seeds, key=lambda seed: (len(seed[1]), seed[0]))[: SMALLEST_SEEDS[target.name]]
    folder.mkdir(parents=True, exist_ok=True)
    probe = folder / f"probe{target.suffix}"
    for attempt in range(TRIES.get(target.name, DEFAULT_TRIES)):
        rng = np.random.default_rng([number, attempt])
        label, data = (
            seeds[(number + attempt) % len(seeds)]
            if target.name in SMALLEST_SEEDS
            else (seeds[int(rng.integers(len(seeds)))])
        )
        mutated = target.mutations[category](data, rng)
        probe.write_bytes(mutated)  # for readers that read the file (C3D)
        try:
            target.read(probe, mutated, label)
        except MotionFileError:
            return mutated, label
    return None


def write_case(folder: Path, target, data: bytes, label: str) -> Path:
    """The case as a file the app can open (an AMC beside its real skeleton)."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"bad{target.suffix}"
    if target.name == "amc":
        from gmr_studio.core.formats.acclaim import asf_beside

        shutil.copy(asf_beside(shared_data_dir() / label), folder / "skeleton.asf")
    path.write_bytes(data)
    return path


def assert_explained(shown: list, path: Path, text_format: bool) -> None:
    assert len(shown) == 1, shown
    text, details = shown.pop()
    assert f"Cannot read {path.name}" in text
    assert details.startswith(str(path)), details
    if text_format:
        assert "line " in text, text
        assert details.split(":")[1].isdigit(), details  # path:line:column: what
    assert len(text.splitlines()) >= 2 and text.splitlines()[-1].strip(), text  # what is wrong


def assert_untouched(window, before) -> None:
    snapshot, path, count, index = before
    state = window.state
    assert state.snapshot is snapshot and state.path == path
    assert state.undo_stack.count() == count and state.undo_stack.index() == index and state.modified


def document(window):
    state = window.state
    return state.snapshot, state.path, state.undo_stack.count(), state.undo_stack.index()


@pytest.mark.parametrize("name", FED_FORMATS)
def test_every_fuzz_category_through_the_open_path(qtbot, edited, dialogs, tmp_path, name):
    if not shared_data_dir().is_dir():
        pytest.skip(f"the real data folder {shared_data_dir()} is absent")
    before = document(edited)
    explained, read = [], []
    target = all_targets()[name]
    for number, category in enumerate(sorted(target.mutations)):
        case = refused_case(target, category, number, tmp_path / "probe")
        if case is None:  # this category's mutations all still read (e.g. frame numbers changed)
            read.append(category)
            continue
        data, label = case
        path = write_case(tmp_path / name / str(number), target, data, label)
        if name in MARKER_FORMATS:
            edited.files.add_markers_path(path, wait=True)
        else:
            edited.files.open_path(path, ask=False, wait=True)
        assert_explained(dialogs, path, name in TEXT_FORMATS)
        assert_untouched(edited, before)
        explained.append(category)
    assert edited.state.marker_overlay is None
    assert not (tmp_path / "config" / "crash.log").exists()
    assert len(explained) >= EXPLAINED_AT_LEAST.get(name, 5), (explained, read)


@pytest.fixture
def bad_bvh(tmp_path) -> Path:
    path = tmp_path / "bad.bvh"
    path.write_text("HIERARCHY\nROOT hips\n{\n  OFFSET 0 0 zero\n}\n")
    return path


def test_the_open_dialog(qtbot, edited, dialogs, bad_bvh, monkeypatch):
    before = document(edited)
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.StandardButton.Discard)
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *a, **k: (str(bad_bvh), ""))
    edited.files.open_dialog()
    qtbot.waitUntil(lambda: not edited.files.busy())
    assert_explained(dialogs, bad_bvh, True)
    assert "line 4" in edited.status.text() or str(bad_bvh) in edited.status.text()
    assert_untouched(edited, before)


def test_a_drop(qtbot, edited, dialogs, bad_bvh, monkeypatch):
    before = document(edited)
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.StandardButton.Discard)
    mime = QMimeData()
    mime.setUrls([QUrl.fromLocalFile(str(bad_bvh))])
    event = QDropEvent(
        QPointF(100, 100), Qt.DropAction.CopyAction, mime, Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier
    )
    edited.dropEvent(event)
    qtbot.waitUntil(lambda: not edited.files.busy())
    assert_explained(dialogs, bad_bvh, True)
    assert_untouched(edited, before)


def test_the_recent_files_menu(qtbot, edited, dialogs, bad_bvh, monkeypatch):
    before = document(edited)
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.StandardButton.Discard)
    edited.files.settings.setValue("recent_files", [str(bad_bvh)])
    edited.files.recent_changed.emit([str(bad_bvh)])  # as the files' list says when it changes
    (entry,) = [a for a in edited.recent_menu.actions() if a.text() == bad_bvh.name]
    entry.trigger()
    qtbot.waitUntil(lambda: not edited.files.busy())
    assert_explained(dialogs, bad_bvh, True)
    assert_untouched(edited, before)


def test_the_command_line_and_add_markers_dialog(qtbot, edited, dialogs, tmp_path, monkeypatch):
    before = document(edited)
    bad_trc = tmp_path / "bad.trc"
    bad_trc.write_text("PathFileType\t4\t(X/Y/Z)\tbad.trc\nnothing else\n")
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *a, **k: (str(bad_trc), ""))
    edited.files.add_markers_dialog()
    qtbot.waitUntil(lambda: not edited.files.busy())
    assert_explained(dialogs, bad_trc, True)
    assert_untouched(edited, before)
    # what `gmr-studio FILE` does once the window is up (app.main.main)
    missing = tmp_path / "missing.bvh"
    edited.files.open_path(missing, ask=False)
    qtbot.waitUntil(lambda: not edited.files.busy())
    assert_explained(dialogs, missing, False)
    assert_untouched(edited, before)
