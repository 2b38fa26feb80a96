"""The timeline dock: slider, play/pause, step, loop, speed, frame number and time.

The keys (space, arrows, Home/End) are window shortcuts defined with the actions; the
buttons here trigger the same actions, so both stay in step. The slider also shows the
state's frame range and selects it with Shift+drag (:mod:`app.range_slider`); the I and O
buttons (and keys) set its start and end at the current frame. Under its groove, the
quality checks' flags (:class:`app.model.problems.Problems`), coloured by severity.
"""

from __future__ import annotations

from PyQt6.QtCore import Qt
from PyQt6.QtGui import QAction, QValidator
from PyQt6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QSpinBox, QToolButton, QWidget

from gmr_studio.app.docks.range_slider import RangeSlider
from gmr_studio.app.model.formatting import frame_of
from gmr_studio.app.model.playback import SPEEDS, Player
from gmr_studio.app.model.problems import Problems
from gmr_studio.app.model.state import StudioState
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.timebase.clock import duration_of, frame_seconds, rate_text


class FrameBox(QSpinBox):
    """The frame number: any whole number may be typed, and one past the last frame lands
    on the last frame (a plain QSpinBox refuses the digit that passes the maximum, so
    typing 99999999 in a 2,752-frame take left 999)."""

    def validate(self, text: str, position: int) -> tuple[QValidator.State, str, int]:
        digits = text.strip()
        if digits.isdigit():
            inside = self.minimum() <= int(digits) <= self.maximum()
            return (QValidator.State.Acceptable if inside else QValidator.State.Intermediate), text, position
        return super().validate(text, position)

    def fixup(self, text: str) -> str:
        digits = text.strip()
        if digits.isdigit():
            return str(min(max(int(digits), self.minimum()), self.maximum()))
        return super().fixup(text)


class Timeline(QWidget):
    """Frame slider and transport controls."""

    def __init__(
        self,
        state: StudioState,
        player: Player,
        actions: dict[str, QAction],
        problems: Problems | None = None,
        parent: QWidget | None = None,
    ) -> None:
        super().__init__(parent)
        self.state = state
        self.player = player
        # opaque: a frame change repaints the slider and the labels, not the dock and the
        # window behind them (the dock's title style alone reloaded an icon file each time)
        self.setAutoFillBackground(True)
        layout = QHBoxLayout(self)
        layout.setContentsMargins(6, 2, 6, 2)
        for name in ("first_frame", "step_back", "play", "step_forward", "last_frame"):
            button = QToolButton(self)
            button.setDefaultAction(actions[name])
            button.setAutoRaise(True)
            layout.addWidget(button)
        self.slider = RangeSlider(self)
        self.slider.setFocusPolicy(Qt.FocusPolicy.NoFocus)  # arrows belong to the window shortcuts
        self.slider.setToolTip("Drag: frame; Shift+drag: frame range (I / O: its start / end)")
        self.slider.valueChanged.connect(state.set_frame)
        self.slider.range_selected.connect(state.set_frame_range)
        state.range_changed.connect(self.slider.set_frame_range)
        layout.addWidget(self.slider, 1)
        self.range_buttons = {}
        for name, text in (("range_start", "I"), ("range_end", "O")):
            button = QToolButton(self)  # short text; the action (and its key) does the work
            button.setText(text)
            button.setToolTip(f"{actions[name].text().replace('&', '')} ({text})")
            button.setAutoRaise(True)
            button.clicked.connect(actions[name].trigger)
            layout.addWidget(button)
            self.range_buttons[name] = button
        self.frame_box = FrameBox(self)
        self.frame_box.setKeyboardTracking(False)
        self.frame_box.setToolTip("Frame number (0-based: the first frame is 0)")
        self.frame_box.valueChanged.connect(state.set_frame)
        layout.addWidget(self.frame_box)
        self.time_label = QLabel(self)
        layout.addWidget(self.time_label)
        loop = QToolButton(self)
        loop.setDefaultAction(actions["loop"])
        loop.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonTextOnly)
        layout.addWidget(loop)
        self.speed_box = QComboBox(self)
        self.speed_box.setToolTip("Playback speed")
        for speed in SPEEDS:
            self.speed_box.addItem(f"{speed:g}x", speed)
        self.speed_box.setCurrentIndex(SPEEDS.index(1.0))
        self.speed_box.currentIndexChanged.connect(lambda i: player.set_speed(self.speed_box.itemData(i)))
        layout.addWidget(self.speed_box)
        state.document_changed.connect(self._on_document_changed)
        state.motion_changed.connect(self._on_document_changed)
        state.frame_changed.connect(self._on_frame_changed)
        player.speed_changed.connect(self._on_speed_changed)
        self.problems = problems
        if problems is not None:  # the checks' flags under the groove, their findings as tooltips
            problems.changed.connect(self._on_problems_changed)
            self.slider.flag_text = problems.describe
        self._on_document_changed()
        self._on_problems_changed()

    def _on_problems_changed(self) -> None:
        if self.problems is not None:
            self.slider.set_levels(self.problems.frame_levels() if self.problems.flags is not None else None)

    def _on_document_changed(self) -> None:
        last = max(self.state.n_frames - 1, 0)
        for widget in (self.slider, self.frame_box):
            widget.blockSignals(True)
            widget.setRange(0, last)
            widget.blockSignals(False)
        self.slider.setPageStep(max(1, round(self.state.motion.frame_rate)) if self.state.motion else 10)
        self.setEnabled(self.state.motion is not None)
        self._fit_time_label()
        self.time_label.setToolTip(rate_tooltip(self.state.motion) if self.state.motion is not None else "")
        self._on_frame_changed(self.state.frame)

    def _fit_time_label(self) -> None:
        """Size the time label once per document for its widest text, at a fixed size: a label
        whose size follows its text asks the window to lay out its docks again on every frame
        (a layout pass and a repaint of the dock area, on every frame during playback)."""
        motion = self.state.motion
        widest = time_text(motion, motion.n_frames - 1) if motion is not None else ""
        metrics = self.time_label.fontMetrics()
        digit = max("0123456789", key=metrics.horizontalAdvance)  # every digit as the widest one
        widest = widest.translate(str.maketrans("0123456789", digit * 10))
        width = max(150, metrics.horizontalAdvance(widest) + metrics.averageCharWidth())
        self.time_label.setFixedSize(width, self.time_label.sizeHint().height())

    def _on_frame_changed(self, frame: int) -> None:
        for widget in (self.slider, self.frame_box):
            widget.blockSignals(True)
            widget.setValue(frame)
            widget.blockSignals(False)
        motion = self.state.motion
        if motion is None:
            self.time_label.setText("")
            return
        self.time_label.setText(time_text(motion, frame))

    def _on_speed_changed(self, speed: float) -> None:
        index = self.speed_box.findData(speed)
        if index >= 0 and index != self.speed_box.currentIndex():
            self.speed_box.blockSignals(True)
            self.speed_box.setCurrentIndex(index)
            self.speed_box.blockSignals(False)


def time_text(motion: Motion, frame: int) -> str:
    """The timeline's label: the frame's time and the motion's duration (:mod:`core.timebase.clock`:
    frame ``i`` at ``i * frame_time``, ``F`` frames last ``F * frame_time``), the frame,
    0-based like the frame box and the inspector (:func:`app.model.formatting.frame_of`),
    and the rate as the file's authors meant it (:func:`core.timebase.clock.rate_text`)."""
    count = f"{frame_of(frame, motion.n_frames)} @ {rate_text(motion.frame_time)} Hz"
    return f"{frame_seconds(frame, motion.frame_time):7.3f} s / {duration_of(motion):.3f} s  ({count})"


def rate_tooltip(motion: Motion) -> str:
    """The time label's tooltip: the frame time as read and the exact rate it gives."""
    return (
        f"frame time {motion.frame_time:.9g} s: {motion.frame_rate:.9g} Hz exactly "
        f"(shown as {rate_text(motion.frame_time)} Hz, the rate within the frame time's rounding)"
    )
