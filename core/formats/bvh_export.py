"""BVH export of anything GMR can hold: trees with independent siblings, forests.

:func:`bvh_export` turns any motion into a post-rotation motion that the BVH writer prints
as a standard file (docs/formats.md, "Writing BVH"):

- siblings with different rotations get one zero-offset dummy joint each, named after the
  child (:func:`core.kinematics.convention.post_from_pre`);
- a forest hangs under one synthetic root (``World``: identity, at the origin, 6 zero
  channels); each tree root is a 6-channel joint whose positions are its world positions.
  :func:`bvh_export_trees` gives one motion per tree instead;
- joints with per-frame offsets keep them as position channels;
- every joint has 0 or 3 rotation channels (Blender's importer misreads 1 or 2), in the
  joint's original order where it had one, and 0 or 3 position channels;
- a channel-free leaf named as readers name an End Site (``<parent>_End``, maybe
  numbered) is written as an ``End Site``; every other leaf keeps its name as a JOINT
  with 3 rotation channels (zero for a channel-free leaf, e.g. one left childless by a
  split) and a zero-offset End Site below it: Blender, bvhio, pybvh and our reader all
  read such a joint back with its name (``CHANNELS 0`` would keep it too, but pybvh
  rejects it); no comments, no SOFTLINKs; joint names are single words (spaces become
  underscores).

The writer (:mod:`core.formats.textmotion`) makes the Euler angles continuous over time.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.formats.textmotion import format_text_motion
from gmr_studio.core.kinematics.convention import post_from_pre, pre_from_post
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import complete_order

#: name of the synthetic root of an exported forest (numbered if a joint has it already)
WORLD_ROOT = "World"
#: rotation order of joints that carry no rotation of their own (the World root)
NEUTRAL_ORDER = "ZYX"


@dataclasses.dataclass(frozen=True)
class BvhExport:
    """A motion ready for :func:`core.formats.bvh.write_bvh`, and how it maps back.

    Attributes
    ----------
    motion : the post-rotation motion to write.
    names : for each joint of the source motion (by index), its name in the BVH as a BVH
        reader reads it back (the source name, with spaces as underscores), or None for a
        joint not in this export (another tree).
    dummies : names of the dummy joints added for independent siblings.
    world_root : name of the synthetic root, or None for a single tree.
    """

    motion: Motion
    names: tuple[str | None, ...]
    dummies: tuple[str, ...]
    world_root: str | None

    def text(self) -> str:
        """The BVH file as one string."""
        return "".join(format_text_motion(self.motion, "bvh"))

    def write(self, path: str | Path) -> None:
        """Write the BVH file atomically."""
        atomic_write_text(path, format_text_motion(self.motion, "bvh"))


def _unique(base: str, taken: set[str]) -> str:
    name, n = base, 2
    while name in taken:
        name, n = f"{base}{n}", n + 1
    return name


def bvh_export(motion: Motion, *, world_root: str = WORLD_ROOT) -> BvhExport:
    """The standard-BVH form of a motion (either convention, tree or forest).

    World positions of every source joint are those of ``names[j]`` in the result, to
    rounding (the file then keeps them to ~1e-14 of the size: 15 significant digits).
    """
    pre = pre_from_post(motion).replace(soft_parents=None)
    post, dummies = post_from_pre(pre)
    n_source = motion.n_joints
    names = _single_word_names(post.names)
    parents = list(post.parents)
    orders = list(post.rotation_orders)
    flags = list(post.has_translation)
    offsets = list(post.offsets)
    rotations = [post.rotations[:, j] for j in range(post.n_joints)]
    translations = [post.translations[:, j] for j in range(post.n_joints)]
    n_frames = post.n_frames
    roots = [j for j in range(post.n_joints) if parents[j] < 0]
    world = None
    if len(roots) > 1:
        world = _unique(world_root, set(names))
        names.append(world)
        parents.append(-1)
        orders.append(NEUTRAL_ORDER)
        flags.append(True)
        offsets.append(np.zeros(3))
        rotations.append(np.broadcast_to(np.eye(3), (n_frames, 3, 3)))
        translations.append(np.zeros((n_frames, 3)))
        for r in roots:
            parents[r] = len(names) - 1
    for j in roots:  # tree roots: 6 channels, positions = world positions
        flags[j] = True
    children = _children_in_file_order(names, parents, world)
    all_names = set(names)
    read_back: set[str] = set()  # names a reader has given, in file order
    for j in _depth_first(parents, children):
        p = parents[j]
        leaf = not children[j]
        if leaf and p >= 0 and not orders[j] and not flags[j]:
            if names[j] == _unique(f"{names[p]}_End", read_back):
                read_back.add(names[j])  # an End Site a reader names just so
                continue
            # any other channel-free leaf (e.g. one left childless by a split) keeps its
            # name: three zero rotation channels and a zero-offset End Site below
            source_order = pre.rotation_orders[j] if j < pre.n_joints else ""
            orders[j] = source_order or NEUTRAL_ORDER
        read_back.add(names[j])
        if orders[j]:
            orders[j] = complete_order(orders[j])
        if leaf:  # a leaf with channels: a zero-offset End Site below it
            end = _unique(f"{names[j]}_End", read_back)
            if end in all_names and end not in read_back:
                # a joint later in the file has the name a reader gives this End Site (the
                # End Site split off as a tree of its own): that joint is renamed in the
                # export (``names`` maps it back), else the reader would see the name twice
                later = names.index(end)
                names[later] = _unique(end, all_names | read_back)
                all_names.add(names[later])
            if end not in read_back:
                read_back.add(end)
                names.append(end)
                parents.append(j)
                orders.append("")
                flags.append(False)
                offsets.append(np.zeros(3))
                rotations.append(np.broadcast_to(np.eye(3), (n_frames, 3, 3)))
                translations.append(np.zeros((n_frames, 3)))
    source_names = tuple(names[:n_source])
    # the joints in the order the writer prints them and the loop above read them back
    order = _depth_first(parents, _children_in_file_order(names, parents, world))
    new_index = {old: new for new, old in enumerate(order)}
    result = Motion(
        names=[names[j] for j in order],
        parents=[new_index[parents[j]] if parents[j] >= 0 else -1 for j in order],
        offsets=np.array([offsets[j] for j in order]),
        rotation_orders=[orders[j] for j in order],
        has_translation=np.array([flags[j] for j in order]),
        rotations=np.stack([rotations[j] for j in order], axis=1),
        translations=np.stack([translations[j] for j in order], axis=1),
        frame_time=post.frame_time,
        convention="post",
        comments=post.comments,
        facts=post.facts,
    )
    return BvhExport(result, source_names, tuple(dummies), world)


#: a name a BVH reader may give an End Site (``<parent>_End``, maybe numbered)
_END_SITE_NAME = re.compile(r"_End\d*$")


def _children_in_file_order(names: list[str], parents: list[int], world: str | None) -> list[list[int]]:
    """Each joint's children by index, except that the trees of a forest whose root is named
    like an End Site (``Toes_End``, split off as a tree of its own) come first under the
    synthetic root: then a reader has seen that name before it names the End Site below the
    former parent (``Toes``), numbers that one ``Toes_End2``, and every joint keeps its name."""
    children: list[list[int]] = [[] for _ in names]
    for j, p in enumerate(parents):
        if p >= 0:
            children[p].append(j)
    if world is not None:
        children[names.index(world)].sort(key=lambda r: (_END_SITE_NAME.search(names[r]) is None, r))
    return children


def _single_word_names(names: tuple[str, ...]) -> list[str]:
    """Names with spaces get underscores (BVH names are one word; Blender would do the same),
    numbered if that name is taken."""
    taken = set(names)
    out = []
    for name in names:
        if " " in name:
            name = _unique(name.replace(" ", "_"), taken)
            taken.add(name)
        out.append(name)
    return out


def _depth_first(parents: list[int], children: list[list[int]]) -> list[int]:
    """Joints in the writer's order: depth first from each root, children by index."""
    order: list[int] = []
    stack = [j for j in reversed(range(len(parents))) if parents[j] < 0]
    while stack:
        j = stack.pop()
        order.append(j)
        stack.extend(reversed(children[j]))
    return order


def bvh_export_trees(motion: Motion) -> list[tuple[str, BvhExport]]:
    """One BVH export per tree of the forest: ``(root name, export)`` in root order.

    ``export.names`` maps every joint of ``motion`` (None for joints of other trees)."""
    pre = pre_from_post(motion).replace(soft_parents=None)
    out = []
    for root in pre.roots:
        joints = pre.subtree(int(root))
        single = bvh_export(pre.joint_slice(joints))
        names: list[str | None] = [None] * motion.n_joints
        for k, j in enumerate(joints):
            names[j] = single.names[k]
        out.append((pre.names[int(root)], dataclasses.replace(single, names=tuple(names))))
    return out


def tree_file_name(path: str | Path, root: str) -> Path:
    """``walk.bvh`` and root ``LeftFoot`` -> ``walk_LeftFoot.bvh`` (unsafe characters -> ``_``)."""
    path = Path(path)
    safe = re.sub(r"[^\w.-]+", "_", root).strip("._") or "tree"
    return path.with_name(f"{path.stem}_{safe}{path.suffix}")
