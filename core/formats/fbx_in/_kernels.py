"""Compiled kernel of the FBX reader (numba); imported by :mod:`.compiled_pose` only.

Importing this module raises ImportError when numba is not installed; the reader then
composes the skeleton with numpy (:func:`core.formats.gltf_in.pose.skeleton_pose`, the
reference), whose operations the kernel performs one frame at a time.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(inline="always", boundscheck=False)
def _value(planes, extra, rows, constants, j, k, f):  # pragma: no cover - compiled
    """Component ``k`` of joint ``j`` at frame ``f``: a row of ``planes`` (rows[j, k] >= 0),
    a row of ``extra`` (rows[j, k] = -2 - that row) or ``constants[j, k]`` (-1)."""
    row = rows[j, k]
    if row >= 0:
        return planes[row, f]
    if row == -1:
        return constants[j, k]
    return extra[-2 - row, f]


@numba.njit(nogil=True, cache=True, boundscheck=False)
def carried_translations(  # pragma: no cover - compiled
    rotations,
    planes,
    extra,
    rows,
    constants,
    parents,
    inner,
    turned,
    base_turn,
    base_place,
    base_stretch,
    first,
    start,
    stop,
    translations,
    spread,
    size,
):
    """Frames start..stop-1: each joint's translation carried through the scales above it
    (:mod:`core.formats.gltf_in.pose`: ``M_p t_j``, ``M_j = R_j^T M_p R_j S_j``), written
    to ``translations`` (F, J, 3); a root's is ``P_a + U_a M_a t`` and, where ``turned``,
    its rotation becomes ``U_a R`` (the armature above it: ``base_turn`` (J, 3, 3),
    ``base_place`` (J, 3), ``base_stretch`` (J, 3, 3), read for roots only).

    rotations (F, J, 3, 3): the joints' local rotations; planes (C, F) and extra (E, F):
    rows of values over the frames; rows (J, 6) int64: where each joint's translation and
    scale (x y z each) are (:func:`_value`), constants (J, 6); parents (J,) int64, every
    parent before its children (-1 for roots); inner (J,) bool: the joints with children
    (the others carry no scale on).
    spread and size (J,): the largest distance of each translation from ``first`` (J, 3)
    and its largest component, over these frames (NaN when a translation is NaN)."""
    n_joints = parents.shape[0]
    stretch = np.empty((n_joints, 3, 3))
    carried = np.empty((3, 3))
    product = np.empty((3, 3))
    for j in range(n_joints):
        spread[j] = 0.0
        size[j] = 0.0
    for f in range(start, stop):
        for j in range(n_joints):
            t0 = _value(planes, extra, rows, constants, j, 0, f)
            t1 = _value(planes, extra, rows, constants, j, 1, f)
            t2 = _value(planes, extra, rows, constants, j, 2, f)
            p = parents[j]
            for a in range(3):
                for b in range(3):
                    carried[a, b] = base_stretch[j, a, b] if p < 0 else stretch[p, a, b]
            x0 = (carried[0, 0] * t0 + carried[0, 1] * t1) + carried[0, 2] * t2
            x1 = (carried[1, 0] * t0 + carried[1, 1] * t1) + carried[1, 2] * t2
            x2 = (carried[2, 0] * t0 + carried[2, 1] * t1) + carried[2, 2] * t2
            if p < 0:
                y0 = (base_turn[j, 0, 0] * x0 + base_turn[j, 0, 1] * x1) + base_turn[j, 0, 2] * x2
                y1 = (base_turn[j, 1, 0] * x0 + base_turn[j, 1, 1] * x1) + base_turn[j, 1, 2] * x2
                y2 = (base_turn[j, 2, 0] * x0 + base_turn[j, 2, 1] * x1) + base_turn[j, 2, 2] * x2
                x0 = base_place[j, 0] + y0
                x1 = base_place[j, 1] + y1
                x2 = base_place[j, 2] + y2
            if inner[j]:  # R^T (M R) S
                for b in range(3):
                    r0 = rotations[f, j, 0, b]
                    r1 = rotations[f, j, 1, b]
                    r2 = rotations[f, j, 2, b]
                    for a in range(3):
                        product[a, b] = (carried[a, 0] * r0 + carried[a, 1] * r1) + carried[a, 2] * r2
                for a in range(3):
                    r0 = rotations[f, j, 0, a]
                    r1 = rotations[f, j, 1, a]
                    r2 = rotations[f, j, 2, a]
                    for b in range(3):
                        scale = _value(planes, extra, rows, constants, j, 3 + b, f)
                        stretch[j, a, b] = ((r0 * product[0, b] + r1 * product[1, b]) + r2 * product[2, b]) * scale
            if p < 0 and turned[j]:  # U R, by columns
                for b in range(3):
                    r0 = rotations[f, j, 0, b]
                    r1 = rotations[f, j, 1, b]
                    r2 = rotations[f, j, 2, b]
                    for a in range(3):
                        rotations[f, j, a, b] = (base_turn[j, a, 0] * r0 + base_turn[j, a, 1] * r1) + base_turn[
                            j, a, 2
                        ] * r2
            translations[f, j, 0] = x0
            translations[f, j, 1] = x1
            translations[f, j, 2] = x2
            d0 = abs(x0 - first[j, 0])
            d1 = abs(x1 - first[j, 1])
            d2 = abs(x2 - first[j, 2])
            if not (d0 == d0 and d1 == d1 and d2 == d2 and x0 == x0 and x1 == x1 and x2 == x2):
                spread[j] = np.nan
                size[j] = np.nan
            elif spread[j] == spread[j]:
                spread[j] = max(spread[j], max(d0, max(d1, d2)))
                size[j] = max(size[j], max(abs(x0), max(abs(x1), abs(x2))))
