"""Rigid fits for every frame at once: batched least squares and nearest rotations by SVD.

Two fits, both vectorised over frames (one batched SVD, no loop):

- :func:`fit_rigid`: the rotation and translation that carry a template point set onto
  measured points in the least-squares sense (orthogonal Procrustes / Kabsch), with a mask
  for missing points and a per-frame RMS residual. Used for marker clusters. Its home is
  :mod:`core.space.similarity` (every rigid and similarity fit of the project); it is re-exported here.
- :func:`frame_from_triple`: the technical note's pelvis frame ``[p1, p2, p3]`` of three
  points (Gram-Schmidt, with the note's equation 2 corrected as in MATH.md), used by
  :func:`core.markers.pelvis.recover_pelvis`.

Shapes: points are ``(..., K, 3)`` with the frames in the leading axes; rotations
``(..., 3, 3)`` act on column vectors.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.space.similarity import DEGENERATE_RATIO, fit_rigid

__all__ = ["DEGENERATE_RATIO", "fit_rigid", "frame_from_triple"]


def frame_from_triple(x1: np.ndarray, x2: np.ndarray, x3: np.ndarray, min_sine: float = 1e-6):
    """The note's orthonormal frame of three points, for every frame.

    ``p1 = (X1 - X2)/|X1 - X2|``, ``p2* = (X1 - X3) - ((X1 - X3).p1) p1``,
    ``p2 = p2*/|p2*|``, ``p3 = p1 x p2``.

    Parameters
    ----------
    x1, x2, x3 : (..., 3) float.
    min_sine : the triple is degenerate when the sine of the angle at X1 between X2 and
        X3 is below this, or when X2 or X3 is within ``min_sine`` of the triangle's longest
        side from X1.

    Returns
    -------
    frames : (..., 3, 3), columns p1, p2, p3 (identity where not ``ok``).
    ok : (..., ) bool, finite and not degenerate.
    coincident : (..., ) bool, two of the points (nearly) coincide.
    collinear : (..., ) bool, the points are (nearly) on one line but distinct.
    """
    a = np.asarray(x1, dtype=np.float64) - np.asarray(x2, dtype=np.float64)
    b = np.asarray(x1, dtype=np.float64) - np.asarray(x3, dtype=np.float64)
    finite = np.isfinite(a).all(axis=-1) & np.isfinite(b).all(axis=-1)
    a = np.where(finite[..., None], a, 0.0)
    b = np.where(finite[..., None], b, 0.0)
    len_a, len_b = np.linalg.norm(a, axis=-1), np.linalg.norm(b, axis=-1)
    longest = np.maximum(np.maximum(len_a, len_b), np.linalg.norm(a - b, axis=-1))
    coincident = finite & ((len_a <= min_sine * longest) | (len_b <= min_sine * longest))
    p1 = a / np.where(len_a > 0, len_a, 1.0)[..., None]
    p2 = b - np.sum(b * p1, axis=-1)[..., None] * p1
    len_p2 = np.linalg.norm(p2, axis=-1)
    collinear = finite & ~coincident & (len_p2 <= min_sine * len_b)
    ok = finite & ~coincident & ~collinear
    p2 = p2 / np.where(len_p2 > 0, len_p2, 1.0)[..., None]
    frames = np.stack([p1, p2, np.cross(p1, p2)], axis=-1)
    frames[~ok] = np.eye(3)
    return frames, ok, coincident, collinear
