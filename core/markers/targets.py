"""What the refinement fits on a given skeleton, and whether a map fits the markers at all.

- :func:`check_map_fits`: a map most of whose markers the file lacks is refused, naming the
  file's own marker set (rather than reporting the map's missing markers as gaps).
- :func:`transported`: targets for the joints below a bone the skeleton lacks (CMU's BVH has
  no thorax bone): the markers moved by that bone.
- :func:`below_missing_bones`: those joints, which the root's fit leaves out.
- :func:`inverse_variance`: each joint's weight, ``1 / rms^2`` of its calibrated virtual marker.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.model.motion import Motion


def check_map_fits(markers: MarkerSet, marker_map) -> None:
    """Refuse a map most of whose markers the file lacks, naming the file's own set: "this
    file's markers are set X, not map Y (missing: ...)" rather than a pelvis gap that reads as
    if the file had holes."""
    from gmr_studio.core.markers.sets import identify_marker_set

    needed = marker_map.labels()
    absent = [label for label in needed if label not in markers.labels]
    if marker_map.joints or not needed or len(absent) * 2 <= len(needed):
        return
    match = identify_marker_set(markers)
    found = f"set {match.definition.name}" if match is not None else "of no known set"
    raise OperationError(
        f"this file's markers are {found}, not map {marker_map.name} (missing: {', '.join(absent)})"
        + ("; without --skeleton and --map, gmr markers builds a skeleton from them" if match is not None else "")
    )


def transported(motion: Motion, measured: np.ndarray, starts: np.ndarray, skeleton: Motion) -> np.ndarray | None:
    """Refinement targets on a skeleton that lacks a bone of the map's (CMU's BVH has no thorax).

    Where a joint's bone starts, by the map, at a virtual marker that is not where the skeleton
    starts it (``starts`` (F, J, 3) away from the joint's parent in the seed ``motion``), the
    measured joint and everything below it are moved by ``P_parent(seed) - start``: the
    skeleton cannot reach the markers beyond a missing bone, but it can take their shape.
    None when nothing moves (then the targets are ``measured``).
    """
    from gmr_studio.core.kinematics.fk import world_positions as positions_of

    seed = positions_of(motion)
    shift = np.zeros_like(measured)
    moved = False
    for j in skeleton.topological_order:
        p = int(skeleton.parents[j])
        if p < 0:
            continue
        shift[:, j] = shift[:, p]
        begin = starts[:, j]
        if np.isfinite(begin).all(axis=1).any() and not np.isfinite(measured[:, p]).any():
            gap = np.where(np.isfinite(begin), seed[:, p] - begin, 0.0)
            shift[:, j] = gap
            moved = True
    return measured + shift if moved else None


def below_missing_bones(measured: np.ndarray, starts: np.ndarray, skeleton: Motion) -> np.ndarray:
    """(J,) bool: the joints below a bone the skeleton lacks, whose measured positions the
    skeleton cannot reach (CMU's BVH: the neck and arms, below the map's thorax).

    A joint's bone (``starts`` (F, J, 3), NaN: the map gives none) starts where the skeleton
    starts it when it is the measured position (``measured`` (F, J, 3)) of the joint's parent
    or of an ancestor the parent sits on through bones of length zero; any other start (a
    virtual marker the skeleton has no joint for) is a bone the skeleton lacks, and the joint
    and everything below it are below it.
    """
    below = np.zeros(skeleton.n_joints, bool)
    lengths = np.linalg.norm(skeleton.offsets, axis=1)
    for j in skeleton.topological_order:
        p = int(skeleton.parents[j])
        if p < 0:
            continue
        same_place = [p]
        while lengths[same_place[-1]] == 0 and skeleton.parents[same_place[-1]] >= 0:
            same_place.append(int(skeleton.parents[same_place[-1]]))
        own_start = not np.isfinite(starts[:, j]).any() or any(
            np.array_equal(starts[:, j], measured[:, a], equal_nan=True) for a in same_place
        )
        below[j] = below[p] or not own_start
    return below


def inverse_variance(marker_map, names) -> np.ndarray | None:
    """(J,) ``1 / rms^2`` of each joint's calibrated virtual marker, scaled to mean 1 over
    those that have one (the others get 1); None when no virtual marker has an rms."""
    rms = {v.name: v.rms for v in marker_map.virtual if v.rms}
    if not rms:
        return None
    weights = np.array([1.0 / rms[n] ** 2 if n in rms else np.nan for n in names])
    weights /= np.nanmean(weights)
    return np.where(np.isfinite(weights), weights, 1.0)
