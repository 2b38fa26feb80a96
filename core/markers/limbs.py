"""A limb's rotation from its bone direction: two angles from the markers, the twist from elsewhere.

In GMR (pre-rotation) a joint j's bone runs from its parent p to j: ``P_j - P_p = W_p R_j t_j``
with ``W_p`` the parent's world rotation and ``t_j`` the rest bone vector. The markers give
the bone's direction in the parent's frame, ``c = W_p^T (P_j - P_p) / |P_j - P_p|``, which fixes
two of the three angles of ``R_j``; the third, the twist about the bone, is free. Every
rotation taking the rest direction ``u = t_j/|t_j|`` to ``c`` is

    ``R_j = S(u -> c) Rot(u, gamma)``

where ``S(u -> c)`` is the *swing*, the shortest rotation from u to c (axis ``u x c``), and
``gamma`` the *twist*. The two swing angles are the polar angles of c about u.

Why not the note's Euler form ``R_1 = Rx(a) Ry(b) Rz(g)`` with ``c = R_1 z``: its angles are
undefined where c is along the parent frame's x axis (cos b = 0), and CMU's arms rest along
x: a T-pose sits on the singularity. The swing is singular only where the bone points exactly
against its rest direction (c = -u), a pose limbs do not take; there the swing is a half
turn about an axis perpendicular to u, and the result is still a rotation taking u to c.
The twist of a known rotation R (the reference pose's) is measured against the same swing,
``Rot(u, gamma) = S(u -> R u)^T R``, so there is exactly one twist in (-pi, pi] and no
second Euler branch to choose between (picking the other branch of the note's Euler pair
would turn the limb half a turn about itself).

All functions are vectorised over leading axes (frames).
"""

from __future__ import annotations

import numpy as np

#: below this, 1 + cos(angle between u and c) counts as zero: c points against u
ANTIPARALLEL_EPSILON = 1e-12


def cross_matrix(v: np.ndarray) -> np.ndarray:
    """(..., 3) -> (..., 3, 3) with ``cross_matrix(v) @ w == v x w``."""
    v = np.asarray(v, dtype=np.float64)
    out = np.zeros((*v.shape[:-1], 3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def perpendicular(u: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each unit vector u: (..., 3) -> (..., 3)."""
    u = np.asarray(u, dtype=np.float64)
    axis = np.zeros_like(u)
    smallest = np.argmin(np.abs(u), axis=-1)
    np.put_along_axis(axis, smallest[..., None], 1.0, axis=-1)
    out = np.cross(u, axis)
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def swing(u: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The shortest rotation taking unit vector u to unit vector c.

    Parameters
    ----------
    u : (3,) or (..., 3) unit vectors (rest bone directions).
    c : (..., 3) unit vectors (measured bone directions).

    Returns
    -------
    (..., 3, 3): ``R = I + K + K^2 / (1 + u.c)`` with ``K = [u x c]_x`` (Rodrigues), and a half
    turn about a vector perpendicular to u where c = -u.
    """
    c = np.asarray(c, dtype=np.float64)
    u = np.broadcast_to(np.asarray(u, dtype=np.float64), c.shape)
    cosine = np.sum(u * c, axis=-1)
    k = cross_matrix(np.cross(u, c))
    against = 1.0 + cosine <= ANTIPARALLEL_EPSILON
    denominator = np.where(against, 1.0, 1.0 + cosine)[..., None, None]
    out = np.eye(3) + k + (k @ k) / denominator
    if np.any(against):
        w = perpendicular(u[against])
        out[against] = 2.0 * w[:, :, None] * w[:, None, :] - np.eye(3)
    return out


def about_axis(u: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotations by ``angle`` (...) about unit axes u ((3,) or (..., 3)): (..., 3, 3)."""
    angle = np.asarray(angle, dtype=np.float64)
    u = np.broadcast_to(np.asarray(u, dtype=np.float64), (*angle.shape, 3))
    k = cross_matrix(u)
    s, c = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def twist_angle(rotation: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The angle of the rotation about u nearest ``rotation``: (..., 3, 3) -> (...), in (-pi, pi].

    ``gamma = atan2(u . axial(Q), (tr Q - u^T Q u) / 2)``: exact for a rotation about u, and
    for any Q the gamma that maximises ``tr(Rot(u, gamma)^T Q)``.
    """
    q = np.asarray(rotation, dtype=np.float64)
    u = np.broadcast_to(np.asarray(u, dtype=np.float64), (*q.shape[:-2], 3))
    axial = 0.5 * np.stack([q[..., 2, 1] - q[..., 1, 2], q[..., 0, 2] - q[..., 2, 0], q[..., 1, 0] - q[..., 0, 1]], -1)
    along = np.einsum("...a,...ab,...b->...", u, q, u)
    return np.arctan2(np.sum(u * axial, axis=-1), 0.5 * (np.trace(q, axis1=-2, axis2=-1) - along))


def twist_of(rotation: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The twist of known rotations R (..., 3, 3) about the rest direction u (3,): the gamma
    with ``R = S(u -> R u) Rot(u, gamma)``."""
    rotation = np.asarray(rotation, dtype=np.float64)
    direction = rotation @ np.asarray(u, dtype=np.float64)
    return twist_angle(np.swapaxes(swing(u, direction), -1, -2) @ rotation, u)


def limb_rotation(u: np.ndarray, c: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    """``S(u -> c) Rot(u, gamma)``: u (3,), c (..., 3) unit, gamma (...) -> (..., 3, 3)."""
    return swing(u, c) @ about_axis(u, gamma)


def least_change_twists(u: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Twists along a sequence of directions, each changing the joint's rotation least from
    the one before (no reference motion).

    With ``S_f = S(u -> c_f)``, the rotation ``S_f Rot(u, gamma_f)`` is nearest the previous
    one when ``delta_f = gamma_f - gamma_{f-1}`` maximises ``tr(S_{f-1}^T S_f Rot(u, delta))``:
    the twists commute, so delta depends only on the two swings and the whole sequence is a
    cumulative sum, computed for all frames at once. ``gamma_0 = 0``.

    Parameters
    ----------
    u : (3,) unit rest direction.
    c : (N, 3) unit directions of consecutive (valid) frames.

    Returns
    -------
    (N,) twists, unwrapped (they may leave (-pi, pi] to stay continuous).
    """
    swings = swing(u, c)
    if len(c) < 2:
        return np.zeros(len(c))
    step = np.swapaxes(swings[:-1], -1, -2) @ swings[1:]
    delta = -twist_angle(step, u)
    return np.concatenate([[0.0], np.cumsum(delta)])


def marker_twists(u: np.ndarray, c: np.ndarray, third: np.ndarray) -> np.ndarray:
    """Twists (N,) about the rest direction u (3,) from a third marker rigid with the bone.

    c (N, 3) unit bone directions and third (N, 3) the marker from the bone's start, both in
    the parent's frame. Undoing the swing, ``v = S(u -> c)^T third`` is the marker in the
    rest frame turned by the twist alone; its part perpendicular to u, compared with its mean
    direction ``w0`` over the frames, gives ``gamma = atan2(u . (w0 x v), w0 . v)``. The rest
    pose's twist is thereby the take's mean one (the marker is rigid with the bone, so any
    constant choice gives the same positions).
    """
    v = np.einsum("fba,fb->fa", swing(u, c), third)
    v -= np.outer(v @ u, u)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    w0 = v.mean(axis=0)
    w0 -= (w0 @ u) * u
    w0 /= np.linalg.norm(w0)
    return np.arctan2(np.cross(w0, v) @ u, v @ w0)
