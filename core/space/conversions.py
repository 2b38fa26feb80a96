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

The conversions applied are recorded in the motion's header comments. The up axis (one
module for the rule): what a motion's comments state (``up axis: z``) always wins; a file
that states nothing means Y (:func:`up_axis_of`: BVH, ASF/AMC and GMR are Y up), which is
what conversions, comparisons, contacts and exports use; a view of such a file
(:func:`figure_up_axis`) looks at the figure (:func:`detect_up_axis`, also the markers'
rule, :mod:`core.markers.alignment`), so a Z-up export without a header still stands up.
"""

from __future__ import annotations

import re

import numpy as np

from gmr_studio.core.model.motion import Motion

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


def stated_up_axis(motion: Motion) -> str | None:
    """The up axis a motion's comments state (the last ``up axis: y|z`` line), else None."""
    for comment in reversed(motion.comments):
        match = _UP_COMMENT.match(comment.strip())
        if match:
            return match.group(1).lower()
    return None


def up_axis_of(motion: Motion) -> str:
    """The up axis a file means: what its comments state (``up axis: z``), else ``"y"``
    (BVH, ASF/AMC and GMR are Y up unless they say otherwise). Conversions, comparisons,
    contacts and exports use this; :func:`figure_up_axis` is the same rule for a view."""
    return stated_up_axis(motion) or "y"


def figure_up_axis(motion: Motion, positions: np.ndarray | None = None) -> int:
    """1 (Y) or 2 (Z): the axis to stand a motion up along in a view (the app's scene,
    filmstrips): what its comments state, as :func:`up_axis_of`; a file that states nothing
    (a Z-up export without a header line) is looked at, :func:`detect_up_axis` on the joints
    that make the figure (leaving out :attr:`~core.model.motion.Motion.anchors`) at the frames
    :attr:`~core.model.motion.Motion.size` samples, or at ``positions`` (F, J, 3) if given."""
    stated = stated_up_axis(motion)
    if stated is not None:
        return 1 if stated == "y" else 2
    points = motion._sampled_positions if positions is None else positions
    anchors = motion.anchors
    return detect_up_axis(points[:, ~anchors] if anchors.any() else points)


def detect_up_axis(points: np.ndarray) -> int:
    """1 (Y) or 2 (Z): the axis the figure spans more in its median frame (a standing or
    walking figure is taller than it is wide or deep; X is never taken as up, since a T-pose
    is as wide as it is tall; up is taken along +axis).

    points : (F, N, 3) positions; NaN (gaps) ignored.
    """
    extents = median_extents(points)
    return 1 if extents[1] >= extents[2] else 2


def median_extents(points: np.ndarray) -> np.ndarray:
    """(3,) median over frames of each axis' per-frame extent of points (F, N, 3) (frames
    with no point skipped; zeros when there is none)."""
    finite = np.isfinite(points).all(axis=-1)
    seen = finite.any(axis=1)
    if not seen.any():
        return np.zeros(3)
    high = np.where(finite[..., None], points, -np.inf).max(axis=1)[seen]
    low = np.where(finite[..., None], points, np.inf).min(axis=1)[seen]
    return np.median(high - low, axis=0)


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
