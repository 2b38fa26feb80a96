"""Compiled per-frame programs of the operations (numba); imported by :mod:`core.edits.frame_programs` only.

Importing this module raises ImportError when numba is not installed; the operations then
run their numpy path (:mod:`core.edits.operations`), which is the reference these kernels are
tested against.

A program is a list of steps (shift the root one bone, split, join, fold a dummy joint),
each row ``(kind, a, b, first, count, first2, count2, extra)`` of an int64 table, the
lists of joints it names held in one int64 array (:class:`core.edits.frame_programs.FrameProgram`).

Each frame is copied to the output as rows of numbers (copying joint by joint, or
through views reshaped frame by frame, was markedly slower than a copy), and every step
then edits it there while it sits in the L1 cache. Split and join read the input's frame,
never the edited one: the world transforms they need are the input's (every operation
keeps them). So a program of splits and joins alone copies only the joints no step
writes, and every number of the output is written once; a join whose static offset the
caller expects (the one its split kept) writes that offset and measures the per-frame one.

3x3 matrices are held as 9-tuples, in registers (through scratch arrays the Newton-Schulz
steps ran at half the speed); a join's products, the bulk of join all, are computed by rows
of 4 lanes with the FK kernels' vector intrinsics (the same operations lane by lane).
Products are summed ``(a0 b0 + a1 b1) + a2 b2`` as in the FK kernels
(:mod:`core.kinematics._kernels`), and nothing is compiled with fast-math, so a split gives
the FK engine's world transform of the joint bit for bit.

Tried and dropped: eight frames at a time in vector lanes (structure-of-arrays scratches
of the touched joints, frames last). LLVM unrolls lane loops of constant length into scalar
code (it cannot prove that the views do not overlap); with the length hidden it vectorises
them behind run-time overlap checks, and the orthonormalisations then ran slower than the
scalar code in registers.
"""

from __future__ import annotations

import numba
import numpy as np

from gmr_studio.core.edits.frame_programs import JOIN, SPLIT, SWAP
from gmr_studio.core.kinematics._kernels import _add, _combine, _lane_max, _lane_min
from gmr_studio.core.kinematics._kernels import _load as _load_lanes
from gmr_studio.core.kinematics._kernels import _store as _store_lanes
from gmr_studio.core.rotations.euler import ORTHONORMAL_TOLERANCE


@numba.njit(inline="always", boundscheck=False)
def _load(m):  # pragma: no cover - compiled
    """The nine entries of a (3, 3) array, row by row (held in registers from here on)."""
    return m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2]


@numba.njit(inline="always", boundscheck=False)
def _store(m, v):  # pragma: no cover - compiled
    m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2] = v


@numba.njit(inline="always", boundscheck=False)
def _mul(a, b):  # pragma: no cover - compiled
    """a @ b of two 9-tuples."""
    return (
        (a[0] * b[0] + a[1] * b[3]) + a[2] * b[6],
        (a[0] * b[1] + a[1] * b[4]) + a[2] * b[7],
        (a[0] * b[2] + a[1] * b[5]) + a[2] * b[8],
        (a[3] * b[0] + a[4] * b[3]) + a[5] * b[6],
        (a[3] * b[1] + a[4] * b[4]) + a[5] * b[7],
        (a[3] * b[2] + a[4] * b[5]) + a[5] * b[8],
        (a[6] * b[0] + a[7] * b[3]) + a[8] * b[6],
        (a[6] * b[1] + a[7] * b[4]) + a[8] * b[7],
        (a[6] * b[2] + a[7] * b[5]) + a[8] * b[8],
    )


@numba.njit(inline="always", boundscheck=False)
def _transposed(a):  # pragma: no cover - compiled
    return a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]


@numba.njit(inline="always", boundscheck=False)
def _times(a, v0, v1, v2):  # pragma: no cover - compiled
    """a @ v of a 9-tuple and a vector."""
    return (
        (a[0] * v0 + a[1] * v1) + a[2] * v2,
        (a[3] * v0 + a[4] * v1) + a[5] * v2,
        (a[6] * v0 + a[7] * v1) + a[8] * v2,
    )


@numba.njit(inline="always", boundscheck=False)
def _gram(a):  # pragma: no cover - compiled
    """The six distinct entries of ``a^T a`` (00, 01, 02, 11, 12, 22) of a 9-tuple."""
    return (
        (a[0] * a[0] + a[3] * a[3]) + a[6] * a[6],
        (a[0] * a[1] + a[3] * a[4]) + a[6] * a[7],
        (a[0] * a[2] + a[3] * a[5]) + a[6] * a[8],
        (a[1] * a[1] + a[4] * a[4]) + a[7] * a[7],
        (a[1] * a[2] + a[4] * a[5]) + a[7] * a[8],
        (a[2] * a[2] + a[5] * a[5]) + a[8] * a[8],
    )


@numba.njit(inline="always", boundscheck=False)
def _orthonormal(a):  # pragma: no cover - compiled
    """core.rotations.orthonormalize of a 9-tuple: ``a`` itself when its Gram matrix is
    within ``ORTHONORMAL_TOLERANCE`` of the identity, else two steps ``R <- R (1.5 I - 0.5 R^T R)``
    (the Gram matrix is symmetric: six of its products are computed, the same numbers)."""
    g00, g01, g02, g11, g12, g22 = _gram(a)
    off = max(max(abs(g00 - 1.0), abs(g11 - 1.0)), max(abs(g22 - 1.0), max(abs(g01), max(abs(g02), abs(g12)))))
    if off <= ORTHONORMAL_TOLERANCE:
        return a
    for step in range(2):
        if step:
            g00, g01, g02, g11, g12, g22 = _gram(a)
        f01, f02, f12 = 0.0 - 0.5 * g01, 0.0 - 0.5 * g02, 0.0 - 0.5 * g12
        a = _mul(a, (1.5 - 0.5 * g00, f01, f02, f01, 1.5 - 0.5 * g11, f12, f02, f12, 1.5 - 0.5 * g22))
    return a


@numba.njit(inline="always", boundscheck=False)
def _rows(m):  # pragma: no cover - compiled
    """The rows of a (3, 3) array as 4-lane tuples (the last lane 0)."""
    return (m[0, 0], m[0, 1], m[0, 2], 0.0), (m[1, 0], m[1, 1], m[1, 2], 0.0), (m[2, 0], m[2, 1], m[2, 2], 0.0)


@numba.njit(inline="always", boundscheck=False)
def _store_turned_back(target, world, r0, r1, r2):  # pragma: no cover - compiled
    """target (3, 3) = ``_orthonormal(_mul(_transposed(world), R))`` for ``world`` a 9-tuple
    and R given by its rows r0, r1, r2 (:func:`_rows`), computed on 4 lanes: row a of
    ``W^T R`` is ``(W0a r0 + W1a r1) + W2a r2`` and row a of its Gram matrix ``P^T P`` is
    ``(P0a p0 + P1a p1) + P2a p2``, lane by lane the scalar sums of :func:`_mul` and
    :func:`_gram` (products commute exactly), so the same numbers."""
    p0 = _combine(r0, r1, r2, world[0], world[3], world[6])
    p1 = _combine(r0, r1, r2, world[1], world[4], world[7])
    p2 = _combine(r0, r1, r2, world[2], world[5], world[8])
    g0 = _combine(p0, p1, p2, p0[0], p1[0], p2[0])
    g1 = _combine(p0, p1, p2, p0[1], p1[1], p2[1])
    g2 = _combine(p0, p1, p2, p0[2], p1[2], p2[2])
    diagonal = max(abs(g0[0] - 1.0), abs(g1[1] - 1.0))
    off = max(diagonal, max(abs(g2[2] - 1.0), max(abs(g0[1]), max(abs(g0[2]), abs(g1[2])))))
    if off <= ORTHONORMAL_TOLERANCE:
        target[0, 0], target[0, 1], target[0, 2] = p0[0], p0[1], p0[2]
        target[1, 0], target[1, 1], target[1, 2] = p1[0], p1[1], p1[2]
        target[2, 0], target[2, 1], target[2, 2] = p2[0], p2[1], p2[2]
    else:
        _store(target, _orthonormal((p0[0], p0[1], p0[2], p1[0], p1[1], p1[2], p2[0], p2[1], p2[2])))


@numba.njit(inline="always", boundscheck=False)
def _walk(rot, trans, lists, first, count, last_is_leaf):  # pragma: no cover - compiled
    """World rotation (a 9-tuple) and position (p0, p1, p2) of the last joint of the root
    path ``lists[first:first + count]`` (pre-rotation), with the FK kernel's operations:
    ``W_j = W_p R_j`` and ``P_j = P_p + W_j t_j``, or for a leaf ``P_j = P_p + W_p (R_j t_j)``."""
    root = lists[first]
    world = _load(rot[root])
    p0, p1, p2 = trans[root, 0], trans[root, 1], trans[root, 2]
    for step in range(1, count):
        j = lists[first + step]
        local = _load(rot[j])
        if last_is_leaf and step == count - 1:
            v0, v1, v2 = _times(local, trans[j, 0], trans[j, 1], trans[j, 2])
            d0, d1, d2 = _times(world, v0, v1, v2)
            world = _mul(world, local)
        else:
            world = _mul(world, local)
            d0, d1, d2 = _times(world, trans[j, 0], trans[j, 1], trans[j, 2])
        p0, p1, p2 = p0 + d0, p1 + d1, p2 + d2
    return world, p0, p1, p2


@numba.njit(inline="always", boundscheck=False)
def _fold(measures, sums, lows, highs, b):  # pragma: no cover - compiled
    """Add the join offsets measured over frames of block ``b`` (``measures`` (n_joins, 3, 4):
    per join the running sum, minimum and maximum on 4 lanes) into ``sums``, ``lows`` and
    ``highs`` at ``b`` (none when negative), and start ``measures`` afresh."""
    for k in range(measures.shape[0]):
        for x in range(3):
            if b >= 0 and k < sums.shape[1]:
                sums[b, k, x] += measures[k, 0, x]
                lows[b, k, x] = min(lows[b, k, x], measures[k, 1, x])
                highs[b, k, x] = max(highs[b, k, x], measures[k, 2, x])
        for x in range(4):
            measures[k, 0, x] = 0.0
            measures[k, 1, x] = np.inf
            measures[k, 2, x] = -np.inf


@numba.njit(inline="always", boundscheck=False)
def _run_steps(src_rot, src_trans, rot, trans, steps, lists, measures, static):  # pragma: no cover - compiled
    """Every step of the program on one frame: ``rot`` (J, 3, 3) and ``trans`` (J, 3)
    edited in place; ``src_*`` the input's frame (read by split and join). A join's
    per-frame offset ``R_j^T (t_j - t_p)`` is added into ``measures[k]`` (k its ``extra``;
    see :func:`_fold`) and is its translation, unless ``static[k]`` is a number: the offset the caller expects the
    joint to keep over all frames, written instead (NaN: none)."""
    for s in range(steps.shape[0]):
        kind = steps[s, 0]
        a = steps[s, 1]
        b = steps[s, 2]
        if kind == SWAP:  # the root a hands the root over to its child b
            r0 = _load(rot[a])
            r1 = _load(rot[b])
            t0, t1, t2 = trans[b, 0], trans[b, 1], trans[b, 2]
            turned_back = _transposed(r1)
            for i in range(steps[s, 4]):
                c = lists[steps[s, 3] + i]
                _store(rot[c], _orthonormal(_mul(turned_back, _load(rot[c]))))
            for i in range(steps[s, 6]):
                c = lists[steps[s, 5] + i]
                _store(rot[c], _orthonormal(_mul(r1, _load(rot[c]))))
            d0, d1, d2 = _times(_mul(r0, r1), t0, t1, t2)
            trans[b, 0], trans[b, 1], trans[b, 2] = trans[a, 0] + d0, trans[a, 1] + d1, trans[a, 2] + d2
            trans[a, 0], trans[a, 1], trans[a, 2] = -t0, -t1, -t2
            _store(rot[b], r0)
            _store(rot[a], r1)
        elif kind == SPLIT:  # a takes its world transform
            world, p0, p1, p2 = _walk(src_rot, src_trans, lists, steps[s, 3], steps[s, 4], steps[s, 7] == 1)
            _store(rot[a], world)
            trans[a, 0], trans[a, 1], trans[a, 2] = p0, p1, p2
        elif kind == JOIN:  # the root a goes back under the last joint of its path
            world, p0, p1, p2 = _walk(src_rot, src_trans, lists, steps[s, 3], steps[s, 4], False)
            r0, r1, r2 = _rows(src_rot[a])
            k = steps[s, 7]
            o = _combine(r0, r1, r2, src_trans[a, 0] - p0, src_trans[a, 1] - p1, src_trans[a, 2] - p2)  # R_j^T d
            _store_lanes(measures, k, 0, _add(_load_lanes(measures, k, 0), o))
            _store_lanes(measures, k, 1, _lane_min(_load_lanes(measures, k, 1), o))
            _store_lanes(measures, k, 2, _lane_max(_load_lanes(measures, k, 2), o))
            if static[k, 0] == static[k, 0]:  # the static offset the caller expects (not NaN)
                trans[a, 0], trans[a, 1], trans[a, 2] = static[k, 0], static[k, 1], static[k, 2]
            else:
                trans[a, 0], trans[a, 1], trans[a, 2] = o[0], o[1], o[2]
            _store_turned_back(rot[a], world, r0, r1, r2)
        else:  # FOLD: the dummy a's rotation goes into each of its children
            dummy = _load(rot[a])
            for i in range(steps[s, 4]):
                c = lists[steps[s, 3] + i]
                _store(rot[c], _mul(dummy, _load(rot[c])))


@numba.njit(nogil=True, cache=True, boundscheck=False)
def run_program(
    rotations, translations, rows, rows_t, steps, lists, kept, copied, start, stop, block, sums, lows, highs,
    out_rotations, out_translations, out_rows, out_rows_t, rot, trans, measures, static,
):  # pragma: no cover - compiled  # fmt: skip
    """Frames start..stop-1 of the edited motion.

    rotations (F, J, 3, 3), translations (F, J, 3): the input, and the same numbers as
    rows (F, J * 9) and (F, J * 3); out_* likewise for the output (J' joints). ``kept``
    (J',): the output's joints, in order, when the program removes some (the frame is then
    edited in the scratch ``rot`` (J, 3, 3) and ``trans`` (J, 3) and its kept joints written
    out); empty: all of them, edited in place in the output after the joints of ``copied``
    (C, 2), ranges [first, stop) of joints, are copied there as rows of numbers: every joint
    when a step reads the edited frame (swap, fold), else only those no step writes (a
    split or join writes the whole of its joint), so that each number is written once.
    Each join's offsets are summed per block of ``block`` frames (counted from frame 0, in
    frame order) into ``sums`` (n_blocks, n_joins, 3), their minimum and maximum into
    ``lows`` and ``highs`` (the same shape, starting at +inf and -inf), through the scratch
    ``measures`` (max(n_joins, 1), 3, 4) that keeps them on 4 lanes within a block
    (:func:`_fold`; the same numbers, summed in the same order). static: (max(n_joins, 1),
    3) each join's expected static offset or NaN (see :func:`_run_steps`)."""
    n_joins = sums.shape[1]
    in_place = kept.shape[0] == 0
    whole = copied.shape[0] == 1 and copied[0, 0] == 0 and copied[0, 1] * 9 == rows.shape[1]
    row = rot.reshape(rot.size)
    row_t = trans.reshape(trans.size)
    _fold(measures, sums, lows, highs, -1)
    for f in range(start, stop):
        if in_place and whole:  # one loop over the row: the copy runs at its best
            for i in range(rows.shape[1]):
                out_rows[f, i] = rows[f, i]
            for i in range(rows_t.shape[1]):
                out_rows_t[f, i] = rows_t[f, i]
        elif in_place:
            source, target, source_t, target_t = rows[f], out_rows[f], rows_t[f], out_rows_t[f]
            for c in range(copied.shape[0]):
                for i in range(copied[c, 0] * 9, copied[c, 1] * 9):
                    target[i] = source[i]
                for i in range(copied[c, 0] * 3, copied[c, 1] * 3):
                    target_t[i] = source_t[i]
        if in_place:
            edited_rot, edited_trans = out_rotations[f], out_translations[f]
            _run_steps(rotations[f], translations[f], edited_rot, edited_trans, steps, lists, measures, static)
        else:
            for i in range(rows.shape[1]):
                row[i] = rows[f, i]
            for i in range(rows_t.shape[1]):
                row_t[i] = rows_t[f, i]
            _run_steps(rotations[f], translations[f], rot, trans, steps, lists, measures, static)
            for n in range(kept.shape[0]):
                _store(out_rotations[f, n], _load(rot[kept[n]]))
                for x in range(3):
                    out_translations[f, n, x] = trans[kept[n], x]
        if n_joins and ((f + 1) % block == 0 or f + 1 == stop):
            _fold(measures, sums, lows, highs, f // block)
