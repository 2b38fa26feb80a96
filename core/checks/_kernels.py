"""Compiled per-frame statistics of the checks (numba); imported by :mod:`core.checks.passes` only.

Importing this module raises ImportError when numba is not installed; the checks then run
the numpy path of :mod:`core.checks.passes`, the reference these kernels are tested
against. Each kernel reads the positions or rotations once, in storage order, and writes
only its small result: no temporaries of the motion's size. The middles are formed with the
numpy path's operations (the same numbers); sums of three products may differ from numpy's
in the last bit.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(nogil=True, cache=True, boundscheck=False)
def second_differences(positions, deviations, products):  # pragma: no cover - compiled
    """positions (F, J, 3) -> deviations (F-2, J): the length of each middle ``m_f = P_f -
    (P_{f-1} + P_{f+1}) / 2`` (frames 1..F-2), and products (F-3, J): ``m_f . m_{f+1}``."""
    n_frames, n_joints = positions.shape[0], positions.shape[1]
    previous = np.empty((n_joints, 3))
    for f in range(n_frames - 2):
        for j in range(n_joints):
            m0 = (positions[f, j, 0] + positions[f + 2, j, 0]) * -0.5 + positions[f + 1, j, 0]
            m1 = (positions[f, j, 1] + positions[f + 2, j, 1]) * -0.5 + positions[f + 1, j, 1]
            m2 = (positions[f, j, 2] + positions[f + 2, j, 2]) * -0.5 + positions[f + 1, j, 2]
            deviations[f, j] = math.sqrt((m0 * m0 + m1 * m1) + m2 * m2)
            if f > 0:
                products[f - 1, j] = (previous[j, 0] * m0 + previous[j, 1] * m1) + previous[j, 2] * m2
            previous[j, 0] = m0
            previous[j, 1] = m1
            previous[j, 2] = m2


@numba.njit(nogil=True, cache=True, boundscheck=False)
def largest_steps(positions, joints, out):  # pragma: no cover - compiled
    """positions (F, J, 3) -> out (F-1,): the largest squared step ``|P_{f+1} - P_f|^2`` of
    the ``joints``, NaN ignored as ``numpy.fmax`` ignores it (NaN when every one is)."""
    for f in range(positions.shape[0] - 1):
        largest = np.nan
        for k in range(joints.shape[0]):
            j = joints[k]
            d0 = positions[f + 1, j, 0] - positions[f, j, 0]
            d1 = positions[f + 1, j, 1] - positions[f, j, 1]
            d2 = positions[f + 1, j, 2] - positions[f, j, 2]
            value = (d0 * d0 + d1 * d1) + d2 * d2
            if math.isnan(largest) or value > largest:
                if not math.isnan(value):
                    largest = value
        out[f] = largest


@numba.njit(nogil=True, cache=True, boundscheck=False)
def step_cosines(rotations, joints, out):  # pragma: no cover - compiled
    """rotations (F, J, 3, 3) -> out (F-1, K): the cosine of the angle of ``R_f^T R_{f+1}``
    of each of the ``joints`` (K,), ``(trace - 1) / 2`` from the sum of the entries'
    products, clipped to [-1, 1] (NaN stays NaN)."""
    for f in range(rotations.shape[0] - 1):
        for k in range(joints.shape[0]):
            j = joints[k]
            total = 0.0
            for a in range(3):
                for b in range(3):
                    total += rotations[f + 1, j, a, b] * rotations[f, j, a, b]
            cos = 0.5 * (total - 1.0)
            if cos < -1.0:
                cos = -1.0
            elif cos > 1.0:
                cos = 1.0
            out[f, k] = cos
