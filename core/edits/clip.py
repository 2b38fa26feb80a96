"""Clip edits over time: trim to a frame range, resample to another frame rate.

Both work on a motion in either convention and return a new one (the input is never
changed); the skeleton (names, parents, offsets, orders) is untouched.

Resampling is by time, on the project's one grid and interpolator
(:mod:`core.timebase.sampling`). Frame ``k`` of the result is at ``k / rate`` seconds; the
last one is the last that does not pass the source's last frame time by more than the
rounding of a printed frame time (a 31-frame take at 0.033333 s resampled to 15 Hz has 16
frames, the last at 1 s on the source's last frame). At each new time ``s = (i + u) *
frame_time`` (``i`` a source frame, ``0 <= u < 1``), every joint's local rotation is the
slerp of frames ``i`` and ``i + 1`` at ``u`` and every local translation their linear
interpolation. Where ``s`` is a source frame time (to rounding), the source frame is copied
bit for bit: the times of the kept frames are exact, and so are the poses there.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.errors import OperationError
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.timebase.sampling import interpolate, interpolate_rotations, resample_grid


def frame_range(n_frames: int, start: int | None, stop: int | None) -> tuple[int, int]:
    """The half-open range ``[start, stop)`` checked against ``n_frames`` (None: the ends).

    Raises OperationError when it is empty or outside the motion.
    """
    first = 0 if start is None else int(start)
    end = n_frames if stop is None else int(stop)
    if not 0 <= first < end <= n_frames:
        raise OperationError(f"frame range {first}:{end} is empty or outside the motion's 0:{n_frames}")
    return first, end


def trim(motion: Motion, start: int | None, stop: int | None) -> Motion:
    """The frames ``[start, stop)`` of the motion (0-based, stop excluded), copied."""
    return trim_edit(motion, start, stop).motion


def trim_edit(motion: Motion, start: int | None, stop: int | None) -> Edited:
    """:func:`trim`; the result's world transforms are the input's of the frames kept."""
    first, end = frame_range(motion.n_frames, start, stop)
    if (first, end) == (0, motion.n_frames):
        return Edited.same_joints(motion)
    result = motion.replace(
        rotations=motion.rotations[first:end].copy(), translations=motion.translations[first:end].copy()
    )
    return Edited.same_joints(result, rows=(first, end))


def resample(motion: Motion, rate: float) -> Motion:
    """The motion at ``rate`` frames per second (see the module docstring): rotations by
    slerp, translations linearly, source frames copied exactly where a new frame falls on one;
    the motion itself when every new frame falls on the source frame of its number."""
    return resample_edit(motion, rate).motion


def resample_edit(motion: Motion, rate: float) -> Edited:
    """:func:`resample`; when the new frames are every n-th source frame (a rate that
    divides the motion's), the result's world transforms are the input's of those frames;
    else they are to be computed (``Edited.frames`` None)."""
    if not np.isfinite(rate) or rate <= 0:
        raise OperationError(f"the frame rate must be a positive number, not {rate}")
    at = resample_grid(motion.n_frames, motion.frame_time, rate)
    if motion.n_frames >= 2 and np.array_equal(at, np.arange(motion.n_frames)):
        return Edited.same_joints(motion)  # every new frame is a source frame: the rate is the motion's own
    result = motion.replace(
        rotations=interpolate_rotations(motion.rotations, at),
        translations=interpolate(motion.translations, at),
        frame_time=1.0 / rate,
        comments=(*motion.comments, f"resampled from {motion.frame_rate:.12g} Hz to {rate:.12g} Hz"),
    )
    step = int(at[1] - at[0]) if at.size > 1 else 1
    whole = at.size and np.array_equal(at, np.rint(at))
    if whole and step >= 1 and np.array_equal(at, at[0] + step * np.arange(at.size)):
        first = int(at[0])
        return Edited.same_joints(result, rows=(first, first + step * (at.size - 1) + 1, step))
    every = np.arange(motion.n_joints)
    return Edited(result, every, None)
