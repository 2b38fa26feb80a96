"""Playback at the motion's own frame rate, dropping frames rather than slowing down.

The frame shown is computed from the time elapsed since play was pressed
(:func:`frame_at`), never counted up tick by tick, so a slow render skips frames and the
motion keeps its real speed. :class:`Player` owns the timer and writes the frame into the
state; the timeline only sends it play, pause, speed and loop.
"""

from __future__ import annotations

from PyQt6.QtCore import QElapsedTimer, QObject, Qt, QTimer, pyqtSignal

from gmr_studio.app.model.state import StudioState

SPEEDS = (0.25, 0.5, 1.0, 2.0, 4.0)


def frame_at(elapsed: float, start: int, rate: float, speed: float, n_frames: int, loop: bool) -> tuple[int, bool]:
    """The frame to show ``elapsed`` seconds after playing from frame ``start``.

    Returns (frame, finished): without loop, playback stops on the last frame.
    """
    if n_frames <= 0:
        return 0, True
    advance = int(elapsed * rate * speed + 1e-9)
    frame = start + advance
    if loop:
        return frame % n_frames, False
    if frame >= n_frames - 1:
        return n_frames - 1, True
    return frame, False


class Player(QObject):
    """Plays the state's motion: a precise timer ticks, the elapsed time picks the frame."""

    playing_changed = pyqtSignal(bool)
    speed_changed = pyqtSignal(float)
    loop_changed = pyqtSignal(bool)

    def __init__(self, state: StudioState, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.speed = 1.0
        self.loop = True
        self._clock = QElapsedTimer()
        self._start = 0
        self._timer = QTimer(self)
        self._timer.setTimerType(Qt.TimerType.PreciseTimer)
        self._timer.timeout.connect(self._on_tick)
        self._shown = -1
        self.range: tuple[int, int] | None = None  # frames [start, stop) played by play_range
        self._range_loop = False
        state.document_changed.connect(self._on_document_changed)
        state.frame_changed.connect(self._on_frame_changed)

    @property
    def playing(self) -> bool:
        return self._timer.isActive()

    def play_range(self, loop: bool) -> None:
        """Play the state's frame range once (``loop`` False) or in a loop, from its start
        unless the frame is already inside it; a plain :meth:`play` plays everything again."""
        selected = self.state.frame_range
        if selected is None or selected[1] - selected[0] < 2:
            return
        self.pause()
        self.range, self._range_loop = selected, bool(loop)
        if not selected[0] <= self.state.frame < selected[1] - 1:
            self.state.set_frame(selected[0])
        self._start_playing()

    def play(self) -> None:
        self.range = None
        self._start_playing()

    def _start_playing(self) -> None:
        motion = self.state.motion
        if motion is None or motion.n_frames < 2 or self.playing:
            return
        if self.range is not None and not self.range[0] <= self.state.frame < self.range[1]:
            self.range = None  # moved outside the range played last: play everything
        if self.range is None and not self.loop and self.state.frame >= motion.n_frames - 1:
            self.state.set_frame(0)
        elif self.range is not None and not self._range_loop and self.state.frame >= self.range[1] - 1:
            self.state.set_frame(self.range[0])
        self._restart_clock()
        # tick at the motion's rate, at most ~120 Hz (the frame is computed from time anyway)
        interval = max(8, int(1000 * motion.frame_time / self.speed))
        self._timer.start(min(interval, 40))
        self.playing_changed.emit(True)

    def pause(self) -> None:
        if self.playing:
            self._timer.stop()
            self.playing_changed.emit(False)

    def toggle(self) -> None:
        self.pause() if self.playing else self._start_playing()

    def set_speed(self, speed: float) -> None:
        speed = float(min(max(speed, SPEEDS[0]), SPEEDS[-1]))
        if speed != self.speed:
            self.speed = speed
            if self.playing:
                self._restart_clock()
            self.speed_changed.emit(speed)

    def set_loop(self, loop: bool) -> None:
        if loop != self.loop:
            self.loop = bool(loop)
            self.loop_changed.emit(self.loop)

    def _restart_clock(self) -> None:
        self._start = self.state.frame
        if self.range is not None:
            self._start = min(max(self._start, self.range[0]), self.range[1] - 1)
        self._clock.start()

    def _on_tick(self) -> None:
        motion = self.state.motion
        if motion is None:
            self.pause()
            return
        first, stop = self.range or (0, motion.n_frames)
        loop = self._range_loop if self.range else self.loop
        frame, finished = frame_at(
            self._clock.nsecsElapsed() * 1e-9, self._start - first, motion.frame_rate, self.speed, stop - first, loop
        )
        frame += first
        self._shown = frame
        self.state.set_frame(frame)
        if finished:
            self.pause()

    def _on_document_changed(self) -> None:
        self.pause()
        self.range = None

    def _on_frame_changed(self, frame: int) -> None:
        if self.playing and frame != self._shown:  # the user moved the slider: play on from there
            self._restart_clock()
