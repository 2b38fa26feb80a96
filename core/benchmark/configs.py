"""The paper's configurations C_k: the same motion with k chosen joints as roots."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.edits.operations import shift_root, with_joint_data
from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.model.motion import Motion


def random_root_sets(n_joints: int, k: int, instances: int, rng: np.random.Generator) -> list[np.ndarray]:
    """``instances`` random sets of ``k`` distinct joints (each (k,) int64, in draw order)."""
    return [rng.choice(n_joints, size=k, replace=False).astype(np.int64) for _ in range(instances)]


def with_roots(motion: Motion, roots: np.ndarray) -> Motion:
    """The motion (one tree, pre-rotation) with exactly ``roots`` as its roots.

    The tree is re-rooted at the first of them (:func:`core.edits.operations.shift_root`; not
    needed when one of them is the root already), then the others are split off, all at
    once: each gets its world rotation and position from one FK pass and becomes a root.
    That is what :func:`core.edits.operations.split` does one joint at a time (splitting one
    joint changes no world transform, so the order does not matter), without copying
    the (F, J, 3, 3) arrays once per joint. Soft links are not recorded (not needed here).
    """
    roots = [int(r) for r in roots]
    current = [r for r in roots if motion.parents[r] < 0]
    first = current[0] if current else roots[0]
    if motion.parents[first] >= 0:
        motion = shift_root(motion, first)
    others = [r for r in roots if r != first]
    if not others:
        return motion
    positions, world = fk_engine.forward_kinematics(motion)
    rotation = world[:, others]
    del world
    return with_joint_data(
        motion,
        others,
        parent=-1,
        rotation=rotation,
        translation=positions[:, others],
        offset=np.zeros(3),
        has_translation=True,
        soft_parents=np.full(motion.n_joints, -1),
    )
