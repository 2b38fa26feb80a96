"""A motion's clock: when each frame is, and how long a motion lasts (one definition).

Frame ``i`` (0-based) is at ``i * frame_time`` seconds: the first frame is at 0 s. Each frame
is shown for one frame time, so a motion of ``F`` frames lasts ``F * frame_time`` seconds (its
*duration*: what ``gmr info`` prints, the timeline's total, the length of a video of every
frame at the motion's rate); its last frame is at ``(F - 1) * frame_time``, one frame time
before the end. A motion with one frame lasts one frame time; one with none lasts 0 s.

Every surface that speaks of seconds calls these: ``gmr info`` (duration), ``gmr curves``
(its ``time`` column), ``gmr compare`` (A's compared frames' times), the app's timeline.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.motion import Motion


def frame_seconds(frames, frame_time: float):
    """Seconds of 0-based frame numbers: ``frames * frame_time`` (a number or an array (F,))."""
    if np.isscalar(frames):
        return float(frames) * float(frame_time)
    return np.asarray(frames, dtype=np.float64) * float(frame_time)


def duration_seconds(n_frames: int, frame_time: float) -> float:
    """How long ``n_frames`` frames last: ``n_frames * frame_time`` (each shows one frame time)."""
    return float(n_frames) * float(frame_time)


def motion_duration(motion: Motion) -> float:
    """:func:`duration_seconds` of a motion."""
    return duration_seconds(motion.n_frames, motion.frame_time)


def motion_frame_seconds(motion: Motion, frames=None):
    """:func:`frame_seconds` of a motion's frames (default: all, (F,))."""
    return frame_seconds(np.arange(motion.n_frames) if frames is None else frames, motion.frame_time)


#: frame rates a file's authors mean when its frame time is rounded: whole numbers of frames
#: a second, and the NTSC video rates ``n * 1000 / 1001`` (23.976, 29.97, 59.94 ... Hz)
NTSC_RATES = tuple(n * 1000.0 / 1001.0 for n in (24, 30, 48, 60, 120, 240))
#: relative rounding every frame time may carry: glTF stores key times as 32-bit floats, so a
#: frame time taken from them is off by about 1e-7 of itself
SINGLE_PRECISION = 1e-6


def frame_time_rounding(frame_time: float) -> float:
    """How far the true frame time may be from ``frame_time`` as printed: half a unit of its
    last decimal (``0.008333``: 5e-7) as the shortest text of the number shows it, and at
    least :data:`SINGLE_PRECISION` of it."""
    text = np.format_float_positional(float(frame_time), unique=True, trim="-")
    decimals = len(text.partition(".")[2])
    return max(0.5 * 10.0**-decimals, SINGLE_PRECISION * float(frame_time))


def nominal_rate(frame_time: float) -> float:
    """The frame rate a file's authors meant (Hz): the *nice* rate whose frame time lies
    within the rounding of ``frame_time`` (:func:`frame_time_rounding`): a whole number of
    frames a second (``0.008333`` is 120 Hz, not 120.005), else an NTSC rate
    (:data:`NTSC_RATES`: ``0.0333667`` is 29.97 Hz); the exact ``1 / frame_time`` when none
    is, or when the printed time is too coarse to single out one whole number (``0.03``:
    anything from 29 to 40 Hz).

    The app's timeline and ``gmr info`` show this rate (with the exact one on hover or
    beside it); every computation keeps the frame time as read."""
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
