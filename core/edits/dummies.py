"""Dummy joints: find them, and fold them out of a GMR motion (MATH.md "Dummy joints").

A dummy is a non-root joint with a zero offset (relative to :attr:`Motion.size`), no
translation channels and at least one child: post-rotation files need them where the
children of one joint turn differently (CMU's LHipJoint, RHipJoint, LowerBack sit at the
Hips). In pre-rotation each child can absorb the dummy on its own, exactly:
``R''_c = R_d R_c`` and ``t''_c = t_c``, its parent becoming the dummy's parent.

The reverse (dummies back in, where a BVH needs them) is :func:`core.kinematics.convention.post_from_pre`.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.model.motion import DEFAULT_RELATIVE_TOLERANCE, Motion


def find_dummies(motion: Motion, *, tolerance: float = DEFAULT_RELATIVE_TOLERANCE) -> list[int]:
    """Indices of the dummy joints, in index order (either convention).

    A dummy: not a root, ``|offset| <= tolerance * motion.size``, no translation channels,
    at least one child, and no soft link held or received (a soft link names that joint).
    """
    limit = tolerance * motion.size
    linked = set(np.flatnonzero(motion.soft_parents >= 0).tolist()) | set(
        motion.soft_parents[motion.soft_parents >= 0].tolist()
    )
    lengths = np.linalg.norm(motion.offsets, axis=1)
    return [
        j
        for j in range(motion.n_joints)
        if motion.parents[j] >= 0
        and lengths[j] <= limit
        and not motion.has_translation[j]
        and motion.children[j]
        and j not in linked
    ]


def remove_dummies(motion: Motion, *, tolerance: float = DEFAULT_RELATIVE_TOLERANCE) -> tuple[Motion, list[str]]:
    """Fold every dummy joint into its children.

    Parameters
    ----------
    motion : any motion; a post-rotation one is converted to GMR first (paper 5.2).
    tolerance : a joint's offset counts as zero up to ``tolerance * motion.size``.

    Returns
    -------
    (GMR motion without the dummies, names of the joints removed). The other joints keep
    their names, order, offsets and rotation orders; each child of a removed joint ``d``
    gets ``R_d R_c`` (chains of dummies compose) and ``d``'s parent. World positions of the
    remaining joints are unchanged (to rounding, ~1e-15 of the size).
    """
    motion = pre_from_post(motion)
    dummies = find_dummies(motion, tolerance=tolerance)
    if not dummies:
        return motion, []
    removed = np.zeros(motion.n_joints, bool)
    removed[dummies] = True
    parents = motion.parents.copy()
    rotations = motion.rotations.copy()
    # parents before children: a dummy below a dummy has already absorbed its parent
    for d in motion.topological_order:
        if not removed[d]:
            continue
        for child in motion.children[d]:
            rotations[:, child] = rotations[:, d] @ rotations[:, child]
            parents[child] = parents[d]
    result = motion.replace(parents=parents, rotations=rotations).joint_slice(np.flatnonzero(~removed))
    return result, [motion.names[d] for d in dummies]
