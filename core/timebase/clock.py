"""The clock of a motion or a marker set: when each frame is, and how long it lasts (one definition).

Anything with ``n_frames`` and ``frame_time`` has a clock (:class:`Timed`: a
:class:`~core.model.motion.Motion`, a :class:`~core.markers.markerset.MarkerSet`). Frame ``i``
(0-based) is at ``i * frame_time`` seconds: the first frame is at 0 s. Each frame is shown for
one frame time, so ``F`` frames last ``F * frame_time`` seconds (the *duration*: what ``gmr
info`` prints for motions and markers, the timeline's total, the length of a video of every
frame at its rate); the last frame is at ``(F - 1) * frame_time``, one frame time before the
end. One frame lasts one frame time; none lasts 0 s.

Every surface that speaks of seconds calls these: ``gmr info`` (duration), ``gmr curves``
(its ``time`` column), ``gmr compare`` (A's compared frames' times), the app's timeline.

A frame time read from a file is printed with a few digits (BVH's ``0.033333`` is 30.0003 Hz,
``0.0083333`` 120.0005 Hz), so the times counted in it carry that rounding, one frame after
another. Two rates closer than :data:`SAME_RATE_TOLERANCE` (relative) are one rate
(:func:`common_rate`, what ``gmr compare`` uses), and a new clock's frames reach a motion's
last frame when they pass it by no more than the rounding of its frame time on every frame
(:func:`frames_within`: a 31-frame take at 0.033333 s resampled to 15 Hz has 16 frames, the
last at 1 s). Resampling a motion (``core.edits.clip``), ``gmr dataset --rate`` and markers put on
a motion's clock count their frames with it.
"""

from __future__ import annotations

from decimal import Decimal
from typing import Protocol

import numpy as np

#: frame rates closer than this (relative) are one rate: BVH prints its frame time to ~7
#: digits (0.0083333 s is 120.0005 Hz), which would otherwise drift one clock against the
#: other by a frame in 2,000 s
SAME_RATE_TOLERANCE = 1e-5
#: the most a frame time is taken to be off when counting frames on another clock (seconds):
#: half a unit of the sixth decimal, as BVH writers print it at the least (0.033333, 0.008333)
FRAME_TIME_ROUNDING = 5e-7
#: relative rounding every frame time may carry: glTF stores key times as 32-bit floats, so a
#: frame time taken from them is off by about 1e-7 of itself
SINGLE_PRECISION = 1e-6
#: frame rates a file's authors mean when its frame time is rounded: whole numbers of frames
#: a second, and the NTSC video rates ``n * 1000 / 1001`` (23.976, 29.97, 59.94 ... Hz)
NTSC_RATES = tuple(n * 1000.0 / 1001.0 for n in (24, 30, 48, 60, 120, 240))
#: new frames past a motion's last frame within this are at it (float rounding of products)
_FLOAT_SLACK = 1e-9


def frame_seconds(frames, frame_time: float):
    """Seconds of 0-based frame numbers: ``frames * frame_time`` (a number or an array (F,))."""
    if np.isscalar(frames):
        return float(frames) * float(frame_time)
    return np.asarray(frames, dtype=np.float64) * float(frame_time)


def duration_seconds(n_frames: int, frame_time: float) -> float:
    """How long ``n_frames`` frames last: ``n_frames * frame_time`` (each shows one frame time)."""
    return float(n_frames) * float(frame_time)


class Timed(Protocol):
    """Frames on a clock: a motion, a marker set."""

    @property
    def n_frames(self) -> int: ...

    @property
    def frame_time(self) -> float: ...


def duration_of(timed: Timed) -> float:
    """:func:`duration_seconds` of a motion's or a marker set's frames."""
    return duration_seconds(timed.n_frames, timed.frame_time)


def times_of(timed: Timed, frames=None):
    """:func:`frame_seconds` of a motion's or a marker set's frames (default: all, (F,))."""
    return frame_seconds(np.arange(timed.n_frames) if frames is None else frames, timed.frame_time)


def common_rate(rate_a: float, rate_b: float) -> float:
    """B's rate as a comparison of A and B uses it: A's when the two differ by less than
    :data:`SAME_RATE_TOLERANCE` (the rounding of a printed frame time), else B's own."""
    if rate_b != rate_a and abs(rate_b / rate_a - 1.0) < SAME_RATE_TOLERANCE:
        return rate_a
    return rate_b


def frame_time_rounding(frame_time: float) -> float:
    """How far a frame time read from a file may be from the one its authors meant (seconds):
    half a unit of the last decimal of its shortest printed form (5e-7 for 0.008333, 5e-8 for
    0.0083333, 5e-5 for 0.0417), and at least :data:`SINGLE_PRECISION` of it (glTF's 32-bit
    key times: 0.041666668 is 1/24 s)."""
    exponent = Decimal(repr(float(frame_time))).as_tuple().exponent
    return max(0.5 * 10.0 ** int(exponent), SINGLE_PRECISION * float(frame_time))


def nominal_rate(frame_time: float) -> float:
    """The frame rate a file's authors meant (Hz): the *nice* rate whose frame time lies
    within the rounding of ``frame_time`` (:func:`frame_time_rounding`): a whole number of
    frames a second (``0.008333`` is 120 Hz, not 120.005), else an NTSC rate
    (:data:`NTSC_RATES`: ``0.0333667`` is 29.97 Hz); the exact ``1 / frame_time`` when none is.

    The app's timeline and ``gmr info`` show this rate (with the exact one on hover or
    beside it); every computation keeps the frame time as read (but a rate that divides it
    to within that rounding counts every n-th frame: :func:`frames_per_frame`)."""
    frame_time = float(frame_time)
    rounding = frame_time_rounding(frame_time)
    low, high = 1.0 / (frame_time + rounding), 1.0 / max(frame_time - rounding, 1e-300)
    whole = np.arange(max(np.ceil(low), 1.0), np.floor(high) + 1.0)
    if len(whole) == 1:
        return float(whole[0])
    ntsc = [r for r in NTSC_RATES if low <= r <= high]
    if len(whole) == 0 and len(ntsc) == 1:
        return ntsc[0]
    return 1.0 / frame_time


def rate_text(frame_time: float) -> str:
    """A motion's rate as people say it: :func:`nominal_rate` to 6 significant digits
    (``"120"``, ``"29.97"``, ``"30.0003"`` for an unrounded 0.03333 s)."""
    return f"{nominal_rate(frame_time):.6g}"


def counting_rounding(frame_time: float) -> float:
    """How far a frame time is taken to be off when its frames are counted on another clock
    (seconds): its printed rounding (:func:`frame_time_rounding`), at most
    :data:`FRAME_TIME_ROUNDING`."""
    return min(frame_time_rounding(frame_time), FRAME_TIME_ROUNDING)


def frames_per_frame(frame_time: float, rate: float) -> int | None:
    """The whole number ``n`` of frames of ``frame_time`` s in one frame of a clock at
    ``rate`` Hz, when ``rate`` divides the frame rate to within :func:`counting_rounding`
    (60 Hz of 0.0083333 s: 2, though 2.000008 as printed); None when it does not."""
    step = 1.0 / (float(rate) * float(frame_time))
    every = round(step)
    if every >= 1 and abs(step - every) <= every * counting_rounding(frame_time) / float(frame_time):
        return every
    return None


def frames_within(n_frames: int, frame_time: float, rate: float) -> int:
    """How many frames of a clock at ``rate`` Hz (frame ``k`` at ``k / rate`` s) fall within
    ``n_frames`` frames of ``frame_time``: from 0 s to the last frame, at
    ``(n_frames - 1) * frame_time`` give or take :func:`frame_time_rounding` on every frame (31
    frames of 0.033333 s end at 0.99999 s, 1 s as meant: at 15 Hz, 16 frames). ``rate`` > 0."""
    if n_frames <= 0:
        return 0
    last = (n_frames - 1) * (float(frame_time) + counting_rounding(frame_time))
    return int(np.floor(last * float(rate) + _FLOAT_SLACK)) + 1
