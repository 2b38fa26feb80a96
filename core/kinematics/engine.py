"""The tuned forward-kinematics engine: world positions (and rotations) of any forest.

Same results as the reference :mod:`core.kinematics.fk` (to rounding), for both conventions.
With ``W`` the world rotation and ``P`` the world position:

- root r:          ``P_r = t_r`` (a copy; ``W_r = R_r`` only when someone needs it)
- pre (GMR):       ``W_j = W_p R_j``,  ``P_j = P_p + W_j t_j``
- post (BVH):      ``W_j = W_p R_j``,  ``P_j = P_p + W_p t_j``

Two backends compute exactly the same floating-point operations in the same order, so
their results are bitwise identical (tested): a compiled kernel (numba, optional) and a
pure-numpy path. Both start from the :class:`~core.model.motion.Motion` arrays as they are, the
rotations cached at load as ``(F, J, 3, 3)`` matrices. :func:`positions_from_euler` starts
from the Euler angles instead (what a file stores) and turns them into matrices on the fly.

Choices (``gmr bench`` times them; docs/benchmark.md):

- **A compiled kernel, frame-major.** numpy's batched 3x3 matmul costs about the same per
  joint however it is batched, so a per-joint numpy loop is bound by call overhead. The
  numba kernel walks each frame's joints with the world rotations of one frame in a small
  scratch that stays in L1, reading the rotations once, in the order they are stored
  (frame-major, the Motion layout). It keeps each world rotation by columns, 4-lane
  vectors, so that a column of ``W_p R_j`` is three vector products and two sums (SIMD
  within a frame, the same operations per lane). It indexes the frame arrays flat, joint
  j of frame f at row ``f J + j``: no per-frame array views (each costs reference
  counting and stride arithmetic), and no check of each index for numba's negative-index
  wraparound (the indices never are negative). Tried and dropped: joint-major component
  planes so that LLVM vectorises across frames (the transposes cost more than SIMD saves);
  several frames interleaved in one joint loop; a breadth-first walk; a copy of the walk
  per convention and output, the roots handled before the step loop, or per-step offsets
  precomputed in the step table (none pays for its code); fused multiply-add (it would
  break the bitwise equality below).
- **Memory order of the walk.** A depth-first walk from a new root (after shift root) jumps
  back and forth in the frame's memory and the hardware prefetchers stop following. The
  kernel walks parents before children and otherwise by increasing index (a min-heap
  topological order), which is plain memory order for a file's own root; for any other
  order it first copies, in memory order, the rotations it will read and the frame's
  translations into an L1 scratch (``staged``). Staging is skipped for a walk already in
  memory order. Touching the frame's cache lines instead of copying them was slower.
- **Known weak spot: many roots, a few scattered non-roots**: the few rotations read are
  sparse in each frame's memory and the prefetchers do not follow. A software prefetch (an
  ``llvm.prefetch`` numba intrinsic) helps those forests but slows every other one and ties
  the code to LLVM's intrinsic names: not adopted.
- **Matrices, not quaternions.** The Motion stores matrices (see core/model/motion.py); a
  quaternion kernel would first have to convert them, a pass costing more than the FK.
- **float64 throughout**: the operations promise 1e-9 of the size over chains of edits,
  and the kernel is bound by arithmetic latency and memory order, not by bytes.
- **Leaves skip their world rotation** (pre-rotation): ``P_j = P_p + W_p (R_j t_j)``,
  18 multiplications instead of 36 and no store; post-rotation leaves never read their
  rotation. Roots with world coordinates cost one copy of their translation, and a
  forest of roots only (fully translational) is one array copy: the positions are the data.
- **numba is optional** (the ``fast`` extra; ``bench`` includes it). Each kernel compiles
  once and ``cache=True`` keeps the machine code on disk. Without numba the numpy backend
  below (per depth level, frames in blocks laid out joint-major with frames last so that
  every ufunc runs over long rows) gives the same bits: numba compiles without fast-math,
  so ``a*b + c`` rounds twice as in numpy, and both sum ``(a0 b0 + a1 b1) + a2 b2`` in that
  order (tested bitwise on random forests). ``GMR_DISABLE_NUMBA=1`` forces the numpy backend.
- **Threads on request.** The kernels release the GIL, so ``threads=N`` splits the frames
  into N blocks computed at once (each with its own scratch; same bits). The default is
  one thread: the benchmark compares against a single-threaded copy, and reports the
  threaded figure beside it. The app asks for all cores when it caches a motion.
- **Memory**: positions only, the kernel allocates the (F, J, 3) output and nothing of
  size F; with world rotations, one more (F, J, 3, 3) array. The numpy backend holds a
  few blocks of 1024 frames.
"""

from __future__ import annotations

import dataclasses
import heapq
import itertools
import os

import numpy as np

from gmr_studio.core.compiled import Backend, chosen_kernels, optional_kernels
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import _indices_and_parity, complete_order

_kernels = optional_kernels("gmr_studio.core.kinematics._kernels")

#: joint kinds in a :class:`FKPlan`
ROOT, INNER, LEAF = 0, 1, 2
#: frames per block in the numpy backend (its temporaries stay in the L2 cache)
NUMPY_CHUNK_FRAMES = 1024


def have_numba() -> bool:
    """True when the compiled kernels can be used."""
    return _kernels is not None


def _resolve(backend: Backend) -> str:
    return "numpy" if chosen_kernels(backend, _kernels) is None else "numba"


@dataclasses.dataclass(frozen=True)
class FKPlan:
    """What the kernels need to know about a forest, as small arrays.

    order : (J,) int64, every joint after its parent, and otherwise by increasing index
        (the most ascending walk through a frame's memory; see ``staged``).
    parents : (J,) int64, -1 for roots.
    kinds : (J,) int8, ROOT, INNER (has children) or LEAF (no children: its world
        rotation is computed only when ``keep_world``).
    keep_root : (J,) bool, the roots whose world rotation (their local one) is kept:
        those with children, or all when ``keep_world``.
    keep_world : the caller wants every joint's world rotation.
    pre : True for pre-rotation (GMR), False for post-rotation (BVH).
    staged : (S,) int64, increasing: the joints whose rotations the compiled kernel first
        copies, each frame, into a small scratch in memory order (with the frame's
        translations), because the walk reads them out of memory order (see the module
        docstring); empty when the walk reads them in order.
    """

    order: np.ndarray
    parents: np.ndarray
    kinds: np.ndarray
    keep_root: np.ndarray
    keep_world: bool
    pre: bool
    staged: np.ndarray

    @classmethod
    def of(cls, motion: Motion, with_rotations: bool) -> FKPlan:
        parents = np.ascontiguousarray(motion.parents, dtype=np.int64)
        has_children = np.zeros(motion.n_joints, bool)
        has_children[parents[parents >= 0]] = True
        kinds = np.where(has_children, INNER, LEAF).astype(np.int8)
        kinds[parents < 0] = ROOT
        keep_root = (parents < 0) & (has_children | with_rotations)
        order = _ascending_topological_order(parents, motion.children)
        plan = cls(order, parents, kinds, keep_root, with_rotations, motion.convention == "pre", np.zeros(0, np.int64))
        read = plan.needs_rotation()
        walk = order[read[order]]
        if np.any(np.diff(walk) < 0):
            plan = dataclasses.replace(plan, staged=np.flatnonzero(read).astype(np.int64))
        return plan

    def needs_rotation(self) -> np.ndarray:
        """(J,) bool: the joints whose local rotation is read."""
        if self.pre or self.keep_world:
            return (self.kinds != ROOT) | self.keep_root
        return (self.kinds == INNER) | self.keep_root


def _ascending_topological_order(parents: np.ndarray, children: tuple[tuple[int, ...], ...]) -> np.ndarray:
    """(J,) int64: parents before children, otherwise the smallest index first."""
    ready = [int(j) for j in np.flatnonzero(parents < 0)]
    heapq.heapify(ready)
    order = []
    while ready:
        j = heapq.heappop(ready)
        order.append(j)
        for child in children[j]:
            heapq.heappush(ready, child)
    return np.asarray(order, dtype=np.int64)


def forward_kinematics(
    motion: Motion, *, with_rotations: bool = True, backend: Backend = "auto", threads: int | None = 1
) -> tuple[np.ndarray, np.ndarray | None]:
    """World positions and (optionally) world rotations of every joint for every frame.

    Parameters
    ----------
    motion : any forest, either convention.
    with_rotations : also return the world rotations (one more (F, J, 3, 3) array).
    backend : 'numba' (compiled), 'numpy', or 'auto' (numba when installed). Both give
        bitwise identical results.
    threads : with the compiled backend, blocks of frames computed at once (None: one per
        core); the result does not depend on it.

    Returns
    -------
    positions : (F, J, 3) float64
    rotations : (F, J, 3, 3) float64, or None when ``with_rotations`` is False.
    """
    plan = FKPlan.of(motion, with_rotations)
    rotations = np.ascontiguousarray(motion.rotations)
    translations = np.ascontiguousarray(motion.translations)
    n_frames, n_joints = motion.n_frames, motion.n_joints
    positions = np.empty((n_frames, n_joints, 3))
    world = np.empty((n_frames, n_joints, 3, 3)) if with_rotations else None
    if n_frames == 0:
        return positions, world
    backend = _resolve(backend)
    if not np.any(plan.parents >= 0):  # fully translational: the positions are the data
        np.copyto(positions, translations)
        if world is not None:
            np.copyto(world, rotations)
        return positions, world
    if backend == "numba":

        def block(frames: slice) -> None:
            scratch = world[frames] if world is not None else np.empty((1, n_joints, 3, 3))
            _kernels.fk_matrices(
                rotations[frames],
                translations[frames],
                plan.order,
                plan.parents,
                plan.kinds,
                plan.keep_root,
                plan.keep_world,
                plan.pre,
                plan.staged,
                positions[frames],
                scratch,
                np.empty((n_joints, 3, 3)),
                np.empty((n_joints, 3)),
            )

        in_blocks(block, n_frames, threads)
    else:
        _numpy_fk(rotations, translations, plan, positions, world)
    return positions, world


def world_positions(motion: Motion, *, backend: Backend = "auto", threads: int | None = 1) -> np.ndarray:
    """(F, J, 3) world positions of every joint."""
    return forward_kinematics(motion, with_rotations=False, backend=backend, threads=threads)[0]


#: fewer frames than this per thread are not worth a thread
MIN_FRAMES_PER_THREAD = 4096


def thread_count(n_frames: int, threads: int | None, *, align: int = 1) -> int:
    """How many threads work on ``n_frames`` frames when ``threads`` are asked for (None: one
    per core): at most one per :data:`MIN_FRAMES_PER_THREAD` frames (or ``align``, if more)."""
    count = (os.cpu_count() or 1) if threads is None else max(1, int(threads))
    return min(count, max(1, n_frames // max(MIN_FRAMES_PER_THREAD, align)))


def in_blocks(work, n_frames: int, threads: int | None, *, align: int = 1) -> None:
    """``work(frames)`` over consecutive blocks of frames, on up to ``threads`` threads
    (None: one per core; :func:`thread_count`); every block but the last starts and ends on
    a multiple of ``align`` frames."""
    count = thread_count(n_frames, threads, align=align)
    if count == 1:
        work(slice(0, n_frames))
        return
    from concurrent.futures import ThreadPoolExecutor

    bounds = np.linspace(0, n_frames, count + 1).astype(int)
    bounds[1:-1] = bounds[1:-1] // align * align
    with ThreadPoolExecutor(max_workers=count) as pool:
        list(pool.map(work, [slice(a, b) for a, b in itertools.pairwise(bounds)]))


def gather_joints(array: np.ndarray, joints: np.ndarray, *, threads: int | None = 1) -> np.ndarray:
    """``array[:, joints]`` of a per-frame, per-joint array (F, J, ...): a new C-contiguous
    (F, len(joints), ...) array, computed in one pass over the frames by the compiled kernel
    (on ``threads`` threads, None: one per core) or by ``numpy.take``; the same numbers.
    numpy's ``take`` along the joints copies each joint's few numbers with a call of its own,
    several times slower than copying the array; the kernel runs at about a copy's speed."""
    joints = np.asarray(joints, dtype=np.int64)
    if _kernels is None or array.dtype != np.float64 or array.ndim < 2 or not array.shape[0] or not joints.size:
        return np.ascontiguousarray(np.take(array, joints, axis=1))
    source = np.ascontiguousarray(array)
    n_frames, width = source.shape[0], int(np.prod(source.shape[2:], dtype=np.int64))
    out = np.empty((n_frames, joints.size, *source.shape[2:]))
    rows, out_rows = source.reshape(n_frames, -1), out.reshape(n_frames, -1)

    def block(frames: slice) -> None:
        _kernels.gather_joints(rows, joints, width, frames.start, frames.stop, out_rows)

    in_blocks(block, n_frames, threads)
    return out


def signed_axes(turn: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(axes (3,) int64, signs (3,) float64) with ``turn[a, axes[a]] = signs[a]`` and every
    other entry 0 when ``turn`` (3, 3) is a signed permutation (an axis swap or reflection);
    None otherwise."""
    turn = np.asarray(turn, dtype=np.float64)
    axes = np.argmax(np.abs(turn), axis=1)
    signs = turn[np.arange(3), axes]
    exact = np.zeros((3, 3))
    exact[np.arange(3), axes] = signs
    if not (np.array_equal(np.abs(signs), np.ones(3)) and np.array_equal(exact, turn)):
        return None
    return axes.astype(np.int64), signs


def turned_joints(
    array: np.ndarray,
    joints: np.ndarray | None = None,
    *,
    rows: tuple[int, int] | None = None,
    turn: np.ndarray | None = None,
    scale: float = 1.0,
    shift: np.ndarray | None = None,
    backend: Backend = "auto",
    threads: int | None = 1,
) -> np.ndarray:
    """Vectors (F, J, 3) or matrices (F, J, 3, 3) of some rows and joints, in a turned world.

    The frames ``rows`` (first, stop) (None: all) and the joints ``joints`` (J',) (None: all,
    in order) of ``array``, each vector ``v`` becoming ``scale * turn @ v + shift[n]`` and each
    matrix ``M`` becoming ``turn @ M @ turn.T`` (``scale`` and ``shift`` are for vectors only).
    ``turn`` (3, 3): an orthogonal matrix (None: the identity); ``shift``: (J', 3) or (3,)
    (None: zero). Returns a new C-contiguous (F', J', ...) array.

    When ``turn`` is a signed permutation (an axis swap or reflection: up axis, mirror) the
    compiled kernel makes it in one pass over the frames (on ``threads``, None: one per core),
    with exactly the operations and results of the numpy path (``backend``: as for
    :func:`forward_kinematics`): ``turn @`` picks and signs entries, so the only rounding is
    the scale's product and the shift's sum. It reads each frame's joints in memory order
    and writes them where they go (a mirror's swapped sides, a new root's path).
    """
    first, stop = (0, array.shape[0]) if rows is None else (int(rows[0]), int(rows[1]))
    every = np.arange(array.shape[1])
    joints = every if joints is None else np.asarray(joints, dtype=np.int64)
    turn = np.eye(3) if turn is None else np.asarray(turn, dtype=np.float64)
    matrices = array.ndim == 4
    shift = np.zeros((joints.size, 3)) if shift is None else np.broadcast_to(np.asarray(shift, float), (joints.size, 3))
    signed = signed_axes(turn)
    n_frames = stop - first
    compiled = _resolve(backend) == "numba" and signed is not None and array.dtype == np.float64
    if not (compiled and n_frames and joints.size):
        return _turned_numpy(array[first:stop], joints, turn, scale, shift, matrices)
    source = np.ascontiguousarray(array)
    out = np.empty((n_frames, joints.size, *array.shape[2:]))
    axes, signs = signed
    if matrices:  # entry (a, b) of joint n: entry (axes[a], axes[b]) of joint joints[n], signed twice
        within = (3 * axes[:, None] + axes[None, :]).ravel()
        index = (9 * joints[:, None] + within).ravel()
        factor = np.tile(np.outer(signs, signs).ravel(), joints.size)
        flat_shift = np.zeros(index.size)
    else:
        index = (3 * joints[:, None] + axes).ravel()
        factor = np.tile(signs, joints.size)
        flat_shift = np.ascontiguousarray(shift, dtype=np.float64).ravel()
    place = _read_order(joints, index.size // joints.size)
    if place.size:
        index, factor, flat_shift = index[place], factor[place], flat_shift[place]
    rows, out_rows, scale = source.reshape(source.shape[0], -1), out.reshape(n_frames, -1), float(scale)

    def block(frames: slice) -> None:
        _kernels.signed_gather(
            rows, first, index, place, factor, scale, flat_shift, frames.start, frames.stop, out_rows
        )

    in_blocks(block, n_frames, threads)
    return out


def _read_order(joints: np.ndarray, width: int) -> np.ndarray:
    """(len(joints) * width,) int64: the output entries of ``joints`` (J',), ``width``
    numbers each, listed by increasing input joint (in output order within a joint and
    among repeats), so that a kernel reads each frame in memory order; empty when that is
    the output order already."""
    by_input = np.argsort(joints, kind="stable")
    if np.array_equal(by_input, np.arange(joints.size)):
        return np.zeros(0, np.int64)
    return (width * by_input[:, None] + np.arange(width)).ravel().astype(np.int64)


def _turned_numpy(
    array: np.ndarray, joints: np.ndarray, turn: np.ndarray, scale: float, shift: np.ndarray, matrices: bool
) -> np.ndarray:
    """:func:`turned_joints` by numpy (the reference), ``array`` already cut to its rows."""
    picked = np.take(array, joints, axis=1)
    if matrices:
        return np.ascontiguousarray(turn @ picked @ turn.T)
    out = picked @ turn.T
    out *= scale
    out += shift
    return out


# ------------------------------------------------------------------ from Euler angles
def euler_codes(orders: tuple[str, ...]) -> np.ndarray:
    """(J, 4) float64 rows ``(i, j, k, parity)`` of each joint's completed Euler order
    (see :func:`core.rotations.euler.matrix_from_euler`); ``""`` counts as 'XYZ' (its angles are 0)."""
    return np.array([_indices_and_parity(order or "XYZ") for order in orders], dtype=np.float64)


def euler_angles(motion: Motion, joints: np.ndarray | None = None) -> np.ndarray:
    """(F, J, 3) radians: each joint's local rotation as Euler angles in its completed
    rotation order (zeros for joints without rotation channels, and for joints left out
    of the (J,) bool mask ``joints``). For BVH files these are the channel values as
    stored (in radians; a joint's missing channels are 0)."""
    from gmr_studio.core.rotations.euler import euler_from_matrix

    angles = np.zeros((motion.n_frames, motion.n_joints, 3))
    by_order: dict[str, list[int]] = {}
    for j, order in enumerate(motion.rotation_orders):
        if order and (joints is None or joints[j]):
            by_order.setdefault(complete_order(order), []).append(j)
    for order, members in by_order.items():
        angles[:, members] = euler_from_matrix(motion.rotations[:, members], order)
    return angles


def positions_from_euler(
    motion: Motion, angles: np.ndarray, *, codes: np.ndarray | None = None, backend: Backend = "auto"
) -> np.ndarray:
    """World positions (F, J, 3) from Euler angles, converting only the rotations FK reads.

    The path that starts from what a file stores: ``motion`` gives the forest,
    translations and rotation orders (its rotation matrices are ignored); ``angles``
    (F, J, 3) radians are each joint's angles in its completed order (as
    :func:`euler_angles` returns). A root with world coordinates and no children, and a
    post-rotation leaf, convert nothing.
    """
    plan = FKPlan.of(motion, False)
    angles = np.ascontiguousarray(angles, dtype=np.float64)
    if angles.shape != (motion.n_frames, motion.n_joints, 3):
        raise ValueError(f"angles must have shape {(motion.n_frames, motion.n_joints, 3)}, not {angles.shape}")
    codes = euler_codes(motion.rotation_orders) if codes is None else codes
    translations = np.ascontiguousarray(motion.translations)
    positions = np.empty((motion.n_frames, motion.n_joints, 3))
    if motion.n_frames == 0:
        return positions
    backend = _resolve(backend)
    if not np.any(plan.parents >= 0):  # fully translational: no angle is read
        np.copyto(positions, translations)
        return positions
    needed = plan.needs_rotation()
    if backend == "numba":
        scratch = np.empty((1, motion.n_joints, 3, 3))
        _kernels.fk_euler(
            angles, codes, needed, translations, plan.order, plan.parents, plan.kinds, plan.keep_root, plan.pre,
            plan.staged.shape[0] > 0, positions, scratch, np.empty((motion.n_joints, 3)),
        )  # fmt: skip
        return positions
    from gmr_studio.core.rotations.euler import matrix_from_euler

    rotations = np.empty((motion.n_frames, motion.n_joints, 3, 3))
    rotations[:] = np.eye(3)
    for order in {complete_order(motion.rotation_orders[j] or "XYZ") for j in np.flatnonzero(needed)}:
        joints = [j for j in np.flatnonzero(needed) if complete_order(motion.rotation_orders[j] or "XYZ") == order]
        rotations[:, joints] = matrix_from_euler(angles[:, joints], order)
    _numpy_fk(rotations, translations, plan, positions, None)
    return positions


# ------------------------------------------------------------------- numpy backend
def _levels(plan: FKPlan) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Per depth level: (inner joints, their parents, leaf joints, their parents)."""
    depth = np.zeros(plan.parents.shape[0], np.int64)
    for j in plan.order:
        if plan.parents[j] >= 0:
            depth[j] = depth[plan.parents[j]] + 1
    levels = []
    for d in range(1, int(depth.max(initial=0)) + 1):
        at = plan.order[depth[plan.order] == d]
        inner = at[plan.kinds[at] == INNER]
        leaf = at[plan.kinds[at] == LEAF]
        levels.append((inner, plan.parents[inner], leaf, plan.parents[leaf]))
    return levels


def _times(matrices: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Planes: matrices (m, 3, 3, n) times vectors (m, 3, n) -> (m, 3, n), summed as
    ``(M[:, 0] v0 + M[:, 1] v1) + M[:, 2] v2`` (the kernel's order)."""
    return (matrices[:, :, 0] * vectors[:, None, 0] + matrices[:, :, 1] * vectors[:, None, 1]) + matrices[
        :, :, 2
    ] * vectors[:, None, 2]


def _product(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Planes: (m, 3, 3, n) @ (m, 3, 3, n) -> (m, 3, 3, n), summed in the kernel's order."""
    return (left[:, :, 0, None] * right[:, None, 0] + left[:, :, 1, None] * right[:, None, 1]) + left[
        :, :, 2, None
    ] * right[:, None, 2]


def _numpy_fk(
    rotations: np.ndarray, translations: np.ndarray, plan: FKPlan, positions: np.ndarray, world: np.ndarray | None
) -> None:
    """The numpy backend: per depth level, frames in blocks; fills positions (and world).

    Each block is turned joint-major with the frames last, ``(J, 3, 3, n)`` (component
    planes), so that every ufunc call runs over long contiguous rows of frames instead of
    3-element ones, where each call's overhead would outweigh its arithmetic.
    """
    n_frames, n_joints = rotations.shape[:2]
    roots = np.flatnonzero(plan.kinds == ROOT)
    kept_roots = np.flatnonzero(plan.keep_root)
    levels = _levels(plan)
    for start in range(0, n_frames, NUMPY_CHUNK_FRAMES):
        block = slice(start, min(start + NUMPY_CHUNK_FRAMES, n_frames))
        local = np.ascontiguousarray(rotations[block].transpose(1, 2, 3, 0))  # (J, 3, 3, n)
        offsets = np.ascontiguousarray(translations[block].transpose(1, 2, 0))  # (J, 3, n)
        pos = np.empty_like(offsets)
        rot = np.empty((n_joints, 3, 3, offsets.shape[-1]))
        pos[roots] = offsets[roots]
        rot[kept_roots] = local[kept_roots]
        for inner, inner_parents, leaf, leaf_parents in levels:
            if inner.size:
                parent_world = rot[inner_parents]
                own = _product(parent_world, local[inner])
                rot[inner] = own
                frame = own if plan.pre else parent_world
                pos[inner] = pos[inner_parents] + _times(frame, offsets[inner])
            if leaf.size:
                parent_world = rot[leaf_parents]
                vectors = offsets[leaf]
                if plan.pre:
                    vectors = _times(local[leaf], vectors)
                pos[leaf] = pos[leaf_parents] + _times(parent_world, vectors)
                if world is not None:
                    rot[leaf] = _product(parent_world, local[leaf])
        positions[block] = pos.transpose(2, 0, 1)
        if world is not None:
            world[block] = rot.transpose(3, 0, 1, 2)
