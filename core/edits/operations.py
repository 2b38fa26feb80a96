"""The three GMR operations (paper section 4.1) and their batch forms.

Every function takes a pre-rotation :class:`~core.model.motion.Motion` and returns a new one;
the input is never changed. World positions of every joint are unchanged by all of them.
World rotations are unchanged by split and join; shift root moves each bone's frame along
the path to the new root (in GMR a joint's frame is the frame of the bone that ends at it).
The ``*_edit`` forms return an :class:`~core.edits.edited.Edited`, which says so joint by
joint, so that a caller holding the input's world transforms (the app's cache) gets the
result's without computing them again.

Two backends: the new forest is decided in Python (a few joints); the frames are edited
either by numpy, vectorised over frames with Python work per joint and step (the
reference), or, by default when numba is installed, by one compiled pass over the motion
(:mod:`core.edits.frame_programs`). They agree to rounding (tested to 1e-12 of the size).

Soft links: a split root remembers the joint it was split from (``soft_parents``). Each
tree holds at most one soft link, the one leading towards the tree it was split from; the
trees and soft links together always form the original forest, so ``join_all`` can
restore it. Refusals raise :class:`~core.errors.OperationError` and change nothing.
"""

from __future__ import annotations

import itertools

import numpy as np

from gmr_studio.core.edits import frame_programs
from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.edits.frame_programs import FrameProgram
from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.kinematics.fk import forward_kinematics, joint_world_transform
from gmr_studio.core.model.motion import RIGID_RELATIVE_TOLERANCE, Motion
from gmr_studio.core.rotations.euler import orthonormalize

Backend = fk_engine.Backend


def _require_pre(motion: Motion, what: str) -> None:
    if motion.convention != "pre":
        raise OperationError(f"{what} needs a GMR (pre-rotation) motion; convert it with pre_from_post first")


def _transposed(rotations: np.ndarray) -> np.ndarray:
    return np.swapaxes(rotations, -1, -2)


def shift_root(motion: Motion, joint: int | str, *, backend: Backend = "auto") -> Motion:
    """Make ``joint`` the root of its tree by swapping roots along the path (paper 4.1.1).

    For the root 0 and its child 1 on the path, per frame: ``G' = G_0 + R_0 R_1 t_1``,
    ``R'_1 = R_0``, ``t'_1 = 0``, ``R'_0 = R_1``, ``t'_0 = -t_1``; other children i of 0
    get ``R'_i = R_1^T R_i`` and children k of 1 get ``R'_k = R_1 R_k``. Rotation orders
    travel with the rotations they describe.

    The new rotations of the children are orthonormalised: the transposes used as inverses
    along the path otherwise let rounding errors grow geometrically over repeated shifts
    (a thousand shifts back and forth overflowed; tested).
    """
    return shift_root_edit(motion, joint, backend=backend).motion


def shift_root_edit(
    motion: Motion, joint: int | str, *, backend: Backend = "auto", threads: int | None = None
) -> Edited:
    """:func:`shift_root`; along the path, each joint takes the frame of the joint below
    it, and the new root the old root's. ``threads``: blocks of frames edited at once by
    the compiled backend (None, the default: one per core; the same result)."""
    _require_pre(motion, "shift root")
    target = motion.joint_index(joint)
    path = motion.path_from_root(target)
    if len(path) == 1:
        return Edited.same_joints(motion)
    parents = motion.parents.copy()
    offsets = motion.offsets.copy()
    has_translation = motion.has_translation.copy()
    orders = list(motion.rotation_orders)
    children = [list(c) for c in motion.children]
    frames = np.arange(motion.n_joints)
    program = FrameProgram()
    for old_root, new_root in itertools.pairwise(path):
        program.swap(old_root, new_root, [i for i in children[old_root] if i != new_root], children[new_root])
        # a root's offset is its rest-pose world position (rest rotations are the identity)
        offsets[old_root], offsets[new_root] = -offsets[new_root], offsets[old_root] + offsets[new_root]
        has_translation[old_root] = has_translation[new_root]
        has_translation[new_root] = True
        orders[old_root], orders[new_root] = orders[new_root], orders[old_root]
        frames[[old_root, new_root]] = frames[[new_root, old_root]]
        parents[new_root] = -1
        parents[old_root] = new_root
        children[old_root].remove(new_root)
        children[new_root].append(old_root)
    if frame_programs.use_kernel(backend) and motion.n_frames:
        rotations, translations, _ = frame_programs.run(motion, program, threads=threads)
    else:
        rotations, translations = _swapped_roots(motion, program)
    result = motion.replace(
        parents=parents,
        offsets=offsets,
        has_translation=has_translation,
        rotation_orders=tuple(orders),
        rotations=rotations,
        translations=translations,
    )
    return Edited.same_joints(result, frames)


def _swapped_roots(motion: Motion, program: FrameProgram) -> tuple[np.ndarray, np.ndarray]:
    """The numpy path of shift root: the program's swaps, each vectorised over frames."""
    rotations = motion.rotations.copy()
    translations = motion.translations.copy()
    for _, old_root, new_root, first, count, first_kid, kids, _ in program.steps:
        r0 = rotations[:, old_root].copy()
        r1 = rotations[:, new_root].copy()
        t1 = translations[:, new_root].copy()
        for i in program.lists[first : first + count]:
            rotations[:, i] = orthonormalize(_transposed(r1) @ rotations[:, i])
        for k in program.lists[first_kid : first_kid + kids]:
            rotations[:, k] = orthonormalize(r1 @ rotations[:, k])
        translations[:, new_root] = translations[:, old_root] + np.einsum("fab,fb->fa", r0 @ r1, t1)
        translations[:, old_root] = -t1
        rotations[:, new_root] = r0
        rotations[:, old_root] = r1
    return rotations, translations


def _soft_links_after_split(motion: Motion, joint: int) -> tuple[np.ndarray, np.ndarray]:
    """Soft links and link offsets after cutting the edge between ``joint`` and its parent.

    Each tree holds at most one soft link, leading towards the tree it was split from. The
    cut makes two trees: the subtree of ``joint`` and the rest. If the old tree's link is
    held inside the subtree, the subtree already leads away through it, so the new link
    goes on the parent, pointing at ``joint``; otherwise it goes on ``joint``, pointing at
    its parent. The holder keeps the cut bone's offset as seen from its side (the parent's
    side is the negated offset, exactly), for :func:`join` to restore bit for bit.
    """
    soft = motion.soft_parents.copy()
    links = motion.link_offsets.copy()
    parent = int(motion.parents[joint])
    tree = motion.tree_roots[joint]
    holders = np.flatnonzero((soft >= 0) & (motion.tree_roots == tree))
    if holders.size and int(holders[0]) in set(motion.subtree(joint)):
        soft[parent] = joint
        links[parent] = -motion.offsets[joint]
    else:
        soft[joint] = parent
        links[joint] = motion.offsets[joint]
    return soft, links


def rest_world_positions(motion: Motion) -> np.ndarray:
    """(J, 3) world positions of the joints in the rest pose (every rotation the identity)."""
    return forward_kinematics(motion.rest_pose(), with_rotations=False)[0][0]


def split(motion: Motion, joint: int | str, *, backend: Backend = "auto") -> Motion:
    """Promote ``joint`` to a root holding its world coordinates (paper 4.1.2).

    With ``M_j = [R_s, t_s]`` before the split: ``R'_j = R_s``, ``t'_j = 0``, ``G_j = t_s``
    (per-frame translation channels); its children are unchanged; a soft link to the old
    parent is kept for :func:`join`, with the bone's offset. The new root's offset is its
    rest-pose world position, so the rest pose (all a motion without frames has) is kept.
    """
    return split_edit(motion, joint, backend=backend).motion


def split_edit(motion: Motion, joint: int | str, *, backend: Backend = "auto", threads: int | None = None) -> Edited:
    """:func:`split`; every joint keeps its world rotation (``threads``: as for
    :func:`shift_root_edit`)."""
    _require_pre(motion, "split")
    j = motion.joint_index(joint)
    if motion.parents[j] < 0:
        raise OperationError(f"cannot split '{motion.names[j]}': it is already a root")
    soft, links = _soft_links_after_split(motion, j)
    if frame_programs.use_kernel(backend) and motion.n_frames:
        program = FrameProgram()
        program.split(j, motion.path_from_root(j), leaf=not motion.children[j])
        rotations, translations, _ = frame_programs.run(motion, program, threads=threads)
        world_rotation, world_position = rotations[:, j], translations[:, j]
    else:
        world_rotation, world_position = joint_world_transform(motion, j)
        rotations = translations = None
    return Edited.same_joints(
        with_joint_data(
            motion,
            j,
            parent=-1,
            rotation=world_rotation,
            translation=world_position,
            offset=rest_world_positions(motion)[j],
            has_translation=True,
            soft_parents=soft,
            link_offsets=links,
            edited=(rotations, translations),
        )
    )


def join(
    motion: Motion, joint: int | str, *, tolerance: float = RIGID_RELATIVE_TOLERANCE, backend: Backend = "auto"
) -> Motion:
    """Put the split root ``joint`` back under its soft-link parent (paper 4.1.3).

    With ``M_p = [R_p, t_p]`` the soft-link parent's world transform and ``[R_s, t_s]`` the
    root's: ``R_j = R_p^T R_s`` and ``t_j = R_s^T (t_s - t_p)`` per frame. When ``t_j`` is
    constant over the frames to ``tolerance`` times the skeleton's size it becomes the
    static offset; otherwise the joint keeps per-frame translation channels. The offset the
    split kept (``link_offsets``) is restored bit for bit when it agrees with ``t_j`` to that
    tolerance, and is the offset of a motion without frames (else its rest pose gives it).
    """
    return join_edit(motion, joint, tolerance=tolerance, backend=backend).motion


def _check_join(motion: Motion, j: int) -> int:
    """The soft-link parent the root ``j`` joins; OperationError when it cannot."""
    name = motion.names[j]
    if motion.parents[j] >= 0:
        raise OperationError(f"cannot join '{name}': it is not a root")
    if len(motion.roots) == 1:
        raise OperationError(f"cannot join '{name}': it is the last root of the forest")
    target = int(motion.soft_parents[j])
    if target < 0:
        raise OperationError(f"cannot join '{name}': it has no soft link to a parent (it was never split)")
    return target


def join_edit(
    motion: Motion,
    joint: int | str,
    *,
    tolerance: float = RIGID_RELATIVE_TOLERANCE,
    backend: Backend = "auto",
    threads: int | None = None,
) -> Edited:
    """:func:`join`; every joint keeps its world rotation (``threads``: as for
    :func:`shift_root_edit`)."""
    _require_pre(motion, "join")
    j = motion.joint_index(joint)
    target = _check_join(motion, j)
    kept = motion.link_offsets[j]
    soft = motion.soft_parents.copy()
    soft[j] = -1
    edited = (None, None)
    if motion.n_frames and frame_programs.use_kernel(backend):
        program = FrameProgram()
        program.join(j, motion.path_from_root(target))
        new_rotations, new_translations, means, rigid = _joined_in_one_pass(motion, program, [j], tolerance, threads)
        edited = (new_rotations, new_translations)
        rotation, translation, mean, rigid = new_rotations[:, j], new_translations[:, j], means[0], bool(rigid[0])
    else:
        if motion.n_frames:
            parent_rotation, parent_position = joint_world_transform(motion, target)
            own_rotation = motion.rotations[:, j]
            own_position = motion.translations[:, j]
            rotation = orthonormalize(_transposed(parent_rotation) @ own_rotation)
            offset_per_frame = np.einsum("fba,fb->fa", own_rotation, own_position - parent_position)
            mean = offset_per_frame.mean(axis=0)
            spread = np.abs(offset_per_frame - mean).max()
            if np.abs(mean - kept).max() <= tolerance * motion.size:  # False when kept is NaN
                mean = kept.copy()
        elif np.isfinite(kept).all():
            rotation, offset_per_frame = motion.rotations[:, j], np.zeros((0, 3))
            mean, spread = kept.copy(), 0.0
        else:
            rest = rest_world_positions(motion)
            rotation, offset_per_frame = motion.rotations[:, j], np.zeros((0, 3))
            mean, spread = rest[j] - rest[target], 0.0
        rigid = spread <= tolerance * motion.size
        translation = np.broadcast_to(mean, offset_per_frame.shape) if rigid else offset_per_frame
    return Edited.same_joints(
        with_joint_data(
            motion,
            j,
            parent=target,
            rotation=rotation,
            translation=translation,
            offset=mean,
            has_translation=not rigid,
            soft_parents=soft,
            edited=edited,
        )
    )


def with_joint_data(
    motion: Motion,
    j: int | list[int],
    *,
    parent: int,
    rotation: np.ndarray,
    translation: np.ndarray,
    offset: np.ndarray,
    has_translation: bool,
    soft_parents: np.ndarray,
    link_offsets: np.ndarray | None = None,
    edited: tuple[np.ndarray | None, np.ndarray | None] = (None, None),
) -> Motion:
    """A copy of ``motion`` in which joint j (or each joint of a list, with values for each:
    ``rotation`` (F, 3, 3) or (F, k, 3, 3), ...) has new local data and a new parent.
    ``link_offsets`` (J, 3) replaces the motion's when given. ``edited``: the new
    rotations (F, J, 3, 3) and translations (F, J, 3) with joint j's data already in place
    (the compiled pass's), used as they are instead of copies of the motion's."""
    parents = motion.parents.copy()
    parents[j] = parent
    offsets = motion.offsets.copy()
    offsets[j] = offset
    flags = motion.has_translation.copy()
    flags[j] = has_translation
    rotations, translations = edited
    if rotations is None:
        rotations = motion.rotations.copy()
        rotations[:, j] = rotation
        translations = motion.translations.copy()
        translations[:, j] = translation
    return motion.replace(
        parents=parents,
        soft_parents=soft_parents,
        link_offsets=motion.link_offsets if link_offsets is None else link_offsets,
        offsets=offsets,
        has_translation=flags,
        rotations=rotations,
        translations=translations,
    )


def split_all(motion: Motion, *, backend: Backend = "auto") -> Motion:
    """Every joint a root with its world coordinates: the fully translational form.

    One forward-kinematics pass for all joints: the result's rotations and translations
    are the world rotations and positions. The soft links are laid out so that
    :func:`join_all` restores the trees (each joint links to its neighbour towards the
    root of its original tree).
    """
    return split_all_edit(motion, backend=backend).motion


def split_all_edit(
    motion: Motion,
    *,
    kinematics: tuple[np.ndarray, np.ndarray] | None = None,
    backend: Backend = "auto",
    threads: int | None = None,
) -> Edited:
    """:func:`split_all`; every joint keeps its world rotation. ``kinematics``: the
    motion's world positions (F, J, 3) and rotations (F, J, 3, 3) when the caller has them
    (they become the result's translations and rotations, shared, not copied); else they
    are computed (on ``threads`` threads, None, the default: one per core)."""
    _require_pre(motion, "split all")
    if len(motion.roots) == motion.n_joints:
        return Edited.same_joints(motion)
    if kinematics is None:
        kinematics = fk_engine.forward_kinematics(motion, backend=backend, threads=threads)
    positions, world = kinematics
    soft = _soft_links_towards(motion, _union_edges(motion))
    result = motion.replace(
        parents=np.full(motion.n_joints, -1),
        soft_parents=soft,
        link_offsets=_link_offsets_of(motion, soft),
        offsets=rest_world_positions(motion),
        has_translation=np.ones(motion.n_joints, bool),
        rotations=world,
        translations=positions,
    )
    return Edited.same_joints(result)


def _union_edges(motion: Motion) -> list[tuple[int, int]]:
    """Undirected edges of the original forest: tree edges and soft links."""
    edges = [(j, int(p)) for j, p in enumerate(motion.parents) if p >= 0]
    edges += [(j, int(s)) for j, s in enumerate(motion.soft_parents) if s >= 0]
    return edges


def _link_offsets_of(motion: Motion, soft: np.ndarray) -> np.ndarray:
    """(J, 3) offset of each holder of a new soft link ``soft`` under its soft parent, from
    the bone or old soft link it replaces (negated, exactly, where it runs the other way)."""
    holder = np.flatnonzero(soft >= 0)
    target = soft[holder]
    links = np.full((motion.n_joints, 3), np.nan)
    links[holder] = np.select(
        [
            (motion.parents[holder] == target)[:, None],
            (motion.parents[target] == holder)[:, None],
            (motion.soft_parents[holder] == target)[:, None],
            (motion.soft_parents[target] == holder)[:, None],
        ],
        [motion.offsets[holder], -motion.offsets[target], motion.link_offsets[holder], -motion.link_offsets[target]],
        np.nan,
    )
    return links


def _soft_links_towards(motion: Motion, edges: list[tuple[int, int]]) -> np.ndarray:
    """Soft links for a forest of single joints: each joint links to its neighbour towards
    the top of its component (the root of the tree that holds no soft link)."""
    neighbours: list[list[int]] = [[] for _ in range(motion.n_joints)]
    for a, b in edges:
        neighbours[a].append(b)
        neighbours[b].append(a)
    holders = {int(motion.tree_roots[j]) for j in np.flatnonzero(motion.soft_parents >= 0)}
    tops = [int(r) for r in motion.roots if int(r) not in holders]
    soft = np.full(motion.n_joints, -1, np.int64)
    seen = np.zeros(motion.n_joints, bool)
    for top in tops + list(range(motion.n_joints)):
        if seen[top]:
            continue
        seen[top] = True
        queue = [top]
        for a in queue:
            for b in neighbours[a]:
                if not seen[b]:
                    seen[b] = True
                    soft[b] = a
                    queue.append(b)
    return soft


def join_all(motion: Motion, *, tolerance: float = RIGID_RELATIVE_TOLERANCE, backend: Backend = "auto") -> Motion:
    """Join every soft link, re-rooting a tree at its link holder where needed, until no
    soft link is left (the original trees, each rooted where its top tree is rooted)."""
    return join_all_edit(motion, tolerance=tolerance, backend=backend).motion


def join_all_edit(
    motion: Motion,
    *,
    tolerance: float = RIGID_RELATIVE_TOLERANCE,
    backend: Backend = "auto",
    threads: int | None = None,
) -> Edited:
    """:func:`join_all`; the frames move only where a tree is re-rooted (as in
    :func:`shift_root_edit`).

    When no tree needs re-rooting (the holders are roots, as after :func:`split_all`), the
    compiled backend runs all the joins in one pass over the motion (on ``threads``, as for
    :func:`shift_root_edit`); otherwise each shift root and join runs on its own."""
    _require_pre(motion, "join all")
    joins = _joins_only(motion)
    if joins is not None and joins and motion.n_frames and frame_programs.use_kernel(backend):
        return _joined_at_once(motion, joins, tolerance, threads)
    frames = np.arange(motion.n_joints)
    while True:
        holders = np.flatnonzero(motion.soft_parents >= 0)
        if holders.size == 0:
            return Edited.same_joints(motion, frames)
        root_holders = [int(j) for j in holders if motion.parents[j] < 0]
        j = root_holders[0] if root_holders else int(holders[0])
        if motion.parents[j] >= 0:
            shifted = shift_root_edit(motion, j, backend=backend, threads=threads)
            motion, frames = shifted.motion, frames[shifted.frames]
        motion = join_edit(motion, j, tolerance=tolerance, backend=backend, threads=threads).motion


def _joins_only(motion: Motion) -> list[tuple[int, int]] | None:
    """The (joint, soft-link parent) pairs :func:`join_all` joins, in its order, when it
    re-roots no tree; None when it would."""
    parents = motion.parents.copy()
    soft = motion.soft_parents.copy()
    joins = []
    while (soft >= 0).any():
        holders = np.flatnonzero(soft >= 0)
        root_holders = [int(j) for j in holders if parents[j] < 0]
        if not root_holders:
            return None
        j = root_holders[0]
        joins.append((j, int(soft[j])))
        parents[j], soft[j] = soft[j], -1
    return joins


def _joined_at_once(motion: Motion, joins: list[tuple[int, int]], tolerance: float, threads: int | None) -> Edited:
    """:func:`join_all` of ``joins`` as one program, one pass over the frames
    (:func:`_joined_in_one_pass`)."""
    parents = motion.parents.copy()
    program = FrameProgram()
    for j, target in joins:
        program.join(j, motion.path_from_root(target))  # the input's world transforms: joins keep them
        parents[j] = target
    joined = [j for j, _ in joins]
    rotations, translations, means, rigid = _joined_in_one_pass(motion, program, joined, tolerance, threads)
    offsets = motion.offsets.copy()
    offsets[joined] = means
    flags = motion.has_translation.copy()
    flags[joined] = ~rigid
    soft = motion.soft_parents.copy()
    soft[joined] = -1
    result = motion.replace(
        parents=parents,
        soft_parents=soft,
        offsets=offsets,
        has_translation=flags,
        rotations=rotations,
        translations=translations,
    )
    return Edited.same_joints(result)


def _joined_in_one_pass(
    motion: Motion, program: FrameProgram, joined: list[int], tolerance: float, threads: int | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The compiled pass of a ``program`` of joins of the joints ``joined`` (K,), in its
    order: the new rotations (F, J, 3, 3) and translations (F, J, 3), and each joint's
    offset (K, 3) and whether it is rigid (K,) bool.

    A joint whose offset under its new parent varies by at most ``tolerance`` times the
    size over the frames is rigid: its translation in every frame is its static offset, the
    offset its split kept (``link_offsets``) where the mean agrees with it to that
    tolerance (restored bit for bit), else the mean. A kept offset is written in the pass
    itself (joining what a split cut restores it); should such a joint prove not rigid, the
    pass runs again to write its per-frame offsets. Others are written over afterwards
    (:func:`core.edits.frame_programs.set_static`)."""
    joined = np.asarray(joined, dtype=np.int64)
    kept = motion.link_offsets[joined]
    expected = np.isfinite(kept).all(axis=1)
    static = np.where(expected[:, None], kept, np.nan)
    rotations, translations, measured = frame_programs.run(motion, program, static=static, threads=threads)
    limit = tolerance * motion.size
    means = measured.mean.copy()
    restored = np.abs(means - kept).max(axis=1) <= limit  # False where NaN
    means[restored] = kept[restored]
    rigid = measured.spread <= limit
    if np.any(expected & ~rigid):
        rotations, translations, _ = frame_programs.run(motion, program, threads=threads)
        expected[:] = False
    over = rigid & ~(expected & restored)
    frame_programs.set_static(translations, joined[over], means[over])
    return rotations, translations, means, rigid
