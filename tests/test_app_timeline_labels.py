"""Issue 13.5: the frame box keeps to the take's range, long undo labels do not widen the
toolbar."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QToolBar

from gmr_studio.app.model.commands import run_edit
from gmr_studio.app.window.actions import UNDO_LABEL_CHARS
from gmr_studio.core.edits.operations import split
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio


def type_frame(qtbot, studio, text: str) -> None:
    box = studio.timeline.frame_box
    box.lineEdit().selectAll()
    qtbot.keyClicks(box.lineEdit(), text)
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)


def test_a_frame_past_the_end_lands_on_the_last_frame(qtbot, studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    state = studio.state
    last = state.n_frames - 1
    type_frame(qtbot, studio, "99999999")
    assert state.frame == last and studio.timeline.frame_box.value() == last
    type_frame(qtbot, studio, "1234")
    assert state.frame == 1234
    type_frame(qtbot, studio, str(last + 1))
    assert state.frame == last


def test_long_undo_labels_are_elided_and_do_not_widen_the_toolbar(qtbot, studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    state = studio.state
    toolbar = studio.findChild(QToolBar, "tools")
    width = toolbar.sizeHint().width()
    label = "Split at '" + "VeryLongJointName" * 12 + "'"
    assert run_edit(state, label, lambda m: split(m, "LeftFoot"))
    undo = studio.actions["undo"]
    assert len(undo.text()) <= UNDO_LABEL_CHARS and undo.text().endswith("\u2026")
    assert undo.toolTip() == f"Undo {label}"
    assert toolbar.sizeHint().width() <= width
    state.undo_stack.undo()
    redo = studio.actions["redo"]
    assert len(redo.text()) <= UNDO_LABEL_CHARS and redo.toolTip() == f"Redo {label}"
    assert toolbar.sizeHint().width() <= width


def test_a_frame_change_lays_nothing_out_and_repaints_no_dock_frame(qtbot, studio):
    """Issue 26: during playback only what shows the frame repaints. The time label keeps
    one size per document (its text changing width asked the window to lay out every dock
    again on each frame), and the timeline is opaque, so neither its dock nor the window
    behind it is painted again; the label is still wide enough for every frame's text."""
    from PyQt6.QtCore import QEvent, QObject
    from PyQt6.QtWidgets import QApplication, QDockWidget, QMainWindow

    from gmr_studio.app.docks.timeline import time_text
    from gmr_studio.core.demo import MOTION_FILE, demo_folder

    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    state.select(1)
    state.set_frame(1)
    qtbot.wait(200)  # the window settles after the document and selection arrive

    class Events(QObject):
        def __init__(self) -> None:
            super().__init__()
            self.seen: list[tuple[str, str]] = []

        def eventFilter(self, watched, event) -> bool:
            if event.type() == QEvent.Type.LayoutRequest:
                self.seen.append(("layout", type(watched).__name__))
            elif event.type() == QEvent.Type.Paint and isinstance(watched, (QDockWidget, QMainWindow)):
                self.seen.append(("paint", type(watched).__name__))
            return False

    events = Events()
    QApplication.instance().installEventFilter(events)
    try:
        for frame in (9, 10, 99, 100, state.n_frames - 1, 0):
            state.set_frame(frame)
            QApplication.processEvents()
            label = studio.timeline.time_label
            assert label.text() == time_text(state.motion, frame)
            assert label.fontMetrics().horizontalAdvance(label.text()) <= label.width()
    finally:
        QApplication.instance().removeEventFilter(events)
    assert events.seen == [], str(events.seen)
    assert studio.timeline.autoFillBackground()


def test_the_time_label_keeps_150_pixels_without_a_document_and_fits_a_long_take(studio):
    """Before any document the label holds its place at 150 pixels; a take whose widest time
    text is longer gets that text's width (every digit as the widest one), fixed."""
    from gmr_studio.app.docks.timeline import time_text
    from gmr_studio.core.demo import MOTION_FILE, demo_folder

    label = studio.timeline.time_label
    assert studio.state.motion is None
    assert (label.minimumWidth(), label.maximumWidth()) == (150, 150)
    open_file(studio, demo_folder() / MOTION_FILE)
    motion = studio.state.motion
    metrics = label.fontMetrics()
    digit = max("0123456789", key=metrics.horizontalAdvance)
    widest = time_text(motion, motion.n_frames - 1).translate(str.maketrans("0123456789", digit * 10))
    expected = max(150, metrics.horizontalAdvance(widest) + metrics.averageCharWidth())
    assert expected > 150
    assert (label.minimumWidth(), label.maximumWidth()) == (expected, expected)


def test_frames_are_numbered_from_0_everywhere_as_on_the_command_line(qtbot, studio, tmp_path):
    """Issue 40.5: at the first and the last frame, the frame box, the timeline's label and
    the inspector give the same number, the one ``gmr curves`` writes in its frame column."""
    import csv

    from gmr_studio.core.cli import main

    path = shared_path("bvh/bvh-python_test_mocapbank.bvh")
    table = tmp_path / "hips.csv"
    assert main(["curves", str(path), "--joints", "Hips", "--quantity", "world", "-o", str(table)]) == 0
    with open(table, newline="") as handle:
        cli_frames = [int(row["frame"]) for row in csv.DictReader(handle)]
    open_file(studio, path)
    state = studio.state
    state.select(0)
    last = state.n_frames - 1
    assert (cli_frames[0], cli_frames[-1]) == (0, last)
    for frame in (0, last):
        state.set_frame(frame)
        assert studio.timeline.frame_box.value() == frame
        assert f"({frame} of 0-{last} @ " in studio.timeline.time_label.text()
        assert " ".join(studio.inspector.text().split()).startswith(f"Frame {frame} of 0-{last} ")


def test_the_rate_is_shown_as_meant_and_exactly_on_hover(qtbot, studio):
    """Issue 40.8e: a frame time printed as 0.033333 s is 30 Hz on the timeline, and its
    tooltip gives the exact 30.0003 Hz."""
    open_file(studio, shared_path("bvh/bvh-python_test_mocapbank.bvh"))
    label = studio.timeline.time_label
    assert label.text().endswith("@ 30 Hz)")
    assert "0.033333 s" in label.toolTip() and "30.0003 Hz exactly" in label.toolTip()
