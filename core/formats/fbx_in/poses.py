"""The FBX nodes' local transforms over the frames, from what :mod:`.worker` sent: the numpy
path, the reference of :mod:`.compiled_pose`.

A node sent as ``channels`` (its Lcl values at every frame, as the file stores them) is
composed here with the transform stack the worker checks with
(:mod:`core.kinematics.fbx_stack`): the joints' rotations all at once, one array per
rotation order, kept as the skeleton's rotations. A node ``evaluated`` or ``static`` comes
as ufbx's translation, quaternion and scale.

Arrays: a node's translation and scale (F|1, 3), a leading 1 when they do not change; the
joints' rotations one block (F|1, J, 3, 3), each joint's pose holding a view of its column.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.formats.fbx_in.worker import CHANNEL_BLOCK
from gmr_studio.core.formats.gltf_in.pose import NodePose
from gmr_studio.core.kinematics.fbx_stack import STATIC_STACK, stack_rotation, stack_translation
from gmr_studio.core.rotations.quaternions import matrix_from_quaternion

#: a node's nine channels: translation, rotation (degrees), scale, x y z each
TRANSLATION, ROTATION, SCALE = slice(0, 3), slice(3, 6), slice(6, 9)
#: frames gathered at a time
CHUNK_FRAMES = 2048


def node_poses(meta: dict, arrays: dict[str, np.ndarray]) -> tuple[dict[int, NodePose], np.ndarray]:
    """The poses of the joints and of the nodes above them (node index -> pose), and the
    joints' rotations (F|1, J, 3, 3) that the joints' poses hold views of."""
    joints, frames = list(meta["joints"]), int(meta["frames"])
    specs = {int(k): spec for k, spec in meta["nodes"].items()}
    turning = any(_varies(node, specs[node], arrays) for node in joints)
    length = frames if turning else 1
    groups: dict[int, list[int]] = {}
    for j, node in enumerate(joints):
        if specs[node]["kind"] == "channels":
            groups.setdefault(specs[node]["order"], []).append(j)
    if len(groups) == 1 and len(next(iter(groups.values()))) == len(joints):  # one array: the block itself
        order = next(iter(groups))
        block = channel_rotations([specs[node] for node in joints], arrays, order, length)
        if len(block) < length:
            block = np.repeat(block, length, axis=0)
    else:
        block = np.empty((length, len(joints), 3, 3))
        for order, members in groups.items():
            block[:, members] = channel_rotations([specs[joints[j]] for j in members], arrays, order, length)
        for j, node in enumerate(joints):
            if specs[node]["kind"] != "channels":
                block[:, j] = matrix_from_quaternion(arrays[f"q{node}"], scalar_last=True)
    parts = translations_and_scales(joints, specs, arrays, frames)
    poses = {node: _pose(node, specs[node], arrays, block[:, j], parts) for j, node in enumerate(joints)}
    poses.update(above_poses(meta, arrays))
    return poses, block


def above_poses(meta: dict, arrays: dict[str, np.ndarray]) -> dict[int, NodePose]:
    """The poses of the nodes above the joints (node index -> pose)."""
    above, frames = list(meta["above"]), int(meta["frames"])
    specs = {node: meta["nodes"][str(node)] for node in above}
    parts = translations_and_scales(above, specs, arrays, frames)
    poses = {}
    for node in above:
        spec = specs[node]
        if spec["kind"] == "channels":
            turn = channel_rotations([spec], arrays, spec["order"], frames)[:, 0]
        else:
            turn = matrix_from_quaternion(arrays[f"q{node}"], scalar_last=True)
        poses[node] = _pose(node, spec, arrays, turn, parts)
    return poses


def channel_arrays(meta: dict, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The worker's arrays with each channel array it names (``channel_rows``) as a view
    of its row of the block :data:`.worker.CHANNEL_BLOCK`."""
    block = arrays.get(CHANNEL_BLOCK)
    named = {name: block[k] for k, name in enumerate(meta.get("channel_rows", []))}
    return {**arrays, **named}


def _varies(node: int, spec: dict, arrays: dict) -> bool:
    """Whether the node's rotation can change over the frames."""
    if spec["kind"] == "channels":
        return any(isinstance(c, str) for c in spec["channels"][ROTATION])
    return len(arrays[f"q{node}"]) > 1


def _gathered(specs: list[dict], arrays: dict, part: slice, frames: int) -> np.ndarray:
    """(F|1, N, 3) float64: one part of the channels of N nodes (F when one of them has an
    array, 1 when they are all numbers)."""
    channels = [spec["channels"][part] for spec in specs]
    varying = any(isinstance(c, str) for row in channels for c in row)
    out = np.empty((frames if varying else 1, len(specs), 3))
    for start in range(0, len(out), CHUNK_FRAMES):  # the strided writes land in cache
        chunk = slice(start, start + CHUNK_FRAMES)
        for n, row in enumerate(channels):
            for c, channel in enumerate(row):
                out[chunk, n, c] = arrays[channel][chunk] if isinstance(channel, str) else channel
    return out


def _stack(specs: list[dict], name: str) -> np.ndarray:
    """(N, 3): one static vector of the stack for N nodes."""
    return np.array([spec["stack"][name] for spec in specs], dtype=np.float64).reshape(len(specs), 3)


def channel_rotations(specs: list[dict], arrays: dict, order: int, frames: int) -> np.ndarray:
    """(F|1, N, 3, 3): the rotations ``Q`` of N nodes sent as channels, of one rotation order."""
    degrees = _gathered(specs, arrays, ROTATION, frames)
    return stack_rotation(degrees, order, _stack(specs, "PreRotation"), _stack(specs, "PostRotation"))


def translations_and_scales(nodes: list[int], specs: dict, arrays: dict, frames: int) -> dict[int, tuple]:
    """Per node sent as channels, its Lcl translation and scale (F|1, 3), each contiguous
    (what reads them runs along the frames), a leading 1 where they are numbers only."""
    out = {}
    for node in nodes:
        if specs[node]["kind"] != "channels":
            continue
        parts = []
        for part in (TRANSLATION, SCALE):
            channels = specs[node]["channels"][part]
            values = np.empty((frames if any(isinstance(c, str) for c in channels) else 1, 3))
            for c, channel in enumerate(channels):
                values[:, c] = arrays[channel] if isinstance(channel, str) else channel
            parts.append(values)
        out[node] = tuple(parts)
    return out


def _pose(node: int, spec: dict, arrays: dict, turn: np.ndarray, parts: dict[int, tuple]) -> NodePose:
    """The node's pose, given its rotation ``turn`` (F|1, 3, 3) and (channels) its Lcl
    translation and scale."""
    if spec["kind"] != "channels":
        return NodePose(arrays[f"t{node}"], turn, arrays[f"s{node}"])
    translation, scale = parts[node]
    stack = {name: np.asarray(spec["stack"][name], dtype=np.float64) for name in STATIC_STACK}
    return NodePose(stack_translation(translation, turn, scale, stack), turn, scale)
