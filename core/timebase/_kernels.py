"""Compiled slerp of rotation matrices (numba); imported by :mod:`core.timebase.sampling` only.

Importing this module raises ImportError when numba is not installed; the interpolator then
runs its numpy path (:func:`core.timebase.sampling.slerp_component_major`), the reference
this kernel is tested against. The kernel performs the same operations in the same order,
one sample at a time with the matrices in registers instead of numpy's component planes;
sine, cosine and arcsine come from the C library rather than numpy's own, so the results
may differ in the last bits.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(inline="always", boundscheck=False)
def _slerp_far(r0, r1, weight, out):  # pragma: no cover - compiled
    """:func:`core.timebase.sampling._slerp_far` for one sample: r0, r1, out (3, 3)."""
    rel = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            rel[a, b] = (r0[0, a] * r1[0, b] + r0[1, a] * r1[1, b]) + r0[2, a] * r1[2, b]
    s0 = rel[2, 1] - rel[1, 2]
    s1 = rel[0, 2] - rel[2, 0]
    s2 = rel[1, 0] - rel[0, 1]
    cos = 0.5 * (rel[0, 0] + rel[1, 1] + rel[2, 2] - 1.0)
    angle = math.atan2(0.5 * math.sqrt(s0 * s0 + s1 * s1 + s2 * s2), cos)
    pick = 0
    best = -np.inf
    for a in range(3):
        value = rel[a, a] - cos
        if value > best:
            best = value
            pick = a
    c0 = 0.5 * (rel[0, pick] + rel[pick, 0]) - (cos if pick == 0 else 0.0)
    c1 = 0.5 * (rel[1, pick] + rel[pick, 1]) - (cos if pick == 1 else 0.0)
    c2 = 0.5 * (rel[2, pick] + rel[pick, 2]) - (cos if pick == 2 else 0.0)
    norm = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    x = c0 / norm
    y = c1 / norm
    z = c2 / norm
    if x * s0 + y * s1 + z * s2 < 0.0:
        x, y, z = -x, -y, -z
    turn = weight * angle
    sn = math.sin(turn)
    vers = 1.0 - math.cos(turn)
    k = np.zeros((3, 3))
    k[0, 1], k[0, 2], k[1, 2] = -z, y, -x
    k[1, 0], k[2, 0], k[2, 1] = z, -y, x
    step = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            kk = (k[a, 0] * k[0, b] + k[a, 1] * k[1, b]) + k[a, 2] * k[2, b]
            step[a, b] = (1.0 if a == b else 0.0) + sn * k[a, b] + vers * kk
    for a in range(3):
        for b in range(3):
            out[a, b] = (r0[a, 0] * step[0, b] + r0[a, 1] * step[1, b]) + r0[a, 2] * step[2, b]


@numba.njit(nogil=True, cache=True, boundscheck=False)
def slerp_rows(rotations, low, high, weight, columns, out):  # pragma: no cover - compiled
    """out[f, n] = the rotation ``weight[f]`` of the way along the geodesic from
    rotations[low[f], columns[n]] to rotations[high[f], columns[n]] (each (3, 3)), as
    :func:`core.timebase.sampling.slerp_component_major` computes it (near steps by
    Rodrigues' formula on ``u``, steps of 60 degrees or more by the far formula)."""
    u = np.empty(3)
    for f in range(out.shape[0]):
        w = weight[f]
        for n in range(columns.shape[0]):
            j = columns[n]
            r0 = rotations[low[f], j]
            r1 = rotations[high[f], j]
            o = out[f, n]
            for i in range(3):
                a = (i + 1) % 3
                b = (i + 2) % 3
                u[i] = ((r0[a, 0] * r1[b, 0] + r0[a, 1] * r1[b, 1]) + r0[a, 2] * r1[b, 2]) - (
                    (r0[b, 0] * r1[a, 0] + r0[b, 1] * r1[a, 1]) + r0[b, 2] * r1[a, 2]
                )
            dot = 0.0
            for a in range(3):
                for b in range(3):
                    dot += r0[a, b] * r1[a, b]
            cos = (dot - 1.0) * 0.5
            if cos < 0.5:
                _slerp_far(r0, r1, w, o)
                continue
            sin = math.sqrt((u[0] * u[0] + u[1] * u[1]) + u[2] * u[2]) * 0.5
            h = math.sin(math.asin(min(sin, 1.0)) * w * 0.5)
            if sin == 0.0:
                sin = 1.0
            q = h / sin
            root = math.sqrt(1.0 - h * h)
            qa = q * root
            qb = q * 0.5 / root
            a0, a1, a2 = u[0] * qa, u[1] * qa, u[2] * qa
            b0, b1, b2 = u[0] * qb, u[1] * qb, u[2] * qb
            for c in range(3):
                x0 = a1 * r0[2, c] - a2 * r0[1, c]
                x1 = a2 * r0[0, c] - a0 * r0[2, c]
                x2 = a0 * r0[1, c] - a1 * r0[0, c]
                o[0, c] = (x0 + r0[0, c]) + (b1 * x2 - b2 * x1)
                o[1, c] = (x1 + r0[1, c]) + (b2 * x0 - b0 * x2)
                o[2, c] = (x2 + r0[2, c]) + (b0 * x1 - b1 * x0)
