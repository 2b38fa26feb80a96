"""Per-frame statistics several checks read, each one pass over the motion.

- :func:`second_differences`: each joint's middle deviation ``|P_f - (P_{f-1} + P_{f+1}) / 2|``
  and the products of consecutive middles (pops and jitter, :mod:`core.checks.spikes`), or
  (:func:`deviations_and_block_counts`) the deviations and jitter's counts of the products;
- :func:`joint_coordinates`: the coordinates of some joints, taken out once (the feet);
- :func:`largest_steps`: the largest squared step of any joint from frame to frame, and
  :func:`steps_within`: whether it is within a tolerance (frozen and duplicate frames,
  :mod:`core.checks.frames`);
- :func:`step_cosines`: the cosine of the angle of ``R_f^T R_{f+1}`` of every joint (flips,
  :mod:`core.checks.joints`), and :func:`cosines_below`: only the steps whose cosine is
  below a limit, without the (F-1, K) array;
- :func:`medians_and_deviations`: each column's median and median absolute deviation
  (pops' robust level; :func:`column_medians` the medians alone: feet that touch);
- :func:`block_counts_at_most`: per block of rows, how many are at most a limit (jitter: a
  block's median is at most a value when more than half are);
- :func:`flat_indices_above`: where values exceed their column's limit (pops' candidates);
- :func:`root_jumps`: the roots' jumps beyond their own velocity (teleports);
- :func:`skate_windows`: the steps of a foot in windows that slide, and its stillest steps
  (foot skate, :mod:`core.checks.feet`).

With numba installed each is a compiled kernel (:mod:`core.checks._kernels`) that writes only
its result; without it (or with ``backend='numpy'``) numpy computes the same (the reference;
the two agree to rounding, tested; the selections, medians and counts exactly).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.compiled import chosen_kernels, optional_kernels

_kernels = optional_kernels("gmr_studio.core.checks._kernels")


def _first_guess(n: int) -> int:
    """Room for the indices a kernel picks out of n values before it knows how many: one in
    256 (a second pass when there are more)."""
    return max(4096, n // 256)


def _compiled(backend: str, array: np.ndarray) -> bool:
    return chosen_kernels(backend, _kernels) is not None and array.dtype == np.float64


def middles(positions: np.ndarray) -> np.ndarray:
    """(F-2, J, 3): ``P_f - (P_{f-1} + P_{f+1}) / 2`` for frames 1..F-2 of positions (F, J, 3)."""
    out = np.add(positions[:-2], positions[2:])
    out *= -0.5
    out += positions[1:-1]
    return out


def second_differences(positions: np.ndarray, *, backend: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """(deviations (F-2, J), products (F-3, J)) of positions (F, J, 3), F >= 2: the length of
    each middle and the dot product of the middles of frames f and f+1."""
    n_frames, n_joints = positions.shape[:2]
    if _compiled(backend, positions):
        deviations = np.empty((max(n_frames - 2, 0), n_joints))
        products = np.empty((max(n_frames - 3, 0), n_joints))
        counts = np.empty((0, n_joints), np.int64)
        _kernels.second_differences(np.ascontiguousarray(positions), deviations, products, 1, 0.0, counts)
        return deviations, products
    m = middles(positions)
    return np.sqrt(np.einsum("fja,fja->fj", m, m)), np.einsum("fja,fja->fj", m[:-1], m[1:])


def deviations_and_block_counts(
    positions: np.ndarray, block: int, limit: float, *, backend: str = "auto"
) -> tuple[np.ndarray, np.ndarray]:
    """(deviations (F-2, J), counts (B, J)) of positions (F, J, 3), F >= 2: the deviations of
    :func:`second_differences` and :func:`block_counts_at_most` of its products, in one pass
    that does not keep the products."""
    n_frames, n_joints = positions.shape[:2]
    n_blocks = max(n_frames - 3, 0) // block
    if _compiled(backend, positions):
        deviations = np.empty((max(n_frames - 2, 0), n_joints))
        counts = np.empty((n_blocks, n_joints), np.int64)
        products = np.empty((0, n_joints))
        _kernels.second_differences(np.ascontiguousarray(positions), deviations, products, block, limit, counts)
        return deviations, counts
    deviations, products = second_differences(positions, backend=backend)
    return deviations, block_counts_at_most(products, block, limit, backend=backend)


def largest_steps(positions: np.ndarray, joints: np.ndarray | None = None, *, backend: str = "auto") -> np.ndarray:
    """(F-1,): the largest squared step of the ``joints`` (None: all) from frame f to f+1 of
    positions (F, J, 3); NaN steps are left out, NaN where every one is."""
    if _compiled(backend, positions):
        every = np.arange(positions.shape[1]) if joints is None else np.asarray(joints, dtype=np.int64)
        out = np.empty(max(positions.shape[0] - 1, 0))
        _kernels.largest_steps(np.ascontiguousarray(positions), every, out)
        return out
    picked = positions if joints is None else positions[:, joints]
    steps = picked[1:] - picked[:-1]
    return np.fmax.reduce(np.einsum("fja,fja->fj", steps, steps), axis=1)


def steps_within(
    positions: np.ndarray, joints: np.ndarray | None, tolerance: float, *, backend: str = "auto"
) -> np.ndarray:
    """(F-1,) bool: ``largest_steps(positions, joints) <= tolerance`` (a step of every joint NaN
    is not), the kernel leaving each frame at its first step above the tolerance."""
    if _compiled(backend, positions):
        every = np.arange(positions.shape[1]) if joints is None else np.asarray(joints, dtype=np.int64)
        out = np.empty(max(positions.shape[0] - 1, 0), bool)
        _kernels.steps_within(np.ascontiguousarray(positions), every, tolerance, out)
        return out
    return largest_steps(positions, joints, backend="numpy") <= tolerance


def step_cosines(rotations: np.ndarray, joints: np.ndarray | None = None, *, backend: str = "auto") -> np.ndarray:
    """(F-1, K): the cosine of the angle between consecutive rotations (F, J, 3, 3) of the
    ``joints`` (K,) (None: all), ``(trace(R_f^T R_{f+1}) - 1) / 2`` clipped to [-1, 1]."""
    every = np.arange(rotations.shape[1]) if joints is None else np.asarray(joints, dtype=np.int64)
    if _compiled(backend, rotations):
        out = np.empty((max(rotations.shape[0] - 1, 0), every.size))
        _kernels.step_cosines(np.ascontiguousarray(rotations), every, out)
        return out
    picked = rotations[:, every]
    trace = np.einsum("fkab,fkab->fk", picked[1:], picked[:-1])
    return np.clip(0.5 * (trace - 1.0), -1.0, 1.0)


def step_angles(rotations: np.ndarray, joints: np.ndarray | None = None, *, backend: str = "auto") -> np.ndarray:
    """(F-1, K): the angles in degrees of :func:`step_cosines`."""
    return np.degrees(np.arccos(step_cosines(rotations, joints, backend=backend)))


def cosines_below(
    rotations: np.ndarray, joints: np.ndarray | None, limit: float, *, backend: str = "auto"
) -> tuple[np.ndarray, np.ndarray]:
    """The steps whose :func:`step_cosines` is below ``limit``: (N,) int64 flat indices
    ``f * K + k`` into the (F-1, K) cosines, in order, and (N,) their cosines (NaN is not below)."""
    every = np.arange(rotations.shape[1]) if joints is None else np.asarray(joints, dtype=np.int64)
    if _compiled(backend, rotations):
        rotations = np.ascontiguousarray(rotations)
        room = _first_guess(max(rotations.shape[0] - 1, 0) * every.size)
        indices, cosines = np.empty(room, np.int64), np.empty(room)
        count = _kernels.cosines_below(rotations, every, limit, indices, cosines)
        if count > indices.size:  # more than the first guess: again with room for all
            indices, cosines = np.empty(count, np.int64), np.empty(count)
            _kernels.cosines_below(rotations, every, limit, indices, cosines)
        return indices[:count], cosines[:count]
    cosines = step_cosines(rotations, every, backend="numpy")
    indices = np.flatnonzero(cosines < limit)
    return indices, cosines.flat[indices]


def medians_and_deviations(
    values: np.ndarray, step: int = 1, *, backend: str = "auto"
) -> tuple[np.ndarray, np.ndarray]:
    """Of each column of ``values[::step]`` (N, J): its median and the median of its absolute
    deviations from that median, two (J,) arrays (``numpy.median``'s: NaN where a column has a
    NaN; the kernel selects, and leaves values that are not finite to numpy)."""
    if _compiled(backend, values) and values.shape[0]:
        medians, deviations = np.empty(values.shape[1]), np.empty(values.shape[1])
        if _kernels.medians_and_deviations(np.ascontiguousarray(values), step, medians, deviations):
            return medians, deviations
    columns = np.ascontiguousarray(values[::step].T)
    medians = np.median(columns, axis=1)
    return medians, np.median(np.abs(columns - medians[:, None]), axis=1)


def column_medians(values: np.ndarray, *, backend: str = "auto") -> np.ndarray:
    """(J,): the median of each column of values (N, J), N > 0, ``numpy.median(values, axis=0)``."""
    if _compiled(backend, values):
        medians = np.empty(values.shape[1])
        if _kernels.medians_and_deviations(np.ascontiguousarray(values), 1, medians, np.empty(0)):
            return medians
    return np.median(values, axis=0)


def block_counts_at_most(values: np.ndarray, block: int, limit: float, *, backend: str = "auto") -> np.ndarray:
    """(B, J) int64: how many of each block of ``block`` rows of values (N, J) are at most
    ``limit`` (B = N // block, the rows after the last whole block left out; NaN is not)."""
    n_blocks = values.shape[0] // block
    if _compiled(backend, values):
        out = np.empty((n_blocks, values.shape[1]), np.int64)
        _kernels.counts_at_most(np.ascontiguousarray(values), block, limit, out)
        return out
    blocks = values[: n_blocks * block].reshape(n_blocks, block, values.shape[1])
    return np.count_nonzero(blocks <= limit, axis=1)


def joint_coordinates(positions: np.ndarray, joints: np.ndarray, *, backend: str = "auto") -> np.ndarray:
    """(3, K, F): each coordinate of each of the ``joints`` (K,) over the frames of positions
    (F, J, 3), contiguous (``.transpose(2, 1, 0)`` is ``positions[:, joints]``, laid out so
    that operations along the frames read contiguous memory)."""
    joints = np.asarray(joints, dtype=np.int64)
    if _compiled(backend, positions):
        out = np.empty((3, joints.size, positions.shape[0]))
        _kernels.joint_coordinates(positions, joints, out)
        return out
    return np.ascontiguousarray(positions[:, joints].transpose(2, 1, 0))


def flat_indices_above(values: np.ndarray, limits: np.ndarray, *, backend: str = "auto") -> np.ndarray:
    """(N,) int64: the flat indices, in order, where values (F, J) exceed their column's limit
    (J,): ``numpy.flatnonzero(values > limits)`` without the (F, J) mask."""
    limits = np.asarray(limits, dtype=np.float64)
    if _compiled(backend, values):
        values = np.ascontiguousarray(values)
        indices = np.empty(_first_guess(values.size), np.int64)
        count = _kernels.above(values, limits, indices)
        if count > indices.size:  # more than the first guess: again with room for all
            indices = np.empty(count, np.int64)
            _kernels.above(values, limits, indices)
        return indices[:count]
    return np.flatnonzero(values > limits)


def root_jumps(positions: np.ndarray, roots: list[int], *, backend: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """(jumps, changes), two (F-3, R) arrays of the ``roots`` (R,) of positions (F, J, 3), F >= 4:
    with steps ``V_f = P_{f+1} - P_f``, row i holds ``|V_{i+1} - (V_i + V_{i+2}) / 2|`` (the step
    beyond the root's own velocity) and ``|V_{i+2} - V_i|`` (the change of velocity across it)."""
    roots = np.asarray(roots, dtype=np.int64)
    if _compiled(backend, positions):
        jumps = np.empty((positions.shape[0] - 3, roots.size))
        changes = np.empty((positions.shape[0] - 3, roots.size))
        _kernels.root_jumps(positions, roots, jumps, changes)
        return jumps, changes
    v = np.diff(positions[:, roots], axis=0)  # (F-1, R, 3): step f -> f+1
    jumps = np.linalg.norm(v[1:-1] - 0.5 * (v[:-2] + v[2:]), axis=-1)
    return jumps, np.linalg.norm(v[2:] - v[:-2], axis=-1)


def skate_windows(
    x: np.ndarray, y: np.ndarray, planted: np.ndarray, group: list[int], w: int, limit: float, *, backend: str = "auto"
) -> tuple[np.ndarray, np.ndarray]:
    """Of the foot joints ``group`` with horizontal coordinates x, y (K, F) and planted (F, K),
    F > w >= 1: (covered, stillest), (F-1,) each. ``covered``: the steps inside some window
    of frames ``f .. f+w`` that slides (the group's joints planted throughout it all moved
    more than ``limit`` from f to f+w, and there is one); ``stillest``: the shortest step of
    the group's joints planted at both its ends (inf where none is; NaN passed on)."""
    group = np.asarray(group, dtype=np.int64)
    n = x.shape[1]
    if _compiled(backend, x):
        covered, stillest = np.empty(n - 1, bool), np.empty(n - 1)
        rows = np.ascontiguousarray(planted.T)
        _kernels.skate_windows(
            np.ascontiguousarray(x), np.ascontiguousarray(y), rows, group, w, limit, covered, stillest
        )
        return covered, stillest
    xs, ys, held = x[group].T, y[group].T, planted[:, group]  # (F, G)
    count = np.concatenate([np.zeros((1, group.size), np.int64), np.cumsum(held, axis=0)])
    throughout = count[w + 1 :] - count[: -w - 1] == w + 1  # (F-w, G): planted over f..f+w
    moved = _length(xs[w:] - xs[:-w], ys[w:] - ys[:-w])  # (F-w, G)
    window = (np.where(throughout, moved, np.inf).min(axis=1) > limit) & throughout.any(axis=1)
    covered = np.convolve(window.astype(np.int64), np.ones(w, np.int64))[: n - 1] > 0
    steps = _length(np.diff(xs, axis=0), np.diff(ys, axis=0))  # (F-1, G)
    return covered, np.where(held[1:] & held[:-1], steps, np.inf).min(axis=1)


def _length(dx: np.ndarray, dy: np.ndarray) -> np.ndarray:
    """The lengths of the vectors (dx, dy), as ``numpy.linalg.norm`` sums their squares."""
    return np.sqrt(dx * dx + dy * dy)
