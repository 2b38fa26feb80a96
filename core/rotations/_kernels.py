"""Compiled quaternion -> matrix conversion (numba); imported by :mod:`core.rotations.quaternions` only.

Importing this module raises ImportError when numba is not installed; the conversion then
runs its numpy path (:func:`core.rotations.quaternions.matrix_from_quaternion`), the
reference this kernel is tested against. The kernel performs the same operations in the
same order, one quaternion at a time with its products in registers instead of numpy's
temporary arrays; numba compiles without fast-math (no reassociation, no fused
multiply-adds) and divides as numpy does (a zero quaternion gives NaN, not an
error), so the matrices are the numpy path's bit for bit.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(boundscheck=False, cache=True, error_model="numpy")
def matrices_of_quaternions(quaternions, first, out):  # pragma: no cover - compiled
    """Rotation matrices of quaternions (N, 4), float64 or float32, into ``out`` (N, 3, 3)
    float64; ``first`` is the index of the scalar component (0 for ``w, x, y, z``, 3 for
    ``x, y, z, w``). A single quaternion (1, 4) fills every matrix of ``out``."""
    one = quaternions.shape[0] == 1
    axis = 1 if first == 0 else 0
    for n in range(out.shape[0]):
        row = 0 if one else n
        w = np.float64(quaternions[row, first])  # float32 quaternions are worked on in float64
        x = np.float64(quaternions[row, axis])
        y = np.float64(quaternions[row, axis + 1])
        z = np.float64(quaternions[row, axis + 2])
        two = 2.0 / (w * w + x * x + y * y + z * z)
        x2 = x * two
        y2 = y * two
        z2 = z * two
        xx = x * x2
        yy = y * y2
        zz = z * z2
        xy = x * y2
        xz = x * z2
        yz = y * z2
        wx = w * x2
        wy = w * y2
        wz = w * z2
        out[n, 0, 0] = 1 - (yy + zz)
        out[n, 0, 1] = xy - wz
        out[n, 0, 2] = xz + wy
        out[n, 1, 0] = xy + wz
        out[n, 1, 1] = 1 - (xx + zz)
        out[n, 1, 2] = yz - wx
        out[n, 2, 0] = xz - wy
        out[n, 2, 1] = yz + wx
        out[n, 2, 2] = 1 - (xx + yy)
