"""Compiled forward-kinematics kernels (numba); imported by :mod:`core.kinematics.engine` only.

Importing this module raises ImportError when numba is not installed; the engine then
uses its numpy backend, which performs the same operations in the same order.

Every kernel walks frames in storage order and, inside a frame, the joints in
topological order. Arithmetic is spelled out ``(a0 b0 + a1 b1) + a2 b2`` so that it
matches the numpy backend operation for operation (numba compiles without fast-math: no
fused multiply-add, no reassociation).
"""

from __future__ import annotations

import math

import numba
import numpy as np

ROOT, INNER, LEAF = 0, 1, 2


@numba.njit(inline="always", boundscheck=False)
def _product(world, p, local, j):  # pragma: no cover - compiled
    """world[j] = world[p] @ local[j], summed in the numpy backend's order."""
    for a in range(3):
        w0 = world[p, a, 0]
        w1 = world[p, a, 1]
        w2 = world[p, a, 2]
        for b in range(3):
            world[j, a, b] = (w0 * local[j, 0, b] + w1 * local[j, 1, b]) + w2 * local[j, 2, b]


@numba.njit(inline="always", boundscheck=False)
def _frame(local, offsets, order, parents, kinds, keep_root, keep_world, pre, pos, world):  # pragma: no cover
    """One frame: local (J, 3, 3), offsets (J, 3) -> pos (J, 3), world (J, 3, 3).

    Leaves get their world rotation only when ``keep_world``; their positions are computed
    the same way either way (pre-rotation: ``P_p + W_p (R_j t_j)``)."""
    for step in range(order.shape[0]):
        j = order[step]
        p = parents[j]
        t0 = offsets[j, 0]
        t1 = offsets[j, 1]
        t2 = offsets[j, 2]
        kind = kinds[j]
        if kind == ROOT:
            pos[j, 0] = t0
            pos[j, 1] = t1
            pos[j, 2] = t2
            if keep_root[j]:
                for a in range(3):
                    for b in range(3):
                        world[j, a, b] = local[j, a, b]
        elif pre and kind == LEAF:
            v0 = (local[j, 0, 0] * t0 + local[j, 0, 1] * t1) + local[j, 0, 2] * t2
            v1 = (local[j, 1, 0] * t0 + local[j, 1, 1] * t1) + local[j, 1, 2] * t2
            v2 = (local[j, 2, 0] * t0 + local[j, 2, 1] * t1) + local[j, 2, 2] * t2
            for a in range(3):
                pos[j, a] = pos[p, a] + ((world[p, a, 0] * v0 + world[p, a, 1] * v1) + world[p, a, 2] * v2)
            if keep_world:
                _product(world, p, local, j)
        elif pre:
            _product(world, p, local, j)
            for a in range(3):
                pos[j, a] = pos[p, a] + ((world[j, a, 0] * t0 + world[j, a, 1] * t1) + world[j, a, 2] * t2)
        else:
            for a in range(3):
                pos[j, a] = pos[p, a] + ((world[p, a, 0] * t0 + world[p, a, 1] * t1) + world[p, a, 2] * t2)
            if kind == INNER or keep_world:
                _product(world, p, local, j)


@numba.njit(inline="always", boundscheck=False)
def _stage(rotations, translations, joints, local, offsets):  # pragma: no cover - compiled
    """Copy one frame's (J, 3) translations and the (J, 3, 3) rotations of ``joints``
    (increasing) in memory order."""
    for j in range(translations.shape[0]):
        for a in range(3):
            offsets[j, a] = translations[j, a]
    for i in range(joints.shape[0]):
        j = joints[i]
        for a in range(3):
            for b in range(3):
                local[j, a, b] = rotations[j, a, b]


@numba.njit(nogil=True, cache=True, boundscheck=False)
def fk_matrices(  # pragma: no cover - compiled
    rotations, translations, order, parents, kinds, keep_root, keep_world, pre, staged, positions, world, local, offsets
):
    """rotations (F, J, 3, 3), translations (F, J, 3) -> positions (F, J, 3) and world:
    (F, J, 3, 3) when ``keep_world`` (every frame's world rotations), else (1, J, 3, 3)
    scratch. When ``staged`` (increasing joint indices) is not empty, the rotations of
    those joints and all translations of each frame are first copied, in memory order, into
    the scratch ``local`` (J, 3, 3) and ``offsets`` (J, 3): the walk in tree order then
    reads from L1 instead of jumping about in memory the prefetchers cannot follow."""
    stage = staged.shape[0] > 0
    for f in range(rotations.shape[0]):
        w = world[f] if keep_world else world[0]
        if stage:
            _stage(rotations[f], translations[f], staged, local, offsets)
            _frame(local, offsets, order, parents, kinds, keep_root, keep_world, pre, positions[f], w)
        else:
            _frame(rotations[f], translations[f], order, parents, kinds, keep_root, keep_world, pre, positions[f], w)


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
    a rotation matrix, computed in memory order. scratch (2, J, 3, 3): local and world
    rotations of one frame; offsets (J, 3): the frame's translations, copied there in
    memory order first when ``staged`` (the walk is not in memory order)."""
    local = scratch[0]
    world = scratch[1]
    n_joints = angles.shape[1]
    for f in range(angles.shape[0]):
        for j in range(n_joints):
            if needed[j]:
                _euler_matrix(angles[f, j, 0], angles[f, j, 1], angles[f, j, 2], codes[j], local[j])
        if staged:
            for j in range(n_joints):
                for a in range(3):
                    offsets[j, a] = translations[f, j, a]
            _frame(local, offsets, order, parents, kinds, keep_root, False, pre, positions[f], world)
        else:
            _frame(local, translations[f], order, parents, kinds, keep_root, False, pre, positions[f], world)


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
def signed_gather(rows, first, index, factor, scale, shift, start, stop, out):  # pragma: no cover - compiled
    """out[f, i] = (factor[i] * rows[first + f, index[i]]) * scale + shift[i] for frames
    start..stop-1 of ``out`` (F', W'): every output number one input number of its frame's
    row, signed, scaled and shifted (the axes of each joint's vector or matrix permuted)."""
    for f in range(start, stop):
        source = rows[first + f]
        target = out[f]
        for i in range(index.shape[0]):
            target[i] = (factor[i] * source[index[i]]) * scale + shift[i]
