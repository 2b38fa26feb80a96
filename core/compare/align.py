"""The alignment of B onto A: ``b' = scale * rotation @ b + translation``, fitted or not.

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
from gmr_studio.core.space.similarity import finite_rows, fit_points

__all__ = ["ALIGN_KINDS", "Alignment", "finite_rows", "fit_alignment", "rms_distance", "rms_of_squares"]

AlignKind = Literal["none", "rigid", "similarity"]
ALIGN_KINDS: tuple[str, ...] = ("none", "rigid", "similarity")


@dataclasses.dataclass(frozen=True, eq=False)
class Alignment:
    """``b' = scale * rotation @ b + translation`` in A's space, and the clock offset.

    kind : "none", "rigid" or "similarity" (what was fitted after units and up axis).
    rotation : (3, 3), translation : (3,) in A's units, scale : float (fitted; 1 unless
    similarity). units_scale, up_rotation : the space change applied before the fit
    (``b_A = units_scale * up_rotation @ b``). offset_frames : B's time minus A's, in A's
    frames; offset_seconds : the same in seconds; offset_found : True when searched (auto);
    offset_search : the search's best and next best offsets with their mismatch (auto only).
    rms_before, rms_after : RMS distance of matched points before and after the fit.
    notes : how units and up axis were decided.
    """

    kind: str = "none"
    rotation: np.ndarray = dataclasses.field(default_factory=lambda: np.eye(3))
    translation: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))
    scale: float = 1.0
    units_scale: float = 1.0
    up_rotation: np.ndarray = dataclasses.field(default_factory=lambda: np.eye(3))
    offset_frames: float = 0.0
    offset_seconds: float = 0.0
    offset_found: bool = False
    offset_search: OffsetSearch | None = None
    rms_before: float = float("nan")
    rms_after: float = float("nan")
    notes: tuple[str, ...] = ()

    @property
    def total_rotation(self) -> np.ndarray:
        """(3, 3) from B's own axes to A's: fitted rotation after the up-axis change."""
        return self.rotation @ self.up_rotation

    @property
    def total_scale(self) -> float:
        return self.scale * self.units_scale

    def apply(self, points: np.ndarray) -> np.ndarray:
        """(..., 3) points in B's own space -> A's space."""
        return self.total_scale * np.einsum("ab,...b->...a", self.total_rotation, points) + self.translation

    def apply_rotations(self, rotations: np.ndarray) -> np.ndarray:
        """(..., 3, 3) world rotations of B -> A's space.

        The up-axis change turns the world and the rest pose with it (``Q W Q^T``, as ``gmr
        convert --up``); the fitted rotation turns B's motion as a whole (``R W``).
        """
        q = self.up_rotation
        return self.rotation @ q @ rotations @ q.T

    def to_json(self) -> dict:
        return {
            "kind": self.kind,
            "rotation": self.rotation.tolist(),
            "translation": self.translation.tolist(),
            "scale": self.scale,
            "units_scale": self.units_scale,
            "up_rotation": self.up_rotation.tolist(),
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
