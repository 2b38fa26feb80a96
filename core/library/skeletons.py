"""Skeleton signatures: which takes share a rig, and how near two rigs are.

A :class:`Skeleton` is a take's joint names and topology (each joint's parent). Two hashes
name it:

- :attr:`Skeleton.signature`: names and topology; the order the file lists its joints in does
  not count (each joint is described by its name and the descriptions of its children,
  sorted), so two files of one rig have one signature;
- :attr:`Skeleton.topology`: the shape alone, names left out (a renamed rig keeps it).

:func:`match_score` says how near two skeletons are, from 0 to 1: joints are paired by name,
by name with the namespace and case left out (``mixamorig:LeftArm`` is ``leftarm``), and
through every joint map shipped in ``resources/jointmaps`` (:func:`core.jointmap.
match_joints`: CMU's BVH and ASF name their joints differently); a pair counts when its
nearest paired ancestors pair too (so the tree agrees, dummy joints between them aside). The
score is the Dice ratio ``2 * counted / (J_a + J_b)`` of the best of these pairings: 1 for
the same rig, 0.81 for CMU's BVH against its ASF (28 joints paired through the CMU map out
of 38 and 31), 0.70 for another cgspeed BVH whose finger joints are named otherwise, near 0
for rigs that share nothing.

:func:`skeleton_groups` puts skeletons that match at :data:`GROUP_MATCH` or more in one
group (and skeletons linked through others): takes of one rig, renamed or not, share a group
number in the library, the same whatever order the files were read in.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import re
from collections.abc import Iterable, Sequence
from functools import cached_property

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.jointmap import JointMap, available_joint_maps, load_joint_map, match_joints
from gmr_studio.core.model.motion import Motion

#: the least match score at which two skeletons are in one group: two joints in three pair up
GROUP_MATCH = 2 / 3
_NAMESPACE = re.compile(r"^.*[:|]")
_NOT_ALNUM = re.compile(r"[^0-9a-z]")


@dataclasses.dataclass(frozen=True)
class Skeleton:
    """Joint names (J,) and parent indices (J,) (-1 for a root) of a take."""

    names: tuple[str, ...]
    parents: tuple[int, ...]

    @classmethod
    def of(cls, motion: Motion) -> Skeleton:
        return cls(tuple(motion.names), tuple(int(p) for p in motion.parents))

    @property
    def n_joints(self) -> int:
        return len(self.names)

    @property
    def n_roots(self) -> int:
        return sum(1 for p in self.parents if p < 0)

    @cached_property
    def signature(self) -> str:
        """Hex SHA-256 of the names and the topology (joint order left out)."""
        return _digest(self._canonical(with_names=True))

    @cached_property
    def topology(self) -> str:
        """Hex SHA-256 of the topology alone (names and joint order left out)."""
        return _digest(self._canonical(with_names=False))

    def _canonical(self, *, with_names: bool) -> str:
        """Each joint written as ``name(child,child...)`` with its children sorted, deepest
        joints first (no recursion); the roots sorted, joined."""
        children: list[list[int]] = [[] for _ in self.names]
        for joint, parent in enumerate(self.parents):
            if parent >= 0:
                children[parent].append(joint)
        depth = [0] * len(self.names)
        order = [j for j, p in enumerate(self.parents) if p < 0]
        for joint in order:  # grows while it is walked: breadth first
            for child in children[joint]:
                depth[child] = depth[joint] + 1
                order.append(child)
        text = [""] * len(self.names)
        for joint in sorted(order, key=lambda j: -depth[j]):
            inner = ",".join(sorted(text[c] for c in children[joint]))
            label = json.dumps(self.names[joint]) if with_names else ""
            text[joint] = f"{label}({inner})"
        return ";".join(sorted(text[j] for j, p in enumerate(self.parents) if p < 0))

    def to_json(self) -> dict:
        return {"names": list(self.names), "parents": list(self.parents)}


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def plain_name(name: str) -> str:
    """A joint name without its namespace (``mixamorig:``), case and punctuation."""
    return _NOT_ALNUM.sub("", _NAMESPACE.sub("", name).lower())


@functools.cache
def shipped_maps() -> tuple[JointMap, ...]:
    """The joint maps in ``resources/jointmaps`` (a map that cannot be read is left out)."""
    maps = []
    for name in available_joint_maps():
        try:
            maps.append(load_joint_map(name))
        except MotionFileError:
            continue
    return tuple(maps)


def match_score(a: Skeleton, b: Skeleton, maps: Iterable[JointMap] | None = None) -> float:
    """How near two skeletons are, 0 to 1 (module docstring): the best Dice ratio of joints
    paired with agreeing ancestors, pairing by name, by plain name and through each of
    ``maps`` (default: the shipped ones)."""
    if a.signature == b.signature:
        return 1.0
    total = a.n_joints + b.n_joints
    if not total:
        return 0.0
    pairings = [match_joints(a.names, b.names).pairs, _plain_pairs(a, b)]
    pairings += [match_joints(a.names, b.names, m).pairs for m in (shipped_maps() if maps is None else maps)]
    best = max(_consistent(a, b, dict(pairs)) for pairs in pairings)
    return 2.0 * best / total


def best_joint_map(a: Skeleton, b: Skeleton) -> str | None:
    """The name of the shipped joint map that pairs ``a``'s joints with ``b``'s best (by the
    count of :func:`match_score`), or None when equal names pair as many: what a
    comparison of the two takes is given (``gmr compare --map``, the app's layers)."""
    by_name = _consistent(a, b, dict(match_joints(a.names, b.names).pairs))
    best, best_count = None, by_name
    for joint_map in shipped_maps():
        counted = _consistent(a, b, dict(match_joints(a.names, b.names, joint_map).pairs))
        if counted > best_count:
            best, best_count = joint_map.name, counted
    return best


def _plain_pairs(a: Skeleton, b: Skeleton) -> list[tuple[int, int]]:
    """Joints paired by :func:`plain_name` (names that become the same plain name on one
    side pair with none)."""
    plain_a = [plain_name(n) for n in a.names]
    plain_b = [plain_name(n) for n in b.names]
    once_b = {n: j for j, n in enumerate(plain_b) if plain_b.count(n) == 1}
    once_a = {n for n in plain_a if plain_a.count(n) == 1}
    return [(i, once_b[n]) for i, n in enumerate(plain_a) if n in once_a and n in once_b]


def _consistent(a: Skeleton, b: Skeleton, pairs: dict[int, int]) -> int:
    """Pairs whose nearest paired ancestors pair with each other (or both have none)."""
    paired_b = set(pairs.values())
    up_a = _paired_ancestors(a.parents, set(pairs))
    up_b = _paired_ancestors(b.parents, paired_b)
    count = 0
    for i, j in pairs.items():
        above_a, above_b = up_a[i], up_b[j]
        if (above_a < 0 and above_b < 0) or (above_a >= 0 and pairs.get(above_a) == above_b):
            count += 1
    return count


def _paired_ancestors(parents: Sequence[int], paired: set[int]) -> list[int]:
    """For each joint, its nearest ancestor in ``paired`` (-1: none)."""
    found = [-2] * len(parents)

    def nearest(joint: int) -> int:
        chain = []
        parent = parents[joint]
        while parent >= 0 and parent not in paired and found[parent] == -2:
            chain.append(parent)
            parent = parents[parent]
        result = found[parent] if parent >= 0 and parent not in paired else parent
        for link in chain:
            found[link] = result
        return result

    for joint in range(len(parents)):
        if found[joint] == -2:
            found[joint] = nearest(joint)
    return found


def could_match(a: Skeleton, b: Skeleton, least: float = GROUP_MATCH) -> bool:
    """Whether the joint counts allow a score of ``least``: the score is at most
    ``2 min(J_a, J_b) / (J_a + J_b)``."""
    total = a.n_joints + b.n_joints
    return total > 0 and 2 * min(a.n_joints, b.n_joints) >= least * total


def best_match(skeleton: Skeleton, others: Sequence[Skeleton]) -> tuple[int | None, float]:
    """(index, score) of the skeleton of ``others`` that matches ``skeleton`` best at
    :data:`GROUP_MATCH` or more (the first on a tie), or (None, 0.0)."""
    best, best_score = None, 0.0
    for k, other in enumerate(others):
        if could_match(skeleton, other):
            score = match_score(skeleton, other)
            if score >= GROUP_MATCH and score > best_score:
                best, best_score = k, score
    return best, best_score


def skeleton_groups(skeletons: Sequence[Skeleton], keys: Sequence[str]) -> tuple[list[int], list[float]]:
    """Group numbers (1, 2, ...) and each skeleton's best score within its group (1.0
    alone): skeletons matching at :data:`GROUP_MATCH` or more share a group, and so do
    skeletons linked through others (the connected parts of that relation), whatever order
    they are given in. Groups are numbered in the order of their least ``key`` (the
    library gives the first path of a file of each skeleton)."""
    n = len(skeletons)
    link = list(range(n))
    best = [0.0] * n

    def find(x: int) -> int:
        while link[x] != x:
            link[x] = link[link[x]]
            x = link[x]
        return x

    for i in range(n):
        for j in range(i + 1, n):
            if not could_match(skeletons[i], skeletons[j]):
                continue
            score = match_score(skeletons[i], skeletons[j])
            if score >= GROUP_MATCH:
                link[find(i)] = find(j)
                best[i], best[j] = max(best[i], score), max(best[j], score)
    first: dict[int, str] = {}
    for i in range(n):
        root = find(i)
        first[root] = min(first.get(root, keys[i]), keys[i])
    number = {root: g + 1 for g, root in enumerate(sorted(first, key=lambda r: first[r]))}
    return [number[find(i)] for i in range(n)], [b if b > 0 else 1.0 for b in best]
