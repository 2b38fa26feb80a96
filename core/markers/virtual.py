"""Virtual markers (joint centres) from real markers through a marker map, and calibration.

:func:`compute_virtual_markers` evaluates a :class:`~core.markers.markermap.MarkerMap` on a
marker set for every frame at once:

- ``marker``: the marker itself; ``mean``: the mean of the markers, a gap if any is missing;
- ``cluster``: the calibrated template is fitted to the markers present in each frame
  (least squares, :func:`~core.markers.procrustes.fit_rigid`: at least three, not
  collinear) and the offset is carried along: ``v = R offset + t``. A missing marker is
  tolerated while three others are seen; the per-frame fit RMS says how rigid the cluster
  was.

A virtual marker that cannot be formed is NaN in that frame, and ``reasons`` names its
frames and the missing markers. :func:`calibrate_marker_map` finds the clusters' templates
(generalised Procrustes over the calibration frames) and offsets (least squares: the mean of
``R_f^T (J_f - t_f)``) from frames whose joint positions are known.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.markermap import MarkerMap, VirtualMarker
from gmr_studio.core.markers.markerset import MarkerSet, frame_ranges
from gmr_studio.core.markers.procrustes import fit_rigid
from gmr_studio.core.space.similarity import Similarity

#: generalised-Procrustes iterations for a cluster template (the template moves by less
#: than 1e-9 of its size after three on the CMU clusters)
TEMPLATE_ITERATIONS = 6


@dataclasses.dataclass(frozen=True, eq=False)
class VirtualMarkers:
    """Virtual marker trajectories.

    Attributes
    ----------
    names : tuple of V str, the joints they place.
    positions : (F, V, 3) float64, marker axes, ``units``; NaN where not ``valid``.
    valid : (F, V) bool.
    fit_rms : (F, V) float64, cluster fit RMS (NaN for other kinds and invalid frames).
    units : str, alignment : Similarity (to skeleton space), rate : float.
    reasons : tuple of str, one per virtual marker with invalid frames.
    """

    names: tuple[str, ...]
    positions: np.ndarray
    valid: np.ndarray
    fit_rms: np.ndarray
    units: str
    alignment: Similarity
    rate: float
    reasons: tuple[str, ...] = ()

    @property
    def n_frames(self) -> int:
        return self.positions.shape[0]

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise OperationError(f"no virtual marker {name!r}") from None

    def skeleton_positions(self) -> np.ndarray:
        """(F, V, 3) positions in the skeleton's axes and units (through the alignment)."""
        return self.alignment.apply(self.positions)


def resolve_map(
    marker_map: MarkerMap,
    markers: MarkerSet,
    joint_names: Sequence[str] | None = None,
    *,
    skeleton=None,
    joint_map=None,
) -> MarkerMap:
    """The built-in ``joints`` map made concrete: one virtual marker per joint name that the
    marker set has (every label when no names are given; the skeleton's names when a
    skeleton is given); other maps are returned as they are.

    Without a pelvis named by the map, the triple is chosen by
    :func:`core.markers.pelvis_guess.choose_pelvis` (the note's root, left femur, lower back
    first; with the skeleton, any non-collinear triple of pelvis joints after) and
    ``pelvis_note`` says which and why.

    Other maps name the joints of the skeleton they were made for; given a skeleton whose
    joints are named otherwise (CMU's BVH for the ``cmu`` map made on CMU's ASF), they are
    renamed through a joint-name map (``joint_map``, or the shipped one that pairs them):
    :func:`core.markers.joint_names.through_joint_map`.
    """
    if not marker_map.joints:
        if skeleton is None and joint_map is None:
            return marker_map
        from gmr_studio.core.markers.joint_names import through_joint_map

        return through_joint_map(marker_map, skeleton.names if skeleton is not None else joint_names, joint_map)
    from gmr_studio.core.markers.markermap import guess_pelvis, joints_map
    from gmr_studio.core.markers.pelvis_guess import choose_pelvis, sampled_positions

    if joint_names is None and skeleton is not None:
        joint_names = skeleton.names
    all_names = list(joint_names if joint_names is not None else markers.labels)
    labels = set(markers.labels)
    names = [n for n in all_names if n in labels]
    if not names:
        raise OperationError(
            f"the 'joints' map needs markers labelled with joint names; {markers.source or 'the marker set'} has none"
        )
    pelvis = marker_map.pelvis if marker_map.pelvis and all(p in names for p in marker_map.pelvis) else None
    note = ""
    if pelvis is None:
        positions = np.full((markers.n_frames, len(all_names), 3), np.nan)
        for k, name in enumerate(all_names):
            if name in labels:
                positions[:, k] = markers.positions[:, markers.index(name)]
        structure = skeleton is not None and list(skeleton.names) == all_names
        choice = choose_pelvis(
            all_names,
            positions,
            skeleton.parents if structure else None,
            np.asarray(skeleton.offsets) if structure else None,
            sampled_positions(skeleton) if structure and skeleton.n_frames >= 2 else None,
        )
        if choice is not None:
            pelvis, note = choice.triple, choice.describe()
    resolved = joints_map(names, pelvis or guess_pelvis(names))
    return resolved.replace(alignment=marker_map.alignment, pelvis_note=note)


def _in_map_units(markers: MarkerSet, marker_map: MarkerMap) -> MarkerSet:
    return markers.in_units(marker_map.units) if marker_map.units and marker_map.units != markers.units else markers


def compute_virtual_markers(markers: MarkerSet, marker_map: MarkerMap) -> VirtualMarkers:
    """Evaluate every virtual marker of the map on every frame (see the module docstring).

    Parameters
    ----------
    markers : the marker set (converted to the map's units first).
    marker_map : a resolved map (see :func:`resolve_map`); clusters must be calibrated.

    Returns
    -------
    VirtualMarkers in marker axes and the map's units.
    """
    markers = _in_map_units(markers, marker_map)
    n_frames = markers.n_frames
    n_virtual = len(marker_map.virtual)
    positions = np.full((n_frames, n_virtual, 3), np.nan)
    fit_rms = np.full((n_frames, n_virtual), np.nan)
    reasons: list[str] = []
    absent = [label for label in marker_map.labels() if label not in markers.labels]
    if absent:
        reasons.append(f"the markers {', '.join(absent)} are not in {markers.source or 'the marker set'}")
    fits = _ClusterFits()
    for v, virtual in enumerate(marker_map.virtual):
        if not virtual.calibrated:
            raise OperationError(
                f"virtual marker {virtual.name!r} of map {marker_map.name!r} is not calibrated: "
                "calibrate the map on frames of known pose first"
            )
        inputs = _inputs(virtual.markers, markers, marker_map.names, positions)
        if virtual.kind == "cluster":
            positions[:, v], fit_rms[:, v] = fits.place(virtual, inputs)
        else:
            positions[:, v] = inputs.mean(axis=1)  # NaN if any input is missing
        bad = ~np.isfinite(positions[:, v]).all(axis=1)
        if bad.any():
            lacking = [m for k, m in enumerate(virtual.markers) if not np.isfinite(inputs[bad, k]).all()]
            reasons.append(
                f"{virtual.name}: missing in frames {frame_ranges(bad)} ({int(bad.sum())} frames), "
                f"its markers {', '.join(lacking) or 'are degenerate'}" + (" lack there" if lacking else "")
            )
    valid = np.isfinite(positions).all(axis=2)
    return VirtualMarkers(
        names=marker_map.names,
        positions=positions,
        valid=valid,
        fit_rms=fit_rms,
        units=markers.units,
        alignment=marker_map.alignment,
        rate=markers.rate,
        reasons=tuple(reasons),
    )


class _ClusterFits:
    """Rigid fits of clusters, each computed once: maps place several joints on one
    cluster (the pelvis markers carry root and both hips), and a fit depends only on the
    cluster's markers and template (virtual markers are evaluated in map order, so an
    ``@NAME`` input is final when it is read)."""

    def __init__(self) -> None:
        self._fits: dict[tuple, tuple[np.ndarray, ...]] = {}

    def place(self, virtual: VirtualMarker, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(F, 3) positions of a calibrated cluster marker (NaN where the fit failed) and
        (F,) fit RMS, from its (F, K, 3) inputs."""
        key = (virtual.markers, virtual.template.tobytes())
        if key not in self._fits:
            self._fits[key] = fit_rigid(virtual.template, inputs)
        rotation, translation, rms, ok = self._fits[key]
        positions = np.einsum("fab,b->fa", rotation, virtual.offset) + translation
        positions[~ok] = np.nan
        return positions, rms


def _inputs(labels: Sequence[str], markers: MarkerSet, names: tuple[str, ...], virtual: np.ndarray) -> np.ndarray:
    """(F, K, 3) the positions of a virtual marker's inputs (NaN for absent markers);
    ``@NAME`` inputs come from ``virtual`` (F, V, 3), V in the order of ``names``."""
    out = np.full((markers.n_frames, len(labels), 3), np.nan)
    for k, label in enumerate(labels):
        if label.startswith("@"):
            out[:, k] = virtual[:, names.index(label[1:])]
        elif label in markers.labels:
            out[:, k] = markers.positions[:, markers.index(label)]
    return out


def calibrate_marker_map(
    marker_map: MarkerMap,
    markers: MarkerSet,
    joint_positions: np.ndarray,
    joint_names: Sequence[str],
    frames: np.ndarray | slice | None = None,
    *,
    pelvis_home: np.ndarray | None = None,
    note: dict | None = None,
) -> MarkerMap:
    """Fit every cluster's template and offset on frames where the joints are known.

    Parameters
    ----------
    marker_map : the map to calibrate (offsets already there are replaced).
    markers : the marker set, frame-aligned with ``joint_positions``.
    joint_positions : (F, J, 3) world positions in skeleton space (a reference motion of the
        same trial), or (1, J, 3) for a static pose held during the calibration frames.
    joint_names : the J joint names.
    frames : which frames to use (slice, indices or (F,) bool; default all).
    pelvis_home : (3, 3) rest positions of the pelvis triple (skeleton space) to store.
    note : extra ``[calibration]`` entries (source files, frames, command).

    Returns
    -------
    A new MarkerMap with ``offset``, ``template`` and ``rms`` (map units) for each cluster.
    """
    markers = _in_map_units(markers, marker_map)
    n_frames = markers.n_frames
    chosen = np.zeros(n_frames, bool)
    chosen[np.arange(n_frames)[frames if frames is not None else slice(None)]] = True
    joint_positions = np.asarray(joint_positions, dtype=np.float64)
    if joint_positions.shape[0] == 1:
        joint_positions = np.broadcast_to(joint_positions, (n_frames, *joint_positions.shape[1:]))
    if joint_positions.shape[0] != n_frames:
        raise OperationError(
            f"the reference has {joint_positions.shape[0]} frames and the markers {n_frames}: "
            "calibration needs the same trial, frame for frame (or a one-frame static pose)"
        )
    known = marker_map.alignment.inverse().apply(joint_positions)  # (F, J, 3) marker space
    names = list(joint_names)
    positions = np.full((n_frames, len(marker_map.virtual), 3), np.nan)
    calibrated: list[VirtualMarker] = []
    templates: dict[tuple, tuple[np.ndarray, ...]] = {}
    fits = _ClusterFits()
    for v, virtual in enumerate(marker_map.virtual):
        inputs = _inputs(virtual.markers, markers, marker_map.names, positions)
        if virtual.kind == "cluster":
            if virtual.name not in names:
                raise OperationError(f"virtual marker {virtual.name!r} is not a joint of the reference")
            target = known[:, names.index(virtual.name)]
            virtual = _calibrate_cluster(virtual, inputs, target, chosen, templates)
            positions[:, v] = fits.place(virtual, inputs)[0]
        else:
            positions[:, v] = inputs.mean(axis=1)
        calibrated.append(virtual)
    calibration = dict(marker_map.calibration)
    calibration.update(note or {})
    return marker_map.replace(
        virtual=tuple(calibrated),
        calibration=calibration,
        pelvis_home=pelvis_home if pelvis_home is not None else marker_map.pelvis_home,
    )


def _calibrate_cluster(
    virtual: VirtualMarker, inputs: np.ndarray, target: np.ndarray, chosen: np.ndarray, templates: dict
) -> VirtualMarker:
    """The cluster's template (which depends only on its markers and the frames used, so
    it is kept in ``templates`` for the map's other joints on the same cluster) and its
    offset to ``target`` (F, 3)."""
    complete = chosen & np.isfinite(inputs).all(axis=(1, 2)) & np.isfinite(target).all(axis=1)
    if not complete.any():
        raise OperationError(
            f"cluster {virtual.name!r} ({', '.join(virtual.markers)}) is never complete in the calibration frames"
        )
    key = (virtual.markers, complete.tobytes())
    if key not in templates:
        templates[key] = _cluster_template(virtual.name, inputs[complete])
    template, rotation, translation, ok = templates[key]
    goal = target[complete]
    local = np.einsum("fba,fb->fa", rotation[ok], goal[ok] - translation[ok])
    offset = local.mean(axis=0)
    fitted = np.einsum("fab,b->fa", rotation[ok], offset) + translation[ok]
    rms = float(np.sqrt(np.mean(np.sum((fitted - goal[ok]) ** 2, axis=1))))
    return dataclasses.replace(virtual, offset=offset, template=template, rms=rms)


def _cluster_template(name: str, points: np.ndarray) -> tuple[np.ndarray, ...]:
    """Template (K, 3) of a cluster from its (C, K, 3) complete calibration frames, and the
    fit of every one of those frames to it: rotation (C, 3, 3), translation (C, 3), ok (C,)."""
    template = points[0] - points[0].mean(axis=0)
    for _ in range(TEMPLATE_ITERATIONS):
        rotation, translation, _, ok = fit_rigid(template, points)
        if not ok.any():
            raise OperationError(f"cluster {name!r}: its markers are collinear in every calibration frame")
        aligned = np.einsum("fba,fkb->fka", rotation[ok], points[ok] - translation[ok, None, :])
        template = aligned.mean(axis=0)
        template -= template.mean(axis=0)
    rotation, translation, _, ok = fit_rigid(template, points)
    return template, rotation, translation, ok
