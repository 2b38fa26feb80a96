"""Compiled kernel of the FBX reader (numba); imported by :mod:`.compiled_pose` only.

Importing this module raises ImportError when numba is not installed; the reader then
composes the skeleton with numpy (:func:`core.formats.gltf_in.pose.skeleton_pose`, the
reference), whose operations the kernel performs one frame at a time.
"""

from __future__ import annotations

import numba
import numpy as np

from gmr_studio.core.edits._kernels import _load, _mul, _times, _transposed

#: frames whose translations and scales are gathered at a time (into a buffer that stays in cache)
TILE_FRAMES = 128


@numba.njit(inline="always", boundscheck=False)
def _gather(planes, extra, rows, constants, first, stop, values):  # pragma: no cover - compiled
    """values[f - first, j, k] for frames first..stop-1: component ``k`` of joint ``j``, a
    row of ``planes`` (rows[j, k] >= 0), a row of ``extra`` (rows[j, k] = -2 - that row)
    or ``constants[j, k]`` (-1); each row read along the frames."""
    for j in range(rows.shape[0]):
        for k in range(rows.shape[1]):
            row = rows[j, k]
            if row >= 0:
                for f in range(first, stop):
                    values[f - first, j, k] = planes[row, f]
            elif row == -1:
                for f in range(first, stop):
                    values[f - first, j, k] = constants[j, k]
            else:
                for f in range(first, stop):
                    values[f - first, j, k] = extra[-2 - row, f]


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
    bound,
    left,
    right,
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
    ``base_place`` (J, 3), ``base_stretch`` (J, 3, 3), read for roots only). When
    ``bound``, each rotation then becomes ``left[j] R right[j]`` and each translation
    ``left[j] t`` (the rest orientations taken out, :func:`core.formats.gltf_in.rest.bind_turns`).

    rotations (F, J, 3, 3): the joints' local rotations; planes (C, F) and extra (E, F):
    rows of values over the frames; rows (J, 6) int64: where each joint's translation and
    scale (x y z each) are (:func:`_gather`), constants (J, 6); parents (J,) int64, every
    parent before its children (-1 for roots); inner (J,) bool: the joints with children
    (the others carry no scale on).
    spread and size (J,): the largest distance of each translation from ``first`` (J, 3)
    and its largest component, over these frames (NaN when a translation is NaN)."""
    n_joints = parents.shape[0]
    stretch = np.empty((n_joints, 3, 3))
    for j in range(n_joints):
        spread[j] = 0.0
        size[j] = 0.0
    values = np.empty((TILE_FRAMES, n_joints, 6))
    for tile in range(start, stop, TILE_FRAMES):
        end = min(tile + TILE_FRAMES, stop)
        _gather(planes, extra, rows, constants, tile, end, values)
        for f in range(tile, end):
            _frame(rotations[f], values[f - tile], parents, inner, turned, base_turn, base_place, base_stretch, stretch,
                   bound, left, right, first, translations[f], spread, size)  # fmt: skip


@numba.njit(inline="always", boundscheck=False)
def _frame(  # pragma: no cover - compiled
    frame, values, parents, inner, turned, base_turn, base_place, base_stretch, stretch, bound, left, right, first,
    out, spread, size
):  # fmt: skip
    """One frame of :func:`carried_translations`: ``values`` (J, 6) its translations and
    scales, ``frame`` (J, 3, 3) its rotations (rewritten where turned), ``out`` (J, 3)."""
    for j in range(parents.shape[0]):
        t0 = values[j, 0]
        t1 = values[j, 1]
        t2 = values[j, 2]
        p = parents[j]
        m = _load(base_stretch[j]) if p < 0 else _load(stretch[p])
        x0, x1, x2 = _times(m, t0, t1, t2)
        if p < 0:
            y0, y1, y2 = _times(_load(base_turn[j]), x0, x1, x2)
            x0 = base_place[j, 0] + y0
            x1 = base_place[j, 1] + y1
            x2 = base_place[j, 2] + y2
        r = _load(frame[j])
        if inner[j]:  # R^T (M R) S
            q = _mul(_transposed(r), _mul(m, r))
            for b in range(3):
                scale = values[j, 3 + b]
                stretch[j, 0, b] = q[b] * scale
                stretch[j, 1, b] = q[3 + b] * scale
                stretch[j, 2, b] = q[6 + b] * scale
        if p < 0 and turned[j]:  # U R
            r = _mul(_load(base_turn[j]), r)
        if bound:
            r = _mul(_mul(_load(left[j]), r), _load(right[j]))
            out[j, 0], out[j, 1], out[j, 2] = _times(_load(left[j]), x0, x1, x2)
        else:
            out[j, 0] = x0
            out[j, 1] = x1
            out[j, 2] = x2
        if bound or (p < 0 and turned[j]):
            for a in range(3):
                for b in range(3):
                    frame[j, a, b] = r[3 * a + b]
        d0 = abs(x0 - first[j, 0])
        d1 = abs(x1 - first[j, 1])
        d2 = abs(x2 - first[j, 2])
        if not (d0 == d0 and d1 == d1 and d2 == d2 and x0 == x0 and x1 == x1 and x2 == x2):
            spread[j] = np.nan
            size[j] = np.nan
        elif spread[j] == spread[j]:
            spread[j] = max(spread[j], max(d0, max(d1, d2)))
            size[j] = max(size[j], max(abs(x0), max(abs(x1), abs(x2))))
