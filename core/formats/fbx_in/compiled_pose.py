"""The FBX joints' rotations and translations straight from the worker's channel block, compiled.

When the nodes above the joints do not move (an armature, or none), the motion's arrays
are made in two compiled passes over the frames, on every core, reading the channel rows
of the block (C, F) where the worker wrote them (:mod:`.worker`: the joints sent as
``channels``, an exported or baked take): the Euler angles to matrices by the one
compiled Euler rule (:func:`core.kinematics.euler_matrices.degrees_to_matrices_compiled`; static
pre- and post-rotations applied after, :func:`core.kinematics.fbx_stack.pre_and_post`), then the
translations carried through the scales down the skeleton by the operations of
:func:`core.formats.gltf_in.pose.skeleton_pose`, the joints' rest orientations taken out
on the way (:func:`core.formats.gltf_in.rest.turn_to_bind`; :func:`._kernels.carried_translations`).
Joints sent otherwise (ufbx's evaluation; pivots and offsets folded into a translation)
are made as :mod:`.poses` makes them and join the second pass as rows of their own.
Animated nodes above the joints, a single frame, and any process without numba
(``GMR_DISABLE_NUMBA=1``) take the numpy path (:func:`.poses.node_poses`, then
``skeleton_pose``), the reference: the two agree to rounding (sine and cosine from the C
library; a uniform scale carried as a matrix).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.compiled import Backend, chosen_kernels, optional_kernels
from gmr_studio.core.formats.fbx_in.poses import (
    ROTATION,
    SCALE,
    TRANSLATION,
    above_poses,
    channel_rotations,
    translations_and_scales,
)
from gmr_studio.core.formats.fbx_in.worker import CHANNEL_BLOCK
from gmr_studio.core.formats.gltf_in.pose import NodePose, armature_world, fill_from_first, moving_joints
from gmr_studio.core.formats.gltf_in.rest import bind_turns
from gmr_studio.core.kinematics.engine import in_blocks
from gmr_studio.core.kinematics.euler_matrices import degrees_to_matrices_compiled
from gmr_studio.core.kinematics.fbx_stack import EULER_ORDERS, STATIC_STACK, pre_and_post, stack_translation
from gmr_studio.core.rotations.quaternions import matrix_from_quaternion

#: the stack's vectors that move a translation (:func:`core.kinematics.fbx_stack.stack_translation`)
PIVOTS = ("RotationPivot", "RotationOffset", "ScalingPivot", "ScalingOffset")


def compiled_skeleton(
    meta: dict, arrays: dict[str, np.ndarray], parents: np.ndarray, bind: np.ndarray, backend: Backend = "auto"
) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray] | None:
    """(poses of the joints and the nodes above (their scales for the notes), rotations
    (F, J, 3, 3), translations (F, J, 3), moving (J,) bool) as
    :func:`core.formats.gltf_in.pose.skeleton_pose` gives them from :func:`.poses.node_poses`,
    with the joints' rest orientations ``bind`` (J, 3, 3) taken out as
    :func:`core.formats.gltf_in.rest.turn_to_bind` takes them out; None when the numpy path
    is to make them (module docstring; ``backend`` as :func:`core.compiled.chosen_kernels`
    takes it). ``parents``: every node's."""
    kernels = chosen_kernels(backend, optional_kernels("gmr_studio.core.formats.fbx_in._kernels"))
    joints, frames = list(meta["joints"]), int(meta["frames"])
    if kernels is None or frames < 2:
        return None
    above = above_poses(meta, arrays)
    if any(len(part) > 1 for pose in above.values() for part in (pose.translation, pose.rotation, pose.scale)):
        return None
    specs = [meta["nodes"][str(node)] for node in joints]
    planes = arrays.get(CHANNEL_BLOCK)
    planes = planes if planes is not None and planes.ndim == 2 else np.zeros((0, frames))
    row = {name: k for k, name in enumerate(meta.get("channel_rows", []))}
    rotations = _rotations_of(joints, specs, arrays, planes, row, frames)
    sources = [
        _sources(node, spec, arrays, planes, row, rotations[:, j]) for j, (node, spec) in enumerate(zip(joints, specs))
    ]
    index = {node: j for j, node in enumerate(joints)}
    joint_parents = np.array([index.get(int(parents[node]), -1) for node in joints], dtype=np.int64)
    bases = _bases(joints, joint_parents, parents, above)
    turns = bind_turns(bind, joint_parents)
    rest = (False, *np.zeros((2, 1, 3, 3))) if turns is None else (True, *map(np.ascontiguousarray, turns))
    translations, moving = _translations(kernels, planes, sources, joint_parents, (*bases, *rest), rotations)
    poses = {node: NodePose(translations[:, j], rotations[:, j], sources[j][1]) for j, node in enumerate(joints)}
    return {**poses, **above}, rotations, translations, moving


def _rotations_of(
    joints: list[int], specs: list[dict], arrays: dict, planes: np.ndarray, row: dict, frames: int
) -> np.ndarray:
    """(F, J, 3, 3): each joint's rotation ``Q``; the Euler angles of joints whose rotation
    channels are rows or zero converted in one compiled pass (then ``Rpre R Rpost^-1``),
    the others' as :func:`.poses.node_poses` makes them."""
    rotations = np.empty((frames, len(specs), 3, 3))
    groups: dict[str, tuple[list[int], list[list[int]]]] = {}
    for j, (node, spec) in enumerate(zip(joints, specs)):
        channels = spec["channels"][ROTATION] if spec["kind"] == "channels" else None
        if channels is not None and all(isinstance(c, str) or c == 0 for c in channels):
            intrinsic = EULER_ORDERS[spec["order"]]
            members, columns = groups.setdefault(intrinsic, ([], []))
            members.append(j)
            in_order = [channels["XYZ".index(axis)] for axis in intrinsic]
            columns.append([row[c] if isinstance(c, str) else -1 for c in in_order])
        elif channels is not None:
            rotations[:, j] = channel_rotations([spec], arrays, spec["order"], frames)[:, 0]
        else:
            rotations[:, j] = matrix_from_quaternion(arrays[f"q{node}"], scalar_last=True)
    listed = [(order, members, np.array(columns)) for order, (members, columns) in groups.items()]
    degrees_to_matrices_compiled(planes.T, listed, rotations, 0, frames, threads=None)
    for j in [j for members, _ in groups.values() for j in members]:
        pre, post = (np.asarray(specs[j]["stack"][name], dtype=np.float64) for name in ("PreRotation", "PostRotation"))
        if pre.any() or post.any():
            rotations[:, j] = pre_and_post(rotations[:, j], pre, post)
    return rotations


def _sources(node: int, spec: dict, arrays: dict, planes: np.ndarray, row: dict, turn: np.ndarray) -> tuple:
    """(the six sources of the joint's translation and scale, x y z each: a row of the
    block (int), a number, or values (F,); its scale (F|1, 3))."""
    if spec["kind"] != "channels":
        translation, scale = arrays[f"t{node}"], arrays[f"s{node}"]
        return _columns(translation) + _columns(scale), scale
    if any(any(spec["stack"][name]) for name in PIVOTS):
        translation, scale = translations_and_scales([node], {node: spec}, arrays, len(turn))[node]
        stack = {name: np.asarray(spec["stack"][name], dtype=np.float64) for name in STATIC_STACK}
        return _columns(stack_translation(translation, turn, scale, stack)) + _columns(scale), scale
    channels = spec["channels"][TRANSLATION] + spec["channels"][SCALE]
    found = [row[c] if isinstance(c, str) else float(c) for c in channels]
    return found, _scale(spec, planes, row)


def _columns(values: np.ndarray) -> list:
    """The sources of values (F|1, 3): numbers when one frame, else the columns."""
    return [float(v) for v in values[0]] if len(values) == 1 else [values[:, c] for c in range(3)]


def _bases(joints: list[int], joint_parents: np.ndarray, parents: np.ndarray, above: dict) -> tuple:
    """(turned (J,) bool, turn (J, 3, 3), place (J, 3), stretch (J, 3, 3)): the world of the
    armature above each root (:func:`core.formats.gltf_in.pose.armature_world`), the identity
    elsewhere; ``turned`` where its rotation is not the identity."""
    n_joints = len(joints)
    turn = np.broadcast_to(np.eye(3), (n_joints, 3, 3)).copy()
    place, stretch, turned = np.zeros((n_joints, 3)), turn.copy(), np.zeros(n_joints, bool)
    for j in np.flatnonzero(joint_parents < 0):
        if above:
            turn[j], place[j], stretch[j] = armature_world(above, parents, joints[j])
            turned[j] = not np.array_equal(turn[j], np.eye(3))
    return turned, turn, place, stretch


def _translations(
    kernels, planes: np.ndarray, sources: list[tuple], joint_parents: np.ndarray, bases: tuple, rotations: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(translations (F, J, 3), moving (J,) bool); the rotations turned in place (the
    roots' by the armature above them, every one by the rest orientations: ``bases``)."""
    n_frames, n_joints = rotations.shape[:2]
    rows = np.full((n_joints, 6), -1, dtype=np.int64)
    constants = np.zeros((n_joints, 6))
    extra = []
    for j, (found, _) in enumerate(sources):
        for k, source in enumerate(found):
            if isinstance(source, int):
                rows[j, k] = source
            elif isinstance(source, float):
                constants[j, k] = source
            else:
                rows[j, k] = -2 - len(extra)
                extra.append(source)
    extra_rows = np.array(extra, dtype=np.float64).reshape(len(extra), n_frames)
    inner = np.zeros(n_joints, bool)
    inner[joint_parents[joint_parents >= 0]] = True
    translations = np.empty((n_frames, n_joints, 3))
    fixed = (rotations, planes, extra_rows, rows, constants, joint_parents, inner, *bases)
    first = np.zeros((1, n_joints, 3))  # the first frame's translations before the rest turn: what moves is judged on
    unturned = (rotations[:1].copy(), *fixed[1:-3], False, *fixed[-2:])
    kernels.carried_translations(*unturned, first[0], 0, 1, first, np.empty(n_joints), np.empty(n_joints))
    found = []

    def block(frames: slice) -> None:
        spread, size = np.empty(n_joints), np.empty(n_joints)
        kernels.carried_translations(*fixed, first[0], frames.start, frames.stop, translations, spread, size)
        found.append((spread, size))

    in_blocks(block, n_frames, None)
    spread = np.maximum.reduce([spread for spread, _ in found])
    size = np.maximum.reduce([size for _, size in found])
    moving = moving_joints(spread, size, n_frames)
    fill_from_first(translations, ~moving)
    return translations, moving


def _scale(spec: dict, planes: np.ndarray, row: dict) -> np.ndarray:
    """A joint's Lcl scale (F|1, 3): a view of its rows when they follow each other."""
    channels = spec["channels"][SCALE]
    if not any(isinstance(c, str) for c in channels):
        return np.array([channels], dtype=np.float64)
    first = row.get(channels[0]) if isinstance(channels[0], str) else None
    if first is not None and [row.get(c) for c in channels] == [first, first + 1, first + 2]:
        return planes[first : first + 3].T
    scale = np.empty((planes.shape[1], 3))
    for c, channel in enumerate(channels):
        scale[:, c] = planes[row[channel]] if isinstance(channel, str) else channel
    return scale


def warm_up() -> None:
    """Load the compiled kernels the reader calls (numba's cache, else compiling them) on a
    two-frame take of one joint, so that the first file read does not wait for them: the
    reader runs this while its child loads the file. Does nothing without numba."""
    if optional_kernels("gmr_studio.core.formats.fbx_in._kernels") is None:
        return
    still = {name: [0.0, 0.0, 0.0] for name in STATIC_STACK}
    spec = {"kind": "channels", "order": 0, "stack": still, "channels": [f"c0.{c}" for c in range(9)]}
    meta = {"joints": [0], "above": [], "frames": 2, "nodes": {"0": spec}, "channel_rows": spec["channels"]}
    block = np.zeros((9, 2))
    for bind in (np.eye(3)[None], np.array([[[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]])):
        compiled_skeleton(meta, {CHANNEL_BLOCK: block}, np.array([-1]), bind)
