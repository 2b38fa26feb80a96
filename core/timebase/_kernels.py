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


@numba.njit(boundscheck=False)
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
    Rodrigues' formula on ``u``, steps of 60 degrees or more by the far formula).

    Each frame in three passes over its joints (``u`` and the cosine; the two factors;
    the rotations): the square roots, divisions and the arcsine and sine of one joint do
    not wait for another's, so that the processor overlaps them."""
    n_columns = columns.shape[0]
    u = np.empty((n_columns, 3))
    factors = np.empty((n_columns, 2))
    far = np.empty(n_columns, np.bool_)
    for f in range(out.shape[0]):
        w = weight[f]
        lo = low[f]
        hi = high[f]
        for n in range(n_columns):
            j = columns[n]
            dot = 0.0
            for a in range(3):
                for b in range(3):
                    dot += rotations[lo, j, a, b] * rotations[hi, j, a, b]
            far[n] = (dot - 1.0) * 0.5 < 0.5
            u[n, 0] = _row_cross(rotations, lo, hi, j, 1, 2)
            u[n, 1] = _row_cross(rotations, lo, hi, j, 2, 0)
            u[n, 2] = _row_cross(rotations, lo, hi, j, 0, 1)
        for n in range(n_columns):
            sin = math.sqrt((u[n, 0] * u[n, 0] + u[n, 1] * u[n, 1]) + u[n, 2] * u[n, 2]) * 0.5
            h = math.sin(math.asin(min(sin, 1.0)) * w * 0.5)
            if sin == 0.0:
                sin = 1.0
            q = h / sin
            root = math.sqrt(1.0 - h * h)
            factors[n, 0] = q * root
            factors[n, 1] = q * 0.5 / root
        for n in range(n_columns):
            j = columns[n]
            if far[n]:
                _slerp_far(rotations[lo, j], rotations[hi, j], w, out[f, n])
                continue
            qa = factors[n, 0]
            qb = factors[n, 1]
            a0, a1, a2 = u[n, 0] * qa, u[n, 1] * qa, u[n, 2] * qa
            b0, b1, b2 = u[n, 0] * qb, u[n, 1] * qb, u[n, 2] * qb
            for c in range(3):
                r0c0 = rotations[lo, j, 0, c]
                r0c1 = rotations[lo, j, 1, c]
                r0c2 = rotations[lo, j, 2, c]
                x0 = a1 * r0c2 - a2 * r0c1
                x1 = a2 * r0c0 - a0 * r0c2
                x2 = a0 * r0c1 - a1 * r0c0
                out[f, n, 0, c] = (x0 + r0c0) + (b1 * x2 - b2 * x1)
                out[f, n, 1, c] = (x1 + r0c1) + (b2 * x0 - b0 * x2)
                out[f, n, 2, c] = (x2 + r0c2) + (b0 * x1 - b1 * x0)


@numba.njit(inline="always", boundscheck=False)
def _row_cross(rotations, lo, hi, j, a, b):  # pragma: no cover - compiled
    """Component of ``u`` from rows a and b: R_0[a] . R_1[b] - R_0[b] . R_1[a]."""
    first = (rotations[lo, j, a, 0] * rotations[hi, j, b, 0] + rotations[lo, j, a, 1] * rotations[hi, j, b, 1]) + (
        rotations[lo, j, a, 2] * rotations[hi, j, b, 2]
    )
    second = (rotations[lo, j, b, 0] * rotations[hi, j, a, 0] + rotations[lo, j, b, 1] * rotations[hi, j, a, 1]) + (
        rotations[lo, j, b, 2] * rotations[hi, j, a, 2]
    )
    return first - second


@numba.njit(nogil=True, cache=True, boundscheck=False)
def lerp_rows(values, low, high, weight, out):  # pragma: no cover - compiled
    """out[f, i] = a + (b - a) * weight[f] with a = values[low[f], i], b = values[high[f], i]
    (rows of numbers): the operations of :func:`core.timebase.sampling.interpolate`'s numpy
    path, in one pass."""
    for f in range(out.shape[0]):
        w = weight[f]
        lo = low[f]
        hi = high[f]
        for i in range(out.shape[1]):
            a = values[lo, i]
            out[f, i] = a + (values[hi, i] - a) * w
