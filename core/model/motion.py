"""The motion model: a skeleton forest and its per-frame data, as arrays, frames first.

A :class:`Motion` holds ``J`` joints and ``F`` frames:

=================  ===================  ===================================================
field              shape / type         meaning
=================  ===================  ===================================================
names              tuple of J str       unique joint names; BVH end sites are ordinary joints
parents            (J,) int64           parent index, -1 for a root
soft_parents       (J,) int64           the joint a split root was split from, -1 otherwise
link_offsets       (J, 3) float64       for a soft-link holder, the bone offset it had under
                                        its soft-link parent before the split (NaN where
                                        unknown or no link); join restores these bits
offsets            (J, 3) float64       static local offset ``t_j``; for a root, its static
                                        world position (used when it has no translation
                                        channels)
rotation_orders    tuple of J str       rotation channels in file order, e.g. ``"ZYX"``;
                                        ``""`` means no rotation channels (post only)
has_translation    (J,) bool            the joint has per-frame translation channels
rotations          (F, J, 3, 3) float64 local rotation matrices ``R_j`` per frame
translations       (F, J, 3) float64    local translation ``t_j`` per frame; equals
                                        ``offsets[j]`` where ``has_translation[j]`` is
                                        False; for a root, its world position ``G``
frame_time         float                seconds per frame
convention         "pre" or "post"      how a local transform is composed (below)
comments           tuple of str         free header lines (provenance, notes of edits)
facts              FileFacts            what the file states of its space: length unit, up
                                        axis, the unit the data came from (:mod:`.facts`)
=================  ===================  ===================================================

Conventions. ``"post"`` is BVH and ASF/AMC: ``L_j = [R_j, t_j]``, a joint's rotation moves
its children only. ``"pre"`` is GMR: ``L_j = [R_j, R_j t_j]``, a joint's rotation turns the
bone that ends at it. In both, a root's world transform is ``[R_r, t_r]``: its translation
is its world position (the paper's ``G_r``; roots carry no separate local offset).

Storage choice: local rotations as matrices make the per-joint FK step one batched 3x3
product; as unit quaternions each product and vector rotation is a dozen separate array
operations, slower in numpy for less than half the memory. Matrices it is; the Euler angles
of the files are converted once, at load. Translations are dense ``(F, J, 3)`` so that a
fully translational forest computes its positions as one array copy.

Joint indices never change under the operations (shift root, split, join): arrays of world
positions before and after an edit compare element by element. ``parents`` need not list a
parent before its child; :attr:`Motion.topological_order` gives an order that does.

A motion is immutable: its arrays are read-only views, and operations return new motions
that share the arrays they did not change.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Sequence
from functools import cached_property
from typing import Literal

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.rotations.euler import check_order

Convention = Literal["pre", "post"]

#: relative tolerance, times :attr:`Motion.size`, below which a length counts as zero
DEFAULT_RELATIVE_TOLERANCE = 1e-9
#: a joined bone whose recomputed offset varies less than this, times :attr:`Motion.size`,
#: over the frames gets a static offset. Rounding noise is ~1e-14 of the size; each such
#: join moves positions by at most this much, so even a chain of 60 joins stays far below
#: the 1e-9 to which operations promise to keep positions.
RIGID_RELATIVE_TOLERANCE = 1e-11
#: frames of the motion (evenly spread) that :attr:`Motion.size` measures
SIZE_SAMPLE_FRAMES = 64
#: a joint whose position varies less than this, times the extent of every joint over the
#: sampled frames, stands still; one whose position varies more than the next moves
STILL_RELATIVE_TOLERANCE = 1e-9
MOVING_RELATIVE_TOLERANCE = 1e-3


def _readonly(array: np.ndarray) -> np.ndarray:
    view = array.view()
    view.flags.writeable = False
    return view


def check_joint_name(name: str) -> str:
    """Return ``name`` if the text formats can carry it, else raise ValueError.

    A name is non-empty, has no braces, no tabs or line breaks, and no leading, trailing or
    repeated spaces (names such as ``LeftHand.001``, ``mixamorig:Hips``, ``l-knee`` are fine).
    """
    if not name or name != name.strip() or "  " in name:
        raise ValueError(f"joint name {name!r} is empty or has stray spaces")
    if any(ch in name for ch in "{}\t\r\n\v\f") or not name.isprintable():
        raise ValueError(f"joint name {name!r} contains a brace or a control character")
    return name


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class Motion:
    """Skeletal motion of a skeleton forest; see the module docstring for every field."""

    names: tuple[str, ...]
    parents: np.ndarray
    offsets: np.ndarray
    rotation_orders: tuple[str, ...]
    has_translation: np.ndarray
    rotations: np.ndarray
    translations: np.ndarray
    frame_time: float
    convention: Convention = "pre"
    soft_parents: np.ndarray | None = None
    link_offsets: np.ndarray | None = None
    comments: tuple[str, ...] = ()
    facts: FileFacts = dataclasses.field(default_factory=FileFacts)

    def __post_init__(self) -> None:
        names = tuple(check_joint_name(str(n)) for n in self.names)
        n_joints = len(names)
        if n_joints == 0:
            raise ValueError("a motion needs at least one joint")
        if len(set(names)) != n_joints:
            seen: set[str] = set()
            dup = next(n for n in names if n in seen or seen.add(n))
            raise ValueError(f"joint name {dup!r} appears twice")
        if self.convention not in ("pre", "post"):
            raise ValueError(f"convention must be 'pre' or 'post', not {self.convention!r}")
        parents = np.asarray(self.parents, dtype=np.int64)
        soft = (
            np.full(n_joints, -1, np.int64)
            if self.soft_parents is None
            else np.asarray(self.soft_parents, dtype=np.int64)
        )
        offsets = np.asarray(self.offsets, dtype=np.float64)
        has_translation = np.asarray(self.has_translation, dtype=bool)
        rotations = np.asarray(self.rotations, dtype=np.float64)
        translations = np.asarray(self.translations, dtype=np.float64)
        if parents.shape != (n_joints,) or soft.shape != (n_joints,):
            raise ValueError(f"parents and soft_parents must have shape ({n_joints},)")
        link_offsets = np.full((n_joints, 3), np.nan)
        if self.link_offsets is not None:
            given = np.asarray(self.link_offsets, dtype=np.float64)
            if given.shape != (n_joints, 3):
                raise ValueError(f"link_offsets must have shape ({n_joints}, 3), not {given.shape}")
            link_offsets[soft >= 0] = given[soft >= 0]  # only soft-link holders keep one
        if offsets.shape != (n_joints, 3) or has_translation.shape != (n_joints,):
            raise ValueError(f"offsets must be ({n_joints}, 3) and has_translation ({n_joints},)")
        if rotations.ndim != 4 or rotations.shape[1:] != (n_joints, 3, 3):
            raise ValueError(f"rotations must have shape (F, {n_joints}, 3, 3), not {rotations.shape}")
        if translations.shape != (rotations.shape[0], n_joints, 3):
            raise ValueError(
                f"translations must have shape ({rotations.shape[0]}, {n_joints}, 3), not {translations.shape}"
            )
        orders = tuple(str(o).upper() for o in self.rotation_orders)
        if len(orders) != n_joints:
            raise ValueError(f"rotation_orders must name {n_joints} orders")
        for name, order in zip(names, orders):
            if order == "" and self.convention == "pre":
                raise ValueError(f"joint {name!r}: GMR joints need rotation channels")
            if order:
                check_order(order)
        frame_time = float(self.frame_time)
        if not np.isfinite(frame_time) or frame_time <= 0:
            raise ValueError(f"frame time must be a positive number of seconds, not {frame_time}")
        _check_forest(names, parents, soft)
        set_field = object.__setattr__
        set_field(self, "names", names)
        set_field(self, "rotation_orders", orders)
        set_field(self, "frame_time", frame_time)
        set_field(self, "comments", tuple(str(c) for c in self.comments))
        if not isinstance(self.facts, FileFacts):
            raise ValueError(f"facts must be FileFacts, not {type(self.facts).__name__}")
        for field, value in (
            ("parents", parents),
            ("soft_parents", soft),
            ("link_offsets", link_offsets),
            ("offsets", offsets),
            ("has_translation", has_translation),
            ("rotations", rotations),
            ("translations", translations),
        ):
            set_field(self, field, _readonly(value))

    # ----------------------------------------------------------------- sizes and lookup
    @property
    def n_frames(self) -> int:
        return self.rotations.shape[0]

    @property
    def n_joints(self) -> int:
        return len(self.names)

    @property
    def frame_rate(self) -> float:
        return 1.0 / self.frame_time

    @cached_property
    def _index_of(self) -> dict[str, int]:
        return {name: j for j, name in enumerate(self.names)}

    def joint_index(self, joint: int | str) -> int:
        """Index of a joint given by name or index; OperationError if there is no such joint."""
        if isinstance(joint, (int, np.integer)) and not isinstance(joint, bool):
            if 0 <= joint < self.n_joints:
                return int(joint)
            raise OperationError(f"joint index {joint} is out of range (0..{self.n_joints - 1})")
        try:
            return self._index_of[joint]
        except (KeyError, TypeError):
            raise OperationError(f"unknown joint {joint!r}") from None

    # ---------------------------------------------------------------------- structure
    @cached_property
    def roots(self) -> np.ndarray:
        """(R,) int64: the roots of the forest, in index order."""
        return _readonly(np.flatnonzero(self.parents < 0))

    @cached_property
    def children(self) -> tuple[tuple[int, ...], ...]:
        """For each joint, its children in index order."""
        kids: list[list[int]] = [[] for _ in range(self.n_joints)]
        for j, p in enumerate(self.parents):
            if p >= 0:
                kids[p].append(j)
        return tuple(tuple(k) for k in kids)

    @cached_property
    def topological_order(self) -> np.ndarray:
        """(J,) int64: every joint after its parent (depth-first, children in index order)."""
        order: list[int] = []
        stack = [int(r) for r in self.roots[::-1]]
        while stack:
            j = stack.pop()
            order.append(j)
            stack.extend(reversed(self.children[j]))
        return _readonly(np.asarray(order, dtype=np.int64))

    @cached_property
    def depths(self) -> np.ndarray:
        """(J,) int64: number of edges from each joint up to its root."""
        depth = np.zeros(self.n_joints, np.int64)
        for j in self.topological_order:
            p = self.parents[j]
            if p >= 0:
                depth[j] = depth[p] + 1
        return _readonly(depth)

    @cached_property
    def tree_roots(self) -> np.ndarray:
        """(J,) int64: the root of the tree each joint belongs to."""
        root = np.arange(self.n_joints)
        for j in self.topological_order:
            p = self.parents[j]
            if p >= 0:
                root[j] = root[p]
        return _readonly(root)

    def path_from_root(self, joint: int | str) -> list[int]:
        """Indices from the joint's tree root down to the joint, both included."""
        j = self.joint_index(joint)
        path = [j]
        while self.parents[path[-1]] >= 0:
            path.append(int(self.parents[path[-1]]))
        return path[::-1]

    def subtree(self, joint: int | str) -> list[int]:
        """The joint and all its descendants, parents before children."""
        out = [self.joint_index(joint)]
        for j in out:
            out.extend(self.children[j])
        return out

    # ------------------------------------------------------------------------ scale
    @cached_property
    def sampled_positions(self) -> np.ndarray:
        """(K, J, 3) world positions at up to :data:`SIZE_SAMPLE_FRAMES` frames spread evenly
        over the motion (the rest pose when there are no frames)."""
        from gmr_studio.core.kinematics.fk import world_positions

        if not self.n_frames:
            return world_positions(self.rest_pose())
        frames = np.unique(np.linspace(0, self.n_frames - 1, min(self.n_frames, SIZE_SAMPLE_FRAMES)).round())
        return world_positions(self.frame_slice(frames.astype(np.int64)))

    @cached_property
    def anchors(self) -> np.ndarray:
        """(J,) bool: joints that only pin the figure to a fixed point, not part of it.

        An anchor never moves and every link it has (bones and soft links alike, so shift
        root, split and join do not change it) stretches: the ``Root`` left at the world
        origin by many game and dataset exports while the hips below it carry the walk, or
        the ``World`` root a forest is exported under. A joint whose link to a neighbour
        keeps its length is part of the figure, and a still motion (a T-pose) has none.
        """
        points = self.sampled_positions
        ends = [(np.flatnonzero(links >= 0), links) for links in (self.parents, self.soft_parents)]
        child = np.concatenate([c for c, _ in ends])
        parent = np.concatenate([links[c] for c, links in ends])
        extent = float(np.max(points.max(axis=(0, 1)) - points.min(axis=(0, 1))))
        spread = np.abs(points - points.mean(axis=0)).max(axis=(0, 2))  # (J,)
        still = spread <= STILL_RELATIVE_TOLERANCE * extent
        length = np.linalg.norm(points[:, child] - points[:, parent], axis=-1)  # (F, links)
        rigid = np.ptp(length, axis=0) <= MOVING_RELATIVE_TOLERANCE * extent
        linked = np.zeros(self.n_joints, np.int64)
        np.add.at(linked, child, 1)
        np.add.at(linked, parent, 1)
        held = np.zeros(self.n_joints, np.int64)  # links that keep their length
        np.add.at(held, child[rigid], 1)
        np.add.at(held, parent[rigid], 1)
        anchor = still & (linked > 0) & (held == 0)
        return _readonly(anchor)

    @cached_property
    def size(self) -> float:
        """The actor's size: the largest extent, over the three axes and a sample of frames
        spread over the motion, of the joints' world positions in one frame, leaving out
        :attr:`anchors` (a ``Root`` pinned at the origin would make it the distance from
        the origin to the actor instead).

        Invariant under shift root, split and join (they keep positions, and anchors are
        found from positions and the links between joints, whatever their kind), so
        tolerances scaled by it are too.
        """
        points = self.sampled_positions[:, ~self.anchors]
        extent = float(np.max(points.max(axis=1) - points.min(axis=1))) if points.size else 0.0
        return extent if np.isfinite(extent) and extent > 0 else 1.0

    # ------------------------------------------------------------------- derivations
    def replace(self, **changes) -> Motion:
        """A copy with some fields replaced (arrays not named are shared, not copied)."""
        return dataclasses.replace(self, **changes)

    def frame_slice(self, frames: slice | np.ndarray) -> Motion:
        """The motion restricted to some frames (a slice shares memory; an index array copies)."""
        return self.replace(rotations=self.rotations[frames], translations=self.translations[frames])

    def joint_slice(self, joints: Sequence[int] | np.ndarray) -> Motion:
        """The motion restricted to ``joints`` (in that order), renumbered: each kept joint's
        parent must be kept too, or the joint must be a root. Soft links to joints left out
        are dropped."""
        joints = np.asarray(joints, dtype=np.int64)
        index = np.full(self.n_joints, -1, np.int64)
        index[joints] = np.arange(joints.size)
        parents, soft = self.parents[joints], self.soft_parents[joints]
        return self.replace(
            names=tuple(self.names[j] for j in joints),
            parents=np.where(parents >= 0, index[parents], -1),
            soft_parents=np.where(soft >= 0, index[soft], -1),
            link_offsets=self.link_offsets[joints],
            offsets=self.offsets[joints],
            rotation_orders=tuple(self.rotation_orders[j] for j in joints),
            has_translation=self.has_translation[joints],
            rotations=self.rotations[:, joints],
            translations=self.translations[:, joints],
        )

    def rest_pose(self) -> Motion:
        """One frame with every rotation the identity and every translation its offset."""
        return self.replace(
            rotations=np.broadcast_to(np.eye(3), (1, self.n_joints, 3, 3)).copy(),
            translations=self.offsets[None].copy(),
        )

    def check_invariants(self) -> None:
        """Check what construction does not (it costs a pass over every frame):
        finite data, orthonormal rotations with det +1, and static translations equal to
        the offsets. Raises ValueError."""
        if not (np.isfinite(self.rotations).all() and np.isfinite(self.translations).all()):
            raise ValueError("rotations or translations contain NaN or infinity")
        if not np.isfinite(self.offsets).all():
            raise ValueError("offsets contain NaN or infinity")
        gram = np.einsum("fjab,fjac->fjbc", self.rotations, self.rotations)
        if self.n_frames and not np.allclose(gram, np.eye(3), atol=1e-8):
            raise ValueError("some rotation matrices are not orthonormal")
        if self.n_frames and not np.all(np.linalg.det(self.rotations) > 0):
            raise ValueError("some rotation matrices are reflections")
        static = ~self.has_translation
        if not np.array_equal(
            self.translations[:, static], np.broadcast_to(self.offsets[static], self.translations[:, static].shape)
        ):
            raise ValueError("translations of joints without translation channels differ from their offsets")


def _check_forest(names: tuple[str, ...], parents: np.ndarray, soft: np.ndarray) -> None:
    """Raise ValueError unless parents form a forest and the soft links are canonical.

    Soft links: each joins two different trees, the trees and soft links together form a
    forest again (the union graph is acyclic), and each tree has at most one joint holding
    a soft link (the one that leads towards the tree it was split from).
    """
    n = len(names)
    for arr, what in ((parents, "parent"), (soft, "soft-link parent")):
        bad = np.flatnonzero((arr < -1) | (arr >= n) | (arr == np.arange(n)))
        if bad.size:
            j = int(bad[0])
            raise ValueError(f"joint {names[j]!r} has an invalid {what} index {int(arr[j])}")
    # hard tree membership, detecting cycles
    tree = np.full(n, -1, np.int64)
    for start in range(n):
        chain = []
        j = start
        while tree[j] < 0 and parents[j] >= 0:
            chain.append(j)
            j = int(parents[j])
            if len(chain) > n:
                raise ValueError(f"the parents of joint {names[start]!r} form a cycle")
        root = j if tree[j] < 0 else int(tree[j])
        tree[j] = root
        tree[chain] = root
    # union graph of hard edges and soft links must stay a forest (union-find)
    link = list(range(n))

    def find(x: int) -> int:
        while link[x] != x:
            link[x] = link[link[x]]
            x = link[x]
        return x

    for j in range(n):
        for other in (parents[j], soft[j]):
            if other < 0:
                continue
            a, b = find(j), find(int(other))
            if a == b:
                raise ValueError(
                    f"the soft link from {names[j]!r} to {names[int(other)]!r} closes a cycle: "
                    "a soft link must join two different trees"
                )
            link[a] = b
    holders: dict[int, int] = {}
    for j in np.flatnonzero(soft >= 0):
        root = int(tree[j])
        if root in holders:
            raise ValueError(
                f"the tree rooted at {names[root]!r} holds two soft links (at "
                f"{names[holders[root]]!r} and {names[int(j)]!r}); each tree may hold one"
            )
        holders[root] = int(j)


def build_translations(n_frames: int, offsets: np.ndarray, channels: dict[int, np.ndarray]) -> np.ndarray:
    """Dense translations (F, J, 3): the offsets everywhere, then per-frame values for the
    joints in ``channels`` (joint index -> (F, 3) array)."""
    out = np.empty((n_frames, offsets.shape[0], 3))
    out[:] = offsets
    for j, values in channels.items():
        out[:, j] = values
    return out


def identity_rotations(n_frames: int, n_joints: int) -> np.ndarray:
    """(F, J, 3, 3) identity matrices."""
    out = np.zeros((n_frames, n_joints, 3, 3))
    out[..., 0, 0] = out[..., 1, 1] = out[..., 2, 2] = 1.0
    return out


def joint_names(motion: Motion, joints: Iterable[int]) -> list[str]:
    """Names of some joints, for messages."""
    return [motion.names[j] for j in joints]
