"""One clock for two tracks: B sampled at A's frame times, shifted by an offset.

A's frame ``i`` is at time ``i / rate_A``; it is compared with B at ``i / rate_A + offset``
(seconds), that is B's fractional frame ``u = (i / rate_A + offset) * rate_B``. Where every
``u`` is a whole number (same rate, offset a whole number of frames) B's frames are taken
as they are; otherwise the project's one interpolator (:mod:`core.timebase.sampling`) puts
B on A's clock. Outside B's time range, and next to B's gaps, the samples are NaN.

:func:`core.timebase.clock.common_rate` says when two rates are one (the motion's clock's rule),
:func:`check_overlap` refuses clocks that share no time, :func:`ghost_positions` puts all of
B's points on A's clock and in A's space (what the app draws); :mod:`core.compare.offset`
finds the offset from the whole body.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.timebase.clock import common_rate
from gmr_studio.core.timebase.sampling import WHOLE_FRAME_TOLERANCE, interpolate

#: the offset of every comparison unless one is given: found from the whole body (the
#: CLI's ``--offset`` default and the app's, printed with every comparison)
DEFAULT_OFFSET = "auto"


def sample_frames(n_frames_a: int, rate_a: float, rate_b: float, offset_seconds: float, frames_a=None) -> np.ndarray:
    """B's fractional frame for each compared frame of A: (F,) float64, with B's rate taken
    as A's when they are one (:func:`common_rate`)."""
    frames = np.arange(n_frames_a) if frames_a is None else np.asarray(frames_a)
    return (frames / rate_a + offset_seconds) * common_rate(rate_a, rate_b)


def check_overlap(
    at: np.ndarray, n_frames_b: int, frames_a: np.ndarray, offset_frames: float, offset_seconds: float
) -> None:
    """ValueError (one sentence) when no compared frame of A falls within B's time range.

    at : (F,) B's fractional frames of A's compared frames ``frames_a`` (F,).
    """
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n_frames_b - 1 + WHOLE_FRAME_TOLERANCE)
    if inside.any() or not len(at):
        return
    first, last = int(frames_a[0]), int(frames_a[-1])
    raise ValueError(
        f"the two motions share no time: with the offset B = A {offset_frames:+g} frames "
        f"({offset_seconds:+.6g} s), A's frames {first}-{last} fall at B's frames {at[0]:.6g} to {at[-1]:.6g}, "
        f"outside B's 0-{n_frames_b - 1}; give another --offset (or 'auto')"
    )


def ghost_positions(positions_b: np.ndarray, n_frames_a: int, rate_a: float, rate_b: float, alignment) -> np.ndarray:
    """Every point of B on A's frames and in A's space: (Fb, Jb, 3) -> (Fa, Jb, 3).

    ``alignment``: the :class:`~core.compare.align.Alignment` of a comparison (its offset,
    units, up axis and fit). NaN where B has no sample (outside its time range).
    """
    at = sample_frames(n_frames_a, rate_a, rate_b, alignment.offset_seconds)
    return alignment.apply(interpolate(positions_b, at))
