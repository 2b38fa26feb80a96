"""The best-matching pose of a reference motion for every query frame, all frames at once.

Matching metric. A pose is described by its measured joints in the frame of its pelvis:
``x_j = R_pelvis^T (P_j - P_root)`` (so neither where the subject stands nor which way it
faces matters). The distance between a query frame f and a reference frame g is the mean
over the joints measured in f of ``|x_fj - y_gj|^2`` (its square root is the RMS joint
distance reported). The pelvis rotation of both sides comes from the same Procrustes fit of
the same three joints, so the two descriptions are directly comparable.

Search. Distance matrices are computed in chunks of query frames with
``|x|^2 + |y|^2 - 2 x.y`` (three matrix products; a chunk holds at most ``CHUNK_ELEMENTS``
distances), the few best candidates of each query frame are then re-measured exactly (the
expanded form loses precision near zero), and among candidates equally near (within
rounding) the one closest in time to the query wins: when the reference is the query's own
trial with nothing excluded, that is the query frame itself, whose distance is zero. With
``exclude_within`` seconds, reference frames that close in time to the query are not
candidates (the "twist from the same trial" experiment).

:func:`reference_poses` prepares a reference motion for both (its poses in the skeleton's
joint order, their pelvis-frame features, its root-from-pelvis rotations and times).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import joint_world_transform, world_positions
from gmr_studio.core.markers.pelvis import pelvis_rotations
from gmr_studio.core.model.motion import Motion

#: distances held at once: chunks of query frames x all reference frames
CHUNK_ELEMENTS = 4_000_000
#: candidates per query frame re-measured exactly
CANDIDATES = 4
#: distances within this fraction of the features' squared size count as ties (rounding)
TIE_RELATIVE = 1e-20


def best_matches(
    query: np.ndarray,
    present: np.ndarray,
    reference: np.ndarray,
    *,
    query_times: np.ndarray,
    reference_times: np.ndarray,
    exclude_within: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """For each query frame, the reference frame nearest in the metric above.

    Parameters
    ----------
    query : (F, K, 3) pelvis-frame joint positions of the query (anything where absent).
    present : (F, K) bool, the joints measured in each query frame.
    reference : (G, K, 3) the same joints for the reference frames (all finite).
    query_times, reference_times : (F,), (G,) seconds on a common clock (used for the
        exclusion and to break ties).
    exclude_within : seconds; reference frames with ``|t_g - t_f| <= exclude_within`` are
        not candidates (None: all are).

    Returns
    -------
    index : (F,) int64, the best reference frame, -1 where the query has no measured joint
        or every reference frame is excluded.
    distance : (F,) float64, its RMS joint distance (NaN where index is -1).
    """
    n_query, n_joints = present.shape
    n_reference = reference.shape[0]
    index = np.full(n_query, -1, np.int64)
    distance = np.full(n_query, np.nan)
    if n_reference == 0 or n_query == 0:
        return index, distance
    weight = present.astype(np.float64)
    count = weight.sum(axis=1)
    q = np.where(present[..., None], np.asarray(query, dtype=np.float64), 0.0)
    r = np.asarray(reference, dtype=np.float64)
    r_flat = r.reshape(n_reference, 3 * n_joints)
    r_squares = np.sum(r * r, axis=2)  # (G, K)
    chunk = max(1, CHUNK_ELEMENTS // n_reference)
    k = min(CANDIDATES, n_reference)
    for start in range(0, n_query, chunk):
        rows = slice(start, min(start + chunk, n_query))
        qc = q[rows]
        squares = np.sum(qc * qc, axis=(1, 2))
        d = squares[:, None] + weight[rows] @ r_squares.T - 2.0 * (qc.reshape(len(qc), -1) @ r_flat.T)
        gap = np.abs(query_times[rows, None] - reference_times[None, :])
        if exclude_within is not None:
            d[gap <= exclude_within] = np.inf
        candidates = np.argpartition(d, k - 1, axis=1)[:, :k] if k < n_reference else np.tile(np.arange(k), (len(d), 1))
        allowed = np.isfinite(np.take_along_axis(d, candidates, axis=1))
        diff = qc[:, None] - r[candidates] * present[rows, None, :, None]
        exact = np.sum(diff * diff, axis=(2, 3))
        exact[~allowed] = np.inf
        best = exact.min(axis=1, keepdims=True)
        tie = exact <= best + TIE_RELATIVE * np.maximum(squares, 1e-300)[:, None]
        closeness = np.where(tie, np.take_along_axis(gap, candidates, axis=1), np.inf)
        pick = np.argmin(closeness, axis=1)
        chosen = candidates[np.arange(len(pick)), pick]
        ok = np.isfinite(best[:, 0]) & (count[rows] > 0)
        index[rows] = np.where(ok, chosen, -1)
        distance[rows] = np.where(ok, np.sqrt(best[:, 0] / np.maximum(count[rows], 1)), np.nan)
    return index, distance


def reference_poses(reference: Motion | None, skeleton: Motion, triple_index, home, pelvis_method):
    """What the solver matches against in a reference motion (None: None): local rotations
    (G, J, 3, 3) in skeleton joint order, pelvis-frame positions (G, J, 3), root-from-pelvis
    rotations (G, 3, 3) and times (G,)."""
    if reference is None:
        return None
    missing = [n for n in skeleton.names if n not in reference.names]
    if missing:
        raise OperationError(
            f"the reference motion is not of the skeleton: it lacks the joints {', '.join(missing[:6])}"
            + (" ..." if len(missing) > 6 else "")
        )
    order = [reference.joint_index(n) for n in skeleton.names]
    if reference.n_frames == 0:
        raise OperationError("the reference motion has no frames")
    positions, local = world_positions(reference)[:, order], reference.rotations[:, order]
    rotations, _, valid, reasons = pelvis_rotations(positions[:, triple_index], home, method=pelvis_method)
    if not valid.all():
        raise OperationError("the reference motion's own pelvis is degenerate: " + "; ".join(reasons))
    root = triple_index[0]
    features = np.einsum("fba,fjb->fja", rotations, positions - positions[:, root : root + 1])
    correction = np.swapaxes(rotations, -1, -2) @ joint_world_transform(reference, order[root])[0]
    return local, features, correction, np.arange(reference.n_frames) * reference.frame_time
