"""The paper's configurations C_k: the same motion with k chosen joints as roots."""

from __future__ import annotations

import numpy as np

from core import fk_engine
from core.motion import Motion
from core.operations import shift_root


def random_root_sets(n_joints: int, k: int, instances: int, rng: np.random.Generator) -> list[np.ndarray]:
    """``instances`` random sets of ``k`` distinct joints (each (k,) int64, in draw order)."""
    return [rng.choice(n_joints, size=k, replace=False).astype(np.int64) for _ in range(instances)]


def with_roots(motion: Motion, roots: np.ndarray) -> Motion:
    """The motion (one tree, pre-rotation) with exactly ``roots`` as its roots.

    The tree is re-rooted at the first of them (:func:`core.operations.shift_root`; not
    needed when one of them is the root already), then the others are split off, all at
    once: each gets its world rotation and position from one FK pass and becomes a root.
    That is what :func:`core.operations.split` does one joint at a time (splitting one
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
    rotations = motion.rotations.copy()
    rotations[:, others] = world[:, others]
    del world
    translations = motion.translations.copy()
    translations[:, others] = positions[:, others]
    parents = motion.parents.copy()
    parents[others] = -1
    offsets = motion.offsets.copy()
    offsets[others] = 0.0
    flags = motion.has_translation.copy()
    flags[others] = True
    return motion.replace(
        parents=parents,
        offsets=offsets,
        has_translation=flags,
        rotations=rotations,
        translations=translations,
        soft_parents=np.full(motion.n_joints, -1),
    )
