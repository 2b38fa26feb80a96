"""Foot contact bars under the timeline: one row per foot joint, filled where it is planted.

The contacts come from :func:`core.analysis.contacts.foot_contacts` on the document's cached world
positions, recomputed when the motion or the thresholds change (two spin boxes: height and
speed as percentages of the skeleton's size); a new document's once its first frame is drawn
(``StudioState.document_shown``), which they must not delay. The current frame is a vertical line; a click
or drag in the bars sets the frame. The bars are an image made once per contacts and width,
so playback only redraws the line. Shift+drag selects the state's frame range (shaded), as in
the curves plot.
"""

from __future__ import annotations

import numpy as np
from PyQt6.QtCore import QRect, QRectF, Qt
from PyQt6.QtGui import QColor, QImage, QMouseEvent, QPainter, QPaintEvent
from PyQt6.QtWidgets import QDoubleSpinBox, QHBoxLayout, QLabel, QSizePolicy, QVBoxLayout, QWidget

from gmr_studio.app.docks.frame_follow import follow_frame
from gmr_studio.app.model.state import StudioState
from gmr_studio.core.analysis.contacts import DEFAULT_HEIGHT, DEFAULT_SPEED, Contacts, foot_contacts

ROW_HEIGHT = 14
NAME_WIDTH = 110
PLANTED_COLOUR = QColor("#59a14f")
BACKGROUND = QColor("#26282c")
CURSOR_COLOUR = QColor("#ffd400")
RANGE_COLOUR = QColor(255, 212, 0, 50)


class ContactStrip(QWidget):
    """The painted bars (names on the left, frames across).

    The bars are drawn once per contacts and width into an image (:func:`bars_image`,
    vectorised over frames), so a frame change only blits it and draws the cursor line.
    """

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.contacts: Contacts | None = None
        self._image: QImage | None = None
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self._range_anchor: int | None = None
        self._cursor_x: int | None = None  # where the cursor was last drawn
        self.frame_follower = follow_frame(self, state, self._on_frame_changed)  # only while shown
        state.range_changed.connect(lambda *_: self.update())

    def _on_frame_changed(self, frame: int) -> None:
        """Repaint only the columns of the old and the new cursor (not the whole bars)."""
        x = int(self.x_of_frame(frame + 0.5))
        if self._cursor_x is None:
            self.update()
        elif x != self._cursor_x:
            for column in (self._cursor_x, x):
                self.update(QRect(column - 1, 0, 3, self.height()))
        self._cursor_x = x

    def set_contacts(self, contacts: Contacts | None, *, keep_height: bool = False) -> None:
        """Show ``contacts`` (None: none); ``keep_height``: as tall as before (a new
        document's bars to come, the docks' layout unmoved meanwhile)."""
        self.contacts = contacts
        self._image = None
        if not keep_height:
            rows = 0 if contacts is None else len(contacts.names)
            self.setFixedHeight(max(rows, 1) * ROW_HEIGHT + 2)
        self.update()

    def x_of_frame(self, frame: float) -> float:
        n = max(self.state.n_frames, 1)
        return NAME_WIDTH + (self.width() - NAME_WIDTH) * frame / n

    def frame_at(self, x: float) -> int:
        n = max(self.state.n_frames, 1)
        return int(min(max((x - NAME_WIDTH) / max(self.width() - NAME_WIDTH, 1) * n, 0), n - 1))

    def resizeEvent(self, event) -> None:  # noqa: N802
        self._image = None
        super().resizeEvent(event)

    def paintEvent(self, event: QPaintEvent) -> None:  # noqa: N802
        painter = QPainter(self)
        painter.fillRect(self.rect(), BACKGROUND)
        if self.contacts is not None:
            if self._image is None or self._image.width() != self.width() - NAME_WIDTH:
                self._image = bars_image(self.contacts.planted, self.width() - NAME_WIDTH)
            painter.drawImage(NAME_WIDTH, 1, self._image)
            painter.setPen(QColor("#cfcfcf"))
            for row, name in enumerate(self.contacts.names):
                rect = QRectF(4, 1 + row * ROW_HEIGHT, NAME_WIDTH - 8, ROW_HEIGHT)
                painter.drawText(rect, Qt.AlignmentFlag.AlignVCenter, name)
        if self.state.frame_range is not None:
            start, stop = self.state.frame_range
            x0, x1 = self.x_of_frame(start), self.x_of_frame(stop)
            painter.fillRect(QRectF(x0, 0, max(x1 - x0, 1.0), self.height()), RANGE_COLOUR)
        x = self.x_of_frame(self.state.frame + 0.5)
        self._cursor_x = int(x)
        painter.setPen(CURSOR_COLOUR)
        painter.drawLine(int(x), 0, int(x), self.height())
        painter.end()

    def mousePressEvent(self, event: QMouseEvent) -> None:  # noqa: N802
        frame = self.frame_at(event.position().x())
        if event.modifiers() & Qt.KeyboardModifier.ShiftModifier:  # Shift+drag: a frame range
            self._range_anchor = frame
            self.state.set_frame_range(frame, frame + 1)
        else:
            self._range_anchor = None
            self.state.set_frame(frame)

    def mouseMoveEvent(self, event: QMouseEvent) -> None:  # noqa: N802
        if not event.buttons() & Qt.MouseButton.LeftButton:
            return
        frame = self.frame_at(event.position().x())
        if self._range_anchor is not None:
            self.state.set_frame_range(min(frame, self._range_anchor), max(frame, self._range_anchor) + 1)
        else:
            self.state.set_frame(frame)


def bars_image(planted: np.ndarray, width: int) -> QImage:
    """The bars of planted (F, K) bool as an image ``width`` px wide, ``K * ROW_HEIGHT`` high:
    a pixel column is filled where any of its frames is planted."""
    n_frames, n_rows = planted.shape
    width = max(int(width), 1)
    column = np.minimum((np.arange(n_frames) * width) // max(n_frames, 1), width - 1)
    filled = np.zeros((n_rows, width), bool)
    for row in range(n_rows):
        filled[row, column[planted[:, row]]] = True
    pixels = np.empty((n_rows, ROW_HEIGHT, width, 3), np.uint8)
    pixels[:] = (BACKGROUND.red(), BACKGROUND.green(), BACKGROUND.blue())
    bar = pixels[:, 2 : ROW_HEIGHT - 2]
    bar[np.broadcast_to(filled[:, None, :], bar.shape[:3])] = (
        PLANTED_COLOUR.red(),
        PLANTED_COLOUR.green(),
        PLANTED_COLOUR.blue(),
    )
    rows = np.ascontiguousarray(pixels.reshape(n_rows * ROW_HEIGHT, width, 3))
    return QImage(rows.data, width, rows.shape[0], 3 * width, QImage.Format.Format_RGB888).copy()


class ContactBars(QWidget):
    """Contact strip plus its two thresholds."""

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.strip = ContactStrip(state, self)
        self.height_box = _percent_box(DEFAULT_HEIGHT, "Height threshold, % of the skeleton's size", self)
        self.speed_box = _percent_box(DEFAULT_SPEED, "Speed threshold, % of the skeleton's size per second", self)
        self.summary = QLabel(self)
        controls = QHBoxLayout()
        controls.addWidget(QLabel("Planted: height <", self))
        controls.addWidget(self.height_box)
        controls.addWidget(QLabel("speed <", self))
        controls.addWidget(self.speed_box)
        controls.addWidget(QLabel("/s", self))
        controls.addWidget(self.summary, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 0, 6, 2)
        layout.addLayout(controls)
        layout.addWidget(self.strip)
        self.height_box.valueChanged.connect(lambda _: self.recompute())
        self.speed_box.valueChanged.connect(lambda _: self.recompute())
        state.document_changed.connect(self._on_document_changed)
        state.document_shown.connect(self.recompute)  # a new document's, once its first frame is drawn
        state.motion_changed.connect(self.recompute)
        self.recompute()

    def _on_document_changed(self) -> None:
        """Another document: its contacts follow once its first frame is drawn."""
        self.strip.set_contacts(None, keep_height=True)
        self.summary.setText("")

    def recompute(self) -> None:
        snapshot = self.state.snapshot
        contacts = None
        if snapshot is not None:
            contacts = foot_contacts(
                snapshot.motion,
                snapshot.positions,
                height=self.height_box.value() / 100,
                speed=self.speed_box.value() / 100,
            )
            if not contacts.names:
                contacts = None
        self.strip.set_contacts(contacts)
        if contacts is None:
            self.summary.setText("no foot joints" if snapshot is not None else "")
        else:
            share = ", ".join(f"{n} {100 * p:.0f}%" for n, p in zip(contacts.names, contacts.planted.mean(axis=0)))
            self.summary.setText(f"  planted: {share}")


def _percent_box(fraction: float, tip: str, parent: QWidget) -> QDoubleSpinBox:
    box = QDoubleSpinBox(parent)
    box.setRange(0.0, 1000.0)
    box.setDecimals(1)
    box.setSingleStep(0.5)
    box.setSuffix(" %")
    box.setValue(100 * fraction)
    box.setToolTip(tip)
    box.setKeyboardTracking(False)
    return box
