"""Docks that cost only when seen: a frame change reaches a dock's widget only while it is visible.

:func:`follow_frame` connects ``update(frame)`` to the state's frame changes through a
:class:`FrameFollower`: while the widget is visible (its dock shown and its tab in front) every
frame change calls it at once, so it is painted in the same pass as the view and the
timeline and never lags; while hidden nothing runs, the follower only notes the frame, and
brings the widget up to date when it is shown again. A dock is therefore updated at most
once per drawn frame (the state emits one frame change per frame drawn) and never while
nobody can see it.
"""

from __future__ import annotations

from collections.abc import Callable

from PyQt6.QtCore import QEvent, QObject
from PyQt6.QtWidgets import QWidget


class FrameFollower(QObject):
    """Calls ``update(frame)`` on frame changes while ``widget`` is visible (see the module)."""

    def __init__(self, widget: QWidget, state, update: Callable[[int], None]) -> None:
        super().__init__(widget)
        self.widget = widget
        self.state = state
        self.update = update
        self.stale = False
        self.calls = 0  # updates made (for tests and the bench)
        state.frame_changed.connect(self._on_frame_changed)
        widget.installEventFilter(self)

    def _on_frame_changed(self, frame: int) -> None:
        if self.widget.isVisible():
            self.stale = False
            self.calls += 1
            self.update(frame)
        else:
            self.stale = True

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        if watched is self.widget and event.type() == QEvent.Type.Show and self.stale:
            self.stale = False
            self.calls += 1
            self.update(self.state.frame)
        return False


def follow_frame(widget: QWidget, state, update: Callable[[int], None]) -> FrameFollower:
    """``update(frame)`` for ``widget`` on the state's frame changes, only while it is seen."""
    return FrameFollower(widget, state, update)
