"""Global refinement after the closed form: per-frame least squares over the joint angles.

As OpenSim's inverse kinematics does, every frame minimises
``sum_m w_m |x_m(q) - y_m|^2``: ``y_m`` the measured markers (F, M, 3), ``x_m(q)`` the same
markers carried by the skeleton (bone lengths fixed) at joint angles q. A marker rides on one
bone: the bone ending at joint j (pre-rotation, its world frame ``W_j``), from the bone's start
``q_j = P_p(j)`` (the root's own position for the root): ``x_m = q_j + W_j o_m`` with a
constant local offset ``o_m`` (:func:`attach_markers`: the median over the frames of the
seed motion; a joint centre is the marker ``o = t_j`` itself).

The unknowns per frame are the root translation and a small rotation ``d_k`` of every joint
that carries a marker or an ancestor of one, ``R_k <- R_k exp([d_k])``. Turning joint k by
``d`` turns everything below it about the start of its bone, about the world axis ``W_k d``,
so the Jacobian is analytic: ``dx_m/dd_k = -[x_m - q_k]_x W_k`` for every k on the path from
the root to m's bone, ``dx_m/dG = I``. Levenberg-Marquardt steps
``(J^T W J + lambda diag(J^T W J) + mu I) d = J^T W r`` are solved for all frames at once
(batched ``numpy.linalg.solve`` over chunks of frames); a frame keeps a step only when its cost
goes down, else its lambda grows ten-fold. The closed form is the seed, so a few iterations do.
"""

from __future__ import annotations

import dataclasses
from contextlib import contextmanager

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.limbs import cross_matrix
from gmr_studio.core.model.motion import Motion

CHUNK = 1024  # frames per batched solve (memory: CHUNK x 3M x 3K floats)


@dataclasses.dataclass(frozen=True, eq=False)
class Refinement:
    """The refined motion and its fit.

    motion : the refined GMR motion (same skeleton, bone lengths unchanged).
    residuals : (F, M) distance of each marker from its place on the skeleton after the
        refinement (NaN where the marker is missing); residuals_before (F, M) the seed's.
    iterations : Levenberg-Marquardt iterations run.
    """

    motion: Motion
    residuals: np.ndarray
    residuals_before: np.ndarray
    iterations: int


def rotation_from_vector(v: np.ndarray) -> np.ndarray:
    """``exp([v]_x)``: (..., 3) rotation vectors -> (..., 3, 3) (Rodrigues; exact at 0)."""
    angle = np.linalg.norm(v, axis=-1)[..., None, None]
    k = cross_matrix(v)
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    a = np.where(small, 1.0 - angle**2 / 6, np.sin(safe) / safe)
    b = np.where(small, 0.5 - angle**2 / 24, (1.0 - np.cos(safe)) / safe**2)
    return np.eye(3) + a * k + b * (k @ k)


def _openblas():
    """numpy's bundled OpenBLAS as a ctypes library with its thread-count functions, or None."""
    import ctypes
    from pathlib import Path

    folder = Path(np.__file__).resolve().parent.parent / "numpy.libs"
    for path in sorted(folder.glob("*openblas*.so*")):
        try:
            library = ctypes.CDLL(str(path))
        except OSError:
            continue
        for suffix in ("scipy_openblas_%s_num_threads64_", "openblas_%s_num_threads64_", "openblas_%s_num_threads"):
            setter, getter = getattr(library, suffix % "set", None), getattr(library, suffix % "get", None)
            if setter is not None and getter is not None:
                return setter, getter
    return None


@contextmanager
def one_blas_thread():
    """Run LAPACK on one thread for the block: ``numpy.linalg.solve`` on a stack of small
    systems lets OpenBLAS wake its thread pool for each one, which makes the refinement many
    times slower where cores are shared. Does nothing where numpy's OpenBLAS is not found."""
    functions = _openblas()
    if functions is None:
        yield
        return
    setter, getter = functions
    before = getter()
    setter(1)
    try:
        yield
    finally:
        setter(before)


def _fk(motion: Motion, rotations: np.ndarray, root_position: np.ndarray):
    """World rotations (F, J, 3, 3) and positions (F, J, 3) of a one-root pre-rotation motion."""
    world = np.empty_like(rotations)
    positions = np.empty((*rotations.shape[:2], 3))
    for j in motion.topological_order:
        p = int(motion.parents[j])
        if p < 0:
            world[:, j], positions[:, j] = rotations[:, j], root_position
        else:
            world[:, j] = world[:, p] @ rotations[:, j]
            positions[:, j] = positions[:, p] + world[:, j] @ motion.offsets[j]
    return world, positions


def _pivots(motion: Motion, positions: np.ndarray) -> np.ndarray:
    """(F, J, 3): the start of each joint's bone (the root: its own position)."""
    parent = np.where(motion.parents < 0, np.arange(motion.n_joints), motion.parents)
    return positions[:, parent]


def _check(motion: Motion) -> None:
    if motion.convention != "pre" or len(motion.roots) != 1 or motion.has_translation.sum() != 1:
        raise OperationError("the refinement needs a GMR motion with one root and no other translated joint")


def attach_markers(motion: Motion, targets: np.ndarray, bones: np.ndarray) -> np.ndarray:
    """Local offsets (M, 3) of markers (F, M, 3) on bones (M,) (joint indices), from the motion:
    the median over the frames of ``W_j^T (y_m - q_j)``."""
    _check(motion)
    root = int(motion.roots[0])
    world, positions = _fk(motion, motion.rotations, motion.translations[:, root])
    local = np.einsum("fmba,fmb->fma", world[:, bones], targets - _pivots(motion, positions)[:, bones])
    return np.nanmedian(local, axis=0)


def marker_places(motion: Motion, bones: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """(F, M, 3) where the skeleton carries each marker."""
    root = int(motion.roots[0])
    world, positions = _fk(motion, motion.rotations, motion.translations[:, root])
    return _pivots(motion, positions)[:, bones] + np.einsum("fmab,mb->fma", world[:, bones], offsets)


def refine_motion(
    motion: Motion,
    targets: np.ndarray,
    bones: np.ndarray,
    offsets: np.ndarray,
    weights: np.ndarray | None = None,
    iterations: int = 5,
    fixed: tuple[int, ...] = (),
) -> Refinement:
    """Refine ``motion`` (the seed, F frames) towards the markers ``targets`` (F, M, 3; NaN
    missing) riding on ``bones`` (M,) at ``offsets`` (M, 3), with ``weights`` (M,) (default 1).
    Joints in ``fixed`` keep their local rotations (bones rigid with their parent, such as the
    pelvis-to-hip bones of a built skeleton). See the module docstring."""
    _check(motion)
    targets = np.asarray(targets, dtype=np.float64)
    bones = np.asarray(bones, dtype=np.int64)
    n_frames, n_markers = targets.shape[:2]
    weights = np.ones(n_markers) if weights is None else np.asarray(weights, dtype=np.float64)
    root = int(motion.roots[0])
    ancestors = np.zeros((n_markers, motion.n_joints), bool)  # joint k moves marker m
    for m, j in enumerate(bones):
        k = int(j)
        while k >= 0:
            ancestors[m, k] = True
            k = int(motion.parents[k])
    ancestors[:, list(fixed)] = False
    active = np.flatnonzero(ancestors.any(axis=0))
    rotations = motion.rotations.copy()
    translation = motion.translations[:, root].copy()
    places = marker_places(motion, bones, offsets)
    before = np.linalg.norm(places - targets, axis=2)
    for start in range(0, n_frames, CHUNK):
        chunk = slice(start, min(start + CHUNK, n_frames))
        rotations[chunk], translation[chunk] = _solve_chunk(
            motion, rotations[chunk], translation[chunk], targets[chunk], bones, offsets, weights,
            ancestors[:, active], active, iterations,
        )  # fmt: skip
    translations = motion.translations.copy()
    translations[:, root] = translation
    refined = motion.replace(rotations=rotations, translations=translations)
    after = np.linalg.norm(marker_places(refined, bones, offsets) - targets, axis=2)
    return Refinement(refined, after, before, iterations)


def _solve_chunk(motion, rotations, translation, targets, bones, offsets, weights, moves, active, iterations):
    present = np.isfinite(targets).all(axis=2)
    w = np.where(present, weights[None], 0.0)  # (F, M)
    n_frames = len(present)
    n_active = len(active)
    size = 3 + 3 * n_active
    position = {int(k): a for a, k in enumerate(active)}
    # the active joint each active joint's subtree sums pass to (its nearest active ancestor)
    order = [int(k) for k in motion.topological_order if int(k) in position]
    up = {}
    for k in order:
        p = int(motion.parents[k])
        while p >= 0 and p not in position:
            p = int(motion.parents[p])
        up[k] = p
    owner = np.array([position[_active_at(motion, int(j), position)] for j in bones])
    lam = np.full(n_frames, 1e-3)
    eye = np.eye(3)
    pairs = [
        (a, b, position[d])
        for a in range(n_active)
        for b in range(a, n_active)
        if (d := _deeper(motion, int(active[a]), int(active[b]))) is not None
    ]
    pair_a, pair_b, pair_d = (np.array(column, dtype=np.int64) for column in zip(*pairs))
    three = np.arange(3)
    rows_ab = 3 + 3 * pair_a[:, None, None] + three[None, :, None]
    cols_ab = 3 + 3 * pair_b[:, None, None] + three[None, None, :]
    rows_ba, cols_ba = cols_ab.transpose(0, 2, 1), rows_ab.transpose(0, 2, 1)

    def evaluate(rot, trans):
        world, positions = _fk(motion, rot, trans)
        pivots = _pivots(motion, positions)
        x = pivots[:, bones] + np.einsum("fmab,mb->fma", world[:, bones], offsets)
        r = np.where(present[..., None], targets - x, 0.0)
        return world, pivots, x, r, np.einsum("fm,fma,fma->f", w, r, r)

    def subtree_sums(values):
        """(F, M, ...) per marker -> (F, K, ...) summed over each active joint's subtree."""
        out = np.zeros((n_frames, n_active, *values.shape[2:]))
        for m_owner in np.unique(owner):
            out[:, m_owner] = values[:, owner == m_owner].sum(axis=1)
        for k in reversed(order):
            if up[k] >= 0:
                out[:, position[up[k]]] += out[:, position[k]]
        return out

    world, pivots, x, r, cost = evaluate(rotations, translation)
    for _ in range(iterations):
        wx = w[..., None] * x
        total_w = subtree_sums(w)  # (F, K)
        s = subtree_sums(wx)  # (F, K, 3)
        second = subtree_sums(np.einsum("fma,fmb->fmab", wx, x))  # (F, K, 3, 3)
        wr = w[..., None] * r
        r_sum = subtree_sums(wr)
        xr = subtree_sums(np.cross(x, wr))
        q = pivots[:, active]  # (F, K, 3)
        system = np.zeros((n_frames, size, size))
        system[:, :3, :3] = w.sum(axis=1)[:, None, None] * eye
        lever = cross_matrix(s - total_w[..., None] * q)  # [sum of w (x - q_a) over subtree(a)]_x
        system[:, :3, 3:] = -lever.transpose(0, 2, 1, 3).reshape(n_frames, 3, -1)
        system[:, 3:, :3] = lever.reshape(n_frames, -1, 3)
        qa, qb, sd = q[:, pair_a], q[:, pair_b], s[:, pair_d]
        # M = sum w (x - q_b)(x - q_a)^T over the deeper joint's subtree; block = tr(M) I - M
        m = (
            second[:, pair_d]
            - sd[..., :, None] * qa[..., None, :]
            - qb[..., :, None] * sd[..., None, :]
            + total_w[:, pair_d, None, None] * qb[..., :, None] * qa[..., None, :]
        )
        block = np.trace(m, axis1=-2, axis2=-1)[..., None, None] * eye - m
        system[:, rows_ab, cols_ab] = block
        system[:, rows_ba, cols_ba] = np.swapaxes(block, -1, -2)
        rhs = np.concatenate([wr.sum(axis=1), (xr - np.cross(q, r_sum)).reshape(n_frames, -1)], axis=1)
        diagonal = np.einsum("fjj->fj", system)
        damping = lam[:, None] * diagonal + 1e-9 * (1.0 + diagonal.max(axis=1, keepdims=True))
        system[:, np.arange(size), np.arange(size)] += damping
        with one_blas_thread():
            step = np.linalg.solve(system, rhs[..., None])[..., 0]
        omega = step[:, 3:].reshape(n_frames, n_active, 3)  # world axes
        local = np.einsum("fkba,fkb->fka", world[:, active], omega)
        trial_rot = rotations.copy()
        trial_rot[:, active] = rotations[:, active] @ rotation_from_vector(local)
        trial_trans = translation + step[:, :3]
        t_world, t_pivots, t_x, t_r, t_cost = evaluate(trial_rot, trial_trans)
        better = t_cost < cost
        rotations = np.where(better[:, None, None, None], trial_rot, rotations)
        translation = np.where(better[:, None], trial_trans, translation)
        world = np.where(better[:, None, None, None], t_world, world)
        pivots = np.where(better[:, None, None], t_pivots, pivots)
        x = np.where(better[:, None, None], t_x, x)
        r = np.where(better[:, None, None], t_r, r)
        cost = np.where(better, t_cost, cost)
        lam = np.where(better, lam * 0.3, lam * 10.0)
    return rotations, translation


def _active_at(motion: Motion, joint: int, position: dict[int, int]) -> int:
    """The joint itself, or its nearest ancestor with a free rotation (the root always is)."""
    while joint not in position:
        joint = int(motion.parents[joint])
    return joint


def _deeper(motion: Motion, a: int, b: int) -> int | None:
    """The deeper of two joints when one is an ancestor of (or equal to) the other, else None."""
    k = b
    while k >= 0:
        if k == a:
            return b
        k = int(motion.parents[k])
    k = a
    while k >= 0:
        if k == b:
            return a
        k = int(motion.parents[k])
    return None


def refine_joints(
    motion: Motion, measured: np.ndarray, iterations: int = 5, fitted: bool = False, weights: np.ndarray | None = None
) -> Refinement:
    """Refine towards measured joint centres (F, J, 3; NaN: not measured), each a marker at
    its own joint (bone j, offset ``t_j``): the refinement of a motion onto a given skeleton
    (the residuals are then per joint)."""
    _check(motion)
    measured = np.asarray(measured, dtype=np.float64)
    root = int(motion.roots[0])
    joints = np.array([j for j in range(motion.n_joints) if np.isfinite(measured[:, j]).any()], dtype=np.int64)
    offsets = np.where((joints == root)[:, None], 0.0, motion.offsets[joints])
    if fitted:
        offsets = attach_markers(motion, measured[:, joints], joints)
    w = None if weights is None else np.asarray(weights, dtype=np.float64)[joints]
    result = refine_motion(motion, measured[:, joints], joints, offsets, w, iterations=iterations)
    full_after = np.full(measured.shape[:2], np.nan)
    full_before = np.full(measured.shape[:2], np.nan)
    full_after[:, joints], full_before[:, joints] = result.residuals, result.residuals_before
    return Refinement(result.motion, full_after, full_before, iterations)
