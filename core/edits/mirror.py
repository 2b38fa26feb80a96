"""Mirror a motion left/right across its sagittal plane.

Left/right partners are found by name (:func:`side_partners`), with these rules, tried in
order on each name:

- strict (a name that fits one without a partner is *reported*): ``Left*``/``Right*``
  (after an optional ``namespace:``, e.g. ``mixamorig:LeftArm``), ``*Left``/``*Right``
  (Second Life's ``mHandIndex1Left``, ``mEyeLeft``), ``*_L``/``*_R``, ``*.L``/``*.R``, and
  the same letters between separators, ``*_L_*``/``*.L.*`` (an end site ``Hand_L_End``)
  (either case of the letter);
- loose (a name that fits one without a partner is taken as central, since ``lowerback``
  and ``LowerBack`` are no side): ``l*``/``r*`` followed by a letter, as in CMU ASF
  (``lfemur``) and Poser or Second Life BVH (``lCollar``, ``rShldr``, ``lThigh``), and
  ``L*``/``R*`` followed by an upper-case letter (``LHipJoint``).

With the parents given, a joint left central whose name is its parent's followed by more
(an End Site named ``<parent>_End`` or ``<parent>End`` under a sided parent) takes the
partner named the same way under the parent's partner. Mirror keeps the skeleton: the
partners of two joints linked by a bone (or a soft link) must be linked too, either way
round, bone or soft link (a forest rooted at the left foot mirrors to one rooted at the
right foot, a split at the right arm to one at the left arm), else
:func:`mirror` refuses, naming the bone, rather than move a joint to another parent.

The sagittal plane is perpendicular to the *lateral axis*: the world axis (X, Y or Z) most
aligned with the mean left-minus-right vector of the partners in the rest pose; it passes
through the mean lateral coordinate of all joints at the first frame. With ``S`` the
reflection of that axis and ``σ`` the partner swap (an involution; central joints map to
themselves), joint ``j`` of the result takes the data of ``σ(j)`` reflected:
``R'_j = S R_σ(j) S`` (a rotation again), ``t'_j = S t_σ(j)`` (plus ``2 c n`` for a root's
world position), ``parent'(j) = σ(parent(σ(j)))``, orders and channels of ``σ(j)``. Every
world position becomes ``P'_j = S P_σ(j) + 2 c n`` in either convention (forward kinematics
commutes with the conjugation), and mirroring twice gives the motion back exactly.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.engine import turned_joints
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.motion import Motion

#: (pattern, left, right, strict): the side is group 2; groups 1 and 3 are kept
SIDE_RULES: tuple[tuple[re.Pattern[str], str, str, bool], ...] = (
    (re.compile(r"^((?:.*:)?)(Left|Right)(.*)$"), "Left", "Right", True),
    (re.compile(r"^((?:.*:)?)(left|right)(.*)$"), "left", "right", True),
    (re.compile(r"^(.+)(Left|Right)()$"), "Left", "Right", True),
    (re.compile(r"^(.+_)(L|R)()$"), "L", "R", True),
    (re.compile(r"^(.+_)(l|r)()$"), "l", "r", True),
    (re.compile(r"^(.+\.)(L|R)()$"), "L", "R", True),
    (re.compile(r"^(.+\.)(l|r)()$"), "l", "r", True),
    (re.compile(r"^(.+_)(L|R)(_.+)$"), "L", "R", True),
    (re.compile(r"^(.+_)(l|r)(_.+)$"), "l", "r", True),
    (re.compile(r"^(.+\.)(L|R)(\..+)$"), "L", "R", True),
    (re.compile(r"^(.+\.)(l|r)(\..+)$"), "l", "r", True),
    (re.compile(r"^()(l|r)([A-Za-z].*)$"), "l", "r", False),
    (re.compile(r"^()(L|R)([A-Z].*)$"), "L", "R", False),
)


@dataclasses.dataclass(frozen=True)
class SidePairs:
    """Left/right partners of a motion's joints.

    Attributes
    ----------
    partner : (J,) int64, the index of each joint's partner (itself for central joints).
    pairs : (P, 2) int64, ``(left, right)`` index pairs.
    unmatched : names that follow a strict side rule but whose partner is absent.
    """

    partner: np.ndarray
    pairs: np.ndarray
    unmatched: tuple[str, ...]


def side_partners(names: tuple[str, ...] | list[str], parents: np.ndarray | None = None) -> SidePairs:
    """Partners of each name under :data:`SIDE_RULES`, and with ``parents`` (J,) the
    children named after a sided parent (see the module docstring)."""
    index = {name: j for j, name in enumerate(names)}
    partner = np.arange(len(names), dtype=np.int64)
    pairs: list[tuple[int, int]] = []
    unmatched: list[str] = []
    for j, name in enumerate(names):
        for pattern, left, right, strict in SIDE_RULES:
            match = pattern.match(name)
            if match is None:
                continue
            head, side, tail = match.groups()
            other = index.get(f"{head}{right if side == left else left}{tail}")
            if other is not None:
                partner[j] = other
                if side == left:
                    pairs.append((j, other))
                break
            if strict:
                unmatched.append(name)
                break
    if parents is not None:
        for j in _parents_first(parents):
            p = int(parents[j])
            if partner[j] != j or p < 0 or partner[p] == p or not names[j].startswith(names[p]):
                continue
            other = index.get(names[partner[p]] + names[j][len(names[p]) :])
            if other is not None and other != j and partner[other] == other:
                partner[j], partner[other] = other, j
                left = p in {int(a) for a, _ in pairs}
                pairs.append((j, other) if left else (other, j))
                for name in (names[j], names[other]):
                    if name in unmatched:
                        unmatched.remove(name)
    return SidePairs(partner, np.array(pairs, dtype=np.int64).reshape(-1, 2), tuple(unmatched))


def mirror_pairs(motion: Motion) -> SidePairs:
    """The partners :func:`mirror` swaps: :func:`side_partners` of the motion's names and parents."""
    return side_partners(motion.names, motion.parents)


def pairs_text(names: tuple[str, ...] | list[str], pairs: np.ndarray, limit: int | None = None) -> str:
    """The pairs (P, 2) of ``names`` for a message: ``"2 left/right pairs: lCollar/rCollar,
    lShldr/rShldr"``; with ``limit``, the first ``limit`` pairs and ``"and N more"`` (0: the
    count alone)."""
    count = pairs.shape[0]
    head = f"{count} left/right pair{'' if count == 1 else 's'}"
    if limit == 0:
        return head
    shown = [f"{names[a]}/{names[b]}" for a, b in pairs[:limit]]
    if count > len(shown):
        shown.append(f"and {count - len(shown)} more")
    return f"{head}: {', '.join(shown)}" if shown else head


def _parents_first(parents: np.ndarray) -> list[int]:
    """Joint indices, every joint after its parent."""
    depth = np.zeros(len(parents), np.int64)
    for _ in range(len(parents)):
        deeper = np.where(parents >= 0, depth[np.maximum(parents, 0)] + 1, 0)
        if np.array_equal(deeper, depth):
            break
        depth = deeper
    return [int(j) for j in np.argsort(depth, kind="stable")]


def lateral_axis(motion: Motion, pairs: np.ndarray) -> int:
    """The world axis (0, 1, 2) most aligned with the mean left-minus-right vector of the
    pairs in the rest pose; OperationError when there are no pairs or they coincide."""
    if pairs.shape[0] == 0:
        raise OperationError("mirror needs left/right joints, and no joint names follow a left/right rule")
    rest = world_positions(motion.rest_pose())[0]
    across = np.abs((rest[pairs[:, 0]] - rest[pairs[:, 1]]).mean(axis=0))
    if not across.max() > 1e-9 * motion.size:
        raise OperationError("the left and right joints coincide in the rest pose: no lateral axis")
    return int(np.argmax(across))


def mirror(motion: Motion) -> tuple[Motion, tuple[str, ...]]:
    """The motion mirrored left/right (module docstring) and the names left unmatched; the
    pairs swapped are :func:`mirror_pairs` (:func:`pairs_text` says them).

    Raises OperationError when no joints pair up.
    """
    edited, unmatched = mirror_edit(motion)
    return edited.motion, unmatched


def mirror_edit(motion: Motion, *, threads: int | None = None) -> tuple[Edited, tuple[str, ...]]:
    """:func:`mirror`; joint ``j`` of the result is at ``S P_σ(j) + 2 c n`` with the world
    rotation ``S W_σ(j) S``. The frames are swapped and reflected in one compiled pass (on
    ``threads``, None, the default: one per core; :func:`core.kinematics.engine.turned_joints`)."""
    sides = mirror_pairs(motion)
    axis = lateral_axis(motion, sides.pairs)
    sigma = sides.partner
    links = [(j, int(p)) for j, p in enumerate(motion.parents) if p >= 0]
    links += [(j, int(p)) for j, p in enumerate(motion.soft_parents) if p >= 0]
    edges = {(min(j, p), max(j, p)) for j, p in links}  # bones and soft links, either way round
    for j, p in links:
        a, b = int(sigma[j]), int(sigma[p])
        if (min(a, b), max(a, b)) not in edges:
            raise OperationError(
                f"mirror would change the skeleton: the link {motion.names[p]!r} - {motion.names[j]!r} "
                f"would become {motion.names[b]!r} - {motion.names[a]!r}, which the skeleton does not have; "
                "rename the joints so that left and right sides pair up"
            )
    first = world_positions(motion.frame_slice(slice(0, 1)))[0] if motion.n_frames else np.zeros((1, 3))
    centre = float(first[:, axis].mean())
    flip = np.ones(3)
    flip[axis] = -1.0
    shift = np.zeros(3)
    shift[axis] = 2.0 * centre
    parents = motion.parents[sigma]
    parents = np.where(parents >= 0, sigma[np.maximum(parents, 0)], -1)
    soft = motion.soft_parents[sigma]
    soft = np.where(soft >= 0, sigma[np.maximum(soft, 0)], -1)
    root_shift = np.where((parents < 0)[:, None], shift, 0.0)
    offsets = motion.offsets[sigma] * flip + root_shift
    reflection = np.diag(flip)
    translations = turned_joints(motion.translations, sigma, turn=reflection, shift=root_shift, threads=threads)
    rotations = turned_joints(motion.rotations, sigma, turn=reflection, threads=threads)
    mirrored = motion.replace(
        names=motion.names,
        parents=parents,
        soft_parents=soft,
        offsets=offsets,
        rotation_orders=tuple(motion.rotation_orders[s] for s in sigma),
        has_translation=motion.has_translation[sigma],
        rotations=rotations,
        translations=translations,
    )
    return Edited(mirrored, sigma, sigma, turn=reflection, shift=shift), sides.unmatched
