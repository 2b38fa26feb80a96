"""Conversion from post-rotation motion (BVH, ASF/AMC) to GMR's pre-rotation (paper 5.2).

``R'_root = I``, ``t'_j = t_j``, ``R'_j = R_p(j)`` (the parent's post-rotation), and a
root's translation stays its world position ``G``. Every world position is unchanged (the
world rotation of a joint becomes that of its parent: in GMR a joint's frame is the frame
of the bone that ends at it). End sites become ordinary joints.

A post-rotation leaf joint's own rotation moves nothing, so it has no GMR counterpart and
is dropped; every other rotation survives exactly.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.kinematics.engine import gather_joints
from gmr_studio.core.model.motion import Motion

#: rotation order given to joints whose parent had no rotation channels
DEFAULT_ORDER = "ZYX"


def pre_from_post(motion: Motion) -> Motion:
    """The GMR (pre-rotation) form of a post-rotation motion; the same joints and indices.

    Each joint takes its parent's rotation channel order, so its Euler angles are the
    parent's angles unchanged; a root keeps its own order.
    """
    if motion.convention == "pre":
        return motion
    parents = motion.parents
    roots = np.flatnonzero(parents < 0)
    # one gathering pass over the frames (a root reads its own rotation, replaced just after)
    rotations = gather_joints(motion.rotations, np.where(parents >= 0, parents, np.arange(motion.n_joints)))
    rotations[:, roots] = np.eye(3)
    orders = []
    for j, p in enumerate(parents):
        source = motion.rotation_orders[p] if p >= 0 else motion.rotation_orders[j]
        orders.append(source or DEFAULT_ORDER)
    return motion.replace(rotations=rotations, rotation_orders=tuple(orders), convention="pre")


def _unique_name(base: str, taken: set[str]) -> str:
    name, n = base, 2
    while name in taken:
        name, n = f"{base}{n}", n + 1
    taken.add(name)
    return name


def post_from_pre(motion: Motion, *, tolerance: float = 1e-12) -> tuple[Motion, list[str]]:
    """The post-rotation (BVH) form of a GMR motion, with dummy joints where needed.

    In post-rotation, a joint's rotation is shared by all its children; in GMR each child
    carries its own. A joint whose children all carry the same local rotation (to
    ``tolerance``, max abs difference of matrix entries, on every frame) takes it as its own;
    otherwise one zero-offset dummy joint is inserted above each child, named after the
    child (``<child>_dummy``), carrying that child's rotation. Leaves get the identity and,
    without translation channels, become End Sites when written. A joint that takes its
    children's rotation also takes their rotation order, so BVH -> GMR -> BVH gives every
    joint its original channel order back (:func:`pre_from_post` gives each joint its
    parent's order).

    Returns the post-rotation motion (original joints first, in their order, dummies after)
    and the names of the dummies added. World positions are unchanged.
    """
    if motion.convention == "post":
        return motion, []
    _, world = _pre_world(motion)
    n_frames = motion.n_frames
    names = list(motion.names)
    taken = set(names)
    parents = list(motion.parents)
    offsets = list(motion.offsets)
    orders = list(motion.rotation_orders)
    flags = list(motion.has_translation)
    translations = [motion.translations[:, j] for j in range(motion.n_joints)]
    post_world: list[np.ndarray | None] = [None] * motion.n_joints
    dummies: list[str] = []
    for p in range(motion.n_joints):
        kids = motion.children[p]
        if not kids:
            post_world[p] = world[:, p]
            continue
        first = motion.rotations[:, kids[0]]
        shared = all(np.abs(motion.rotations[:, c] - first).max(initial=0.0) <= tolerance for c in kids[1:])
        if shared:
            post_world[p] = world[:, kids[0]]
            orders[p] = motion.rotation_orders[kids[0]]  # the order of the rotation it now carries
            continue
        post_world[p] = world[:, p]
        for c in kids:
            d = len(names)
            names.append(_unique_name(f"{motion.names[c]}_dummy", taken))
            dummies.append(names[d])
            parents.append(p)
            parents[c] = d
            offsets.append(np.zeros(3))
            orders.append(motion.rotation_orders[c])
            flags.append(False)
            translations.append(np.zeros((n_frames, 3)))
            post_world.append(world[:, c])
    n_joints = len(names)
    rotations = np.empty((n_frames, n_joints, 3, 3))
    for j in range(n_joints):
        p = parents[j]
        rotations[:, j] = post_world[j] if p < 0 else np.swapaxes(post_world[p], -1, -2) @ post_world[j]
    for j in range(motion.n_joints):
        if not motion.children[j] and not motion.has_translation[j] and motion.parents[j] >= 0:
            orders[j] = ""  # a leaf: identity rotation, written as an End Site
            rotations[:, j] = np.eye(3)
    # parents must come before children for the writers' depth-first order: they do,
    # since the writers walk the tree; indices may point forward (to dummies).
    result = Motion(
        names=names,
        parents=parents,
        offsets=np.array(offsets),
        rotation_orders=orders,
        has_translation=np.array(flags),
        rotations=rotations,
        translations=np.stack(translations, axis=1),
        frame_time=motion.frame_time,
        convention="post",
        comments=motion.comments,
        facts=motion.facts,
    )
    return result, dummies


def _pre_world(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    from gmr_studio.core.kinematics.fk import forward_kinematics

    return forward_kinematics(motion)
