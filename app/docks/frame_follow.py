"""Docks that cost only when seen: a frame change reaches a dock's widget only while it is seen.

:func:`follow_frame` connects ``update(frame)`` to the state's frame changes through a
:class:`FrameFollower`: while the widget is seen (its dock shown and its tab in front) every
frame change calls it at once, so it is painted in the same pass as the view and the
timeline and never lags; while unseen nothing runs, the follower only notes the frame, and
brings the widget up to date at the first event it gets once seen again (shown, its tab
brought to front, moved or resized into sight), before it is painted. A
dock is therefore updated at most once per drawn frame (the state emits one frame change
per frame drawn) and never while nobody can see it.

Qt keeps a dock behind another tab *visible* (``isVisible()`` is true): it moves it out of
the window instead of hiding it, and sends no show event when its tab comes to front, only
the dock's ``visibilityChanged``. So "seen" is visible with a non-empty visible region
(:func:`seen`), and the follower listens to the dock holding the widget as well.
"""

from __future__ import annotations

from collections.abc import Callable

from PyQt6.QtCore import QEvent, QObject
from PyQt6.QtWidgets import QDockWidget, QWidget


def seen(widget: QWidget) -> bool:
    """Whether ``widget`` is on screen: shown, and not moved out of sight behind another tab."""
    return widget.isVisible() and not widget.visibleRegion().isEmpty()


class FrameFollower(QObject):
    """Calls ``update(frame)`` on frame changes while ``widget`` is seen (see the module)."""

    def __init__(self, widget: QWidget, state, update: Callable[[int], None]) -> None:
        super().__init__(widget)
        self.widget = widget
        self.state = state
        self.update = update
        self.stale = False
        self.calls = 0  # updates made (for tests and the bench)
        self.dock: QDockWidget | None = None  # the dock whose tab switches are followed
        state.frame_changed.connect(self._on_frame_changed)
        widget.installEventFilter(self)

    def _on_frame_changed(self, frame: int) -> None:
        if seen(self.widget):
            self.stale = False
            self.calls += 1
            self.update(frame)
        else:
            self.stale = True
            self._follow_dock()

    def _follow_dock(self) -> None:
        """Listen to the dock that holds the widget (found once the widget is in one)."""
        if self.dock is not None:
            return
        holder = self.widget.parentWidget()
        while holder is not None and not isinstance(holder, QDockWidget):
            holder = holder.parentWidget()
        if holder is not None:
            self.dock = holder
            holder.visibilityChanged.connect(self._catch_up)

    def _catch_up(self, *_) -> None:
        """Bring the widget to the current frame if it missed frames and is seen now."""
        if self.stale and seen(self.widget):
            self.stale = False
            self.calls += 1
            self.update(self.state.frame)

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        if watched is self.widget:  # shown, or moved, resized or painted into sight
            self._catch_up()
        return False


def follow_frame(widget: QWidget, state, update: Callable[[int], None]) -> FrameFollower:
    """``update(frame)`` for ``widget`` on the state's frame changes, only while it is seen."""
    return FrameFollower(widget, state, update)
