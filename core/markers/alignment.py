"""Putting markers where the skeleton is: units, up axis, heading, offset (pure numpy).

Marker files and motion files rarely share a frame: C3D is millimetres with Z up, BVH is
whatever unit the skeleton was built in with Y up, and a lab's heading is arbitrary. An
alignment is the similarity transform ``p_motion = scale * rotation @ p_marker + offset``
plus a frame shift (``marker frame = motion frame + frame_offset``, after resampling the
markers to the motion's rate).

:func:`auto_alignment` chooses it:

1. If at least three markers are named like joints (case-insensitive) and are spread out,
   the similarity transform is fitted to them by least squares over every frame where
   both are known (Umeyama's method): exact for virtual joint markers.
2. Otherwise the scale is the ratio of the figure's heights (median per-frame extent along
   the up axis), snapped to a unit conversion (m, cm, mm, in, ft, CMU's 1/0.45 in) when one
   is within 25%; the rotation is the axis permutation that takes the markers' up axis to
   the skeleton's and, of the four such headings, the one whose path of the marker
   centroid best follows the skeleton's; when the two differ by a few frames, the frame
   shift that fits best too (:func:`candidate_frame_offsets`); the offset matches the two
   centroids on average.

Up axis: the project's one rule, :func:`core.space.up_axis.detect_up_axis` (Y or Z, whichever
the figure spans more in the median frame). The fit is :func:`core.space.similarity.fit_points`, the
rotations :mod:`core.rotations.euler`. (The app's ``app.model.alignment`` re-exports this module.)
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.rotations.euler import axis_permutations
from gmr_studio.core.space.similarity import Similarity, fit_points
from gmr_studio.core.space.units import LIKELY_UNITS, parse_unit, unit_factor, unit_named
from gmr_studio.core.space.up_axis import axis_index, detect_up_axis, median_extents

#: how far (relative) a height ratio may be from a unit conversion and still snap to it
SNAP_TOLERANCE = 0.25
#: the frame shifts tried between marker and motion frames (e.g. a BVH with an added T-pose frame)
MAX_FRAME_OFFSET = 5


@dataclasses.dataclass(frozen=True)
class MarkerAlignment:
    """Markers put on a motion: ``p_motion = transform.apply(p_marker)`` (a
    :class:`~core.space.similarity.Similarity`, often an axis permutation with a unit
    scale); marker frame = motion frame + ``frame_offset``.

    Attributes
    ----------
    transform : Similarity, marker coordinates to motion coordinates (scale: motion units
        per marker unit).
    frame_offset : int, frames of the (resampled) markers ahead of the motion.
    method : str, how it was found, for the user.
    units : str, the marker file's length unit, when known.
    """

    transform: Similarity = dataclasses.field(default_factory=Similarity)
    frame_offset: int = 0
    method: str = "identity"
    units: str = ""

    def apply(self, points: np.ndarray) -> np.ndarray:
        """(..., 3) marker coordinates -> (..., 3) motion coordinates (NaN stays NaN)."""
        return self.transform.apply(points)

    def replace(self, **changes) -> MarkerAlignment:
        return dataclasses.replace(self, **changes)

    def unit_factor(self, units: str) -> float:
        """Marker-file units per ``units`` (1 when either is unknown), for points measured
        in another unit than the marker file's."""
        if not units or not self.units or units == self.units:
            return 1.0
        return unit_factor(unit_named(units), unit_named(self.units))


#: joint names (lower case) taken as the figure's centre, before the root of the largest tree
PELVIS_NAMES = ("hips", "pelvis", "root")


def turned_about(alignment: MarkerAlignment, up_axis: str, degrees: float, pivot: np.ndarray) -> MarkerAlignment:
    """The alignment followed by a turn of ``degrees`` about the up axis through ``pivot``
    (motion coordinates): ``p' = T (p - c) + c``, so the pivot stays where it is."""
    return alignment.replace(transform=alignment.transform.turned_about(up_axis, np.radians(degrees), pivot))


def figure_centre_joint(names: tuple[str, ...], tree_roots: np.ndarray) -> int:
    """The joint the figure turns about: one named like a pelvis (``Hips``, ``pelvis``,
    ``root``, any case), else the root of the tree with the most joints."""
    lower = [name.lower() for name in names]
    for wanted in PELVIS_NAMES:
        if wanted in lower:
            return lower.index(wanted)
    return int(np.bincount(tree_roots).argmax())


def similarity_fit(source: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, float, np.ndarray, float]:
    """Least-squares ``target ~ scale * R @ source + offset`` (Umeyama 1991, :func:`core.space.similarity.fit_points`).

    Parameters
    ----------
    source, target : (N, 3) corresponding points (finite).

    Returns
    -------
    rotation (3, 3) proper, scale float, offset (3,), rms residual float.
    """
    rotation, offset, scale = fit_points(target, source, scaled=True)
    residual = target - (scale * source @ rotation.T + offset)
    return rotation, scale, offset, float(np.sqrt((residual**2).sum(axis=1).mean()))


def marker_joint_pairs(labels: tuple[str, ...], names: tuple[str, ...]) -> list[tuple[int, int]]:
    """(marker index, joint index) for markers named like a joint (case-insensitive)."""
    joints = {name.lower(): j for j, name in enumerate(names)}
    return [(m, joints[label.lower()]) for m, label in enumerate(labels) if label.lower() in joints]


def auto_alignment(
    marker_positions: np.ndarray,
    labels: tuple[str, ...],
    joint_positions: np.ndarray,
    names: tuple[str, ...],
    marker_units: str = "mm",
) -> MarkerAlignment:
    """The alignment of markers to a skeleton (see the module docstring).

    Parameters
    ----------
    marker_positions : (F, M, 3) markers at the motion's frame rate (NaN gaps), marker units.
    labels : M marker labels.
    joint_positions : (F2, J, 3) the skeleton's world positions.
    names : J joint names.
    marker_units : unit of the markers (a name of :mod:`core.space.units`), used to snap the scale.
    """
    n = min(len(marker_positions), len(joint_positions))
    markers, joints = marker_positions[:n], joint_positions[:n]
    pairs = marker_joint_pairs(labels, names)
    if len(pairs) >= 3:
        source = markers[:, [m for m, _ in pairs]].reshape(-1, 3)
        target = joints[:, [j for _, j in pairs]].reshape(-1, 3)
        known = np.isfinite(source).all(axis=1)
        source, target = source[known], target[known]
        if len(source) >= 3 and np.linalg.matrix_rank(source - source.mean(axis=0), tol=1e-9 * np.ptp(source)) == 3:
            rotation, scale, offset, rms = similarity_fit(source, target)
            return MarkerAlignment(
                transform=Similarity(rotation, scale, offset),
                method=f"fitted to {len(pairs)} markers named like joints (rms {rms:.3g})",
            )
    return _heuristic_alignment(marker_positions, joint_positions, marker_units)


def _heuristic_alignment(all_markers: np.ndarray, joints: np.ndarray, marker_units: str) -> MarkerAlignment:
    markers = markers_on_motion_frames(all_markers, len(joints), 0)
    marker_up, joint_up = axis_index(detect_up_axis(markers)), axis_index(detect_up_axis(joints))
    marker_height = median_extents(markers)[marker_up]
    joint_height = median_extents(joints)[joint_up]
    ratio = joint_height / marker_height if marker_height > 0 and joint_height > 0 else 1.0  # a figure of one point
    scale, unit_note = ratio, "scale from the figure's height"
    marker_unit = parse_unit(marker_units)
    if marker_unit is not None:
        for unit in LIKELY_UNITS:
            factor = unit_factor(marker_unit, unit)
            if abs(ratio / factor - 1) <= SNAP_TOLERANCE:
                scale, unit_note = factor, f"{marker_unit} -> {unit}"
                break
    up_vector = np.eye(3)[joint_up]
    candidates = [r for r in axis_permutations() if np.allclose(r @ np.eye(3)[marker_up], up_vector)]
    joint_centre = joints.mean(axis=1)
    best = (np.inf, candidates[0], np.zeros(3), 0)
    for lag in candidate_frame_offsets(len(joints), len(all_markers)):
        marker_centre = _nan_mean(markers_on_motion_frames(all_markers, len(joints), lag))  # (F, 3)
        usable = np.isfinite(marker_centre).all(axis=1)
        if not usable.any():
            continue
        for rotation in candidates:
            moved = scale * marker_centre[usable] @ rotation.T
            shift = (joint_centre[usable] - moved).mean(axis=0)
            cost = float(((moved + shift - joint_centre[usable]) ** 2).mean())
            if cost < best[0] * (1 - 1e-6):
                best = (cost, rotation, shift, lag)
    _, rotation, offset, lag = best
    axes = "XYZ"
    shift = f", frame offset {lag}" if lag else ""
    return MarkerAlignment(
        transform=Similarity(rotation, float(scale), offset),
        frame_offset=lag,
        method=f"{unit_note}, {axes[marker_up]} up -> {axes[joint_up]} up, "
        f"heading{shift} and offset from the centroid path",
    )


def candidate_frame_offsets(n_motion: int, n_markers: int) -> list[int]:
    """Frame offsets worth trying: when the motion has a few more frames than the markers
    (up to ``MAX_FRAME_OFFSET``, e.g. a BVH export that added a T-pose frame at the start),
    the extra frames may be at the start or the end, and conversely; otherwise none."""
    extra = n_motion - n_markers
    if extra == 0 or abs(extra) > MAX_FRAME_OFFSET:
        return [0]
    return [-k if extra > 0 else k for k in range(abs(extra) + 1)]


def _nan_mean(points: np.ndarray) -> np.ndarray:
    """(F, 3) mean over markers of (F, M, 3), ignoring gaps (NaN where a frame has none)."""
    finite = np.isfinite(points).all(axis=-1)
    count = finite.sum(axis=1)
    total = np.where(finite[..., None], points, 0.0).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count[:, None] > 0, total / np.maximum(count, 1)[:, None], np.nan)


def markers_on_motion_frames(positions: np.ndarray, n_frames: int, frame_offset: int) -> np.ndarray:
    """(n_frames, M, 3): marker frame ``f + frame_offset`` for each motion frame f (NaN outside)."""
    out = np.full((n_frames, positions.shape[1], 3), np.nan)
    source = np.arange(n_frames) + frame_offset
    inside = (source >= 0) & (source < len(positions))
    out[inside] = positions[source[inside]]
    return out
