"""Unit and up-axis conversions of a whole motion (``gmr convert --scale --up``).

Both are changes of the world frame applied consistently to every joint, in either
convention, so that the rest pose, the offsets and the motion all move together:

- scale ``s``: every offset and translation times ``s`` (rotations unchanged);
- up axis: a rotation ``Q`` of the world (90 degrees about X). ``R'_j = Q R_j Q^T`` for every
  joint, ``t'_j = Q t_j`` for every offset and translation. Then every world position is
  ``Q P_j`` and every world rotation ``Q W_j Q^T`` (FK of either convention commutes with
  the change of basis), and the rest pose (all rotations the identity) turns with the world.
  ``Q`` maps Y to Z: Y up -> Z up is ``(x, y, z) -> (x, -z, y)`` (forward -Z becomes +Y, as
  Blender converts BVH on import); Z up -> Y up is its inverse. Rotation orders swap their
  Y and Z letters (``ZYX`` -> ``YZX``): ``Q Ry Q^T = Rz`` and ``Q Rz Q^T = Ry^-1``, so
  each joint keeps an equivalent decomposition (same gimbal behaviour).

The conversions applied are recorded in the motion's header comments; the up axis of a
source file is what its comments say (``up axis: z``), else Y (BVH, ASF/AMC, GMR default).
"""

from __future__ import annotations

import re

import numpy as np

from gmr_studio.core.motion import Motion

UP_AXES = ("y", "z")
#: Y up -> Z up: a rotation of +90 degrees about X
Y_TO_Z = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
_UP_COMMENT = re.compile(r"^up axis:\s*([yz])\b", re.IGNORECASE)


def scale_lengths(motion: Motion, factor: float) -> Motion:
    """Every offset and translation times ``factor`` (> 0); a comment records it."""
    if not np.isfinite(factor) or factor <= 0:
        raise ValueError(f"the scale must be a positive number, not {factor}")
    if factor == 1:
        return motion
    return motion.replace(
        offsets=motion.offsets * factor,
        translations=motion.translations * factor,
        comments=(*motion.comments, f"lengths scaled by {factor:.15g} (gmr convert --scale)"),
    )


def up_axis_of(motion: Motion) -> str:
    """The up axis a motion's comments state (the last ``up axis: y|z`` line), else ``"y"``."""
    for comment in reversed(motion.comments):
        match = _UP_COMMENT.match(comment.strip())
        if match:
            return match.group(1).lower()
    return "y"


def change_up_axis(motion: Motion, target: str, source: str | None = None) -> Motion:
    """The motion with its world turned so that ``target`` ('y' or 'z') is up.

    ``source``: the motion's up axis (default: :func:`up_axis_of`). Nothing changes when
    they agree. Every world position ``P`` becomes ``Q P``; see the module docstring.
    """
    source = (source or up_axis_of(motion)).lower()
    target = target.lower()
    for axis in (source, target):
        if axis not in UP_AXES:
            raise ValueError(f"the up axis must be one of {', '.join(UP_AXES)}, not {axis!r}")
    if source == target:
        return motion
    q = Y_TO_Z if target == "z" else Y_TO_Z.T
    swap = str.maketrans("YZ", "ZY")
    mapping = "(x, y, z) -> (x, -z, y)" if target == "z" else "(x, y, z) -> (x, z, -y)"
    return motion.replace(
        rotations=q @ motion.rotations @ q.T,
        offsets=motion.offsets @ q.T,
        translations=motion.translations @ q.T,
        rotation_orders=tuple(order.translate(swap) for order in motion.rotation_orders),
        comments=(
            *motion.comments,
            f"up axis: {target} (converted from {source} up by gmr convert --up: {mapping})",
        ),
    )
