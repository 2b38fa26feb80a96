"""The timeline's frame slider, which also shows and selects the state's frame range.

A plain drag or click moves the frame as in any QSlider; Shift+drag (or Shift+click) selects
the half-open frame range ``[start, stop)`` under the pointer, shaded over the groove, the
same :attr:`StudioState.frame_range` the curves plot and the contact bars select. The keys I
and O (window actions) set the range's start and end at the current frame through
:func:`range_starting_at` and :func:`range_ending_at`.

It also shows the quality checks' flags (:meth:`RangeSlider.set_levels`): under the groove,
each frame's worst severity as a coloured band (info blue, warning orange, error red, the
colours of :data:`app.model.problems.LEVEL_COLOURS`); a one-frame finding is at least
:data:`FLAG_MIN_WIDTH` pixels wide, and the colour of a pixel column is the worst of its frames.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from PyQt6.QtCore import QEvent, QRectF, Qt, pyqtSignal
from PyQt6.QtGui import QColor, QHelpEvent, QMouseEvent, QPainter, QPaintEvent
from PyQt6.QtWidgets import QAbstractSlider, QSlider, QStyle, QStyleOptionSlider, QToolTip, QWidget

from gmr_studio.app.model.problems import LEVEL_COLOURS

RANGE_COLOUR = QColor(255, 212, 0, 90)
RANGE_EDGE = QColor(255, 212, 0)
FLAG_COLOURS = {level: QColor.fromRgbF(*rgb) for level, rgb in LEVEL_COLOURS.items()}
FLAG_MIN_WIDTH = 3  # pixels: a one-frame finding stays visible on a long take
FLAG_HEIGHT = 5  # pixels: the band under the groove


def range_starting_at(selected: tuple[int, int] | None, frame: int, n_frames: int) -> tuple[int, int]:
    """The range ``selected`` with its start moved to ``frame``: its stop is kept when it lies
    after the frame, else the range runs to the end of the motion (``n_frames``)."""
    stop = selected[1] if selected is not None and selected[1] > frame else n_frames
    return frame, stop


def range_ending_at(selected: tuple[int, int] | None, frame: int) -> tuple[int, int]:
    """The range ``selected`` ending with ``frame`` (included): its start is kept when it is
    not after the frame, else the range starts at frame 0."""
    start = selected[0] if selected is not None and selected[0] <= frame else 0
    return start, frame + 1


class RangeSlider(QSlider):
    """A horizontal frame slider that shades :attr:`frame_range` and selects it with Shift+drag."""

    range_selected = pyqtSignal(int, int)  # half-open [start, stop), emitted while Shift-dragging

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(Qt.Orientation.Horizontal, parent)
        self.frame_range: tuple[int, int] | None = None
        self.levels: np.ndarray | None = None  # (F,) int8 worst severity per frame, or None
        self._spans: tuple | None = None  # (geometry, spans) of the last flag_spans
        #: (first, last) frames -> what is flagged there (the tooltip over a flag), or None
        self.flag_text: Callable[[int, int], str] | None = None
        self._anchor: int | None = None
        self._painted_handle = None  # the handle's rectangle when last painted

    def set_frame_range(self, start: int, stop: int) -> None:
        """Show ``[start, stop)`` (start < 0: no range); no signal."""
        self.frame_range = (int(start), int(stop)) if 0 <= start < stop else None
        self.update()

    def set_levels(self, levels: np.ndarray | None) -> None:
        """Show the checks' flags: (F,) int8 levels per frame (0 none, 1-3), or None."""
        self.levels = None if levels is None or not np.any(levels) else np.asarray(levels, np.int8)
        self._spans = None
        self.update()

    def flag_spans(self) -> list[tuple[int, int, int]]:
        """``(x0, x1, level)`` pixel column spans ([x0, x1)) of the flags as painted, mildest
        first (worse levels are painted over them)."""
        if self.levels is None:
            return []
        left, length = self._span()
        count = max(self.maximum() - self.minimum(), 1)
        key = (left, length, count, self.minimum(), self.width())
        if self._spans is not None and self._spans[0] == key:  # painted at every frame: computed once
            return self._spans[1]
        frames = np.arange(len(self.levels))
        centres = left + length * (frames - self.minimum()) / count
        half = max(length / count, FLAG_MIN_WIDTH) / 2
        width = self.width()
        spans = []
        for level in (1, 2, 3):
            flagged = self.levels == level
            if not flagged.any():
                continue
            x0 = np.clip(np.floor(centres[flagged] - half), 0, width).astype(np.int64)
            x1 = np.clip(np.ceil(centres[flagged] + half), 0, width).astype(np.int64)
            # +1 at a span's first column, -1 after its last
            covered = np.bincount(x0, minlength=width + 1) - np.bincount(x1, minlength=width + 1)
            inside = np.concatenate([[0], (np.cumsum(covered)[:-1] > 0).astype(np.int8), [0]])
            edges = np.flatnonzero(np.diff(inside))
            spans += [(int(a), int(b), level) for a, b in zip(edges[::2], edges[1::2], strict=True)]
        self._spans = (key, spans)
        return spans

    # ------------------------------------------------------------------ geometry
    def _option(self) -> QStyleOptionSlider:
        option = QStyleOptionSlider()
        self.initStyleOption(option)
        return option

    def _span(self) -> tuple[float, float]:
        """The x of the handle's centre at the first frame and the length to the last one."""
        option = self._option()
        style = self.style()
        groove = style.subControlRect(QStyle.ComplexControl.CC_Slider, option, QStyle.SubControl.SC_SliderGroove, self)
        handle = style.subControlRect(QStyle.ComplexControl.CC_Slider, option, QStyle.SubControl.SC_SliderHandle, self)
        return groove.x() + handle.width() / 2, max(groove.width() - handle.width(), 1)

    def x_of_frame(self, frame: float) -> float:
        """The x (widget pixels) of the handle's centre at ``frame`` (fractions allowed)."""
        left, length = self._span()
        count = max(self.maximum() - self.minimum(), 1)
        return left + length * (frame - self.minimum()) / count

    def frame_at(self, x: float) -> int:
        """The frame whose handle position is nearest ``x``, clamped to the slider's range."""
        left, length = self._span()
        count = max(self.maximum() - self.minimum(), 1)
        frame = round(self.minimum() + (x - left) / length * count)
        return int(min(max(frame, self.minimum()), self.maximum()))

    def flag_text_at(self, x: float) -> str:
        """What is flagged under pixel column ``x`` ("" if nothing is)."""
        if self.levels is None or self.flag_text is None:
            return ""
        if not any(x0 <= x < x1 for x0, x1, _level in self.flag_spans()):
            return ""
        half = FLAG_MIN_WIDTH / 2 + 0.5  # a flag is at least this wide around its frame
        return self.flag_text(self.frame_at(x - half), self.frame_at(x + half))

    def _handle(self):
        """The handle's rectangle as the style places it for the current position."""
        return self.style().subControlRect(
            QStyle.ComplexControl.CC_Slider, self._option(), QStyle.SubControl.SC_SliderHandle, self
        )

    # -------------------------------------------------------------------- events
    def sliderChange(self, change: QAbstractSlider.SliderChange) -> None:  # noqa: N802 (Qt's name)
        """A new value repaints the slider only if the handle moves: on a long take several
        frames share a pixel (2752 frames on 600 pixels), and a frame change during playback
        would repaint the groove, the flags and the handle where they are."""
        if change == QAbstractSlider.SliderChange.SliderValueChange and self._handle() == self._painted_handle:
            return
        super().sliderChange(change)

    def event(self, event: QEvent) -> bool:
        if event.type() == QEvent.Type.ToolTip and isinstance(event, QHelpEvent):
            text = self.flag_text_at(event.pos().x())
            if text:  # over a flag: its findings; elsewhere the slider's own tooltip
                QToolTip.showText(event.globalPos(), text, self)
                return True
        return super().event(event)

    def paintEvent(self, event: QPaintEvent) -> None:  # noqa: N802 (Qt's name)
        self._painted_handle = self._handle()
        super().paintEvent(event)
        if self.levels is not None:
            painter = QPainter(self)
            top = self.height() - FLAG_HEIGHT - 1
            for x0, x1, level in self.flag_spans():
                painter.fillRect(QRectF(x0, top, x1 - x0, FLAG_HEIGHT), FLAG_COLOURS[level])
            painter.end()
        if self.frame_range is None:
            return
        start, stop = self.frame_range
        x0, x1 = self.x_of_frame(start - 0.5), self.x_of_frame(stop - 0.5)
        band = QRectF(x0, 1, max(x1 - x0, 2.0), self.height() - 2)
        painter = QPainter(self)
        painter.fillRect(band, RANGE_COLOUR)
        painter.setPen(RANGE_EDGE)
        painter.drawLine(band.topLeft(), band.bottomLeft())
        painter.drawLine(band.topRight(), band.bottomRight())
        painter.end()

    def mousePressEvent(self, event: QMouseEvent) -> None:  # noqa: N802
        if event.button() == Qt.MouseButton.LeftButton and event.modifiers() & Qt.KeyboardModifier.ShiftModifier:
            self._anchor = self.frame_at(event.position().x())
            self.range_selected.emit(self._anchor, self._anchor + 1)
            event.accept()
            return
        self._anchor = None
        super().mousePressEvent(event)

    def mouseMoveEvent(self, event: QMouseEvent) -> None:  # noqa: N802
        if self._anchor is None:
            super().mouseMoveEvent(event)
            return
        frame = self.frame_at(event.position().x())
        self.range_selected.emit(min(frame, self._anchor), max(frame, self._anchor) + 1)
        event.accept()

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:  # noqa: N802
        if self._anchor is None:
            super().mouseReleaseEvent(event)
            return
        self._anchor = None
        event.accept()
