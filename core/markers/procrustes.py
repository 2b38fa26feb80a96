"""Rigid fits for every frame at once: batched least squares and nearest rotations by SVD.

Two fits, both vectorised over frames (one batched SVD, no loop):

- :func:`fit_rigid`: the rotation and translation that carry a template point set onto
  measured points in the least-squares sense (orthogonal Procrustes / Kabsch), with a mask
  for missing points and a per-frame RMS residual. Used for marker clusters.
- :func:`frame_from_triple`: the technical note's pelvis frame ``[p1, p2, p3]`` of three
  points (Gram-Schmidt, with the note's equation 2 corrected as in MATH.md), used by
  :func:`core.markers.pelvis.recover_pelvis`.

Shapes: points are ``(..., K, 3)`` with the frames in the leading axes; rotations
``(..., 3, 3)`` act on column vectors.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.rotations import nearest_rotation

#: a fit whose point spread has a second singular value below this fraction of the first is
#: degenerate (the points are coincident or collinear: the rotation about their line is free)
DEGENERATE_RATIO = 1e-6


def fit_rigid(
    template: np.ndarray, points: np.ndarray, present: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares rigid motion ``x ~ R s + t`` of a template onto measured points.

    Parameters
    ----------
    template : (K, 3) or (F, K, 3) float, the points in their own frame.
    points : (F, K, 3) float, the measured points (NaN where missing).
    present : (F, K) bool, which points take part (default: the finite ones).

    Returns
    -------
    rotations : (F, 3, 3), proper rotations (the det < 0 case is corrected).
    translations : (F, 3).
    rms : (F,), root-mean-square distance of the present points from the fitted template.
    ok : (F,) bool, at least three points present and not collinear; where False the
        other outputs are identity / NaN.
    """
    points = np.asarray(points, dtype=np.float64)
    template = np.broadcast_to(np.asarray(template, dtype=np.float64), points.shape)
    if present is None:
        present = np.isfinite(points).all(axis=-1)
    weight = present.astype(np.float64)
    count = weight.sum(axis=-1)
    safe = np.maximum(count, 1.0)[..., None]
    x = np.where(present[..., None], points, 0.0)
    s = np.where(present[..., None], template, 0.0)
    x_mean = (weight[..., None] * x).sum(axis=-2) / safe
    s_mean = (weight[..., None] * s).sum(axis=-2) / safe
    xc = (x - x_mean[..., None, :]) * weight[..., None]
    sc = (s - s_mean[..., None, :]) * weight[..., None]
    covariance = np.einsum("...ka,...kb->...ab", xc, sc)
    spread = np.linalg.svd(sc, compute_uv=False)  # (F, 3): shape of the template part used
    ok = (count >= 3) & (spread[..., 1] > DEGENERATE_RATIO * spread[..., 0])
    covariance[~ok] = np.eye(3)
    rotations = nearest_rotation(covariance)
    translations = x_mean - np.einsum("...ab,...b->...a", rotations, s_mean)
    fitted = np.einsum("...ab,...kb->...ka", rotations, template) + translations[..., None, :]
    error = np.where(present, np.sum((fitted - np.where(present[..., None], points, 0.0)) ** 2, axis=-1), 0.0)
    rms = np.sqrt(error.sum(axis=-1) / safe[..., 0])
    rotations[~ok] = np.eye(3)
    translations[~ok] = np.nan
    rms[~ok] = np.nan
    return rotations, translations, rms, ok


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
    coincident = finite & ((len_a <= min_sine * longest) | (len_b <= min_sine * longest) | (longest == 0))
    p1 = a / np.where(len_a > 0, len_a, 1.0)[..., None]
    p2 = b - np.sum(b * p1, axis=-1)[..., None] * p1
    len_p2 = np.linalg.norm(p2, axis=-1)
    collinear = finite & ~coincident & (len_p2 <= min_sine * len_b)
    ok = finite & ~coincident & ~collinear
    p2 = p2 / np.where(len_p2 > 0, len_p2, 1.0)[..., None]
    frames = np.stack([p1, p2, np.cross(p1, p2)], axis=-1)
    frames[~ok] = np.eye(3)
    return frames, ok, coincident, collinear
