"""The alignment of B onto A: a :class:`~core.space.similarity.Similarity`, fitted or not.

``none``: the identity (after units and up axis, :mod:`core.compare.tracks`). ``rigid``:
the rotation and translation minimising the sum of squared distances between matched
points over all frames (Kabsch); ``similarity``: the same with a uniform scale (Umeyama,
1991). Points missing on either side are left out of the fit.
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np

from gmr_studio.core.compare.offset import OffsetSearch
from gmr_studio.core.space.similarity import Similarity, finite_rows, fit_points

__all__ = ["ALIGN_KINDS", "Alignment", "finite_rows", "fit_alignment", "rms_distance", "rms_of_squares"]

AlignKind = Literal["none", "rigid", "similarity"]
ALIGN_KINDS: tuple[str, ...] = ("none", "rigid", "similarity")


@dataclasses.dataclass(frozen=True, eq=False)
class Alignment:
    """How B was put into A's space and on A's clock: ``b_A = fit(space(b))``.

    kind : "none", "rigid" or "similarity" (what was fitted after units and up axis).
    space : :class:`~core.space.similarity.Similarity`, B's units and up axis turned into A's
        (scale: A units per B unit; rotation: the up-axis change).
    fit : :class:`~core.space.similarity.Similarity`, the fitted alignment after that (in
        A's units; the identity for "none", scale 1 unless "similarity").
    offset_frames : B's time minus A's, in A's frames; offset_seconds : the same in seconds;
    offset_found : True when searched (auto); offset_search : the search's best and next best
    offsets with their mismatch (auto only).
    rms_before, rms_after : RMS distance of matched points before and after the fit.
    notes : how units and up axis were decided.
    """

    kind: str = "none"
    space: Similarity = dataclasses.field(default_factory=Similarity)
    fit: Similarity = dataclasses.field(default_factory=Similarity)
    offset_frames: float = 0.0
    offset_seconds: float = 0.0
    offset_found: bool = False
    offset_search: OffsetSearch | None = None
    rms_before: float = float("nan")
    rms_after: float = float("nan")
    notes: tuple[str, ...] = ()

    @property
    def total(self) -> Similarity:
        """B's own space to A's: the space change, then the fit."""
        return self.space.then(self.fit)

    def apply(self, points: np.ndarray) -> np.ndarray:
        """(..., 3) points in B's own space -> A's space."""
        return self.total.apply(points)

    def apply_rotations(self, rotations: np.ndarray) -> np.ndarray:
        """(..., 3, 3) world rotations of B -> A's space.

        The up-axis change turns the world and the rest pose with it (``Q W Q^T``, as ``gmr
        convert --up``); the fitted rotation turns B's motion as a whole (``R W``).
        """
        return self.fit.rotation @ self.space.change_frames(rotations)

    def to_json(self) -> dict:
        return {
            "kind": self.kind,
            "rotation": self.fit.rotation.tolist(),
            "translation": self.fit.translation.tolist(),
            "scale": self.fit.scale,
            "units_scale": self.space.scale,
            "up_rotation": self.space.rotation.tolist(),
            "offset_frames": self.offset_frames,
            "offset_seconds": self.offset_seconds,
            "offset_found": self.offset_found,
            "offset_search": None if self.offset_search is None else self.offset_search.to_json(),
            "rms_before": _finite_or_none(self.rms_before),
            "rms_after": _finite_or_none(self.rms_after),
            "notes": list(self.notes),
        }


def fit_alignment(points_a: np.ndarray, points_b: np.ndarray, kind: str) -> tuple[np.ndarray, np.ndarray, float]:
    """Fit ``a ~ scale * R @ b + t`` over all points present on both sides
    (:func:`core.space.similarity.fit_points`).

    points_a, points_b : (..., 3) matched points (NaN where missing), same shape.
    kind : "none" (the identity), "rigid" or "similarity".
    Returns rotation (3, 3), translation (3,), scale.
    Raises ValueError for an unknown kind or fewer than 3 matched points to fit from.
    """
    if kind not in ALIGN_KINDS:
        raise ValueError(f"alignment must be one of {', '.join(ALIGN_KINDS)}, not {kind!r}")
    if kind == "none":
        return np.eye(3), np.zeros(3), 1.0
    return fit_points(points_a, points_b, scaled=kind == "similarity")


def rms_distance(points_a: np.ndarray, points_b: np.ndarray) -> float:
    """RMS distance over the points present on both sides (NaN if none): (..., 3) each."""
    difference = points_a - points_b
    squared = np.einsum("...k,...k->...", difference, difference)
    return rms_of_squares(squared)


def rms_of_squares(squared: np.ndarray) -> float:
    finite = np.isfinite(squared)
    values = squared if finite.all() else squared[finite]
    return float(np.sqrt(values.mean())) if values.size else float("nan")


def _finite_or_none(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None
