"""Docks that work only when seen (app/docks/frame_follow.py): a widget out of sight is not
updated on frame changes, one in sight at every frame change, and one brought into sight
(shown, moved into view, its tab brought to front) is brought up to the current frame at
once; on plain widgets and on tabbed docks of a small main window."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import QObject, Qt, pyqtSignal
from PyQt6.QtWidgets import QDockWidget, QLabel, QMainWindow, QWidget

from gmr_studio.app.docks.frame_follow import FrameFollower, follow_frame, seen

pytestmark = pytest.mark.gui


class FrameState(QObject):
    """The part of the state a follower reads: the frame and its change signal."""

    frame_changed = pyqtSignal(int)

    def __init__(self) -> None:
        super().__init__()
        self.frame = 0

    def set_frame(self, frame: int) -> None:
        self.frame = frame
        self.frame_changed.emit(frame)


class ShownCount(QWidget):
    """A widget that counts the show events it receives."""

    def __init__(self) -> None:
        super().__init__()
        self.shows = 0

    def showEvent(self, event) -> None:
        self.shows += 1
        super().showEvent(event)


def test_a_visible_widget_follows_every_frame_and_a_hidden_one_catches_up_once_shown(qtbot):
    state, widget, updates = FrameState(), ShownCount(), []
    qtbot.addWidget(widget)
    follower = follow_frame(widget, state, updates.append)
    assert isinstance(follower, FrameFollower) and follower.parent() is widget
    state.set_frame(3)  # not shown yet: only noted
    assert updates == [] and follower.stale
    widget.show()
    qtbot.waitExposed(widget)
    assert updates == [3] and not follower.stale
    assert widget.shows == 1  # the show event still reaches the widget
    for frame in (4, 5, 5):
        state.set_frame(frame)
    assert updates == [3, 4, 5, 5] and not follower.stale
    widget.hide()
    widget.show()  # nothing missed while hidden: no update
    assert updates == [3, 4, 5, 5] and widget.shows == 2
    widget.hide()
    for frame in (6, 7, 8):
        state.set_frame(frame)
    assert updates == [3, 4, 5, 5] and follower.stale
    widget.show()  # brought to the current frame once, not once per missed frame
    assert updates == [3, 4, 5, 5, 8] and not follower.stale


def test_nothing_missed_nothing_updated_and_a_widget_moved_into_sight_catches_up(qtbot):
    state, parent = FrameState(), QWidget()
    qtbot.addWidget(parent)
    parent.resize(200, 100)
    fresh, moved = QLabel("fresh", parent), QLabel("moved", parent)
    moved.setGeometry(500, 0, 50, 20)  # outside its parent: shown, yet nothing of it is seen
    updates = {"fresh": [], "moved": []}
    followers = {name: follow_frame(w, state, updates[name].append) for name, w in (("fresh", fresh), ("moved", moved))}
    parent.show()
    qtbot.waitExposed(parent)
    assert updates == {"fresh": [], "moved": []}  # no frame missed yet: nothing to catch up
    state.set_frame(6)
    assert updates == {"fresh": [6], "moved": []} and followers["moved"].stale
    moved.move(10, 40)  # into sight: brought to the frame at once
    assert seen(moved) and updates == {"fresh": [6], "moved": [6]} and not followers["moved"].stale
    moved.move(20, 40)
    assert updates == {"fresh": [6], "moved": [6]}


def test_a_dock_behind_another_tab_waits_until_it_is_in_front(qtbot):
    state, window = FrameState(), QMainWindow()
    qtbot.addWidget(window)
    window.setCentralWidget(QLabel("view"))
    docks, updates = [], {"curves": [], "contacts": []}
    for name in updates:
        dock = QDockWidget(name, window)
        dock.setObjectName(name)
        dock.setWidget(QLabel(name))
        window.addDockWidget(Qt.DockWidgetArea.BottomDockWidgetArea, dock)
        follow_frame(dock.widget(), state, updates[name].append)
        docks.append(dock)
    window.tabifyDockWidget(docks[0], docks[1])
    window.resize(400, 300)
    window.show()
    qtbot.waitExposed(window)
    docks[0].raise_()
    qtbot.waitUntil(lambda: seen(docks[0].widget()) and not seen(docks[1].widget()))
    assert docks[1].widget().isVisible()  # Qt moves the dock behind out of the window, not hidden
    updates["curves"].clear(), updates["contacts"].clear()
    for frame in (10, 11, 12):
        state.set_frame(frame)
    assert updates == {"curves": [10, 11, 12], "contacts": []}
    docks[1].raise_()  # its tab brought to front: the current frame, once
    qtbot.waitUntil(lambda: seen(docks[1].widget()))
    assert updates == {"curves": [10, 11, 12], "contacts": [12]}
    state.set_frame(13)
    assert updates == {"curves": [10, 11, 12], "contacts": [12, 13]}
