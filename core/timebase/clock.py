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

from gmr_studio.core.model.motion import Motion


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
