"""The classroom's numbers: chains both ways against FK of the file, shift root, roots trade-off."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.analysis.classroom import (
    deepest_first,
    explain_shift_root,
    joint_chain,
    roots_tradeoff,
    scaled_rotation,
    split_to_roots,
    stored_per_frame,
)
from gmr_studio.core.edits.operations import shift_root
from gmr_studio.core.formats import read_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics, reference_forward_kinematics
from gmr_studio.core.rotations.euler import matrix_from_euler
from tests.conftest import random_motion, shared_path

FRAMES = (0, 311, 619, 2000)


@pytest.fixture(scope="module")
def cmu():
    post = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    return post, pre_from_post(post)


def test_every_chain_of_a_real_file_multiplies_to_fk_both_ways(cmu):
    """GMR product = FK world transform of the GMR motion; BVH product = FK of the BVH file
    itself (post-rotation, an independent path: the file's own rotations, no conversion)."""
    post, pre = cmu
    frames = np.array(FRAMES)
    post_positions, post_rotations = reference_forward_kinematics(post.frame_slice(frames))
    pre_world = forward_kinematics(pre.frame_slice(frames))
    size = pre.size
    worst = {"gmr_rotation": 0.0, "bvh_rotation": 0.0, "position": 0.0}
    for k in range(len(frames)):
        one = pre.frame_slice(frames[k : k + 1])
        world = (pre_world[0][k : k + 1], pre_world[1][k : k + 1])
        for j in range(pre.n_joints):
            chain = joint_chain(one, j, 0, world)
            assert chain.joints == pre.path_from_root(j)
            worst["position"] = max(
                worst["position"],
                np.abs(chain.gmr_product[:3, 3] - post_positions[k, j]).max(),
                np.abs(chain.bvh_product[:3, 3] - post_positions[k, j]).max(),
            )
            worst["gmr_rotation"] = max(worst["gmr_rotation"], np.abs(chain.gmr_product[:3, :3] - world[1][0, j]).max())
            worst["bvh_rotation"] = max(
                worst["bvh_rotation"], np.abs(chain.bvh_product[:3, :3] - post_rotations[k, j]).max()
            )
            assert chain.position_gap <= 1e-12 * size
    assert worst["position"] <= 1e-12 * size
    assert worst["gmr_rotation"] <= 1e-12
    assert worst["bvh_rotation"] <= 1e-12


def test_chains_of_a_rotated_root_both_ways(rng):
    """Roots and joints with arbitrary rotations (a shifted root is not the identity): the BVH
    product puts every joint at its FK position, and its rotation is the frame of the bones
    leaving the joint (FK's world rotation of its only child)."""
    motion = random_motion(rng, [-1, 0, 1, 2, 1, 4, 0, 6], n_frames=4)
    positions, rotations = forward_kinematics(motion)
    for frame in range(motion.n_frames):
        for j in range(motion.n_joints):
            chain = joint_chain(motion, j, frame)
            np.testing.assert_allclose(chain.bvh_product[:3, 3], positions[frame, j], rtol=0, atol=1e-12 * motion.size)
            np.testing.assert_allclose(chain.gmr_product[:3, :3], rotations[frame, j], rtol=0, atol=1e-12)
            children = motion.children[j]
            if len(children) == 1:
                expected = rotations[frame, children[0]]
                np.testing.assert_allclose(chain.bvh_product[:3, :3], expected, rtol=0, atol=1e-12)


def test_links_are_the_two_conventions_of_the_same_numbers(cmu):
    _, pre = cmu
    chain = joint_chain(pre, "LeftHand", 619)
    names = [link.name for link in chain.links]
    assert names[0] == "Hips" and names[-1] == "LeftHand"
    for k, link in enumerate(chain.links[1:], start=1):
        j = link.joint
        rotation, offset = pre.rotations[619, j], pre.translations[619, j]
        np.testing.assert_array_equal(link.gmr_local[:3, :3], rotation)
        np.testing.assert_allclose(link.gmr_local[:3, 3], rotation @ offset, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(link.bvh_local[:3, 3], offset)
        if k + 1 < len(chain.links):
            np.testing.assert_array_equal(link.bvh_local[:3, :3], pre.rotations[619, chain.links[k + 1].joint])
    end = joint_chain(pre, pre.names.index("Head_End") if "Head_End" in pre.names else pre.n_joints - 1, 10)
    assert end.links[-1].bvh_rotation_from.startswith("none") or end.links[-1].bvh_rotation_from.startswith("R of")


def test_scaled_rotation_goes_from_identity_to_the_rotation(rng):
    angles = rng.uniform(-np.pi, np.pi, (200, 3))
    angles[0] = (np.pi, 0, 0)  # 180 degrees exactly
    rotations = matrix_from_euler(angles, "ZYX")
    np.testing.assert_allclose(scaled_rotation(rotations, 1.0), rotations, atol=1e-9)
    np.testing.assert_allclose(scaled_rotation(rotations, 0.0), np.broadcast_to(np.eye(3), rotations.shape), atol=1e-15)
    half = scaled_rotation(rotations, 0.5)
    np.testing.assert_allclose(half @ half, rotations, atol=1e-9)


def test_shift_root_explained_on_a_real_file(cmu):
    _, pre = cmu
    before = pre.frame_slice(slice(0, 300))
    after = shift_root(before, "LeftHand")
    explanation = explain_shift_root(before, after, "LeftHand")
    assert explanation.old_root == "Hips" and explanation.new_root == "LeftHand"
    path = before.path_from_root("LeftHand")
    assert len(explanation.reversed_links) == len(path) - 1
    assert explanation.reversed_links[0] == ("Hips", before.names[path[1]])
    assert after.parents[before.joint_index("Hips")] == path[1]
    assert 0.0 < explanation.largest_change <= 1e-12 * before.size
    assert "did not move" in explanation.lines()[-1]


def test_roots_tradeoff_keeps_positions_and_counts_storage(rng):
    motion = random_motion(rng, [-1, 0, 1, 2, 3, 1, 5, 6, 0, 8, 9, 10], n_frames=50)
    order = deepest_first(motion)
    depths = motion.depths[order]
    assert list(depths) == sorted(depths, reverse=True)
    for roots in (1, 4, motion.n_joints):
        point = roots_tradeoff(motion, roots, repeats=1)
        assert point.roots == roots
        assert point.largest_change <= 1e-9 * motion.size
        forest, chosen = split_to_roots(motion, roots)
        # counted by hand: every joint rotates (3 each); each root stores its position (3 each)
        assert point.stored_per_frame == 3 * motion.n_joints + 3 * roots
        assert len(forest.roots) == roots and len(chosen) == roots - 1
    one = roots_tradeoff(motion, 1, repeats=1)
    every = roots_tradeoff(motion, motion.n_joints, repeats=1)
    # every joint a root: each stores its world position too
    assert every.stored_per_frame > one.stored_per_frame


POSITION_ONLY_ROOT = b"""HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 3 Xposition Yposition Zposition
  JOINT Spine
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.0333333
0 0 0 10 20 30
1 0 0 15 25 35
"""


def test_a_root_without_rotation_channels_still_stores_its_rotation():
    # planted bug: roots left out of the rotation count (only joints with channels counted)
    motion = read_bvh("root.bvh", POSITION_ONLY_ROOT)
    assert motion.rotation_orders == ("", "ZXY", "") and motion.parents[0] < 0
    # the root's [R, G] (3 + 3), Spine's channels (3), the End Site nothing
    assert stored_per_frame(motion) == 9
