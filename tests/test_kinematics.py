"""Forward kinematics against hand computation and an independent per-frame 4x4 loop."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.kinematics.fk import forward_kinematics, joint_world_transform, world_positions
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import rotation_about_axis
from tests.conftest import random_motion

RZ90 = rotation_about_axis("Z", np.pi / 2)
RX90 = rotation_about_axis("X", np.pi / 2)
RY90 = rotation_about_axis("Y", np.pi / 2)


def chain(rotations, offsets, parents, convention, root_position=(0.0, 0.0, 0.0)) -> Motion:
    n = len(parents)
    offsets = np.array(offsets, float)
    offsets[0] = root_position
    return Motion(
        names=[f"j{j}" for j in range(n)],
        parents=parents,
        offsets=offsets,
        rotation_orders=["XYZ"] * n,
        has_translation=np.zeros(n, bool),
        rotations=np.array(rotations, float)[None],
        translations=offsets[None].copy(),
        frame_time=0.1,
        convention=convention,
    )


def test_two_joints_by_hand():
    # root at (1, 2, 3) turned 90 degrees about z; child one unit along x, turned 90 about y
    rotations = [RZ90, RY90]
    offsets = [[0, 0, 0], [1, 0, 0]]
    post = world_positions(chain(rotations, offsets, [-1, 0], "post", (1, 2, 3)))[0]
    pre = world_positions(chain(rotations, offsets, [-1, 0], "pre", (1, 2, 3)))[0]
    np.testing.assert_allclose(post, [[1, 2, 3], [1, 3, 3]], atol=1e-15)  # child's own turn moves nothing
    np.testing.assert_allclose(pre, [[1, 2, 3], [1, 2, 2]], atol=1e-15)  # Rz Ry x = Rz (0,0,-1) = (0,0,-1)


def test_three_joint_chain_by_hand():
    rotations = [np.eye(3), RZ90, RX90]
    offsets = [[0, 0, 0], [0, 1, 0], [0, 1, 0]]
    pre_positions, pre_world = forward_kinematics(chain(rotations, offsets, [-1, 0, 1], "pre"))
    post_positions, post_world = forward_kinematics(chain(rotations, offsets, [-1, 0, 1], "post"))
    np.testing.assert_allclose(pre_positions[0], [[0, 0, 0], [-1, 0, 0], [-1, 0, 1]], atol=1e-15)
    np.testing.assert_allclose(post_positions[0], [[0, 0, 0], [0, 1, 0], [-1, 1, 0]], atol=1e-15)
    for world in (pre_world, post_world):
        np.testing.assert_allclose(world[0, 2], RZ90 @ RX90, atol=1e-15)


def test_pre_rotation_siblings_turn_independently():
    rotations = [np.eye(3), RZ90, RX90]
    offsets = [[0, 0, 0], [0, 1, 0], [0, 1, 0]]
    pre = world_positions(chain(rotations, offsets, [-1, 0, 0], "pre"))[0]
    post = world_positions(chain(rotations, offsets, [-1, 0, 0], "post"))[0]
    np.testing.assert_allclose(pre, [[0, 0, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-15)
    np.testing.assert_allclose(post, [[0, 0, 0], [0, 1, 0], [0, 1, 0]], atol=1e-15)  # rigid with the root


def homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def per_frame_fk(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """The paper's equation (1), one frame and one joint at a time, with 4x4 matrices."""
    positions = np.zeros((motion.n_frames, motion.n_joints, 3))
    rotations = np.zeros((motion.n_frames, motion.n_joints, 3, 3))
    for f in range(motion.n_frames):
        for j in range(motion.n_joints):
            chain_of_joints = motion.path_from_root(j)
            root = chain_of_joints[0]
            transform = homogeneous(motion.rotations[f, root], motion.translations[f, root])
            for k in chain_of_joints[1:]:
                r, t = motion.rotations[f, k], motion.translations[f, k]
                local = homogeneous(r, r @ t) if motion.convention == "pre" else homogeneous(r, t)
                transform = transform @ local
            positions[f, j] = transform[:3, 3]
            rotations[f, j] = transform[:3, :3]
    return positions, rotations


@pytest.mark.parametrize("convention", ["pre", "post"])
def test_vectorised_fk_matches_per_frame_loop(convention, rng):
    parents = [-1, 0, 1, 1, 0, 4, 5, 5, -1, 8, 9, 2]
    motion = random_motion(rng, parents, n_frames=6, convention=convention, translation_joints=(3, 10))
    expected_positions, expected_rotations = per_frame_fk(motion)
    positions, rotations = forward_kinematics(motion)
    np.testing.assert_allclose(positions, expected_positions, atol=1e-12)
    np.testing.assert_allclose(rotations, expected_rotations, atol=1e-12)
    for j in range(motion.n_joints):
        world, position = joint_world_transform(motion, j)
        np.testing.assert_allclose(world, rotations[:, j], atol=1e-12)
        np.testing.assert_allclose(position, positions[:, j], atol=1e-12)


def test_parent_after_child_in_index_order_is_fine(rng):
    motion = random_motion(rng, [2, 2, -1, 0], n_frames=4)
    np.testing.assert_allclose(forward_kinematics(motion)[0], per_frame_fk(motion)[0], atol=1e-12)
    assert list(motion.topological_order) == [2, 0, 3, 1]


def test_zero_frames_give_empty_arrays(rng):
    motion = random_motion(rng, [-1, 0], n_frames=0)
    positions, rotations = forward_kinematics(motion)
    assert positions.shape == (0, 2, 3) and rotations.shape == (0, 2, 3, 3)
    assert motion.size > 0
