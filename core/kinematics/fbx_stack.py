"""FBX's local transform stack, composed into a rotation and a translation (pure numpy,
over any leading shape of frames and nodes).

FBX composes a node's local transform as ``T Roff Rp Rpre R Rpost^-1 Rp^-1 Soff Sp S Sp^-1``:
a translation, the rotation ``Q = Rpre R Rpost^-1`` (:func:`stack_rotation`) and the scale
``S``, with the pivots and offsets folded into the translation
``T + Roff + Rp + Q (Sp + Soff - Rp - S Sp)`` (:func:`stack_translation`). The FBX reader's
child process (:mod:`core.formats.fbx_in.worker`, which must not import the formats
package) checks its probe frames with these, the parent composes every frame with them.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.rotations.euler import matrix_from_euler

#: ufbx rotation order (``ufbx.RotationOrder``) -> the project's intrinsic order
#: (core/rotations/euler.py: read left to right). FBX ``XYZ`` turns about X first: ``Rz Ry Rx``.
EULER_ORDERS = {0: "ZYX", 1: "YZX", 2: "XZY", 3: "ZXY", 4: "YXZ", 5: "XYZ"}
#: the static vectors of the stack composed with the Lcl values (degrees for the rotations)
STATIC_STACK = ("PreRotation", "PostRotation", "RotationPivot", "RotationOffset", "ScalingPivot", "ScalingOffset")


def euler_matrices(degrees: np.ndarray, order: int) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of FBX Euler angles (..., 3) in degrees, x y z."""
    intrinsic = EULER_ORDERS[order]
    angles = np.take(np.asarray(degrees, dtype=np.float64), ["XYZ".index(axis) for axis in intrinsic], axis=-1)
    return matrix_from_euler(np.radians(angles, out=angles), intrinsic)  # the new array turned in place


def stack_rotation(degrees: np.ndarray, order: int, pre: np.ndarray, post: np.ndarray) -> np.ndarray:
    """``Q = Rpre R Rpost^-1`` (..., 3, 3) of Lcl Rotation angles (..., 3) in degrees turned in
    ``order`` and static pre- and post-rotations (..., 3), degrees in FBX's XYZ order; the
    products with identities are left out."""
    return pre_and_post(euler_matrices(degrees, order), pre, post)


def pre_and_post(turn: np.ndarray, pre: np.ndarray, post: np.ndarray) -> np.ndarray:
    """``Rpre R Rpost^-1`` (..., 3, 3) of rotations ``R`` (..., 3, 3) (:func:`stack_rotation`)."""
    if pre.any():
        turn = euler_matrices(pre, 0) @ turn
    if post.any():
        turn = turn @ np.swapaxes(euler_matrices(post, 0), -1, -2)
    return turn


def stack_translation(translation: np.ndarray, turn: np.ndarray, scale: np.ndarray, stack: dict) -> np.ndarray:
    """The node's translation (..., 3) with its static pivots and offsets (``stack``: name ->
    (..., 3)) folded in: ``T + Roff + Rp + Q (Sp + Soff - Rp - S Sp)`` (module docstring);
    ``translation`` itself when they are all zero."""
    pivot, offset = stack["RotationPivot"], stack["RotationOffset"]
    scale_pivot, scale_offset = stack["ScalingPivot"], stack["ScalingOffset"]
    if not (pivot.any() or offset.any() or scale_pivot.any() or scale_offset.any()):
        return translation
    inner = scale_pivot + scale_offset - pivot - scale * scale_pivot
    return translation + offset + pivot + (turn @ inner[..., None])[..., 0]
