"""glTF node transforms to a post-rotation skeleton (core.formats.gltf_in.pose): two armature
nodes above the root (one scaled unevenly), animated and non-uniform scales along the joints,
every joint position against glTF's own ``parent_world @ T R S`` with 4x4 matrices (scipy's
quaternions); which translations change; many frames converted in chunks (a channel keyed
still on every frame the same as its one value; a change on the last frame alone kept)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.formats.gltf_in.pose import CHUNK_FRAMES, node_poses, skeleton_pose
from gmr_studio.core.rotations.quaternions import matrix_from_quaternion
from tests.gltf_builder import post_rotation_forward, quaternion

F = 3
#: node 0 and 1 the armature; joints 2 (root) .. 7, parents first
PARENTS = np.array([-1, 0, 1, 2, 3, 4, 2, 6])
JOINTS = [2, 3, 4, 5, 6, 7]
ABOVE = [0, 1]


def turns(axis, degrees) -> np.ndarray:
    return np.array([quaternion(axis, a) for a in degrees])


def node_trs(uneven_armature: bool = False) -> dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Each node's translation, quaternion and scale, (F|1, ...)."""
    one = np.ones((1, 3))
    return {
        0: (np.array([[1.0, 2, 3]]), turns([1, 1, 0], [30]), np.array([[1.0, 2, 3] if uneven_armature else [3.0] * 3])),
        1: (np.array([[0.0, 1, 0]]), turns([0, 0, 1], [40]), np.full((1, 3), 2.0)),
        2: (np.array([[0.0, 1, 0], [0.2, 1.1, 0], [0.4, 0.9, 0.3]]), turns([0, 1, 0], [0, 40, -70]), one),
        3: (np.array([[0.0, 0.5, 0]]), turns([1, 0, 0], [10, 20, 60]), np.array([[1.0] * 3, [1.5] * 3, [2.0] * 3])),
        4: (np.array([[0.3, 0, 0]]), turns([0, 1, 1], [0, 45, 90]), np.array([[1.0, 0.5, 2]])),  # not uniform
        5: (np.array([[0.0, 1, 0.2]]), turns([1, 2, 3], [25]), np.array([[3.0, 1, 1]])),
        6: (np.tile([[0.1, 0.2, 0.3]], (F, 1)), turns([0, 0, 1], [5]), one),  # a channel that never moves
        7: (np.zeros((F, 3)), turns([0, 0, 1], [0, 30, 60]), one),  # a channel held at the origin
    }


def matrix(q: np.ndarray) -> np.ndarray:
    return Rotation.from_quat(q).as_matrix()


def gltf_positions(trs) -> np.ndarray:
    """World position (F, N, 3) of every node by glTF's node rule, 4x4 matrices."""
    out = np.empty((F, len(PARENTS), 3))
    for f in range(F):
        world = {}
        for node, parent in enumerate(PARENTS):
            t, q, s = (value[min(f, len(value) - 1)] for value in trs[node])
            local = np.eye(4)
            local[:3, :3] = matrix(q) @ np.diag(s)
            local[:3, 3] = t
            world[node] = (world[parent] if parent >= 0 else np.eye(4)) @ local
            out[f, node] = world[node][:3, 3]
    return out


def post_rotation_positions(rotations, translations, parents) -> np.ndarray:
    """Joint positions (F, J, 3) of a post-rotation motion (:func:`tests.gltf_builder.post_rotation_forward`)."""
    return post_rotation_forward(parents, rotations, translations)[1]


def skeleton(trs):
    poses, block = node_poses(JOINTS, *(list(c) for c in zip(*(trs[n] for n in JOINTS))))
    poses.update(node_poses(ABOVE, *(list(c) for c in zip(*(trs[n] for n in ABOVE))))[0])
    return skeleton_pose(poses, PARENTS, JOINTS, F, block)


@pytest.mark.parametrize("uneven_armature", [False, True])
def test_every_joint_where_gltf_puts_it_through_armature_and_scales(uneven_armature):
    trs = node_trs(uneven_armature)
    rotations, translations, _ = skeleton(trs)
    parents = [-1, 0, 1, 2, 0, 4]
    got = post_rotation_positions(rotations, translations, parents)
    np.testing.assert_allclose(got, gltf_positions(trs)[:, JOINTS], rtol=0, atol=1e-12)


def test_rotations_are_the_nodes_own_and_the_root_takes_the_armatures():
    trs = node_trs(uneven_armature=True)
    rotations, _, _ = skeleton(trs)
    armature = matrix(trs[0][1][0]) @ matrix(trs[1][1][0])  # the scaling between left out
    np.testing.assert_allclose(rotations[:, 0], armature @ matrix(trs[2][1]), rtol=0, atol=1e-14)
    for j, node in enumerate(JOINTS[1:], start=1):
        expected = np.broadcast_to(matrix(trs[node][1]), (F, 3, 3))
        np.testing.assert_allclose(rotations[:, j], expected, rtol=0, atol=1e-15)


def test_which_translations_change():
    """The root moves; 3 hangs still from it (scaled evenly); 4 rides on 3's animated
    scale, 5 on 4's uneven scale turning; 6 is held by its channel, 7 at the origin:
    static, their one value for every frame."""
    trs = node_trs()
    _, translations, moving = skeleton(trs)
    assert moving.tolist() == [True, False, True, True, False, False]
    np.testing.assert_array_equal(translations[:, 4], np.broadcast_to(translations[0, 4], (F, 3)))
    np.testing.assert_array_equal(translations[:, 5], np.zeros((F, 3)))


def test_a_translation_varying_by_its_relative_tolerance_is_static():
    trs = node_trs()
    held = np.tile([[0.0, 0.0, 1.0]], (F, 1))
    held[1, 2] += 0.5e-12
    trs[7] = (held, trs[7][1], trs[7][2])
    assert skeleton(trs)[2][5] == np.False_
    held[1, 2] += 1e-12
    assert skeleton(trs)[2][5] == np.True_


def test_a_still_skeleton_is_repeated_over_the_frames():
    trs = {node: tuple(value[:1] for value in values) for node, values in node_trs().items()}
    rotations, translations, moving = skeleton(trs)
    assert rotations.shape == (F, len(JOINTS), 3, 3) and not moving.any()
    np.testing.assert_array_equal(rotations, np.broadcast_to(rotations[:1], rotations.shape))
    np.testing.assert_array_equal(translations, np.broadcast_to(translations[:1], translations.shape))
    positions = post_rotation_positions(rotations[:1], translations[:1], [-1, 0, 1, 2, 0, 4])
    np.testing.assert_allclose(positions[0], gltf_positions(trs)[0, JOINTS], rtol=0, atol=1e-12)


def test_many_frames_are_converted_in_chunks_all_of_them():
    frames = 2 * CHUNK_FRAMES + 5
    moving = np.random.default_rng(7).normal(size=(frames, 4))
    still = turns([0, 1, 0], [50])
    poses, block = node_poses([4, 9], [np.zeros((1, 3))] * 2, [still, moving], [np.ones((1, 3))] * 2)
    assert block.shape == (frames, 2, 3, 3)
    np.testing.assert_allclose(block[:, 0], np.broadcast_to(matrix(still), (frames, 3, 3)), rtol=0, atol=1e-15)
    np.testing.assert_allclose(block[:, 1], matrix(moving), rtol=0, atol=1e-14)
    assert np.shares_memory(poses[9].rotation, block) and poses[9].rotation.shape == (frames, 3, 3)


def test_uniform_scales_fold_into_offsets_exactly_and_two_equal_frames_are_static():
    """A bone along x under turned parents scaled 2 and 1.5 stays along x, three times as
    long, bit for bit (the scale kept a number, no matrix rounding); a channel holding it
    for two frames does not move it."""
    parents = np.array([-1, 0, 1])
    turn = turns([1, 2, 3], [37, 37])
    t = [np.zeros((1, 3)), np.array([[0.3, 0, 0]]), np.array([[0.0, 0.7, 0]] * 2)]
    q = [turn[:1], turn, turns([0, 1, 0], [20])]
    s = [np.full((1, 3), 2.0), np.full((1, 3), 1.5), np.ones((1, 3))]
    poses, block = node_poses([0, 1, 2], t, q, s)
    _, translations, moving = skeleton_pose(poses, parents, [0, 1, 2], 2, block)
    np.testing.assert_array_equal(translations[:, 1], [[0.6, 0, 0]] * 2)
    np.testing.assert_array_equal(translations[:, 2], [[0, 3.0 * 0.7, 0]] * 2)
    assert moving.tolist() == [False, False, False]


def long_skeleton(trs, frames: int):
    """:func:`skeleton` of ``trs`` whose animated values repeat over ``frames`` frames."""
    long = {
        node: tuple(v if len(v) == 1 else v[np.arange(frames) % len(v)] for v in values) for node, values in trs.items()
    }
    poses, block = node_poses(JOINTS, *(list(c) for c in zip(*(long[n] for n in JOINTS))))
    poses.update(node_poses(ABOVE, *(list(c) for c in zip(*(long[n] for n in ABOVE))))[0])
    return skeleton_pose(poses, PARENTS, JOINTS, frames, block)


def test_a_channel_keyed_still_on_every_frame_reads_as_one_value_bit_for_bit():
    """Over several chunks of frames, under animated and uneven scales: a translation keyed
    with one value on every frame gives the very numbers of that value given once."""
    frames = 2 * CHUNK_FRAMES + 7
    keyed = node_trs(uneven_armature=True)
    once = {**keyed, 6: (keyed[6][0][:1], *keyed[6][1:])}
    for got, expected in zip(long_skeleton(keyed, frames), long_skeleton(once, frames)):
        assert got.tobytes() == expected.tobytes()


def test_a_joint_moving_on_the_last_frame_alone_moves():
    """The last chunk of frames may hold one frame: a translation changing there alone is
    still a moving one, every frame kept."""
    frames = 2 * CHUNK_FRAMES + 1
    trs = node_trs()
    late = np.zeros((frames, 3))
    late[-1] = [0.0, 0.25, 0.0]
    trs[7] = (late, trs[7][1][:1], trs[7][2])
    _, translations, moving = long_skeleton(trs, frames)
    assert moving[5]
    np.testing.assert_array_equal(translations[:-1, 5], np.zeros((frames - 1, 3)))
    assert translations[-1, 5, 1] > 0


def test_float32_keys_read_as_their_float64_values_bit_for_bit():
    """A file's float32 keys, worked on as stored, give the very numbers of their float64
    copies over several chunks of frames, under animated and uneven scales, a channel
    keyed still on every frame among them."""
    frames = 2 * CHUNK_FRAMES + 7
    rng = np.random.default_rng(11)
    trs = node_trs(uneven_armature=True)
    trs[2] = (rng.normal(size=(frames, 3)), rng.normal(size=(frames, 4)), trs[2][2][:1])
    stored = {node: tuple(v.astype(np.float32) if len(v) > 1 else v for v in values) for node, values in trs.items()}
    wide = {node: tuple(v.astype(np.float64) for v in values) for node, values in stored.items()}
    for got, expected in zip(long_skeleton(stored, frames), long_skeleton(wide, frames)):
        assert got.tobytes() == expected.tobytes()


def test_a_root_below_an_identity_node_keeps_its_own_transform():
    """A node that neither turns, moves nor scales above the root (an exported World node)
    leaves the root's rotation and translation as the file gives them, bit for bit."""
    rng = np.random.default_rng(12)
    q = rng.normal(size=(5, 4))
    t = np.array([[0.5, -0.0, 2.0]] * 4 + [[0.25, -0.0, 1.0]])
    identity = [np.zeros((1, 3)), np.array([[0.0, 0, 0, 1]]), np.ones((1, 3))]
    poses, block = node_poses([1], [t], [q], [np.ones((1, 3))])
    poses.update(node_poses([0], *([v] for v in identity))[0])
    rotations, translations, _ = skeleton_pose(poses, np.array([-1, 0]), [1], 5, block)
    assert rotations[:, 0].tobytes() == matrix_from_quaternion(q, scalar_last=True).tobytes()
    assert translations[:, 0].tobytes() == t.tobytes()
