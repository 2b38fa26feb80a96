"""The kinematics classroom: a joint's chain both ways, shift root explained, roots traded for time.

Everything here is what the Teach dock shows, computed from a GMR (pre-rotation) motion:

- :func:`joint_chain`: the chain from a joint's root to the joint at one frame, each link's
  local transform as GMR's pre-rotation ``[R_j, R_j t_j]`` and as BVH's post-rotation
  ``[Q_j, t_j]``, the two products, and the world transform forward kinematics gives.
  Post-rotation stores on a joint the rotation of the bones leaving it, so along a chain
  ``r = j_0, j_1, ..., j_n``: ``Q_r = R_r R_{j_1}``, ``Q_{j_k} = R_{j_{k+1}}`` and for the
  last joint the rotation of its own child bones (one child's ``R``, the identity for an end
  site). Both products put the joint at the same world position; their rotations are the
  frames of the bone ending at the joint (GMR) and of the bones leaving it (BVH).
- :func:`explain_shift_root`: which parent/child links a shift root reversed, and the largest
  change of any joint's world position over all frames (rounding).
- :func:`roots_tradeoff`: the paper's Figure 4 on the user's motion: split ``k - 1`` joints
  (the deepest first) to get ``k`` roots, and measure the FK time per frame, the stored
  numbers per frame and the largest change of the positions.
"""

from __future__ import annotations

import dataclasses
import itertools
import time

import numpy as np

from gmr_studio.core.edits.operations import split
from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion


def homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """(4, 4) ``[rotation, translation; 0 0 0 1]`` from (3, 3) and (3,)."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = translation
    return matrix


@dataclasses.dataclass(frozen=True)
class ChainLink:
    """One joint of a chain at one frame.

    ``gmr_local`` is ``[R_j, R_j t_j]`` (for the root ``[R_r, G]``), ``bvh_local`` is
    ``[Q_j, t_j]`` (for the root ``[Q_r, G]``), both (4, 4). ``bvh_rotation_from`` names
    the joint whose GMR rotation ``Q_j`` is made of, in words.
    """

    joint: int
    name: str
    gmr_local: np.ndarray
    bvh_local: np.ndarray
    bvh_rotation_from: str


@dataclasses.dataclass(frozen=True)
class JointChain:
    """A joint's chain from its root at one frame, both ways, and what FK says.

    ``gmr_product`` and ``bvh_product`` are the products of the links' locals (4, 4);
    ``world`` is the joint's world transform from forward kinematics (4, 4);
    ``position_gap`` is the largest coordinate difference between either product's
    position and FK's, ``rotation_gap`` the largest entry difference between the GMR
    product's rotation and FK's world rotation (both rounding).
    """

    frame: int
    links: tuple[ChainLink, ...]
    gmr_product: np.ndarray
    bvh_product: np.ndarray
    world: np.ndarray
    position_gap: float
    rotation_gap: float
    children_differ: bool

    @property
    def joints(self) -> list[int]:
        return [link.joint for link in self.links]


def _leaving_rotation(motion: Motion, joint: int, frame: int) -> tuple[np.ndarray, str, bool]:
    """The rotation of the bones leaving ``joint`` (3, 3), where it comes from, and whether the
    children disagree (then post-rotation needs a dummy joint per child; the first child's
    rotation is used)."""
    children = motion.children[joint]
    if not children:
        return np.eye(3), "none: an end site has no channels", False
    rotations = motion.rotations[frame, list(children)]
    differ = bool(np.abs(rotations - rotations[0]).max() > 1e-12) if len(children) > 1 else False
    return rotations[0], f"R of {motion.names[children[0]]}", differ


def joint_chain(
    motion: Motion, joint: int | str, frame: int, world: tuple[np.ndarray, np.ndarray] | None = None
) -> JointChain:
    """The chain of ``joint`` at ``frame`` (see the module docstring).

    ``world``: optional FK results (positions (F, J, 3), rotations (F, J, 3, 3)) to compare
    with; computed for the one frame when not given.
    """
    if motion.convention != "pre":
        raise ValueError("the classroom explains a GMR (pre-rotation) motion")
    target = motion.joint_index(joint)
    path = motion.path_from_root(target)
    rotations, translations = motion.rotations[frame], motion.translations[frame]
    links = []
    for k, j in enumerate(path):
        rotation, translation = rotations[j], translations[j]
        is_root = k == 0
        gmr = homogeneous(rotation, translation if is_root else rotation @ translation)
        if k + 1 < len(path):
            nxt = path[k + 1]
            leaving, source = rotations[nxt], f"R of {motion.names[nxt]}"
        else:
            leaving, source, _ = _leaving_rotation(motion, j, frame)
        if is_root:
            leaving = rotation @ leaving
            source = f"R of {motion.names[j]} times {source}" if source.startswith("R of") else source
        links.append(ChainLink(j, motion.names[j], gmr, homogeneous(leaving, translation), source))
    gmr_product = np.linalg.multi_dot([link.gmr_local for link in links] + [np.eye(4)])
    bvh_product = np.linalg.multi_dot([link.bvh_local for link in links] + [np.eye(4)])
    if world is None:
        positions, world_rotations = forward_kinematics(motion.frame_slice(slice(frame, frame + 1)))
        position, world_rotation = positions[0, target], world_rotations[0, target]
    else:
        position, world_rotation = world[0][frame, target], world[1][frame, target]
    fk = homogeneous(world_rotation, position)
    position_gap = max(
        float(np.abs(gmr_product[:3, 3] - position).max()), float(np.abs(bvh_product[:3, 3] - position).max())
    )
    rotation_gap = float(np.abs(gmr_product[:3, :3] - world_rotation).max())
    _, _, differ = _leaving_rotation(motion, target, frame)
    return JointChain(frame, tuple(links), gmr_product, bvh_product, fk, position_gap, rotation_gap, differ)


def scaled_rotation(rotation: np.ndarray, amount: float) -> np.ndarray:
    """``rotation`` (..., 3, 3) scaled along its own axis: identity at 0, itself at 1.

    The rotation angle is multiplied by ``amount`` about the same axis (Rodrigues), so the
    classroom's slider turns a bone smoothly from rest to its pose at this frame.
    """
    rotation = np.asarray(rotation, dtype=float)
    trace = np.trace(rotation, axis1=-2, axis2=-1)
    angle = np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0))
    axis = np.stack(
        [
            rotation[..., 2, 1] - rotation[..., 1, 2],
            rotation[..., 0, 2] - rotation[..., 2, 0],
            rotation[..., 1, 0] - rotation[..., 0, 1],
        ],
        axis=-1,
    )
    norm = np.linalg.norm(axis, axis=-1, keepdims=True)
    near_pi = (norm[..., 0] < 1e-9) & (angle > 1.0)
    if np.any(near_pi):  # sin(angle) ~ 0 at 180 degrees: the axis is the symmetric part's column
        symmetric = (rotation + np.eye(3)) / 2.0
        column = np.argmax(np.diagonal(symmetric, axis1=-2, axis2=-1), axis=-1)
        picked = np.take_along_axis(symmetric, column[..., None, None].repeat(3, -1), axis=-1)[..., 0]
        axis = np.where(near_pi[..., None], picked, axis)
        norm = np.linalg.norm(axis, axis=-1, keepdims=True)
    axis = np.divide(axis, norm, out=np.zeros_like(axis), where=norm > 0)
    theta = angle * amount
    x, y, z = axis[..., 0], axis[..., 1], axis[..., 2]
    zero = np.zeros_like(x)
    cross = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)], -2)
    sin, cos = np.sin(theta)[..., None, None], np.cos(theta)[..., None, None]
    return np.eye(3) + sin * cross + (1.0 - cos) * (cross @ cross)


@dataclasses.dataclass(frozen=True)
class ShiftRootExplanation:
    """What a shift root did: the links whose direction reversed (parent, child) as names,
    before -> after, and the largest change of any world position over all frames."""

    new_root: str
    old_root: str
    reversed_links: tuple[tuple[str, str], ...]
    largest_change: float
    size: float

    def lines(self) -> list[str]:
        out = [f"{self.new_root} became the root of its tree (it was under {self.old_root})."]
        for parent, child in self.reversed_links:
            out.append(f"  {parent} -> {child} is now {child} -> {parent}")
        out.append(
            f"Largest change of any joint's world position over all frames: {self.largest_change:.3g} "
            f"({self.largest_change / self.size:.2g} of the skeleton's size): rounding, the positions did not move."
        )
        return out


def explain_shift_root(
    before: Motion, after: Motion, joint: int | str, positions: tuple[np.ndarray, np.ndarray] | None = None
) -> ShiftRootExplanation:
    """Explain ``after = shift_root(before, joint)``; ``positions``: optional (before, after)
    world positions (F, J, 3) already computed."""
    target = before.joint_index(joint)
    path = before.path_from_root(target)
    reversed_links = tuple((before.names[a], before.names[b]) for a, b in itertools.pairwise(path))
    if positions is None:
        positions = (
            forward_kinematics(before, with_rotations=False)[0],
            forward_kinematics(after, with_rotations=False)[0],
        )
    change = float(np.abs(positions[1] - positions[0]).max()) if before.n_frames else 0.0
    return ShiftRootExplanation(before.names[target], before.names[path[0]], reversed_links, change, before.size)


@dataclasses.dataclass(frozen=True)
class TradeoffPoint:
    """One setting of the roots slider: ``roots`` trees, FK microseconds per frame,
    numbers stored per frame, and the largest position change (vs one root)."""

    roots: int
    split_joints: tuple[str, ...]
    fk_us_per_frame: float
    stored_per_frame: int
    largest_change: float


def stored_per_frame(motion: Motion) -> int:
    """Numbers stored per frame: 3 per joint with rotation channels (a root always has them)
    plus 3 per joint with translation channels."""
    rotating = np.array([bool(order) for order in motion.rotation_orders]) | (motion.parents < 0)
    return int(3 * rotating.sum() + 3 * motion.has_translation.sum())


def deepest_first(motion: Motion) -> list[int]:
    """Non-root joints ordered deepest first (ties by index): the split order of the slider."""
    candidates = np.flatnonzero(motion.parents >= 0)
    depths = motion.depths[candidates]
    return [int(j) for j in candidates[np.lexsort((candidates, -depths))]]


def split_to_roots(motion: Motion, roots: int, order: list[int] | None = None) -> tuple[Motion, list[int]]:
    """``motion`` with joints split (``order``, default deepest first) until it has ``roots``
    trees; returns the motion and the joints split."""
    order = deepest_first(motion) if order is None else order
    have = int((motion.parents < 0).sum())
    chosen = [j for j in order if motion.parents[j] >= 0][: max(0, roots - have)]
    for j in chosen:
        motion = split(motion, j)
    return motion, chosen


def roots_tradeoff(
    motion: Motion, roots: int, *, reference: np.ndarray | None = None, repeats: int = 3, order: list[int] | None = None
) -> TradeoffPoint:
    """Measure FK of ``motion`` split to ``roots`` trees (best of ``repeats`` runs).

    ``reference``: world positions (F, J, 3) of the unsplit motion (computed when None).
    """
    if reference is None:
        reference = fk_engine.world_positions(motion)
    forest, chosen = split_to_roots(motion, roots, order)
    best = np.inf
    positions = reference
    for _ in range(max(1, repeats)):
        start = time.perf_counter()
        positions = fk_engine.world_positions(forest)
        best = min(best, time.perf_counter() - start)
    change = float(np.abs(positions - reference).max()) if motion.n_frames else 0.0
    return TradeoffPoint(
        int((forest.parents < 0).sum()),
        tuple(motion.names[j] for j in chosen),
        1e6 * best / max(1, motion.n_frames),
        stored_per_frame(forest),
        change,
    )
