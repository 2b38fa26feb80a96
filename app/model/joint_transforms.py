"""A joint's local transform both ways, as the inspector shows it (pure numpy, no Qt).

GMR (pre-rotation) stores on joint ``j`` the rotation ``R_j`` of the bone that *ends* at
``j``: ``L_j = [R_j, R_j t_j]``. BVH (post-rotation) stores on ``j`` the rotation of the
bones that *start* at ``j``: ``L_j = [R'_j, t_j]``. So the BVH rotation of ``j`` is the GMR
rotation of its children (they all carry the same one in a motion read from a BVH; when
they differ, a BVH needs one dummy joint per child), and the GMR rotation of ``j`` is the
BVH rotation of its parent. For a root both are ``[R, G]`` with ``G`` its world position,
and its BVH rotation is its GMR (world) rotation times its children's.

For a motion read from a BVH the angles shown are the file's own channel values (unwrapped
as written, :class:`core.formats.bvh.FileChannels`) as long as they still make the
rotation shown (an edit may have changed it); otherwise they are the principal Euler angles
of the matrix, in the joint's order.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.formats.bvh import FileChannels
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import complete_order, euler_from_matrix

#: children whose GMR rotations differ by less than this (max abs entry) share one BVH rotation
SHARED_TOLERANCE = 1e-12


@dataclasses.dataclass(frozen=True)
class LocalTransform:
    """One joint's local transform in one convention at one frame.

    Attributes
    ----------
    matrix : (3, 4) ``[R, R t]`` (GMR) or ``[R, t]`` (BVH); None when there is no single one
        (a BVH joint whose children turn independently).
    channels_of : the joint whose rotation channels hold ``R`` in this convention, or None
        (no rotation channels: an End Site or a BVH leaf).
    order : the Euler order of ``angles`` ("" without angles).
    angles : (3,) degrees in ``order``, or None.
    from_file : the angles are the file's own channel values.
    note : a sentence saying where the rotation comes from.
    """

    matrix: np.ndarray | None
    channels_of: str | None
    order: str
    angles: np.ndarray | None
    from_file: bool
    note: str


def _angles(
    rotation: np.ndarray, order: str, name: str | None, frame: int, file_channels: FileChannels | None
) -> tuple[str, np.ndarray, bool]:
    """(order, degrees, from_file): the file's values for ``name`` if they make ``rotation``."""
    found = file_channels.of(name, frame) if file_channels is not None and name is not None else None
    if found is not None and file_channels.still_make(name, rotation, frame):  # core's one rule
        file_order, degrees = found
        return file_order, np.asarray(degrees, dtype=np.float64), True
    full = complete_order(order) if order else "ZYX"
    return full, np.degrees(euler_from_matrix(rotation, full)), False


def gmr_local(motion: Motion, frame: int, joint: int, file_channels: FileChannels | None = None) -> LocalTransform:
    """The GMR (pre-rotation) local transform ``[R_j, R_j t_j]`` of a joint of a GMR motion
    (a root's is ``[R, G]``); its rotation is a BVH's rotation of the parent."""
    if motion.convention != "pre":
        raise ValueError("gmr_local needs the GMR (pre-rotation) form of the motion")
    rotation = motion.rotations[frame, joint]
    translation = motion.translations[frame, joint]
    parent = int(motion.parents[joint])
    name = motion.names[joint]
    is_root = parent < 0
    matrix = np.column_stack([rotation, translation if is_root else rotation @ translation])
    # in a file read as BVH, this rotation is the file's channels of the parent
    source = None if is_root else motion.names[parent]
    order, angles, from_file = _angles(rotation, motion.rotation_orders[joint], source, frame, file_channels)
    if is_root:
        note = f"GMR channels of {name} (a root: its world rotation and position)"
    else:
        note = f"GMR channels of {name}: the rotation of the bone {motion.names[parent]} -> {name}"
        if from_file:
            note += f", the file's BVH channels of {motion.names[parent]}"
    return LocalTransform(matrix, name, order, angles, from_file, note)


def bvh_rotation(motion: Motion, frame: int, joint: int) -> tuple[np.ndarray | None, int | None]:
    """(R', child) the BVH (post-rotation) local rotation of a joint of a GMR motion and the
    child whose GMR rotation it is; (None, None) for a leaf (no rotation channels in a BVH)
    and (None, -1) when the children turn independently (a BVH needs dummy joints)."""
    children = motion.children[joint]
    if not children:
        return None, None
    rotations = motion.rotations[frame, list(children)]  # (C, 3, 3)
    if np.abs(rotations - rotations[0]).max() > SHARED_TOLERANCE:
        return None, -1
    rotation = rotations[0]
    if motion.parents[joint] < 0:  # a root's BVH rotation is its world rotation
        rotation = motion.rotations[frame, joint] @ rotation
    return rotation, int(children[0])


def bvh_local(motion: Motion, frame: int, joint: int, file_channels: FileChannels | None = None) -> LocalTransform:
    """The BVH (post-rotation) local transform ``[R'_j, t_j]`` of a joint of a GMR motion,
    the rotation from the joint's own BVH channels (the file's values when read from one)."""
    if motion.convention != "pre":
        raise ValueError("bvh_local needs the GMR (pre-rotation) form of the motion")
    name = motion.names[joint]
    translation = motion.translations[frame, joint]
    rotation, child = bvh_rotation(motion, frame, joint)
    if child is None:
        identity = np.column_stack([np.eye(3), translation])
        note = f"{name} is a leaf (an End Site in a BVH): no rotation channels, [I, t]"
        return LocalTransform(identity, None, "", None, False, note)
    if child < 0:
        kids = ", ".join(motion.names[c] for c in motion.children[joint])
        note = (
            f"the children of {name} ({kids}) turn independently: a BVH holds one dummy joint "
            "per child (Export BVH adds them), each with that child's GMR rotation"
        )
        return LocalTransform(None, None, "", None, False, note)
    order, angles, from_file = _angles(rotation, motion.rotation_orders[child], name, frame, file_channels)
    note = f"BVH channels of {name}"
    note += ", as in the file" if from_file else f" (the GMR rotation of its child {motion.names[child]})"
    return LocalTransform(np.column_stack([rotation, translation]), name, order, angles, from_file, note)


def channel_names(motion: Motion, joint: int, has_rotation: bool, order: str) -> str:
    """A joint's CHANNELS as a file lists them: positions where it translates, rotations in ``order``."""
    names = ["Xposition", "Yposition", "Zposition"] if motion.has_translation[joint] else []
    if has_rotation:
        names += [f"{axis}rotation" for axis in order]
    return " ".join(names) or "none"


def bvh_world_rotation(motion: Motion, frame_rotations: np.ndarray, frame: int, joint: int) -> np.ndarray:
    """(3, 3) the joint's world rotation at ``frame`` as a BVH defines it (the frame its
    children hang in), from the GMR world rotations at that frame ``(J, 3, 3)``: its
    children's GMR world rotation when they share one, else (a leaf, or independent
    children under dummies) its own."""
    rotation, child = bvh_rotation(motion, frame, joint)
    return frame_rotations[child if rotation is not None else joint]
