"""Rotation matrices and intrinsic Euler angles, vectorised over any leading shape.

Conventions (the only place they are fixed):

- Column vectors: a rotation ``R`` maps a vector ``v`` to ``R @ v``.
- Euler orders are *intrinsic* and read left to right, as BVH reads its channels:
  order ``"ZXY"`` with angles ``(z, x, y)`` means ``R = Rz(z) @ Rx(x) @ Ry(y)``.
- Angles are radians here; degrees only exist in files (the I/O layer converts).
- An order is a string of one to three distinct axis letters. Orders shorter than three
  (a BVH joint with ``CHANNELS 1 Zrotation``) are completed with the missing axes,
  whose angles are zero, so every order maps to one of the six Tait-Bryan orders.

Why hand-written rather than ``scipy.spatial.transform.Rotation``: the closed forms below
fill the nine matrix entries from the sines and cosines directly, vectorised over frames and
joints, where scipy goes through quaternions and is several times slower on millions of
rotations. scipy stays the independent oracle in the tests.
"""

from __future__ import annotations

import itertools

import numpy as np

AXIS_LETTERS = "XYZ"
EULER_ORDERS = ("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX")

#: below this, cos(middle angle) counts as zero and the first and last axes coincide (the
#: last angle is then 0; above it, the residual step below keeps the matrix exact)
GIMBAL_EPSILON = 1e-15
#: below this cos(middle angle), the last angle is taken from the rotation left over by the
#: first two (see :func:`euler_from_matrix`): near gimbal lock the first and last angles
#: each lose digits (their errors grow as eps / cos), and only this keeps the matrix they
#: make equal to the input to rounding
NEAR_GIMBAL = 1e-2
#: rotations :func:`matrix_from_euler` fills at a time: the chunk of the output and the
#: temporaries stay in cache while each of the nine entries is written
CHUNK_ANGLES = 4096


def check_order(order: str) -> str:
    """Return ``order`` upper-cased if it names 1 to 3 distinct axes, else raise ValueError."""
    upper = order.upper()
    if not 1 <= len(upper) <= 3 or set(upper) - set(AXIS_LETTERS) or len(set(upper)) != len(upper):
        raise ValueError(f"rotation order {order!r} must be 1 to 3 distinct letters from X, Y, Z")
    return upper


def complete_order(order: str) -> str:
    """The Tait-Bryan order that starts with ``order`` and adds the missing axes in XYZ order."""
    order = check_order(order)
    return order + "".join(axis for axis in AXIS_LETTERS if axis not in order)


def _indices_and_parity(order: str) -> tuple[int, int, int, float]:
    i, j, k = (AXIS_LETTERS.index(axis) for axis in complete_order(order))
    parity = 1.0 if (j - i) % 3 == 1 else -1.0  # +1 for cyclic orders XYZ, YZX, ZXY
    return i, j, k, parity


def matrix_from_euler(angles: np.ndarray, order: str) -> np.ndarray:
    """Rotation matrices from intrinsic Euler angles.

    Parameters
    ----------
    angles : array (..., n), radians, ``angles[..., m]`` about axis ``order[m]``; ``n`` is
        ``len(order)`` (1 to 3).
    order : axis letters, composition order left to right.

    Returns
    -------
    array (..., 3, 3) float64: ``R = R_order[0](a) @ R_order[1](b) @ R_order[2](c)``,
    filled :data:`CHUNK_ANGLES` rotations at a time.
    """
    angles = np.asarray(angles, dtype=np.float64)
    n = len(check_order(order))
    if angles.shape[-1:] != (n,):
        raise ValueError(f"angles of shape {angles.shape} do not match order {order!r}")
    flat = angles.reshape(-1, n)
    out = np.empty((len(flat), 3, 3))
    indices = _indices_and_parity(order)
    for start in range(0, len(flat), CHUNK_ANGLES):
        _fill_matrices(flat[start : start + CHUNK_ANGLES], indices, out[start : start + CHUNK_ANGLES])
    return out.reshape(*angles.shape[:-1], 3, 3)


def _fill_matrices(angles: np.ndarray, indices: tuple[int, int, int, float], out: np.ndarray) -> None:
    """Write the matrices (N, 3, 3) of angles (N, n) into ``out``."""
    i, j, k, e = indices
    n = angles.shape[1]
    zero = np.zeros(len(angles))
    a = angles[:, 0]
    b = angles[:, 1] if n > 1 else zero
    c = angles[:, 2] if n > 2 else zero
    ca, sa = np.cos(a), np.sin(a)
    cb, sb = np.cos(b), np.sin(b)
    cc, sc = np.cos(c), np.sin(c)
    out[:, i, i] = cb * cc
    out[:, i, j] = -e * cb * sc
    out[:, i, k] = e * sb
    sa_sb = sa * sb
    ca_sb = ca * sb
    out[:, j, i] = e * ca * sc + sa_sb * cc
    out[:, j, j] = ca * cc - e * sa_sb * sc
    out[:, j, k] = -e * sa * cb
    out[:, k, i] = sa * sc - e * ca_sb * cc
    out[:, k, j] = e * sa * cc + ca_sb * sc
    out[:, k, k] = ca * cb


def euler_from_matrix(matrices: np.ndarray, order: str) -> np.ndarray:
    """Intrinsic Euler angles of rotation matrices, the inverse of :func:`matrix_from_euler`.

    Parameters
    ----------
    matrices : array (..., 3, 3), proper rotations.
    order : 3 distinct axis letters.

    Returns
    -------
    array (..., 3), radians, the first and last angle in (-pi, pi], the middle one in
    [-pi/2, pi/2]. At gimbal lock (middle angle +-90 degrees) the last angle is set to 0
    and the first carries the whole rotation about the coincident axes. Near it (cos of
    the middle angle below :data:`NEAR_GIMBAL`), the last angle is that of the rotation
    ``(R_first R_middle)^T R`` left over by the other two, so that the angles rebuild the
    matrix to rounding even where each of them is ill-conditioned (a hip a few thousandths
    of a degree from lock, as in real takes).
    """
    matrices = np.asarray(matrices, dtype=np.float64)
    if len(check_order(order)) != 3:
        raise ValueError(f"euler_from_matrix needs a three-axis order, got {order!r}")
    i, j, k, e = _indices_and_parity(order)
    r_ii = matrices[..., i, i]
    r_ij = matrices[..., i, j]
    cos_b = np.hypot(r_ii, r_ij)
    middle = np.arctan2(e * matrices[..., i, k], cos_b)
    first = np.arctan2(-e * matrices[..., j, k], matrices[..., k, k])
    last = np.arctan2(-e * r_ij, r_ii)
    locked = cos_b < GIMBAL_EPSILON
    if np.any(locked):
        first = np.where(locked, np.arctan2(e * matrices[..., k, j], matrices[..., j, j]), first)
        last = np.where(locked, 0.0, last)
    near = (cos_b < NEAR_GIMBAL) & ~locked
    if np.any(near):
        last = np.array(last, dtype=np.float64, copy=True)
        zero = np.zeros(int(near.sum()))
        two = matrix_from_euler(np.stack([first[near], middle[near], zero], axis=-1), order[:3])
        rest = matrices[near]
        # the leftover rotation about axis k (the last axis): Q = two^T R, Q[n2, n1] = sin,
        # Q[n1, n1] = cos with (k, n1, n2) cyclic
        n1, n2 = (k + 1) % 3, (k + 2) % 3
        sine = np.einsum("...a,...a->...", two[..., :, n2], rest[..., :, n1])
        cosine = np.einsum("...a,...a->...", two[..., :, n1], rest[..., :, n1])
        last[near] = np.arctan2(sine, cosine)
    return np.stack([first, middle, last], axis=-1)


def rotation_about_axis(axis: str, angles: np.ndarray) -> np.ndarray:
    """Elementary rotations about ``axis`` ('X', 'Y' or 'Z'): angles (...) -> (..., 3, 3)."""
    return matrix_from_euler(np.asarray(angles, dtype=np.float64)[..., None], axis)


def nearest_rotation(matrices: np.ndarray) -> np.ndarray:
    """The proper rotation nearest each matrix in the Frobenius norm (orthogonal Procrustes).

    ``M = U S V^T`` gives ``R = U V^T``; when ``det(U V^T) < 0`` the last column of ``U`` is
    negated so the result is a rotation, not a reflection. matrices (..., 3, 3) -> (..., 3, 3).
    """
    u, _, vt = np.linalg.svd(np.asarray(matrices, dtype=np.float64))
    flip = np.linalg.det(u @ vt) < 0
    u[..., :, 2] = np.where(flip[..., None], -u[..., :, 2], u[..., :, 2])
    return u @ vt


def rotation_angle(matrices: np.ndarray) -> np.ndarray:
    """Angle in radians of each rotation (the geodesic distance to identity): (..., 3, 3) -> (...)."""
    matrices = np.asarray(matrices, dtype=np.float64)
    trace = np.trace(matrices, axis1=-2, axis2=-1)
    # the antisymmetric part gives sin, the trace gives cos: atan2 is accurate at 0 and pi
    skew = np.stack(
        [
            matrices[..., 2, 1] - matrices[..., 1, 2],
            matrices[..., 0, 2] - matrices[..., 2, 0],
            matrices[..., 1, 0] - matrices[..., 0, 1],
        ],
        axis=-1,
    )
    return np.arctan2(0.5 * np.linalg.norm(skew, axis=-1), 0.5 * (trace - 1.0))


#: the largest departure of ``R^T R`` from the identity (any entry) that
#: :func:`orthonormalize` leaves as it is: far below any length or angle a motion holds,
#: far above the rounding of a product of a few rotations
ORTHONORMAL_TOLERANCE = 1e-13


def orthonormalize(matrices: np.ndarray, iterations: int = 2) -> np.ndarray:
    """Nearly-orthonormal matrices made orthonormal to rounding: (..., 3, 3) -> (..., 3, 3).

    Newton-Schulz steps towards the polar factor, ``R <- R (3 I - R^T R) / 2``: the error
    ``|R^T R - I|`` squares at each step, so two steps take 1e-7 to rounding level. A
    matrix whose ``R^T R`` is within :data:`ORTHONORMAL_TOLERANCE` of the identity is
    returned as it is (the steps would only move its last bits), so errors stay below that
    bound however many edits follow. Used where a rotation is recomputed from others (join,
    shift root): without it, rounding errors in ``R^T`` instead of ``R^-1`` double at every
    swap of a chain of shifts.
    """
    out = np.array(matrices, dtype=np.float64)
    gram = np.swapaxes(out, -1, -2) @ out
    off = ~(np.abs(gram - np.eye(3)).max(axis=(-2, -1)) <= ORTHONORMAL_TOLERANCE)  # NaN: off
    if not off.any():
        return out
    fixed = out[off]
    step_gram = gram[off]
    for step in range(iterations):
        if step:
            step_gram = np.swapaxes(fixed, -1, -2) @ fixed
        fixed = fixed @ (1.5 * np.eye(3) - 0.5 * step_gram)
    out[off] = fixed
    return out


def axis_permutations() -> list[np.ndarray]:
    """The 24 proper rotations that permute the coordinate axes (with signs), (3, 3) each."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1.0, -1.0), repeat=3):
            matrix = np.zeros((3, 3))
            matrix[range(3), perm] = signs
            if np.linalg.det(matrix) > 0:
                out.append(matrix)
    return out


def angle_axis_degrees(rotation: np.ndarray) -> tuple[float, np.ndarray]:
    """(degrees, unit axis (3,)) of one (3, 3) rotation; the axis is +Y for no turn, and for
    a half turn the column of ``R + I`` of largest norm."""
    angle = float(np.degrees(rotation_angle(rotation)))
    axis = np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0], rotation[1, 0] - rotation[0, 1]])
    norm = float(np.linalg.norm(axis))
    if norm < 1e-12:
        if angle < 90.0:
            return 0.0, np.array([0.0, 1.0, 0.0])
        both = rotation + np.eye(3)
        column = both[:, int(np.argmax(np.linalg.norm(both, axis=0)))]
        return angle, column / np.linalg.norm(column)
    return angle, axis / norm
