"""The pelvis orientation recovered from three virtual markers (technical note, section 1).

The note's method, for every frame at once: from X1 (pelvis root), X2 (left femur) and X3
(lower back) build the orthonormal frame ``P = [p1 p2 p3]`` (Gram-Schmidt, equation 2 as
corrected in MATH.md), the same frame ``H`` of the three points at the home pose (the
skeleton's rest pose), solve ``R H = P`` in the least-squares sense (equation 7: with nine
equations and nine unknowns, ``R = P H^+``), then take the nearest rotation by SVD
(``R* = U V^T``, the last column of U negated when det < 0).

``method="points"`` fits the home triangle to the measured one instead (Kabsch on the three
centred points: all three weigh the same, where the note's frame trusts the X1-X2 direction
fully and uses X3 only for the plane).

The residual of a frame is the RMS distance between the three measured points and the home
triangle placed on them by ``(R*, X1)``: zero when the pelvis triangle keeps its home shape,
growing with marker noise, skin motion or a calibration that does not fit. Without a home
pose the frame ``P`` itself is the rotation (``H = I``) and the residual is measured against
the triangle's median shape over the valid frames.

When the three virtual markers all come from one rigid cluster (the ``cmu`` map's root and
hips), a Procrustes on them fits by construction; :func:`recover_pelvis` then fits three of
the cluster's real markers, and reports the real markers' fit to the cluster template and
each virtual marker's distance from its fitted home as well.

:class:`PelvisFrames` is the result the app draws over the markers: one frame per motion
frame, with the fit residual and a flag for frames that could not be recovered.
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.markerset import MarkerSet, frame_ranges
from gmr_studio.core.markers.procrustes import fit_rigid, frame_from_triple
from gmr_studio.core.rotations.euler import nearest_rotation

PelvisMethod = Literal["note", "points"]


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class PelvisFrames:
    """Recovered pelvis frames.

    Attributes
    ----------
    rotations : (F, 3, 3) float64, world rotation of the pelvis per frame (identity where
        not ``valid``), in the marker file's axes: it turns the home pelvis into the
        measured one.
    origins : (F, 3) float64, the pelvis root (virtual marker X1) per frame, NaN where not
        ``valid``.
    residuals : (F,) float64, RMS distance (``units``) of the three virtual markers from the
        home triangle placed by the fit (NaN where not ``valid``).
    valid : (F,) bool, the three virtual markers were present and not degenerate.
    units : str, length unit of ``origins``.
    reasons : tuple of str, for each distinct cause of invalid frames, a message naming it
        and the frames it spoiled.
    labels : the names of the three virtual markers (X1, X2, X3).
    fit_labels : the three points the Procrustes fitted: ``labels``, or three real markers
        of the cluster when X1, X2, X3 all come from one rigid cluster (see
        :func:`recover_pelvis`); ``residuals`` are theirs.
    virtual_residuals : (F, 3) float64 or None, distance (``units``) of each virtual marker
        X1, X2, X3 from its home position placed by the fit.
    virtual_fit : (F, 3) float64 or None, for each virtual marker made by a cluster, the RMS
        distance of the cluster's real markers from its template placed by the cluster fit
        (NaN for other kinds): how rigid the markers that make it were in that frame.
    marker_fit : (F,) float64 or None, the same over the distinct clusters of X1, X2, X3: the
        fit of the real markers to the cluster template(s).
    note : how the fit was made, when it was not on the three virtual markers.
    """

    rotations: np.ndarray
    origins: np.ndarray
    residuals: np.ndarray
    valid: np.ndarray
    units: str = "mm"
    reasons: tuple[str, ...] = ()
    labels: tuple[str, ...] = ()
    fit_labels: tuple[str, ...] = ()
    virtual_residuals: np.ndarray | None = None
    virtual_fit: np.ndarray | None = None
    marker_fit: np.ndarray | None = None
    note: str = ""

    @property
    def n_frames(self) -> int:
        return self.rotations.shape[0]


def pelvis_rotations(
    triple: np.ndarray,
    home: np.ndarray | None = None,
    *,
    method: PelvisMethod = "note",
    min_sine: float = 1e-6,
    labels: tuple[str, str, str] = ("X1", "X2", "X3"),
    what: str = "pelvis marker",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """The pelvis rotation of every frame from the three points (the array core of
    :func:`recover_pelvis`).

    Parameters
    ----------
    triple : (F, 3, 3) float, X1, X2, X3 per frame (axis 1), NaN where missing.
    home : (3, 3) float, the three points at the home pose in the same axes and units, or None.
    method : "note" (frames, least squares, nearest rotation) or "points" (Kabsch).
    min_sine : degeneracy threshold of :func:`~core.markers.procrustes.frame_from_triple`.
    labels : names of the three points, for the messages.
    what : what the three points are, for the messages ("pelvis marker"; "joint centre"
        for the joint centres a skeleton built from the markers computes).

    Returns
    -------
    rotations (F, 3, 3), residuals (F,), valid (F,), reasons (list of str).
    """
    triple = np.asarray(triple, dtype=np.float64)
    if method not in ("note", "points"):
        raise ValueError(f"method must be 'note' or 'points', not {method!r}")
    frames, ok, coincident, collinear = frame_from_triple(triple[:, 0], triple[:, 1], triple[:, 2], min_sine)
    missing = ~np.isfinite(triple).all(axis=2)
    reasons = []
    for k, label in enumerate(labels):
        if missing[:, k].any():
            reasons.append(f"{what} {label} missing in frames {frame_ranges(missing[:, k])}")
    names = ", ".join(labels)
    if coincident.any():
        reasons.append(f"{what}s {names} coincide in frames {frame_ranges(coincident)}")
    if collinear.any():
        reasons.append(f"{what}s {names} are collinear in frames {frame_ranges(collinear)}")
    if home is not None:
        home = np.asarray(home, dtype=np.float64)
        home_frame, home_ok, _, _ = frame_from_triple(home[0], home[1], home[2], min_sine)
        if not home_ok:
            raise OperationError(f"the home positions of the pelvis markers {names} are degenerate")
        shape = home - home[0]
    else:
        home_frame = np.eye(3)
        local = np.einsum("fba,fkb->fka", frames[ok], triple[ok] - triple[ok, :1])
        shape = np.median(local, axis=0) if ok.any() else np.zeros((3, 3))
    if method == "note":
        # R H = P in the least-squares sense (H is orthonormal, so H^+ = H^T), then the
        # nearest rotation by SVD with the det < 0 correction
        rotations = nearest_rotation(frames @ np.linalg.pinv(home_frame))
    else:
        present = np.broadcast_to(ok[:, None], triple.shape[:2])
        rotations = fit_rigid(shape, np.where(ok[:, None, None], triple, 0.0), present)[0]
    rotations[~ok] = np.eye(3)
    placed = triple[:, :1] + np.einsum("fab,kb->fka", rotations, shape)
    residuals = np.sqrt(np.mean(np.sum((placed - triple) ** 2, axis=2), axis=1))
    residuals[~ok] = np.nan
    return rotations, residuals, ok, reasons


def recover_pelvis(
    markers: MarkerSet,
    marker_map="joints",
    *,
    skeleton=None,
    home: np.ndarray | None = None,
    method: PelvisMethod = "note",
    min_sine: float = 1e-6,
) -> PelvisFrames:
    """Pelvis frames of a marker set, through a marker map (see the module docstring).

    Parameters
    ----------
    markers : the marker set.
    marker_map : a :class:`~core.markers.markermap.MarkerMap`, or what
        :func:`~core.markers.markermap.load_marker_map` takes: a name (``"joints"``: the
        markers are the joint centres, labelled with joint names; ``"cmu"``: the shipped CMU
        41-marker map) or the path of a map file. The map names the three virtual markers
        (its ``[pelvis]`` section; ``joints`` guesses them from the names, e.g. root,
        lhipjoint, rhipjoint for CMU ASF skeletons).
    skeleton : a :class:`~core.model.motion.Motion` whose rest pose gives the home positions (and,
        for ``joints``, the joint names), or None.
    home : (3, 3) home positions of X1, X2, X3 in skeleton space, overriding the skeleton's
        and the map's; without any, the rotation is the frame P itself.
    method, min_sine : see :func:`pelvis_rotations`.

    Returns
    -------
    PelvisFrames in the marker file's axes, origins in the map's units (the file's for
    ``joints``).
    """
    from gmr_studio.core.markers.markermap import load_marker_map
    from gmr_studio.core.markers.virtual import compute_virtual_markers, resolve_map

    loaded = load_marker_map(marker_map)
    resolved = resolve_map(loaded, markers, skeleton=skeleton)
    if resolved.pelvis is None:
        raise OperationError(
            f"marker map {resolved.name!r} names no pelvis markers (root, left femur, lower back) "
            "and none could be guessed from the names"
        )
    virtual = compute_virtual_markers(markers, resolved)
    index = [virtual.index(name) for name in resolved.pelvis]
    triple = virtual.positions[:, index]
    if home is None and skeleton is not None and all(name in skeleton.names for name in resolved.pelvis):
        home = rest_positions(skeleton, resolved.pelvis)
    if home is None:
        home = resolved.pelvis_home
    home_markers = None if home is None else resolved.alignment.inverse().apply(np.asarray(home, dtype=np.float64))
    sources = [resolved.virtual[resolved.names.index(name)] for name in resolved.pelvis]
    fit_points, fit_home, fit_labels, note = triple, home_markers, tuple(resolved.pelvis), ""
    raw = _raw_triple(sources, home_markers, markers, virtual.units) if home_markers is not None else None
    if raw is not None:
        fit_points, fit_home, fit_labels = raw
        note = (
            f"{', '.join(resolved.pelvis)} all come from one rigid cluster ({', '.join(sources[0].markers)}), "
            f"which fits them by construction: the Procrustes fits its real markers {', '.join(fit_labels)}"
        )
    rotations, residuals, valid, reasons = pelvis_rotations(
        fit_points, fit_home, method=method, min_sine=min_sine, labels=fit_labels
    )
    if raw is not None:  # where a real marker lacks but the cluster fit holds, the virtual triple serves
        by_cluster, _, cluster_ok, reasons = pelvis_rotations(
            triple, home_markers, method=method, min_sine=min_sine, labels=resolved.pelvis
        )
        fallback = cluster_ok & ~valid
        if fallback.any():
            rotations[fallback], valid = by_cluster[fallback], valid | fallback
            fit_points = np.where(fallback[:, None, None], np.nan, fit_points)
            reasons.append(
                f"{', '.join(fit_labels)} incomplete in frames {frame_ranges(fallback)}: the pelvis there is the "
                "cluster's fit to its other markers (no three-marker residual)"
            )
    valid &= np.isfinite(triple[:, 0]).all(axis=1)
    rotations[~valid] = np.eye(3)
    if not valid.any():
        reasons.append("no frame has a usable pelvis")
    virtual_residuals = None
    if fit_home is not None:  # the virtual markers' home, carried by the fit anchored at the first fitted point
        placed = fit_points[:, :1] + np.einsum("fab,kb->fka", rotations, home_markers - fit_home[0])
        virtual_residuals = np.where(valid[:, None], np.linalg.norm(placed - triple, axis=2), np.nan)
    virtual_fit = np.where(valid[:, None], virtual.fit_rms[:, index], np.nan)
    return PelvisFrames(
        rotations=rotations,
        origins=np.where(valid[:, None], triple[:, 0], np.nan),
        residuals=np.where(valid, residuals, np.nan),
        valid=valid,
        units=virtual.units,
        reasons=tuple(reasons),
        labels=resolved.pelvis,
        fit_labels=fit_labels,
        virtual_residuals=virtual_residuals,
        virtual_fit=virtual_fit,
        marker_fit=_distinct_cluster_rms(sources, virtual_fit),
        note=note,
    )


def _raw_triple(sources, home: np.ndarray, markers: MarkerSet, units: str):
    """When the three pelvis virtual markers are one calibrated cluster's, three of its real
    markers (the template triangle of largest area) with their home positions (the template
    carried to the home pose by the rigid motion that takes the virtual markers' offsets onto
    their home), as ((F, 3, 3) positions in ``units``, (3, 3) home, labels); else None."""
    first = sources[0]
    same = all(v.kind == "cluster" and v.markers == first.markers and v.calibrated for v in sources)
    real = [k for k, label in enumerate(first.markers) if not label.startswith("@")]
    if not same or len(real) < 3:
        return None
    best, best_area = None, 0.0
    for a in range(len(real)):
        for b in range(a + 1, len(real)):
            for c in range(b + 1, len(real)):
                t = first.template[[real[a], real[b], real[c]]]
                area = float(np.linalg.norm(np.cross(t[1] - t[0], t[2] - t[0])))
                if area > best_area:
                    best, best_area = (real[a], real[b], real[c]), area
    if best is None:
        return None
    offsets = np.stack([v.offset for v in sources])
    rotation, translation, _, ok = fit_rigid(offsets, home[None])
    if not ok[0]:
        return None
    raw_home = first.template[list(best)] @ rotation[0].T + translation[0]
    labels = tuple(first.markers[k] for k in best)
    in_units = markers.in_units(units) if units != markers.units else markers
    points = np.stack([in_units.positions[:, in_units.index(label)] for label in labels], axis=1)
    return points, raw_home, labels


def _distinct_cluster_rms(sources, virtual_fit: np.ndarray) -> np.ndarray | None:
    """(F,) RMS of the cluster fit over the distinct clusters among the three sources."""
    columns, seen = [], set()
    for k, v in enumerate(sources):
        if v.kind == "cluster" and v.markers not in seen:
            seen.add(v.markers)
            columns.append(k)
    if not columns:
        return None
    return np.sqrt(np.mean(virtual_fit[:, columns] ** 2, axis=1))


def rest_positions(skeleton, names) -> np.ndarray:
    """(len(names), 3) world positions of some joints in the skeleton's rest pose."""
    from gmr_studio.core.kinematics.fk import world_positions

    rest = world_positions(skeleton.rest_pose())[0]
    return rest[[skeleton.joint_index(n) for n in names]]
