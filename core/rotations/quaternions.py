"""Unit quaternions for curves and resampling, vectorised over any leading shape.

Convention: components ``(w, x, y, z)``, scalar first; ``q`` and ``-q`` are the same
rotation. Rotation matrices follow :mod:`core.rotations.euler` (column vectors, active). The
project stores rotations as matrices (see :mod:`core.model.motion`); quaternions only appear
where they are the natural tool: plotting a rotation as four smooth components and
interpolating between two rotations (slerp).

:func:`matrix_from_quaternion` runs as a compiled kernel when numba is installed and
the process has loaded it already (the app and the commands that run the FK engine do;
:func:`compiled_at_hand`), so that a process converting a few quaternions (the FBX
reader's child process) does not pay for loading it: the numpy path's very operations in
the same order, so the same matrices bit for bit; the numpy path is the reference and the
fallback.
"""

from __future__ import annotations

import sys
from types import ModuleType

import numpy as np

from gmr_studio.core.compiled import Backend, chosen_kernels, optional_kernels

#: below this angle (radians) between two quaternions, slerp falls back to a normalised lerp
SLERP_LINEAR_BELOW = 1e-6


def quaternion_from_matrix(matrices: np.ndarray, *, scalar_last: bool = False) -> np.ndarray:
    """Unit quaternions (w, x, y, z) of rotation matrices, ``w >= 0``: (..., 3, 3) -> (..., 4).

    ``scalar_last``: give them as (x, y, z, w), as glTF stores them.

    Shepperd's method: of the four candidate formulas, each entry uses the one with the
    largest denominator, so the result is accurate for every rotation (including 180 degrees).
    """
    m = np.asarray(matrices, dtype=np.float64)
    m00, m11, m22 = m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]
    trace = m00 + m11 + m22
    candidates = np.stack(
        [
            np.stack(
                [1 + trace, m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1]], -1
            ),
            np.stack(
                [
                    m[..., 2, 1] - m[..., 1, 2],
                    1 + m00 - m11 - m22,
                    m[..., 0, 1] + m[..., 1, 0],
                    m[..., 0, 2] + m[..., 2, 0],
                ],
                -1,
            ),
            np.stack(
                [
                    m[..., 0, 2] - m[..., 2, 0],
                    m[..., 0, 1] + m[..., 1, 0],
                    1 - m00 + m11 - m22,
                    m[..., 1, 2] + m[..., 2, 1],
                ],
                -1,
            ),
            np.stack(
                [
                    m[..., 1, 0] - m[..., 0, 1],
                    m[..., 0, 2] + m[..., 2, 0],
                    m[..., 1, 2] + m[..., 2, 1],
                    1 - m00 - m11 + m22,
                ],
                -1,
            ),
        ],
        axis=-2,
    )  # (..., 4 candidates, 4 components); candidate c has 4 q_c^2 on its diagonal entry c
    best = np.argmax(np.stack([trace, m00, m11, m22], axis=-1), axis=-1)
    chosen = np.take_along_axis(candidates, best[..., None, None], axis=-2)[..., 0, :]
    q = chosen / np.linalg.norm(chosen, axis=-1, keepdims=True)
    q = np.where(q[..., :1] < 0, -q, q)
    return np.roll(q, -1, axis=-1) if scalar_last else q


def compiled_kernels() -> ModuleType | None:
    """:mod:`core.rotations._kernels`, or None without numba (:func:`core.compiled.optional_kernels`)."""
    return optional_kernels("gmr_studio.core.rotations._kernels")


def compiled_at_hand() -> ModuleType | None:
    """:func:`compiled_kernels` when numba is loaded in this process already, else None
    (what the backend 'auto' uses)."""
    return compiled_kernels() if "numba" in sys.modules else None


def matrix_from_quaternion(
    quaternions: np.ndarray,
    *,
    scalar_last: bool = False,
    out: np.ndarray | None = None,
    backend: Backend = "auto",
) -> np.ndarray:
    """Rotation matrices of quaternions (w, x, y, z), normalised first: (..., 4) -> (..., 3, 3)
    float64, worked out in float64 (float32 quaternions as well).

    ``scalar_last``: the quaternions are (x, y, z, w), as glTF stores them; ``out``: an
    array (..., 3, 3) to write the matrices into (returned); a single quaternion (1, 4)
    with ``out`` (N, 3, 3) fills all N. ``backend``: 'numba' (the compiled kernel, for
    quaternions (N, 4)), 'numpy', or 'auto' (numba when :func:`compiled_at_hand` and the
    shape is (N, 4)); both give the same matrices bit for bit.
    """
    kernels = chosen_kernels(backend, compiled_kernels() if backend == "numba" else compiled_at_hand())
    q = np.asarray(quaternions)
    if q.dtype != np.float32:  # float32 (a file's keys) is converted as it is read: the same numbers
        q = q.astype(np.float64, copy=False)
    if kernels is not None and q.ndim == 2 and q.shape[-1] == 4 and (out is None or out.ndim == 3):
        out = np.empty((len(q), 3, 3)) if out is None else out
        if out.shape[1:] != (3, 3) or len(q) not in (1, len(out)):
            raise ValueError(f"quaternions {q.shape} do not fit matrices {out.shape}")
        kernels.matrices_of_quaternions(q, 3 if scalar_last else 0, out)
        return out
    if backend == "numba":
        raise ValueError(f"the numba backend converts quaternions (N, 4), not {q.shape}")
    q = q.astype(np.float64, copy=False)
    if scalar_last:
        x, y, z, w = np.moveaxis(q, -1, 0)
    else:
        w, x, y, z = np.moveaxis(q, -1, 0)
    two = 2.0 / (w * w + x * x + y * y + z * z)  # normalising: each product below is of two components
    x2, y2, z2 = x * two, y * two, z * two  # one product per pair, not per entry (large arrays: memory-bound)
    xx, yy, zz, xy, xz, yz = x * x2, y * y2, z * z2, x * y2, x * z2, y * z2
    wx, wy, wz = w * x2, w * y2, w * z2
    out = np.empty((*q.shape[:-1], 3, 3)) if out is None else out
    out[..., 0, 0] = 1 - (yy + zz)
    out[..., 0, 1] = xy - wz
    out[..., 0, 2] = xz + wy
    out[..., 1, 0] = xy + wz
    out[..., 1, 1] = 1 - (xx + zz)
    out[..., 1, 2] = yz - wx
    out[..., 2, 0] = xz - wy
    out[..., 2, 1] = yz + wx
    out[..., 2, 2] = 1 - (xx + yy)
    return out


def slerp(q0: np.ndarray, q1: np.ndarray, fraction: np.ndarray) -> np.ndarray:
    """Spherical linear interpolation along the shorter arc: (..., 4), (..., 4), (...) -> (..., 4).

    ``fraction`` 0 gives ``q0`` and 1 gives ``q1`` (up to sign: the shorter arc may end at
    ``-q1``, the same rotation). Nearly equal quaternions use a normalised lerp.
    """
    q0 = np.asarray(q0, dtype=np.float64)
    q1 = np.asarray(q1, dtype=np.float64)
    t = np.asarray(fraction, dtype=np.float64)[..., None]
    dot = np.sum(q0 * q1, axis=-1, keepdims=True)
    q1 = np.where(dot < 0, -q1, q1)
    dot = np.abs(dot)
    angle = np.arccos(np.clip(dot, -1.0, 1.0))
    sin_angle = np.sin(angle)
    small = angle < SLERP_LINEAR_BELOW
    safe = np.where(small, 1.0, sin_angle)
    w0 = np.where(small, 1.0 - t, np.sin((1.0 - t) * angle) / safe)
    w1 = np.where(small, t, np.sin(t * angle) / safe)
    out = w0 * q0 + w1 * q1
    return out / np.linalg.norm(out, axis=-1, keepdims=True)
