"""Rotations continuous over frames: the one rule for Euler angles and quaternions.

Everything that shows or writes angles over time uses these: the BVH and GMR writers, the
curves dock and ``gmr curves``, the inspector, glTF export and ``gmr dataset``. So the
curves of a motion are the channels of that motion written as BVH, frame for frame.

Euler angles (:func:`continuous_euler`). Every rotation has two intrinsic Tait-Bryan
decompositions, ``(a, b, c)`` and ``(a + pi, pi - b, c + pi)``; :func:`euler_from_matrix`
gives the principal one (``|b| <= pi / 2``), so a motion whose middle angle passes 90 degrees
(a root turning over) jumps there. Frame ``f`` changes branch when the other decomposition
is nearer frame ``f - 1``'s angles than its own *and* the middle angle is beyond
:data:`BRANCH_MIDDLE` at both frames, i.e. on the way through 90 degrees. A jump in the data
itself (CMU's T-pose first frame) changes nothing: the angles stay principal wherever the
motion allows. The wrapped distance between consecutive frames does not depend on which
branch the previous frame took (both branches differ by the same shift), only on whether the
branch changes, so the changes add up with a cumulative sum; then ``numpy.unwrap`` adds the
multiples of 360 degrees. The first frame keeps the principal decomposition. All of it is
vectorised over frames and any further axes (joints).

Quaternions (:func:`continuous_quaternions`): signs chosen so that consecutive frames lie in
one hemisphere (``q_f . q_{f-1} >= 0``): the same rotations, smooth curves, and the short way
round for a consumer that interpolates them linearly (glTF).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.rotations.euler import complete_order, euler_from_matrix

#: radians: the Euler branch may change only where the middle angle is beyond this at both
#: frames (on the way through 90 degrees)
BRANCH_MIDDLE = np.radians(60.0)
_TWO_PI = 2.0 * np.pi


def _wrapped_square_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Sum over the last axis of the squared angle differences, each wrapped to [-pi, pi)."""
    difference = np.remainder(a - b + np.pi, _TWO_PI) - np.pi
    return np.einsum("...i,...i->...", difference, difference)


def continuous_euler(matrices: np.ndarray, order: str, previous: np.ndarray | None = None) -> np.ndarray:
    """Intrinsic Euler angles, continuous along the first axis (frames); module docstring.

    Parameters
    ----------
    matrices : (F, ..., 3, 3) rotations, frames first.
    order : 1 to 3 axis letters; shorter orders give the angles about their axes only
        (the rotation must not need the others; no branch change is then possible).
    previous : (..., len(order)) radians, the angles this function returned for the frame
        just before ``matrices[0]``: the result then continues from them, so that a long
        motion converted block by block gets the same angles as in one call (to rounding).
        None: the first frame keeps the principal decomposition.

    Returns
    -------
    (F, ..., len(order)) radians; each angle differs from the previous frame's by less
    than pi, and the angles reproduce the matrices (to rounding).
    """
    angles = euler_from_matrix(matrices, complete_order(order))[..., : len(order)]
    last = None if previous is None else np.asarray(previous, dtype=np.float64)
    on_other = False  # the branch the frame before the first is on
    if last is not None:
        start = last
        if len(order) == 3:  # continue on the previous frame's branch, from its principal form
            on_other = np.cos(last[..., 1]) < 0
            start = np.where(on_other[..., None], _other_branch(last), last)
        angles = np.concatenate([start[None], angles])
    if angles.shape[0] >= 2 and len(order) == 3:
        other = _other_branch(angles)
        stay = _wrapped_square_distance(angles[1:], angles[:-1])
        change = _wrapped_square_distance(other[1:], angles[:-1])
        steep = np.abs(np.remainder(angles[..., 1] + np.pi, _TWO_PI) - np.pi) > BRANCH_MIDDLE
        switch = (change < stay) & steep[1:] & steep[:-1]
        branch = np.concatenate([np.zeros_like(switch[:1]), np.cumsum(switch, axis=0) % 2 == 1]) ^ on_other
        angles = np.where(branch[..., None], other, angles)
    if last is not None:
        angles[0] = last  # the same rotation; unwrapping continues from the values given
    if angles.shape[0] >= 2:
        angles = np.unwrap(angles, axis=0)
    return angles[1:] if last is not None else angles


def _other_branch(angles: np.ndarray) -> np.ndarray:
    """``(a + pi, pi - b, c + pi)`` of three-axis angles (..., 3): the other decomposition."""
    other = angles + np.array([np.pi, 0.0, np.pi])
    other[..., 1] = np.pi - angles[..., 1]
    return other


def continuous_quaternions(quaternions: np.ndarray) -> np.ndarray:
    """Quaternions over frames (F, ..., 4), either component order, with signs chosen so
    that consecutive frames lie in one hemisphere (each ``q_f . q_{f-1} >= 0``)."""
    q = np.asarray(quaternions, dtype=np.float64)
    if q.shape[0] < 2:
        return q.copy()
    flips = np.einsum("f...c,f...c->f...", q[1:], q[:-1]) < 0
    sign = np.concatenate([np.ones((1, *q.shape[1:-1])), np.where(np.cumsum(flips, axis=0) % 2 == 1, -1.0, 1.0)])
    return q * sign[..., None]
