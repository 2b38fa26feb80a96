"""Markers to GMR motion: the pelvis by Procrustes, then every limb down the chains.

:func:`markers_to_motion` turns a marker set, a skeleton and a marker map into a GMR
:class:`~core.model.motion.Motion` of the skeleton's joints (technical note, section 2):

1. the virtual markers (joint centres) are computed and aligned to skeleton space;
2. the pelvis rotation of every frame comes from the three pelvis virtual markers
   (:func:`~core.markers.pelvis.pelvis_rotations`); the root stands at the pelvis root;
3. down every chain, each joint's bone direction in its parent's (already solved) frame
   gives two angles, and the twist about the bone comes from the best-matching pose of a
   reference motion (:mod:`core.markers.match`) or, without one, changes least from the
   previous frame (:func:`~core.markers.limbs.least_change_twists`);
4. the joints named in ``roots`` become roots of their own trees (soft-linked to their
   parent, as a GMR split does) holding their measured world positions; the others are
   rotational, with the skeleton's bone lengths;
5. the root is placed by the least-squares translation of the joints onto their virtual
   markers given those rotations (``root_at="fit"``, :mod:`core.markers.root_fit`), or stays
   at the pelvis root virtual marker as in the paper (``root_at="pelvis"``).

A joint whose bone direction cannot be measured in a frame (no virtual marker, a gap, a
bone of length zero) takes its whole local rotation from the matched reference pose, or
without a reference holds its nearest measured rotation (the rest pose if it never has one);
``sources`` says which, per frame and joint. A frame whose pelvis cannot be recovered
(missing or degenerate pelvis markers) is a copy of the nearest good frame and is flagged in
``frame_valid``; ``reasons`` says why, with the frames. Good frames are computed exactly as
they would be without the bad ones (with a reference; without one the twist runs on over
the gap from the last good frame).

The root's rotation is the pelvis rotation, composed, when a reference is matched, with the
reference's own root-from-pelvis rotation ``R_pelvis,ref(g)^T R_root,ref(g)`` (the identity
when the pelvis markers are rigid with the root, as in ASF skeletons; for skeletons converted
from BVH, whose GMR root carries no rotation, it keeps the reference's convention).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Literal

import numpy as np

from gmr_studio.core.edits.operations import split
from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.limbs import least_change_twists, limb_rotation, marker_twists, twist_of
from gmr_studio.core.markers.markerset import MarkerSet, frame_ranges, gap_runs
from gmr_studio.core.markers.match import best_matches, reference_poses
from gmr_studio.core.markers.pelvis import PelvisFrames, PelvisMethod, pelvis_rotations, rest_positions
from gmr_studio.core.markers.root_fit import hanging_from_root, root_translations
from gmr_studio.core.markers.targets import below_missing_bones, check_map_fits, inverse_variance, transported
from gmr_studio.core.model.motion import Motion

#: ``sources`` codes, per frame and joint
MEASURED, FROM_REFERENCE, HELD, ROOT, TWIST_MARKER = 0, 1, 2, 3, 4
SOURCE_NAMES = {
    MEASURED: "measured",
    FROM_REFERENCE: "from reference",
    HELD: "held",
    ROOT: "root",
    TWIST_MARKER: "twist from its marker",
}
Aim = Literal["markers", "chain"]
RootAt = Literal["fit", "pelvis"]


@dataclasses.dataclass(frozen=True, eq=False)
class MarkerMotion:
    """The result of :func:`markers_to_motion`.

    Attributes
    ----------
    motion : the GMR motion (skeleton units and axes), F frames.
    measured : (F, J, 3) the virtual marker of each joint in skeleton space (NaN: none).
    targets : (F, J, 3) or None, the refinement's targets when they differ from ``measured``.
    weights : (J,) or None, the refinement's weight of each joint's virtual marker: the inverse
        of its calibration variance (``1 / rms^2`` of the map's cluster, mean 1 over the joints).
    sources : (F, J) int8, how each joint's rotation was found (:data:`SOURCE_NAMES`).
    frame_valid : (F,) bool, the pelvis was recovered (False: a copy of the nearest good frame).
    pelvis : PelvisFrames in skeleton axes and units.
    matches : (F,) int64, the matched reference frame (-1: none); match_distances (F,) its
        RMS joint distance in skeleton units.
    reasons : what was missing or degenerate, with the frames.
    pelvis_note : which pelvis triple was used and why, when the map did not name it.
    """

    motion: Motion
    measured: np.ndarray
    sources: np.ndarray
    frame_valid: np.ndarray
    pelvis: PelvisFrames
    matches: np.ndarray
    match_distances: np.ndarray
    reasons: tuple[str, ...] = ()
    pelvis_note: str = ""
    targets: np.ndarray | None = None
    weights: np.ndarray | None = None

    def refine_targets(self) -> np.ndarray:
        """(F, J, 3) what ``--refine`` fits each joint to: the measured joint centres, with
        the joints below a bone the skeleton lacks moved by that bone (:func:`transported`)."""
        return self.measured if self.targets is None else self.targets

    def position_errors(self) -> np.ndarray:
        """(F, J) distance between each joint of the motion and its virtual marker (NaN: none)."""
        positions = world_positions(self.motion)
        return np.linalg.norm(positions - self.measured, axis=2)


def markers_to_motion(
    markers: MarkerSet,
    skeleton: Motion,
    marker_map="joints",
    *,
    reference: Motion | None = None,
    exclude_within: float | None = None,
    roots: Sequence[str] = (),
    frames: slice | None = None,
    fill_gaps: int = 0,
    pelvis_method: PelvisMethod = "note",
    aim: Aim = "markers",
    root_at: RootAt = "fit",
) -> MarkerMotion:
    """Convert markers to a GMR motion of ``skeleton`` (see the module docstring).

    Parameters
    ----------
    markers : the marker set (any units and axes: the map's alignment takes them to the
        skeleton's).
    skeleton : the skeleton (a GMR or BVH motion; only its structure and offsets are used).
    marker_map : a MarkerMap, a map name (``"joints"``, ``"cmu"``) or a map file.
    reference : a motion of the same skeleton whose best-matching poses give the twists.
        Its frame g is at time ``g * frame_time``, the markers' frame i at ``i / rate``.
    exclude_within : seconds: reference frames this close in time to the query are not
        matched (for a reference of the same trial).
    roots : joints that become roots holding their measured positions (besides the pelvis).
    frames : the marker frames to convert (a slice of frame indices from 0).
    fill_gaps : fill marker gaps of at most this many frames by interpolation first.
    pelvis_method : "note" or "points" (:func:`~core.markers.pelvis.pelvis_rotations`).
    aim : bone directions from the measured parent ("markers", the note's) or from the
        parent where the solved chain put it ("chain": errors do not add up along a limb).
    root_at : "fit": the root by the least-squares translation of all the joints given the
        rotations, each weighted by its calibration's inverse variance
        (:mod:`core.markers.root_fit`); "pelvis": at the pelvis root virtual marker (the paper).

    Returns
    -------
    MarkerMotion: the motion (F frames, the skeleton's joints, units and axes) and what
    was measured, matched, held or flagged.

    Raises
    ------
    OperationError : no frame has a usable pelvis, the reference is of another skeleton, the
        map does not fit the skeleton.
    """
    from gmr_studio.core.kinematics.convention import pre_from_post
    from gmr_studio.core.markers.markermap import load_marker_map
    from gmr_studio.core.markers.virtual import compute_virtual_markers, resolve_map

    if skeleton.convention != "pre":
        skeleton = pre_from_post(skeleton)
    if reference is not None and reference.convention != "pre":
        reference = pre_from_post(reference)
    start = range(markers.n_frames)[frames].start if frames is not None and markers.n_frames else 0
    if frames is not None:
        markers = markers.frame_slice(frames)
    if markers.n_frames == 0:
        raise OperationError("there are no marker frames to convert")
    if fill_gaps:
        markers = markers.filled(fill_gaps)
    resolved = resolve_map(load_marker_map(marker_map), markers, skeleton=skeleton)
    check_map_fits(markers, resolved)
    virtual = compute_virtual_markers(markers, resolved)
    measured = np.full((markers.n_frames, skeleton.n_joints, 3), np.nan)
    aligned = virtual.skeleton_positions()
    for v, name in enumerate(virtual.names):
        if name in skeleton.names:
            measured[:, skeleton.joint_index(name)] = aligned[:, v]
    starts = np.full_like(measured, np.nan)
    for name, begin in resolved.bone_starts.items():
        if name in skeleton.names and begin in virtual.names:
            starts[:, skeleton.joint_index(name)] = aligned[:, virtual.names.index(begin)]
    times = (start + np.arange(markers.n_frames)) / markers.rate
    weights = inverse_variance(resolved, skeleton.names)
    result = solve_positions(
        measured,
        skeleton,
        resolved.pelvis,
        reference=reference,
        query_times=times,
        exclude_within=exclude_within,
        roots=roots,
        frame_time=markers.frame_time,
        pelvis_method=pelvis_method,
        aim=aim,
        bone_starts=starts,
        root_at=root_at,
        weights=weights,
    )
    note = f"from markers {markers.source or '(memory)'} with map {resolved.name}"
    motion = result.motion.replace(comments=(note, *result.motion.comments))
    targets = transported(result.motion, measured, starts, skeleton)
    return dataclasses.replace(
        result,
        motion=motion,
        reasons=(*virtual.reasons, *result.reasons),
        pelvis_note=resolved.pelvis_note,
        targets=targets,
        weights=weights,
    )


def solve_positions(
    measured: np.ndarray,
    skeleton: Motion,
    pelvis: Sequence[str] | None,
    *,
    reference: Motion | None = None,
    query_times: np.ndarray | None = None,
    exclude_within: float | None = None,
    roots: Sequence[str] = (),
    frame_time: float | None = None,
    pelvis_method: PelvisMethod = "note",
    aim: Aim = "markers",
    twist_markers: np.ndarray | None = None,
    bone_starts: np.ndarray | None = None,
    root_at: RootAt = "fit",
    weights: np.ndarray | None = None,
    pelvis_points: str = "pelvis marker",
) -> MarkerMotion:
    """The solver on joint positions already in skeleton space.

    Parameters
    ----------
    measured : (F, J, 3) measured position of each skeleton joint (NaN: not measured).
    skeleton : GMR skeleton (pre-rotation).
    pelvis : names of X1 (a root of the skeleton), X2, X3.
    query_times : (F,) seconds of the frames (default ``arange(F) * frame_time``).
    twist_markers : (F, J, 3) for each joint a third marker rigid with its bone (the lateral
        knee for the thigh...; NaN: none): where present with the bone's direction, the twist
        is the angle about the bone of that marker's direction, measured from its mean
        direction over the frames (:func:`~core.markers.limbs.marker_twists`), before any reference or least change.
    bone_starts : (F, J, 3) where each joint's bone starts according to the marker map (its
        ``[bones]``; NaN: none): with ``aim="markers"`` the bone is aimed from there, before the
        measured parent (they agree on the skeleton the map was made for). The joints below a
        bone the skeleton lacks (:func:`~core.markers.targets.below_missing_bones`) are left
        out of the root's fit: the skeleton cannot reach their markers.
    weights : (J,) each joint's weight in the root's fit (None: 1 each).
    pelvis_points : what the pelvis points are, for the reasons ("pelvis marker", or "joint
        centre" for a skeleton built from the markers, whose pelvis triple it computes).
    Other parameters as in :func:`markers_to_motion`.
    """
    if skeleton.convention != "pre":
        raise OperationError("the solver needs a GMR (pre-rotation) skeleton")
    measured = np.asarray(measured, dtype=np.float64)
    n_frames, n_joints = measured.shape[:2]
    frame_time = float(frame_time or skeleton.frame_time)
    query_times = np.arange(n_frames) * frame_time if query_times is None else np.asarray(query_times)
    if pelvis is None or len(pelvis) != 3:
        raise OperationError("the marker map names no pelvis markers (root, left femur, lower back)")
    strangers = [name for name in pelvis if name not in skeleton.names]
    if strangers:
        raise OperationError(
            f"the map's pelvis markers {', '.join(strangers)} are not joints of the skeleton: "
            "a map for markers_to_motion places joints (pelvis-only maps serve recover_pelvis; without "
            "--skeleton, gmr markers builds a skeleton from the markers of a known set)"
        )
    triple_index = [skeleton.joint_index(name) for name in pelvis]
    pelvis_root = triple_index[0]
    if skeleton.parents[pelvis_root] >= 0:
        raise OperationError(f"the pelvis root {pelvis[0]!r} is not a root of the skeleton")
    root_set = {skeleton.joint_index(r) for r in roots} | {int(r) for r in skeleton.roots}
    home = rest_positions(skeleton, pelvis)
    rotations_p, residuals, valid, reasons = pelvis_rotations(
        measured[:, triple_index], home, method=pelvis_method, labels=tuple(pelvis), what=pelvis_points
    )
    pelvis_reasons = tuple(reasons)  # the pelvis's own, for its frames
    if not valid.any():
        raise OperationError("no frame has a usable pelvis: " + "; ".join(reasons))
    reference_data = reference_poses(reference, skeleton, triple_index, home, pelvis_method)
    good = np.flatnonzero(valid)
    m = measured[good]
    have = np.isfinite(m).all(axis=2)
    match, distance = np.full(len(good), -1), np.full(len(good), np.nan)
    if reference_data is not None:
        ref_local, ref_features, ref_correction, ref_times = reference_data
        features = np.einsum("fba,fjb->fja", rotations_p[good], m - m[:, pelvis_root : pelvis_root + 1])
        match, distance = best_matches(
            features,
            have & (np.arange(n_joints) != pelvis_root),
            ref_features,
            query_times=query_times[good],
            reference_times=ref_times,
            exclude_within=exclude_within,
        )
        if (match < 0).any():
            reasons.append(f"no reference frame could be matched in frames {frame_ranges(good[match < 0])}")
    matched = match >= 0
    local = np.empty((len(good), n_joints, 3, 3))
    world = np.empty_like(local)
    chain = np.empty((len(good), n_joints, 3))
    sources = np.full((len(good), n_joints), MEASURED, np.int8)
    for j in skeleton.topological_order:
        p = int(skeleton.parents[j])
        if p < 0:
            rotation = rotations_p[good] if j == pelvis_root else np.broadcast_to(np.eye(3), (len(good), 3, 3))
            if reference_data is not None:
                correction = ref_correction if j == pelvis_root else ref_local[:, j]
                rotation = np.where(matched[:, None, None], rotation @ correction[np.maximum(match, 0)], rotation)
            local[:, j] = world[:, j] = rotation
            chain[:, j] = np.where(have[:, j, None], m[:, j], skeleton.offsets[j])
            sources[:, j] = ROOT
            continue
        offset = skeleton.offsets[j]
        length = np.linalg.norm(offset)
        origin = np.where(have[:, p, None], m[:, p], chain[:, p]) if aim == "markers" else chain[:, p]
        if aim == "markers" and bone_starts is not None:
            begin = bone_starts[good, j]
            origin = np.where(np.isfinite(begin).all(axis=1)[:, None], begin, origin)
        bone = np.einsum("fba,fb->fa", world[:, p], m[:, j] - origin)
        bone_length = np.linalg.norm(bone, axis=1)
        ok = have[:, j] & (length > 0) & (bone_length > 1e-12 * max(length, 1e-300))
        c = bone / np.where(ok, bone_length, 1.0)[:, None]
        u = offset / (length if length > 0 else 1.0)
        result = np.broadcast_to(np.eye(3), (len(good), 3, 3)).copy()
        marked = np.zeros(len(good), bool)
        if twist_markers is not None:
            third = np.einsum("fba,fb->fa", world[:, p], twist_markers[good, j] - origin)
            marked = ok & np.isfinite(third).all(axis=1)
            if marked.any():
                result[marked] = limb_rotation(u, c[marked], marker_twists(u, c[marked], third[marked]))
                sources[marked, j] = TWIST_MARKER
        if reference_data is not None:
            known = ref_local[np.maximum(match, 0), j]
            twist = twist_of(known, u)
            use = ok & matched & ~marked
            result[use] = limb_rotation(u, c[use], twist[use])
            result[~ok & matched] = known[~ok & matched]
            sources[~ok & matched, j] = FROM_REFERENCE
            todo = ok & ~matched & ~marked
        else:
            todo = ok & ~marked
        if todo.any():
            result[todo] = limb_rotation(u, c[todo], least_change_twists(u, c[todo]))
        rest = ~ok & ~matched
        if rest.any():
            result[rest] = _hold(result, ok)[rest]
            sources[rest, j] = HELD
        local[:, j] = result
        world[:, j] = world[:, p] @ result
        chain[:, j] = chain[:, p] + np.einsum("fab,b->fa", world[:, j], offset)
        if j in root_set:
            chain[:, j] = np.where(have[:, j, None], m[:, j], chain[:, j])
    if root_at == "fit":
        follows = hanging_from_root(skeleton, pelvis_root, root_set - {pelvis_root}, have)
        reachable = ~below_missing_bones(measured, bone_starts, skeleton) if bone_starts is not None else True
        shift = root_translations(chain, m, follows & reachable, weights)
        chain = np.where(follows[..., None], chain + shift[:, None], chain)
    return _assemble(
        skeleton, valid, good, local, world, chain, sources, root_set, frame_time,
        measured, rotations_p, residuals, match, distance, reasons, pelvis, pelvis_reasons,
    )  # fmt: skip


def _hold(values: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """values (N, ...) with each row where ``ok`` is False taken from the nearest earlier
    ok row, or the nearest later one; the identity where no row is ok."""
    if not ok.any():
        return values
    before, after = gap_runs(ok)
    source = np.where(before >= 0, before, after)
    return values[source]


def _assemble(
    skeleton, valid, good, local, world, chain, sources, root_set, frame_time,
    measured, rotations_p, residuals, match, distance, reasons, pelvis, pelvis_reasons,
) -> MarkerMotion:  # fmt: skip
    """Scatter the good frames over all frames (bad ones copy the nearest good frame) and
    build the GMR motion, splitting the requested roots off their parents."""
    n_joints = measured.shape[1]
    before, after = gap_runs(valid)
    nearest = np.where(before >= 0, before, after)
    position = np.searchsorted(good, nearest)
    is_root = np.zeros(n_joints, bool)
    is_root[sorted(root_set)] = True
    # the forest and its soft links as core.edits.operations.split leaves them (on the rest pose)
    structure = skeleton.rest_pose()
    for j in skeleton.topological_order:
        if is_root[j] and structure.parents[j] >= 0:
            structure = split(structure, int(j))
    parents, soft = structure.parents, structure.soft_parents
    rotations = np.where(is_root[None, :, None, None], world, local)[position]
    translations = np.where(is_root[None, :, None], chain, skeleton.offsets[None])[position]
    offsets = np.where(is_root[:, None], translations[0], skeleton.offsets)
    orders = tuple(o or "ZYX" for o in skeleton.rotation_orders)
    motion = Motion(
        names=skeleton.names,
        parents=parents,
        soft_parents=soft,
        offsets=offsets,
        rotation_orders=orders,
        has_translation=is_root,
        rotations=rotations,
        translations=translations,
        frame_time=frame_time,
        convention="pre",
        facts=skeleton.facts,
    )
    full_sources = sources[position]
    full_match = np.where(valid, match[position], -1)
    full_distance = np.where(valid, distance[position], np.nan)
    if (~valid).any():
        reasons.append(f"frames {frame_ranges(~valid)} copy the nearest frame with a usable pelvis")
    frames = PelvisFrames(
        rotations=np.where(valid[:, None, None], rotations_p, np.eye(3)),
        origins=np.where(valid[:, None], measured[:, skeleton.joint_index(pelvis[0])], np.nan),
        residuals=residuals,
        valid=valid,
        units="skeleton",
        reasons=pelvis_reasons,
        labels=tuple(pelvis),
    )
    return MarkerMotion(
        motion=motion,
        measured=measured,
        sources=full_sources,
        frame_valid=valid,
        pelvis=frames,
        matches=full_match,
        match_distances=full_distance,
        reasons=tuple(reasons),
    )
