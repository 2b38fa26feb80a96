"""Joint centres and axes from the motion of two marker clusters (functional methods).

Both methods take two clusters, each (F, K, 3) markers rigid with its segment (K >= 3, NaN
where missing), fit each cluster's rigid motion ``R_i, t_i`` to its centred pose in its first
complete frame (:func:`core.markers.procrustes.fit_rigid`) and solve, by least squares over
the frames, for a point fixed in both: ``R_1 c_1 + t_1 = R_2 c_2 + t_2`` (Ehrig R.M., Taylor
W.R., Duda G.N., Heller M.O. 2006, "A survey of formal methods for determining the centre of
rotation of ball joints", J. Biomech. 39:2798-2809, SCoRE).

- :func:`functional_centre`: SCoRE's point (for a hinge, the least-norm point of its axis).
- :func:`flexion_axis`: SARA (Ehrig R.M., Taylor W.R., Duda G.N., Heller M.O. 2007, "A survey
  of formal methods for determining functional joint axes", J. Biomech. 40:2150-2157): for a
  hinge the same system has a one-dimensional null space, the axis, fixed in both clusters;
  its direction is the right singular vector of the smallest singular value.
- :func:`knee_on_flexion_axis`: the knee centre relocated onto the SARA axis where the femur's
  long axis (hip centre to the anatomical knee centre) meets it (the closest point between the
  two lines), as CGM 2.x's functional knee calibration does (pyCGM2,
  ``KneeCalibrationDecorator.sara``; Leboeuf F., Baker R., Barre A., Reay J., Jones R.,
  Sangeux M. 2019, "The conventional gait model, an open-source implementation that
  reproduces the past but prepares for the future", Gait Posture 69:235-241);
  :func:`knee_on_axis` does it when the take flexes the knee enough for the axis.
- :func:`fill_from_cluster`: a joint centre carried by its segment's cluster to the frames
  where its own markers are missing; :func:`most_seen`: the trajectory seen most.

Units: those of the markers (millimetres in the builder).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.markers.procrustes import fit_rigid


def _cluster_motions(proximal: np.ndarray, distal: np.ndarray):
    """The rigid motions (R (F, 3, 3), t (F, 3), ok (F,)) of both clusters, or None when either
    is never complete."""
    fits = []
    for cluster in (proximal, distal):
        complete = np.flatnonzero(np.isfinite(cluster).all(axis=(1, 2)))
        if complete.size == 0:
            return None
        template = cluster[complete[0]] - cluster[complete[0]].mean(axis=0)
        fits.append(fit_rigid(template, cluster))
    (r1, t1, _, ok1), (r2, t2, _, ok2) = fits
    return r1, t1, ok1, r2, t2, ok2


def _system(r1, t1, r2, t2, ok):
    """SCoRE's least-squares system ``[R_1, -R_2] (c_1, c_2) = t_2 - t_1`` over the frames ok."""
    return np.concatenate([r1[ok], -r2[ok]], axis=2).reshape(-1, 6), (t2[ok] - t1[ok]).reshape(-1)


def functional_centre(proximal: np.ndarray, distal: np.ndarray) -> np.ndarray:
    """The centre of rotation (F, 3) between two clusters (F, K, 3) and (F, L, 3) by SCoRE:
    the mid-point of its two placements per frame (NaN where either cluster cannot be
    fitted). For a hinge the point along the axis is the least-norm one (nearest the
    clusters' centroids)."""
    motions = _cluster_motions(proximal, distal)
    if motions is None:
        return np.full((len(proximal), 3), np.nan)
    r1, t1, ok1, r2, t2, ok2 = motions
    ok = ok1 & ok2
    system, rhs = _system(r1, t1, r2, t2, ok)
    local = np.linalg.lstsq(system, rhs, rcond=1e-6)[0]
    centre = 0.5 * (np.einsum("fab,b->fa", r1, local[:3]) + t1 + np.einsum("fab,b->fa", r2, local[3:]) + t2)
    centre[~ok] = np.nan
    return centre


@dataclasses.dataclass(frozen=True)
class FlexionAxis:
    """A SARA axis: ``point`` (6,) a point of it in the proximal (first 3) and distal cluster
    frames, ``direction`` (6,) its unit direction in both, the clusters' motions (``r1, t1``,
    ``r2, t2``: (F, 3, 3), (F, 3)) and ``ok`` (F,) the frames where both are fitted."""

    point: np.ndarray
    direction: np.ndarray
    r1: np.ndarray
    t1: np.ndarray
    r2: np.ndarray
    t2: np.ndarray
    ok: np.ndarray

    def place(self, local: np.ndarray) -> np.ndarray:
        """(F, 3) the world position of a point given in both cluster frames (6,): the mid-point
        of its two placements (NaN where a cluster is not fitted)."""
        out = 0.5 * (
            np.einsum("fab,b->fa", self.r1, local[:3]) + self.t1 + np.einsum("fab,b->fa", self.r2, local[3:]) + self.t2
        )
        out[~self.ok] = np.nan
        return out

    def in_proximal(self, points: np.ndarray) -> np.ndarray:
        """(3,) the median over the fitted frames of world points (F, 3) in the proximal frame."""
        local = np.einsum("fba,fb->fa", self.r1, points - self.t1)
        seen = self.ok & np.isfinite(local).all(axis=1)
        return np.median(local[seen], axis=0)


def flexion_axis(proximal: np.ndarray, distal: np.ndarray) -> FlexionAxis | None:
    """The SARA axis between two clusters (F, K, 3) and (F, L, 3); None when a cluster is never
    complete or the two are never fitted together. A rotation keeps a vector's length, so the
    null vector's two halves have the same length: each is scaled to 1."""
    motions = _cluster_motions(proximal, distal)
    if motions is None:
        return None
    r1, t1, ok1, r2, t2, ok2 = motions
    ok = ok1 & ok2
    if ok.sum() < 2:
        return None
    system, rhs = _system(r1, t1, r2, t2, ok)
    point = np.linalg.lstsq(system, rhs, rcond=1e-6)[0]
    null = np.linalg.svd(system, full_matrices=False)[2][-1]
    direction = null / np.linalg.norm(null[:3])
    return FlexionAxis(point, direction, r1, t1, r2, t2, ok)


def knee_on_flexion_axis(axis: FlexionAxis, hip: np.ndarray, knee: np.ndarray) -> tuple[np.ndarray, float]:
    """The knee centre (F, 3) moved onto the flexion axis: the point of the axis closest to
    the femur's long axis, the line from the hip centre to the anatomical knee centre (both
    (F, 3), taken into the thigh cluster's frame as medians over the frames), placed in every
    frame by both clusters (CGM 2.x's SARA knee). Also returns how far (mm) it lies from the
    anatomical knee centre in the thigh's frame."""
    hip_local, knee_local = axis.in_proximal(hip), axis.in_proximal(knee)
    femur = (knee_local - hip_local) / np.linalg.norm(knee_local - hip_local)
    a = axis.direction[:3]
    # closest point of the axis ``c + s a`` to the line ``h + u femur`` (|a| = |femur| = 1)
    w = axis.point[:3] - hip_local
    along = float(a @ femur)
    s = (along * (femur @ w) - a @ w) / max(1.0 - along**2, 1e-12)
    local = axis.point + s * axis.direction
    return axis.place(local), float(np.linalg.norm(local[:3] - knee_local))


#: the knee flexion range (degrees, 5th to 95th percentile over the take) from which the SARA
#: axis places the knee: SARA's axis is only as good as the range of motion it sees (Ehrig et
#: al. 2007); a walk flexes the knee by about 60 degrees, a static trial by none
SARA_MIN_FLEXION = 30.0


def flexion_range(hjc: np.ndarray, kjc: np.ndarray, ajc: np.ndarray) -> float:
    """The knee's flexion range over the take, degrees: the 5th to 95th percentile of the angle
    between the thigh (hip to knee centre) and the shank (knee to ankle centre), each (F, 3)."""
    thigh, shank = _unit(kjc - hjc), _unit(ajc - kjc)
    angle = np.degrees(np.arccos(np.clip(np.sum(thigh * shank, axis=1), -1.0, 1.0)))
    angle = angle[np.isfinite(angle)]
    return float(np.ptp(np.percentile(angle, [5, 95]))) if angle.size else 0.0


def knee_on_axis(thigh: list, shank: list, hjc: np.ndarray, kjc: np.ndarray, ajc: np.ndarray):
    """The knee centre (F, 3) moved onto the knee's flexion axis (:func:`knee_on_flexion_axis`)
    and its distance from the anatomical one (mm), or None: when thigh or shank has fewer than
    three cluster markers (trajectories (F, 3) each), or the frames where both clusters are
    seen flex the knee (by the centres ``hjc``, ``kjc``, ``ajc``) by less than
    :data:`SARA_MIN_FLEXION` degrees. The skin over the femoral epicondyles can lie off the
    axis the knee turns about (walking5's right knee: 25 mm), and a ball joint at the
    epicondyle mid-point then cannot follow both thigh and shank markers as the knee flexes."""
    if min(len(thigh), len(shank)) < 3:
        return None
    axis = flexion_axis(np.stack(thigh, 1), np.stack(shank, 1))
    if axis is None or flexion_range(hjc[axis.ok], kjc[axis.ok], ajc[axis.ok]) < SARA_MIN_FLEXION:
        return None
    return knee_on_flexion_axis(axis, hjc, kjc)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def most_seen(trajectories: list[np.ndarray]) -> np.ndarray:
    """The trajectory (F, 3) seen in the most frames (the first of equals)."""
    seen = [int(np.isfinite(x).all(axis=1).sum()) for x in trajectories]
    return trajectories[int(np.argmax(seen))]


def fill_from_cluster(centre: np.ndarray, cluster: list[np.ndarray]) -> np.ndarray:
    """A joint centre (F, 3) filled, where it is NaN, from markers rigid with the same segment.

    Labs place medial markers for a static trial and take them off (the shared walking5 file
    and its TRC lack them in most frames). The cluster (K trajectories (F, 3), K >= 3) is
    fitted by least squares (:func:`core.markers.procrustes.fit_rigid`) to its pose in the
    first frame where all of it is seen; the centre's place in the cluster's frame is the
    median over the frames where both are seen, and it is carried to the frames where the
    centre is missing and at least three cluster markers are seen.
    """
    missing = ~np.isfinite(centre).all(axis=1)
    if not missing.any() or len(cluster) < 3:
        return centre
    points = np.stack(cluster, axis=1)
    complete = np.flatnonzero(np.isfinite(points).all(axis=(1, 2)))
    if complete.size == 0:
        return centre
    template = points[complete[0]]
    rotations, translations, _, ok = fit_rigid(template, points)
    local = np.einsum("fba,fb->fa", rotations, centre - translations)
    seen = ok & ~missing
    if not seen.any():
        return centre
    offset = np.median(local[seen], axis=0)
    fill = missing & ok
    out = centre.copy()
    out[fill] = np.einsum("fab,b->fa", rotations[fill], offset) + translations[fill]
    return out
