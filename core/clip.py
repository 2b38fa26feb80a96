"""Clip edits over time: trim to a frame range, resample to another frame rate.

Both work on a motion in either convention and return a new one (the input is never
changed); the skeleton (names, parents, offsets, orders) is untouched.

Resampling is by time. Frame ``k`` of the result is at ``k / rate`` seconds; the last one
is the last that does not pass the source's last frame time. At each new time ``s`` with
``s = (i + u) * frame_time`` (``i`` a source frame, ``0 <= u < 1``), every joint's local
rotation is the slerp of frames ``i`` and ``i + 1`` at ``u`` and every local translation
their linear interpolation. Where ``s`` is a source frame time (``u = 0`` to rounding,
:data:`EXACT_TIME_TOLERANCE`), the source frame is copied bit for bit: the times of the
kept frames are exact, and so are the poses (and hence every world position) there.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.motion import Motion
from gmr_studio.core.quaternions import matrix_from_quaternion, quaternion_from_matrix, slerp

#: a new frame time within this fraction of a source frame interval counts as that source frame
EXACT_TIME_TOLERANCE = 1e-9


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
    first, end = frame_range(motion.n_frames, start, stop)
    if (first, end) == (0, motion.n_frames):
        return motion
    return motion.replace(
        rotations=motion.rotations[first:end].copy(), translations=motion.translations[first:end].copy()
    )


def resample_positions(n_frames: int, frame_time: float, rate: float) -> np.ndarray:
    """Where the frames of the resampled motion fall, in source frames: (K,) float64.

    ``K`` frames at ``k / rate`` seconds, up to the source's last frame time; values within
    :data:`EXACT_TIME_TOLERANCE` of an integer are snapped to it.
    """
    if not np.isfinite(rate) or rate <= 0:
        raise OperationError(f"the frame rate must be a positive number, not {rate}")
    if n_frames == 0:
        return np.zeros(0)
    ratio = 1.0 / (rate * frame_time)  # source frames per new frame
    count = int(np.floor((n_frames - 1) / ratio + EXACT_TIME_TOLERANCE)) + 1
    positions = np.arange(count) * ratio
    nearest = np.rint(positions)
    return np.minimum(np.where(np.abs(positions - nearest) <= EXACT_TIME_TOLERANCE, nearest, positions), n_frames - 1)


def resample(motion: Motion, rate: float) -> Motion:
    """The motion at ``rate`` frames per second (see the module docstring): rotations by
    slerp, translations linearly, source frames copied exactly where a new frame falls on one."""
    if np.isclose(rate * motion.frame_time, 1.0, rtol=0, atol=EXACT_TIME_TOLERANCE):
        return motion
    where = resample_positions(motion.n_frames, motion.frame_time, rate)
    lower = np.minimum(np.floor(where).astype(np.int64), max(motion.n_frames - 2, 0))
    fraction = where - lower
    exact = fraction == 0.0
    upper = lower + 1
    between = ~exact & (fraction != 1.0)
    rotations = motion.rotations[np.where(fraction == 1.0, upper, lower)].copy()
    translations = motion.translations[np.where(fraction == 1.0, upper, lower)].copy()
    if between.any():
        lo, hi, u = lower[between], upper[between], fraction[between]
        q0 = quaternion_from_matrix(motion.rotations[lo])
        q1 = quaternion_from_matrix(motion.rotations[hi])
        rotations[between] = matrix_from_quaternion(slerp(q0, q1, np.broadcast_to(u[:, None], q0.shape[:-1])))
        t0, t1 = motion.translations[lo], motion.translations[hi]
        translations[between] = t0 + (t1 - t0) * u[:, None, None]
    return motion.replace(
        rotations=rotations,
        translations=translations,
        frame_time=1.0 / rate,
        comments=(*motion.comments, f"resampled from {motion.frame_rate:.12g} Hz to {rate:.12g} Hz"),
    )
