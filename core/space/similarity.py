"""Similarity transforms and their least-squares fits: the one home of both.

:class:`Similarity` is ``x' = scale * rotation @ x + translation`` (column vectors): how marker
axes and units become a skeleton's (marker maps, the marker alignment), how a compared motion
B is brought into A's space (units, up axis, a fitted alignment). It applies to points,
inverts, composes and turns orientations; the fits below return its parts.

Least-squares fits of point sets (Kabsch / Umeyama) come in two shapes, both correcting the
reflection case (``det(U V^T) < 0``: the smallest singular direction flips, so the result is
always a proper rotation):

- :func:`fit_points`: one transform ``a ~ scale R b + t`` over all points present on both
  sides (a comparison's alignment, markers named like joints); rigid or similarity (Umeyama
  1991), from raw sums, so that millions of points need no centred copies.
- :func:`fit_rigid`: one rigid transform per frame ``x ~ R s + t`` of a template onto
  measured points, with a mask of the points present and a per-frame RMS residual, all
  frames at once (one batched SVD): marker clusters, pelvis frames.

Shapes: points ``(N, 3)`` or ``(..., K, 3)``; rotations act on column vectors.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.rotations.euler import nearest_rotation, rotation_about_axis


@dataclasses.dataclass(frozen=True, eq=False)
class Similarity:
    """``x' = scale * rotation @ x + translation``.

    rotation : (3, 3) orthonormal (a rotation, or an axis permutation read from a file).
    scale : float > 0. translation : (3,), in the target's units.
    """

    rotation: np.ndarray = dataclasses.field(default_factory=lambda: np.eye(3))
    scale: float = 1.0
    translation: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        rotation = np.asarray(self.rotation, dtype=np.float64)
        translation = np.asarray(self.translation, dtype=np.float64)
        if rotation.shape != (3, 3) or not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9):
            raise ValueError("the rotation must be an orthonormal 3x3 matrix")
        scale = float(self.scale)
        if not (np.isfinite(scale) and scale > 0) or translation.shape != (3,) or not np.isfinite(translation).all():
            raise ValueError("a similarity needs a positive scale and a finite translation of 3 numbers")
        object.__setattr__(self, "rotation", rotation)
        object.__setattr__(self, "scale", scale)
        object.__setattr__(self, "translation", translation)

    def apply(self, points: np.ndarray) -> np.ndarray:
        """(..., 3) points -> (..., 3) transformed (NaN stays NaN)."""
        return self.scale * np.einsum("ab,...b->...a", self.rotation, points) + self.translation

    def inverse(self) -> Similarity:
        """The transform back: ``x = (R^T (x' - t)) / s``."""
        back = self.rotation.T / self.scale
        return Similarity(self.rotation.T, 1.0 / self.scale, -back @ self.translation)

    def then(self, after: Similarity) -> Similarity:
        """This transform followed by ``after``: ``after.apply(self.apply(x))``."""
        return Similarity(after.rotation @ self.rotation, after.scale * self.scale, after.apply(self.translation))

    def turned_about(self, axis: str, radians: float, pivot: np.ndarray) -> Similarity:
        """This transform followed by a turn of ``radians`` about ``axis`` ('x', 'y' or 'z')
        through ``pivot`` (target space), so the pivot stays where it is."""
        turn = rotation_about_axis(axis.upper(), radians)
        pivot = np.asarray(pivot, dtype=np.float64)
        return Similarity(turn @ self.rotation, self.scale, turn @ (self.translation - pivot) + pivot)

    def change_frames(self, rotations: np.ndarray) -> np.ndarray:
        """(..., 3, 3) rotations written in the source's axes -> the same rotations in the
        target's axes (``R W R^T``)."""
        return self.rotation @ rotations @ self.rotation.T

    @property
    def is_identity(self) -> bool:
        return self.scale == 1.0 and np.array_equal(self.rotation, np.eye(3)) and not self.translation.any()


def fit_similarity(points_a: np.ndarray, points_b: np.ndarray, *, scaled: bool = True) -> Similarity:
    """The :class:`Similarity` taking B onto A by least squares (:func:`fit_points`)."""
    rotation, translation, scale = fit_points(points_a, points_b, scaled=scaled)
    return Similarity(rotation, scale, translation)


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
