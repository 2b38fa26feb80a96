"""Compiled forward-kinematics kernels (numba); imported by :mod:`core.kinematics.engine`, and
their vector intrinsics by the edits' kernels (:mod:`core.edits._kernels`).

Importing this module raises ImportError when numba is not installed; the engine then
uses its numpy backend, which performs the same operations in the same order.

Every kernel walks frames in storage order and, inside a frame, the joints in
topological order. Arithmetic is spelled out ``(a0 b0 + a1 b1) + a2 b2`` so that it
matches the numpy backend operation for operation (numba compiles without fast-math: no
fused multiply-add, no reassociation).

The walk (:func:`_walk`, for :func:`fk_matrices` and :func:`fk_euler`) reads and writes
flat (1-D) views of the frame arrays, joint j of frame f at row ``f J + j``, through
:func:`_at` and :func:`_put` (no per-frame views, no negative-index checks). It keeps
each joint's world rotation by columns, each column (and the position) a vector of 4
lanes (the last unused), and computes a column of ``W_p R_j`` as
``(c0 r0b + c1 r1b) + c2 r2b`` on whole vectors: the same operations, lane by lane, as
the scalar sums. numba turns off LLVM's SLP vectoriser, which would otherwise find these
vector operations; the small intrinsics below spell them out in LLVM IR (plain ``fmul``
and ``fadd`` without fast-math flags: no contraction into fused multiply-add).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

ROOT, INNER, LEAF = 0, 1, 2


@numba.njit(inline="always", boundscheck=False)
def _stage(rotations, translations, row, joints, local, offsets):  # pragma: no cover - compiled
    """Copy, in memory order, the translations of the frame whose first row (joint 0) is
    ``row`` and the rotations of its ``joints`` (increasing) into the scratch ``offsets``
    (J * 3,) and ``local`` (J * 9,). All flat: 9 numbers a rotation row by row, 3 a
    translation."""
    for i in range(offsets.shape[0]):
        offsets[i] = translations[3 * row + i]
    for i in range(joints.shape[0]):
        j = joints[i]
        for k in range(9):
            local[9 * j + k] = rotations[9 * (row + j) + k]


_LANES = ir.VectorType(ir.DoubleType(), 4)
_INDEX = ir.IntType(32)
_QUAD = types.UniTuple(types.float64, 4)


def _as_vector(builder, quad):  # pragma: no cover - compile time
    vector = ir.Constant(_LANES, ir.Undefined)
    for k in range(4):
        vector = builder.insert_element(vector, builder.extract_value(quad, k), ir.Constant(_INDEX, k))
    return vector


def _as_quad(context, builder, vector):  # pragma: no cover - compile time
    quad = ir.Constant(context.get_value_type(_QUAD), ir.Undefined)
    for k in range(4):
        quad = builder.insert_value(quad, builder.extract_element(vector, ir.Constant(_INDEX, k)), k)
    return quad


def _splat(builder, value):  # pragma: no cover - compile time
    vector = builder.insert_element(ir.Constant(_LANES, ir.Undefined), value, ir.Constant(_INDEX, 0))
    return builder.shuffle_vector(vector, vector, ir.Constant(ir.VectorType(_INDEX, 4), [0, 0, 0, 0]))


def _lane_pointer(context, builder, array_type, array, j, c):  # pragma: no cover - compile time
    """Pointer to array[j, c, 0] of a C-contiguous (J, 4, 4) float64 array, as 4 lanes."""
    view = context.make_array(array_type)(context, builder, array)
    zero = context.get_constant(types.intp, 0)
    pointer = cgutils.get_item_pointer(context, builder, array_type, view, [j, c, zero], wraparound=False)
    return builder.bitcast(pointer, _LANES.as_pointer())


@intrinsic
def _load(typingctx, lanes, j, c):  # pragma: no cover - compile time
    """lanes[j, c, :] (lanes: C-contiguous (J, 4, 4)) as one 4-lane vector load."""
    if lanes.layout != "C":
        return None

    def codegen(context, builder, signature, args):
        pointer = _lane_pointer(context, builder, signature.args[0], args[0], args[1], args[2])
        return _as_quad(context, builder, builder.load(pointer, align=8))

    return _QUAD(lanes, j, c), codegen


@intrinsic
def _store(typingctx, lanes, j, c, quad):  # pragma: no cover - compile time
    """lanes[j, c, :] = quad, one 4-lane vector store."""
    if lanes.layout != "C":
        return None

    def codegen(context, builder, signature, args):
        pointer = _lane_pointer(context, builder, signature.args[0], args[0], args[1], args[2])
        builder.store(_as_vector(builder, args[3]), pointer, align=8)
        return context.get_dummy_value()

    return types.void(lanes, j, c, quad), codegen


@intrinsic
def _combine(typingctx, c0, c1, c2, x, y, z):  # pragma: no cover - compile time
    """(c0 x + c1 y) + c2 z lane by lane: c0, c1, c2 4-lane tuples, x, y, z numbers."""

    def codegen(context, builder, signature, args):
        v0, v1, v2 = (_as_vector(builder, quad) for quad in args[:3])
        s0, s1, s2 = (_splat(builder, value) for value in args[3:])
        total = builder.fadd(builder.fadd(builder.fmul(v0, s0), builder.fmul(v1, s1)), builder.fmul(v2, s2))
        return _as_quad(context, builder, total)

    return _QUAD(_QUAD, _QUAD, _QUAD, types.float64, types.float64, types.float64), codegen


@intrinsic
def _add(typingctx, a, b):  # pragma: no cover - compile time
    """a + b lane by lane (4-lane tuples)."""

    def codegen(context, builder, signature, args):
        return _as_quad(context, builder, builder.fadd(_as_vector(builder, args[0]), _as_vector(builder, args[1])))

    return _QUAD(_QUAD, _QUAD), codegen


def _lane_pick(predicate: str):  # pragma: no cover - compile time
    """An intrinsic ``(a, b) ->`` b where ``b <predicate> a``, else a, lane by lane
    (4-lane tuples; ordered comparison: a NaN in b keeps a)."""

    @intrinsic
    def pick(typingctx, a, b):
        def codegen(context, builder, signature, args):
            first, second = _as_vector(builder, args[0]), _as_vector(builder, args[1])
            chosen = builder.fcmp_ordered(predicate, second, first)
            return _as_quad(context, builder, builder.select(chosen, second, first))

        return _QUAD(_QUAD, _QUAD), codegen

    return pick


#: the lesser of a and b lane by lane (as ``min(a, b)`` of numbers), and the greater
_lane_min = _lane_pick("<")
_lane_max = _lane_pick(">")


@intrinsic
def _store_rows(typingctx, world, at, n0, n1, n2):  # pragma: no cover - compile time
    """world[at : at + 9] = the matrix of columns n0, n1, n2 row by row: two 4-lane stores
    and one scalar (world: a C-contiguous 1-D float64 array)."""
    if world.layout != "C" or world.ndim != 1:
        return None

    def codegen(context, builder, signature, args):
        view = context.make_array(signature.args[0])(context, builder, args[0])
        c0, c1, c2 = (_as_vector(builder, quad) for quad in args[2:])

        def pick(a, b, lanes):
            return builder.shuffle_vector(a, b, ir.Constant(ir.VectorType(_INDEX, 4), lanes))

        def pointer(k):
            return builder.gep(view.data, [builder.add(args[1], context.get_constant(types.intp, k))])

        first = pick(pick(c0, c1, [0, 4, 1, 5]), c2, [0, 1, 4, 2])  # W00 W01 W02 W10
        second = pick(pick(c0, c1, [5, 2, 6, 0]), c2, [0, 5, 1, 2])  # W11 W12 W20 W21
        builder.store(first, builder.bitcast(pointer(0), _LANES.as_pointer()), align=8)
        builder.store(second, builder.bitcast(pointer(4), _LANES.as_pointer()), align=8)
        builder.store(builder.extract_element(c2, ir.Constant(_INDEX, 2)), pointer(8))
        return context.get_dummy_value()

    return types.void(world, types.intp, _QUAD, _QUAD, _QUAD), codegen


@intrinsic
def _at(typingctx, array, index):  # pragma: no cover - compile time
    """array[index] of a C-contiguous 1-D float64 array, ``index`` taken as is (no
    negative-index wraparound: the caller's indices are never negative)."""
    if array.layout != "C" or array.ndim != 1:
        return None

    def codegen(context, builder, signature, args):
        view = context.make_array(signature.args[0])(context, builder, args[0])
        return builder.load(builder.gep(view.data, [args[1]]))

    return types.float64(array, types.intp), codegen


@intrinsic
def _put(typingctx, array, index, value):  # pragma: no cover - compile time
    """array[index] = value (as :func:`_at`: a C-contiguous 1-D float64 array, no wraparound)."""
    if array.layout != "C" or array.ndim != 1:
        return None

    def codegen(context, builder, signature, args):
        view = context.make_array(signature.args[0])(context, builder, args[0])
        builder.store(args[2], builder.gep(view.data, [args[1]]))
        return context.get_dummy_value()

    return types.void(array, types.intp, types.float64), codegen


@numba.njit(inline="always", boundscheck=False)
def _turned(c0, c1, c2, local, r):  # pragma: no cover - compiled
    """The columns of W @ R (W by columns c0, c1, c2; R the 9 numbers from local[r], row by row)."""
    n0 = _combine(c0, c1, c2, _at(local, r), _at(local, r + 3), _at(local, r + 6))
    n1 = _combine(c0, c1, c2, _at(local, r + 1), _at(local, r + 4), _at(local, r + 7))
    n2 = _combine(c0, c1, c2, _at(local, r + 2), _at(local, r + 5), _at(local, r + 8))
    return n0, n1, n2


@numba.njit(inline="always", boundscheck=False)
def _keep(columns, world, j, w, n0, n1, n2, here, keep_world):  # pragma: no cover - compiled
    """Joint j's world rotation (columns n0, n1, n2) and position ``here`` into ``columns``
    for its children, and the rotation into ``world[w : w + 9]`` when ``keep_world``."""
    _store(columns, j, 0, n0)
    _store(columns, j, 1, n1)
    _store(columns, j, 2, n2)
    _store(columns, j, 3, here)
    if keep_world:
        _store_rows(world, w, n0, n1, n2)


@numba.njit(inline="always", boundscheck=False)
def _steps(order, parents, kinds, keep_root):  # pragma: no cover - compiled
    """(J, 3) int64: the walk, one row per joint in ``order``: the joint, its parent, and
    its kind plus 4 when ``keep_root`` (one small array the walk reads in order)."""
    steps = np.empty((order.shape[0], 3), np.int64)
    for step in range(order.shape[0]):
        j = order[step]
        steps[step, 0] = j
        steps[step, 1] = parents[j]
        steps[step, 2] = kinds[j] + (4 if keep_root[j] else 0)
    return steps


@numba.njit(inline="always", boundscheck=False)
def _walk(  # pragma: no cover - compiled
    local, row, offsets, offset_row, steps, keep_world, pre, pos, out, world, out_world, columns
):
    """One frame, every array flat (1-D) by rows of joints: joint j's rotation is the 9
    numbers (row by row) from ``local[9 (row + j)]``, its translation the 3 from
    ``offsets[3 (offset_row + j)]``; its position goes to ``pos[3 (out + j)]`` and, when
    ``keep_world``, its world rotation to ``world[9 (out_world + j)]``. steps: as
    :func:`_steps` makes them. columns (J, 4, 4): per joint the world rotation's columns and
    the position, 4 lanes each (the last lane 0), for its children to read.

    The flat arrays are read and written by :func:`_at` and :func:`_put`: no index is
    negative, and numba's indexing would check each one for wraparound.

    Leaves get their world rotation only when ``keep_world``; their positions are computed
    the same way either way (pre-rotation: ``P_p + W_p (R_j t_j)``)."""
    for step in range(steps.shape[0]):
        j = steps[step, 0]
        p = steps[step, 1]
        kind = steps[step, 2] & 3
        r = 9 * (row + j)
        t = 3 * (offset_row + j)
        o = 3 * (out + j)
        w = 9 * (out_world + j)
        t0 = _at(offsets, t)
        t1 = _at(offsets, t + 1)
        t2 = _at(offsets, t + 2)
        if kind == ROOT:
            _put(pos, o, t0)
            _put(pos, o + 1, t1)
            _put(pos, o + 2, t2)
            columns[j, 3, 0] = t0
            columns[j, 3, 1] = t1
            columns[j, 3, 2] = t2
            if steps[step, 2] & 4:  # keep_root
                for a in range(3):
                    for b in range(3):
                        columns[j, b, a] = _at(local, r + 3 * a + b)
                        if keep_world:
                            _put(world, w + 3 * a + b, _at(local, r + 3 * a + b))
            continue
        c0 = _load(columns, p, 0)
        c1 = _load(columns, p, 1)
        c2 = _load(columns, p, 2)
        at = _load(columns, p, 3)
        if pre and kind == LEAF:  # P_p + W_p (R_j t_j): no world rotation needed
            v0 = (_at(local, r) * t0 + _at(local, r + 1) * t1) + _at(local, r + 2) * t2
            v1 = (_at(local, r + 3) * t0 + _at(local, r + 4) * t1) + _at(local, r + 5) * t2
            v2 = (_at(local, r + 6) * t0 + _at(local, r + 7) * t1) + _at(local, r + 8) * t2
            here = _add(at, _combine(c0, c1, c2, v0, v1, v2))
            if keep_world:
                n0, n1, n2 = _turned(c0, c1, c2, local, r)
                _store_rows(world, w, n0, n1, n2)
        elif pre:
            n0, n1, n2 = _turned(c0, c1, c2, local, r)
            here = _add(at, _combine(n0, n1, n2, t0, t1, t2))
            _keep(columns, world, j, w, n0, n1, n2, here, keep_world)
        else:
            here = _add(at, _combine(c0, c1, c2, t0, t1, t2))
            if kind == INNER or keep_world:
                n0, n1, n2 = _turned(c0, c1, c2, local, r)
                _keep(columns, world, j, w, n0, n1, n2, here, keep_world)
        _put(pos, o, here[0])
        _put(pos, o + 1, here[1])
        _put(pos, o + 2, here[2])


@numba.njit(nogil=True, cache=True, boundscheck=False)
def fk_matrices(  # pragma: no cover - compiled
    rotations, translations, order, parents, kinds, keep_root, keep_world, pre, staged, positions, world, local, offsets
):
    """rotations (F, J, 3, 3), translations (F, J, 3) -> positions (F, J, 3) and world:
    (F, J, 3, 3) when ``keep_world`` (every frame's world rotations), else (1, J, 3, 3),
    unused; all C-contiguous. When ``staged`` (increasing joint indices) is not empty, the
    rotations of those joints and all translations of each frame are first copied, in
    memory order, into the scratch ``local`` (J, 3, 3) and ``offsets`` (J, 3): the walk in
    tree order then reads from L1 instead of jumping about in memory the prefetchers cannot
    follow.

    The walk indexes flat views of the arrays by row (frame f, joint j: row f J + j): a
    view per frame would cost reference counting and stride arithmetic every frame."""
    n_frames, n_joints = rotations.shape[0], rotations.shape[1]
    stage = staged.shape[0] > 0
    columns = np.zeros((n_joints, 4, 4))
    steps = _steps(order, parents, kinds, keep_root)
    rot = rotations.reshape(rotations.size)
    off = translations.reshape(translations.size)
    pos = positions.reshape(positions.size)
    out_world = world.reshape(world.size)
    scratch = local.reshape(local.size)
    scratch_offsets = offsets.reshape(offsets.size)
    for f in range(n_frames):
        row = n_joints * f
        world_row = row if keep_world else 0
        if stage:
            _stage(rot, off, row, staged, scratch, scratch_offsets)
            _walk(scratch, 0, scratch_offsets, 0, steps, keep_world, pre, pos, row, out_world, world_row, columns)
        else:
            _walk(rot, row, off, row, steps, keep_world, pre, pos, row, out_world, world_row, columns)


@numba.njit(inline="always", boundscheck=False)
def _euler_matrix(a, b, c, code, out):  # pragma: no cover - compiled
    """core.rotations.euler.matrix_from_euler for one rotation; code = (i, j, k, parity)."""
    i = int(code[0])
    j = int(code[1])
    k = int(code[2])
    e = code[3]
    ca = math.cos(a)
    sa = math.sin(a)
    cb = math.cos(b)
    sb = math.sin(b)
    cc = math.cos(c)
    sc = math.sin(c)
    sa_sb = sa * sb
    ca_sb = ca * sb
    out[i, i] = cb * cc
    out[i, j] = -e * cb * sc
    out[i, k] = e * sb
    out[j, i] = e * ca * sc + sa_sb * cc
    out[j, j] = ca * cc - e * sa_sb * sc
    out[j, k] = -e * sa * cb
    out[k, i] = sa * sc - e * ca_sb * cc
    out[k, j] = e * sa * cc + ca_sb * sc
    out[k, k] = ca * cb


@numba.njit(nogil=True, cache=True, boundscheck=False)
def fk_euler(  # pragma: no cover - compiled
    angles, codes, needed, translations, order, parents, kinds, keep_root, pre, staged, positions, scratch, offsets
):
    """angles (F, J, 3) radians -> positions (F, J, 3); only joints marked ``needed`` get
    a rotation matrix, computed in memory order. scratch (1, J, 3, 3): the local rotations
    of one frame; offsets (J, 3): the frame's translations, copied there in memory order
    first when ``staged`` (the walk is not in memory order)."""
    local = scratch[0]
    flat = scratch.reshape(scratch.size)
    n_joints = angles.shape[1]
    columns = np.zeros((n_joints, 4, 4))
    steps = _steps(order, parents, kinds, keep_root)
    off = translations.reshape(translations.size)
    pos = positions.reshape(positions.size)
    scratch_offsets = offsets.reshape(offsets.size)
    for f in range(angles.shape[0]):
        for j in range(n_joints):
            if needed[j]:
                _euler_matrix(angles[f, j, 0], angles[f, j, 1], angles[f, j, 2], codes[j], local[j])
        row = n_joints * f
        if staged:
            for i in range(scratch_offsets.shape[0]):
                _put(scratch_offsets, i, _at(off, 3 * row + i))
            _walk(flat, 0, scratch_offsets, 0, steps, False, pre, pos, row, flat, 0, columns)
        else:
            _walk(flat, 0, off, row, steps, False, pre, pos, row, flat, 0, columns)


@numba.njit(nogil=True, cache=True, boundscheck=False)
def matrices_from_degrees(values, joints, columns, codes, identities, start, stop, out):  # pragma: no cover
    """out[f, joints[m]] = the rotation of the Euler angles in degrees at ``values[f,
    columns[m]]`` (a column of -1: angle 0), and out[f, identities[n]] = the identity, for
    frames start..stop-1. codes (M, 4) as in :func:`_euler_matrix`. Same operations as
    numpy.radians + core.rotations.matrix_from_euler."""
    scale = np.pi / 180.0
    for f in range(start, stop):
        for n in range(identities.shape[0]):
            for a in range(3):
                for b in range(3):
                    out[f, identities[n], a, b] = 1.0 if a == b else 0.0
        for m in range(joints.shape[0]):
            a = values[f, columns[m, 0]] * scale if columns[m, 0] >= 0 else 0.0
            b = values[f, columns[m, 1]] * scale if columns[m, 1] >= 0 else 0.0
            c = values[f, columns[m, 2]] * scale if columns[m, 2] >= 0 else 0.0
            _euler_matrix(a, b, c, codes[m], out[f, joints[m]])


@numba.njit(inline="always", boundscheck=False)
def _conjugated(c, m, right, out):  # pragma: no cover - compiled
    """out = c m c^T for (3, 3) arrays (core.formats.amc.conjugate for one rotation):
    right = m c^T first, then c right; right is a (3, 3) scratch."""
    for a in range(3):
        for b in range(3):
            right[a, b] = (m[a, 0] * c[b, 0] + m[a, 1] * c[b, 1]) + m[a, 2] * c[b, 2]
    for a in range(3):
        for b in range(3):
            out[a, b] = (c[a, 0] * right[0, b] + c[a, 1] * right[1, b]) + c[a, 2] * right[2, b]


@numba.njit(nogil=True, cache=True, boundscheck=False)
def conjugated_from_angles(  # pragma: no cover - compiled
    values, scale, joints, columns, codes, axes, identities, start, stop, out
):
    """out[f, joints[m]] = axes[m] R axes[m]^T, R the rotation of the Euler angles
    ``values[f, columns[m]] * scale`` (a column of -1: angle 0), and out[f, identities[n]] =
    the identity, for frames start..stop-1. codes (M, 4) as in :func:`_euler_matrix`; axes
    (M, 3, 3). Same operations as core.rotations.matrix_from_euler then
    core.formats.amc.conjugate, one rotation at a time."""
    rotation = np.empty((3, 3))
    right = np.empty((3, 3))
    for f in range(start, stop):
        for n in range(identities.shape[0]):
            for a in range(3):
                for b in range(3):
                    out[f, identities[n], a, b] = 1.0 if a == b else 0.0
        for m in range(joints.shape[0]):
            a = values[f, columns[m, 0]] * scale if columns[m, 0] >= 0 else 0.0
            b = values[f, columns[m, 1]] * scale if columns[m, 1] >= 0 else 0.0
            c = values[f, columns[m, 2]] * scale if columns[m, 2] >= 0 else 0.0
            _euler_matrix(a, b, c, codes[m], rotation)
            _conjugated(axes[m], rotation, right, out[f, joints[m]])


@numba.njit(nogil=True, cache=True, boundscheck=False)
def gather_joints(rows, joints, width, start, stop, out):  # pragma: no cover - compiled
    """out[f, n * width + i] = rows[f, joints[n] * width + i] for frames start..stop-1: the
    joints' numbers (``width`` of them each: 9 for a rotation) picked out of every frame's row."""
    for f in range(start, stop):
        for n in range(joints.shape[0]):
            first = joints[n] * width
            for i in range(width):
                out[f, n * width + i] = rows[f, first + i]


@numba.njit(nogil=True, cache=True, boundscheck=False)
def signed_gather(rows, first, index, place, factor, scale, shift, start, stop, out):  # pragma: no cover - compiled
    """out[f, place[i]] = (factor[i] * rows[first + f, index[i]]) * scale + shift[i] for
    frames start..stop-1 of ``out`` (F', W'), or out[f, i] when ``place`` is empty: every
    output number one input number of its frame's row, signed, scaled and shifted (the axes
    of each joint's vector or matrix permuted). With the entries listed in the order of the
    input's joints, each frame's row is read in memory order and the writes jump instead:
    reading joints out of order is what the hardware prefetchers do not follow."""
    in_order = place.shape[0] == 0
    for f in range(start, stop):
        source = rows[first + f]
        target = out[f]
        if in_order:
            for i in range(index.shape[0]):
                target[i] = (factor[i] * source[index[i]]) * scale + shift[i]
        else:
            for i in range(index.shape[0]):
                target[place[i]] = (factor[i] * source[index[i]]) * scale + shift[i]
