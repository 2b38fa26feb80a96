"""From glTF node transforms (``T R S`` per node, per frame) to a post-rotation skeleton.

glTF composes a node's world transform as ``parent_world @ T(t) R(q) S(s)``; a joint's
position is the translation of its world transform. Write each node's world linear part
as ``A = U M``: ``U`` the product of the rotations down to the node (its world rotation
in the motion read) and ``M`` the scale carried along, ``M_j = R_j^T M_p R_j S_j``. Then
``P_j = P_p + U_p M_p t_j``, so the motion's local rotation is the node's ``R_j`` and its
translation ``M_p t_j``: every joint position is glTF's exactly (to rounding).

- uniform scales keep ``M`` a number ``c`` (the product of the scales above): a uniform
  rest scale folds into the offsets, an animated one into per-frame translations.
- a non-uniform scale makes ``M`` a matrix; positions stay exact, and the world rotation
  given to a joint below it is ``U`` (the node rotations without the scaling between).
- a root takes on the transform of the nodes above it (the armature): ``R_r = U_a R``,
  ``t_r = P_a + U_a M_a t``.

Arrays: each node's ``translation`` (F or 1, 3), ``rotation`` (F or 1, 3, 3) and ``scale``
(F or 1, 3); a leading 1 means the value does not change over the frames.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.rotations.quaternions import matrix_from_quaternion

#: frames converted from quaternions to matrices (and carried down the skeleton) at a time
CHUNK_FRAMES = 2048
#: a per-frame translation that varies less than this, relative to its size, is static
STATIC_RELATIVE_TOLERANCE = 1e-12
#: when at most one joint in this many has a static translation, its frames are set joint by
#: joint (each a strided pass over the frames) rather than chunk by chunk over them all
FEW_STATIC = 8


@dataclasses.dataclass
class NodePose:
    """One node's local transform over the frames (see the module docstring)."""

    translation: np.ndarray
    rotation: np.ndarray
    scale: np.ndarray


@dataclasses.dataclass
class _World:
    """A node's world rotation U (F|1, 3, 3), position P (F|1, 3) and carried scale M:
    (F|1,) when it is a number times the identity, else (3, 3, F|1), the frames last (the
    products of :func:`_product` run along them, as numpy runs fastest)."""

    turn: np.ndarray
    place: np.ndarray
    stretch: np.ndarray

    def carry(self, vector: np.ndarray) -> np.ndarray:
        """``M t`` for vectors (F|1, 3)."""
        if self.stretch.ndim == 1:
            return self.stretch[:, None] * vector
        stretch, vector = _frames_alike(self.stretch, vector.T)
        return np.einsum("ikf,kf->fi", stretch, vector)


def _apply(matrices: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Matrices (F|1, 3, 3) times vectors (F|1, 3), broadcasting the frames."""
    return (matrices @ vectors[..., None])[..., 0]


def _frames_alike(*arrays: np.ndarray) -> list[np.ndarray]:
    """Arrays with the frames last, (F or 1) each, as views with F frames each."""
    frames = max(a.shape[-1] for a in arrays)
    return [a if a.shape[-1] == frames else np.broadcast_to(a, (*a.shape[:-1], frames)) for a in arrays]


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Matrix products (3, 3, F) of matrices (3, 3, F|1) with the frames last."""
    return np.einsum("ijf,jkf->ikf", *_frames_alike(a, b))


def _child(world: _World, pose: NodePose, *, placed: bool = True) -> _World:
    """The child's world; ``placed=False`` carries the scale only (a joint's children need
    nothing else), leaving rotation and position empty."""
    empty = np.zeros((1, 0))
    place = world.place + _apply(world.turn, world.carry(pose.translation)) if placed else empty
    turn = world.turn @ pose.rotation if placed else empty
    scale = pose.scale
    if world.stretch.ndim == 1 and (scale == scale[:, :1]).all():
        return _World(turn, place, world.stretch * scale[:, 0])
    stretch = np.eye(3)[:, :, None] * world.stretch if world.stretch.ndim == 1 else world.stretch
    rotation = np.ascontiguousarray(np.moveaxis(pose.rotation, 0, -1))  # (3, 3, F|1): one pass over a column
    carried = _product(rotation.transpose(1, 0, 2), _product(stretch, rotation))  # R^T M R
    return _World(turn, place, carried * scale.T[None])


def node_poses(
    nodes: list[int], translations: list[np.ndarray], quaternions: list[np.ndarray], scales: list[np.ndarray]
) -> tuple[dict[int, NodePose], np.ndarray]:
    """The poses of some nodes from their translations (F|1, 3), quaternions (F|1, 4,
    ``x, y, z, w``) and scales (F|1, 3), and their rotation matrices as one block
    (F|1, N, 3, 3) float64 (each pose's rotation is a view of it). A translation that is
    the same on every frame, bit for bit, is kept as one frame (1, 3): worked out once.
    Translations and quaternions may be float32 (a file's keys as stored): they are
    worked on in float64.

    Worked :data:`CHUNK_FRAMES` frames at a time: each chunk's quaternions gathered into
    one block (N, 4) a frame, in cache, converted in one call, so the matrices are written
    frame after frame; its translations compared with the first frame's on the way."""
    frames = max(len(q) for q in quaternions)
    matrices = np.empty((frames, len(nodes), 3, 3))
    moving = [k for k, t in enumerate(translations) if len(t) > 1]
    every = max(frames, *(len(t) for t in translations))
    keys = _Gathered(quaternions, 4, frames)
    places = _Gathered([translations[k] for k in moving], 3, every)
    first = np.array([translations[k][0] for k in moving], dtype=places.block.dtype).reshape(-1, 3)
    same = np.isfinite(first).all(axis=1)  # NaN is never the same; equal bits are then equal numbers
    bits = f"u{first.itemsize}"
    for start in range(0, every, CHUNK_FRAMES):
        part = slice(start, start + CHUNK_FRAMES)
        if start < frames:
            out = matrices[part].reshape(-1, 3, 3)
            matrix_from_quaternion(keys.chunk(part).reshape(-1, 4), scalar_last=True, out=out)
        if same.any():
            equal = places.chunk(part).view(bits) == first.view(bits)  # signs of zeros included
            same &= equal.all(axis=0).all(axis=1)
    constant = {moving[m] for m in np.flatnonzero(same)}
    poses = {
        node: NodePose(t[:1] if k in constant else t, matrices[:, k], s)
        for k, (node, t, s) in enumerate(zip(nodes, translations, scales))
    }
    return poses, matrices


def skeleton_pose(
    poses: dict[int, NodePose], parents: np.ndarray, joints: list[int], n_frames: int, block: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Post-rotation local rotations (F, J, 3, 3), translations (F, J, 3), and which
    translations change over the frames (J,) bool, of the joints (node indices, parents
    first); ``poses`` holds every joint and every node above them, ``block`` the joints'
    rotation matrices (F|1, J, 3, 3) from :func:`node_poses`, which become the rotations
    (those of roots below other nodes overwritten). Worked :data:`CHUNK_FRAMES` frames at
    a time, so that what is carried down the skeleton stays in cache; a translation made
    of values that do not change over the frames is worked out once and copied to every
    frame at the end."""
    rotations = block if len(block) == n_frames else np.repeat(block, n_frames, axis=0)
    translations = np.empty((n_frames, len(joints), 3))
    spread, size = np.zeros(len(joints)), np.zeros(len(joints))  # of each translation over the frames
    varying = max(max(len(p.translation), len(p.rotation), len(p.scale)) for p in poses.values()) > 1
    constant = None  # found on the first chunk, which has more than one frame if the motion has
    settled: dict[int, _World] = {}
    for start in range(0, n_frames if varying else min(n_frames, 1), CHUNK_FRAMES):
        part = slice(start, start + CHUNK_FRAMES) if varying else slice(None)
        found = _chunk_pose(poses, parents, joints, part, rotations, translations, constant, settled)
        constant = found if constant is None else constant
        changing = np.flatnonzero(~constant)
        if changing.size:  # reduced over the frames first: a reduction along the outer axis is fast
            local = translations[part, changing] if changing.size < len(joints) else translations[part]
            first = translations[:1, changing]
            spread[changing] = np.maximum(spread[changing], np.abs(local - first).max(axis=0).max(axis=1))
            size[changing] = np.maximum(size[changing], np.abs(local).max(axis=0).max(axis=1))
    first = translations[0, constant]  # every frame's value: the same numbers as a pass over them gives
    spread[constant] = np.maximum(spread[constant], np.abs(first - first).max(axis=1))  # 0, or NaN (a bad file)
    size[constant] = np.maximum(size[constant], np.abs(first).max(axis=1))
    moving = moving_joints(spread, size, n_frames)
    fill_from_first(translations, ~moving | constant)
    return rotations, translations, moving


def moving_joints(spread: np.ndarray, size: np.ndarray, n_frames: int) -> np.ndarray:
    """(J,) bool: the joints whose translation changes over the frames, given each one's
    largest distance from its first frame's ``spread`` (J,) and largest component ``size``
    (J,) over the frames: more than :data:`STATIC_RELATIVE_TOLERANCE` of its size. NaN (a
    bad file) counts as moving, keeping every frame; nothing moves in one frame."""
    static = spread <= STATIC_RELATIVE_TOLERANCE * size
    return ~static if n_frames > 1 else np.zeros(len(spread), bool)


def armature_world(poses: dict[int, NodePose], parents: np.ndarray, node: int) -> tuple[np.ndarray, ...]:
    """The world of the nodes above ``node`` that are in ``poses`` (the armature above a
    root), all of one frame: rotation (3, 3), position (3,) and carried scale (3, 3) (see
    the module docstring), as :func:`skeleton_pose` applies them to the root."""
    world = _World(np.eye(3)[None], np.zeros((1, 3)), np.ones(1))
    for up in _chain(parents, node, poses):
        world = _child(world, poses[up])
    stretch = world.stretch[0] * np.eye(3) if world.stretch.ndim == 1 else world.stretch[:, :, 0]
    return world.turn[0], world.place[0], stretch


def fill_from_first(translations: np.ndarray, same: np.ndarray) -> None:
    """Every frame of the translations (F, J, 3) of the joints ``same`` (J,) bool set to
    the first frame's: each chunk of frames overwritten whole (one pass over memory, unlike
    a masked assignment), the other joints' values put back; or, for a few joints
    (:data:`FEW_STATIC`), each one's frames set on their own."""
    if not same.any():
        return
    if same.sum() * FEW_STATIC <= len(same):
        for j in np.flatnonzero(same):
            translations[1:, j] = translations[0, j]
        return
    others, first = np.flatnonzero(~same), translations[0].copy()
    for start in range(0, len(translations), CHUNK_FRAMES):
        chunk = translations[start : start + CHUNK_FRAMES]
        kept = chunk[:, others]
        chunk[:] = first
        chunk[:, others] = kept


def _chunk_pose(
    poses: dict[int, NodePose],
    parents: np.ndarray,
    joints: list[int],
    part: slice,
    rotations: np.ndarray,
    translations: np.ndarray,
    constant: np.ndarray | None,
    settled: dict[int, _World],
) -> np.ndarray:
    """:func:`skeleton_pose` over the frames ``part``: their translations and the roots'
    rotations written in place. Returns which translations (J,) bool came out as one
    value for all the chunk's frames; of those given as ``constant`` (or, if None, of
    those returned) only the first frame is written. ``constant`` None marks the first
    chunk, which puts the joints' worlds that do not change over the frames in
    ``settled``; later chunks take them from there and skip the non-root joints that have
    nothing else to work out."""
    first = constant is None
    index = {node: j for j, node in enumerate(joints)}
    parents_of_joints = {int(parents[node]) for node in joints}  # the others carry nothing further
    origin = _World(np.eye(3)[None], np.zeros((1, 3)), np.ones(1))
    worlds: dict[int, _World] = dict(settled)
    found = np.zeros(len(joints), bool)
    for j, node in enumerate(joints):
        parent = int(parents[node])
        done = node in settled or node not in parents_of_joints  # its world: the first chunk's, or none needed
        if constant is not None and constant[j] and parent in index and done:
            continue  # its translation was written on the first chunk
        pose = _frames_of(poses[node], part)
        world, placed = origin, False  # placed: a root below an armature that moves it
        if parent in index:
            world = worlds[parent]
        else:
            for up in _chain(parents, node, poses):  # the armature above the root
                world = _child(world, _frames_of(poses[up], part))
            placed = not _is_origin(world)  # else the root keeps its own transform, as it is
        local = world.carry(pose.translation)
        if placed:
            local = world.place + _apply(world.turn, local)
        if node in parents_of_joints:
            worlds[node] = _child(world, pose, placed=False)
            if first and worlds[node].stretch.shape[-1] == 1:
                settled[node] = worlds[node]
        if placed:
            rotations[part, j] = world.turn @ pose.rotation  # pose.rotation is this column: used above first
        found[j] = len(local) == 1
        if found[j] if constant is None else constant[j]:
            translations[0, j] = local[0]
        else:
            translations[part, j] = local
    return found


class _Gathered:
    """Arrays (F|1, C) of some nodes, gathered a chunk of frames at a time into one block
    (chunk, N, C): in their own type when they all have it (float32 keys as stored), else
    float64. Rows of that type with their components side by side are copied as single
    items, one loop a chunk, not one a frame."""

    def __init__(self, arrays: list[np.ndarray], width: int, frames: int) -> None:
        dtype = np.float32 if arrays and all(a.dtype == np.float32 for a in arrays) else np.float64
        self.block = np.empty((min(frames, CHUNK_FRAMES), len(arrays), width), dtype)
        row = np.dtype((np.void, self.block.itemsize * width))
        self.rows = self.block.view(row)[..., 0]  # (chunk, N): a row each
        alike = [a.dtype == dtype and a.shape[1] == width and a.strides[1] == a.itemsize for a in arrays]
        self.sources = [a.view(row)[:, 0] if same else a for a, same in zip(arrays, alike)]
        self.frames = frames

    def chunk(self, part: slice) -> np.ndarray:
        """The block of the frames ``part`` (size, N, C); a one-frame array fills them all."""
        size = min(self.frames - part.start, CHUNK_FRAMES)
        for k, values in enumerate(self.sources):
            target = self.rows if values.ndim == 1 else self.block
            target[:size, k] = values if len(values) == 1 else values[part]
        return self.block[:size]


def _is_origin(world: _World) -> bool:
    """Whether a world is the identity on every frame, exactly (an armature node that
    neither turns, moves nor scales): what is below it keeps its own transform."""
    return (
        world.turn.shape == (1, 3, 3)
        and (world.turn == np.eye(3)).all()
        and not world.place.any()
        and world.stretch.shape == (1,)
        and world.stretch[0] == 1
    )


def _frames_of(pose: NodePose, part: slice) -> NodePose:
    """The pose over some frames (what does not change kept as it is)."""
    values = (pose.translation, pose.rotation, pose.scale)
    return NodePose(*(value if len(value) == 1 else value[part] for value in values))


def _chain(parents: np.ndarray, node: int, poses: dict[int, NodePose]) -> list[int]:
    """The nodes above ``node`` that are in ``poses``, top first."""
    chain, up = [], int(parents[node])
    while up >= 0:
        chain.append(up)
        up = int(parents[up])
    return [n for n in chain[::-1] if n in poses]
