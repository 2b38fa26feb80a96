"""Least-squares rigid and similarity fits of point sets: the one home of Kabsch / Umeyama.

Two shapes of the same fit, both correcting the reflection case (``det(U V^T) < 0``: the
smallest singular direction flips, so the result is always a proper rotation):

- :func:`fit_points`: one transform ``a ~ scale R b + t`` over all points present on both
  sides (a comparison's alignment, markers named like joints); rigid or similarity (Umeyama
  1991), from raw sums, so that millions of points need no centred copies.
- :func:`fit_rigid`: one rigid transform per frame ``x ~ R s + t`` of a template onto
  measured points, with a mask of the points present and a per-frame RMS residual, all
  frames at once (one batched SVD): marker clusters, pelvis frames.

Shapes: points ``(N, 3)`` or ``(..., K, 3)``; rotations act on column vectors.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.rotations.euler import nearest_rotation

#: a per-frame fit whose point spread has a second singular value below this fraction of the
#: first is degenerate (coincident or collinear points: the rotation about their line is free)
DEGENERATE_RATIO = 1e-6


def finite_rows(points: np.ndarray) -> np.ndarray:
    """(N,) bool: the rows of points (N, 3) whose three coordinates are finite (three
    elementwise passes: a reduction along an axis of length 3 is several times slower)."""
    finite = np.isfinite(points[:, 0])
    finite &= np.isfinite(points[:, 1])
    finite &= np.isfinite(points[:, 2])
    return finite


def fit_points(
    points_a: np.ndarray, points_b: np.ndarray, *, scaled: bool = False
) -> tuple[np.ndarray, np.ndarray, float]:
    """Fit ``a ~ scale * R @ b + t`` over all points present on both sides.

    points_a, points_b : (..., 3) matched points (NaN where missing), same shape.
    scaled : fit a uniform scale too (similarity); else scale is 1 (rigid).
    Returns rotation (3, 3) proper, translation (3,), scale.
    Raises ValueError for fewer than 3 points present on both sides, or (scaled) B's points
    all at one place.
    """
    a = points_a.reshape(-1, 3)
    b = points_b.reshape(-1, 3)
    # sums by einsum: numpy's axis-0 reductions of (N, 3) arrays are several times slower;
    # finite sums mean no point is missing (else the rows present on both sides are kept)
    sum_a, sum_b = np.einsum("ni->i", a), np.einsum("ni->i", b)
    if not (np.isfinite(sum_a).all() and np.isfinite(sum_b).all()):
        both = finite_rows(a) & finite_rows(b)
        a, b = a[both], b[both]
        sum_a, sum_b = np.einsum("ni->i", a), np.einsum("ni->i", b)
    n = len(a)
    kind = "similarity" if scaled else "rigid"
    if n < 3:
        raise ValueError(f"a {kind} alignment needs at least 3 matched points present on both sides, not {n}")
    mean_a, mean_b = sum_a / n, sum_b / n
    # covariance from raw sums: no centred copies of millions of points (einsum: a BLAS
    # product would take half the time but sum in another order, moving the fit by 1e-13)
    covariance = np.einsum("ni,nj->ij", a, b) / n - np.outer(mean_a, mean_b)
    u, singular, vt = np.linalg.svd(covariance)
    sign = np.ones(3)
    if np.linalg.det(u @ vt) < 0:
        sign[2] = -1.0
    rotation = (u * sign) @ vt
    scale = 1.0
    if scaled:
        variance_b = float(np.einsum("ij,ij->", b, b) / n - mean_b @ mean_b)
        if variance_b <= 0:
            raise ValueError("a similarity alignment needs B's points to be spread, not all at one place")
        scale = float((singular * sign).sum() / variance_b)
    return rotation, mean_a - scale * rotation @ mean_b, scale


def fit_rigid(
    template: np.ndarray, points: np.ndarray, present: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares rigid motion ``x ~ R s + t`` of a template onto measured points, per frame.

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
