"""Forward kinematics: world positions and rotations of every joint for every frame.

Both conventions of :mod:`core.model.motion`, vectorised over frames with one Python step per
joint (parents before children). With ``W`` the world rotation and ``P`` the world position:

- root r:          ``W_r = R_r``,          ``P_r = t_r`` (its translation is ``G_r``)
- post (BVH):      ``W_j = W_p R_j``,      ``P_j = P_p + W_p t_j``
- pre (GMR):       ``W_j = W_p R_j``,      ``P_j = P_p + W_j t_j``

:func:`reference_forward_kinematics` is the reference implementation, written for clarity
(one numpy step per joint). :func:`forward_kinematics`, which the app, the operations and
the command line call, runs the tuned :mod:`core.kinematics.engine` (tested against the reference
on random forests and real files; it agrees to rounding and is much faster).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.model.motion import Motion


def forward_kinematics(
    motion: Motion, *, with_rotations: bool = True, threads: int | None = 1
) -> tuple[np.ndarray, np.ndarray | None]:
    """World positions (F, J, 3) and, if ``with_rotations``, world rotations (F, J, 3, 3)
    (else None), computed by :func:`core.kinematics.engine.forward_kinematics` (``threads``: blocks
    of frames at once, None for one per core; the result does not depend on it)."""
    return fk_engine.forward_kinematics(motion, with_rotations=with_rotations, threads=threads)


def reference_forward_kinematics(
    motion: Motion, *, with_rotations: bool = True
) -> tuple[np.ndarray, np.ndarray | None]:
    """World positions and (optionally) world rotations: the reference implementation.

    Returns
    -------
    positions : (F, J, 3) float64
    rotations : (F, J, 3, 3) float64, or None when ``with_rotations`` is False (world
        rotations are then kept only for joints that have children).
    """
    n_frames, n_joints = motion.n_frames, motion.n_joints
    positions = np.empty((n_frames, n_joints, 3))
    world = np.empty((n_frames, n_joints, 3, 3))
    local = motion.rotations
    translation = motion.translations
    pre = motion.convention == "pre"
    for j in motion.topological_order:
        p = motion.parents[j]
        if p < 0:
            world[:, j] = local[:, j]
            positions[:, j] = translation[:, j]
            continue
        np.matmul(world[:, p], local[:, j], out=world[:, j])
        frame = world[:, j] if pre else world[:, p]
        positions[:, j] = positions[:, p] + np.einsum("fab,fb->fa", frame, translation[:, j])
    return positions, (world if with_rotations else None)


def world_positions(motion: Motion) -> np.ndarray:
    """(F, J, 3) world positions of every joint."""
    return forward_kinematics(motion, with_rotations=False)[0]


def world_rotations(motion: Motion) -> np.ndarray:
    """(F, J, 3, 3) world rotations of every joint."""
    return forward_kinematics(motion)[1]


def joint_world_transform(motion: Motion, joint: int) -> tuple[np.ndarray, np.ndarray]:
    """World rotation (F, 3, 3) and position (F, 3) of one joint, walking only its root path."""
    path = motion.path_from_root(joint)
    world = motion.rotations[:, path[0]].copy()
    position = motion.translations[:, path[0]].copy()
    pre = motion.convention == "pre"
    for j in path[1:]:
        if pre:
            world = world @ motion.rotations[:, j]
            position += np.einsum("fab,fb->fa", world, motion.translations[:, j])
        else:
            position += np.einsum("fab,fb->fa", world, motion.translations[:, j])
            world = world @ motion.rotations[:, j]
    return world, position
