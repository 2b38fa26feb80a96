"""Curves at their edges (core/analysis/curves.py): Euler branches through 90 degrees, one- and two-channel
wraps, two frames, no channels, the file's values kept bit for bit, leaves and independent
children, a post motion's GMR rotations, the block type."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.analysis.curves import (
    Curves,
    bvh_rotations,
    derivative,
    euler_degrees,
    gmr_rotations,
    joint_curves,
    world_acceleration,
)
from gmr_studio.core.formats import read_motion_with_channels
from gmr_studio.core.kinematics.convention import DEFAULT_ORDER, post_from_pre, pre_from_post
from gmr_studio.core.rotations.continuity import BRANCH_MIDDLE as EULER_BRANCH_MIDDLE
from gmr_studio.core.rotations.continuity import continuous_euler as continuous_euler_of
from gmr_studio.core.rotations.euler import euler_from_matrix, matrix_from_euler
from tests.conftest import random_motion, shared_path


def continuous_euler(angles: np.ndarray) -> np.ndarray:
    """The continuous ZYX angles (radians) of the rotations that angles (F, 3) in radians make."""
    return continuous_euler_of(matrix_from_euler(np.asarray(angles, dtype=np.float64), "ZYX"), "ZYX")


def principal(degrees: np.ndarray, order: str = "ZYX") -> np.ndarray:
    """The angles euler_from_matrix gives (middle within +-90 degrees) of a path (F, 3) in degrees."""
    return euler_from_matrix(matrix_from_euler(np.radians(degrees), order), order)


def test_a_middle_angle_through_90_degrees_is_followed_there_and_back():
    up = np.arange(43.0, 140.0, 6.0)  # 85 then 91: not at the lock itself (90 degrees)
    middle = np.concatenate([up, up[::-1][1:]])  # over 90 degrees and back again
    path = np.stack([np.full_like(middle, 20.0), middle, np.full_like(middle, -30.0)], axis=-1)
    got = np.degrees(continuous_euler(principal(path)))
    np.testing.assert_allclose(got, path, rtol=0, atol=1e-9)
    # two frames across 90 degrees switch too (no shortcut but for one frame)
    two = np.array([[10.0, 80.0, 5.0], [12.0, 100.0, 7.0]])
    np.testing.assert_allclose(np.degrees(continuous_euler(principal(two))), two, rtol=0, atol=1e-9)


def test_outer_angles_across_180_degrees_are_unwrapped_not_switched():
    # a steep middle angle, the first and last angles passing 180: the principal angles jump
    # from 179 to -179 degrees, the other solution is no nearer than a 2-degree step
    path = np.array([[177.0, 85.0, 177.0], [179.0, 85.0, 179.0], [181.0, 85.0, 181.0], [183.0, 85.0, 183.0]])
    got = np.degrees(continuous_euler(principal(path)))
    np.testing.assert_allclose(got, path, rtol=0, atol=1e-9)


def test_the_branch_changes_only_beyond_the_middle_threshold():
    """Frame 1's other solution (middle 180 - b) is the nearer one: it is taken when b is
    beyond EULER_BRANCH_MIDDLE (60 degrees), not at it or below (a jump in the data)."""
    threshold = float(np.degrees(EULER_BRANCH_MIDDLE))
    assert threshold == pytest.approx(60.0, abs=1e-12)
    for middle, switches in ((60.0, False), (60.5, True), (59.5, False)):
        b = EULER_BRANCH_MIDDLE if middle == 60.0 else np.radians(middle)
        angles = np.array([[0.3, np.radians(85.0), -0.2], [0.3 - np.pi, b, -0.2 + np.pi]])
        got = continuous_euler(angles)
        if switches:
            np.testing.assert_allclose(got[1], [0.3, np.pi - b, -0.2], rtol=0, atol=1e-12)
        else:
            np.testing.assert_allclose(got, np.unwrap(angles, axis=0), rtol=0, atol=1e-12)


def test_a_jump_at_a_shallow_middle_angle_switches_nothing():
    # T-pose to a pose whose other solution is nearer, middle angle 10 degrees: kept as read
    angles = np.radians([[0.0, 0.0, 0.0], [170.0, 10.0, 170.0], [171.0, 11.0, 171.0]])
    np.testing.assert_allclose(continuous_euler(angles), np.unwrap(angles, axis=0), rtol=0, atol=1e-12)


def test_one_and_no_frame_are_returned_as_given():
    one = np.radians([[170.0, 80.0, -20.0]])
    np.testing.assert_allclose(continuous_euler(one), one, rtol=0, atol=1e-12)
    assert continuous_euler(np.zeros((0, 3))).shape == (0, 3)


def test_fewer_than_three_channels_are_unwrapped_over_time():
    degrees = np.array([[150.0], [170.0], [190.0], [210.0]])
    np.testing.assert_allclose(euler_degrees(matrix_from_euler(np.radians(degrees), "Y"), "Y"), degrees, atol=1e-9)
    two = np.array([[150.0, 10.0], [175.0, 20.0], [200.0, 30.0]])
    np.testing.assert_allclose(euler_degrees(matrix_from_euler(np.radians(two), "ZX"), "ZX"), two, atol=1e-9)
    # no channels: no columns, a row per frame
    rotations = matrix_from_euler(np.zeros((5, 3)), "ZYX")
    assert euler_degrees(rotations, "").shape == (5, 0)


def test_derivatives_of_two_frames_are_the_step():
    positions = np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0]])
    np.testing.assert_allclose(derivative(positions, 0.5), [[6.0, 8.0, 0.0], [6.0, 8.0, 0.0]])
    np.testing.assert_array_equal(derivative(positions[:1], 0.5), [[0.0, 0.0, 0.0]])


def test_acceleration_of_several_joints_is_each_joints_own():
    t = np.arange(6.0)[:, None]
    # joint 0 accelerates at 2 along x, joint 1 at 6 along z; (F, J, 3)
    positions = np.stack([np.hstack([t**2, 0 * t, 0 * t]), np.hstack([0 * t, 0 * t, 3 * t**2])], axis=1)
    got = world_acceleration(positions, 1.0)
    assert got.shape == (6, 2)
    np.testing.assert_allclose(got[2:-2], np.tile([2.0, 6.0], (2, 1)), rtol=1e-12)  # central twice


LEAF_AND_FORK = b"""HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Tip
  {
    OFFSET 0 1 0
    CHANNELS 2 Zrotation Xrotation
  }
  JOINT Chest
  {
    OFFSET 0 0 1
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT ArmA
    {
      OFFSET 1 0 0
      CHANNELS 3 Zrotation Yrotation Xrotation
      End Site
      {
        OFFSET 1 0 0
      }
    }
    JOINT ArmB
    {
      OFFSET -1 0 0
      CHANNELS 3 Zrotation Yrotation Xrotation
      End Site
      {
        OFFSET -1 0 0
      }
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.0333333
0 0 0 5 6 7 10 30 40 50 60 1 2 3 4 5 6
0 0 0 6 7 8 11 31 41 51 61 1 2 3 4 5 6
0 0 0 7 8 9 12 32 42 52 62 1 2 3 4 5 6
"""


def _leaf_and_fork(tmp_path):
    path = tmp_path / "fork.bvh"
    path.write_bytes(LEAF_AND_FORK)
    post, channels = read_motion_with_channels(path)
    return post, pre_from_post(post), channels


def test_a_leafs_channels_are_the_files_and_a_fork_turning_two_ways_has_none(tmp_path):
    post, pre, channels = _leaf_and_fork(tmp_path)
    for motion in (post, pre):
        tip = joint_curves(motion, "Tip", "channels", file_channels=channels)
        assert tip.columns == ("Tip.channels.Zrotation", "Tip.channels.Xrotation")
        np.testing.assert_array_equal(tip.values, [[10, 30], [11, 31], [12, 32]])
    # in GMR form, ArmA's bone turned apart from ArmB's: Chest has no one BVH rotation left
    chest = pre.joint_index("Chest")
    arm_a = pre.joint_index("ArmA")
    turned = pre.rotations.copy()
    turned[:, arm_a] = turned[:, arm_a] @ matrix_from_euler(np.radians([[0.0, 0.0, 0.5]] * 3), "ZYX")
    forked = pre.replace(rotations=turned)
    assert bvh_rotations(forked, chest) is None
    values = joint_curves(forked, "Chest", "channels", file_channels=channels).values
    assert values.shape == (3, 3) and np.isnan(values).all()
    # the same turn on the second child only is seen too
    turned = pre.rotations.copy()
    arm_b = pre.joint_index("ArmB")
    assert list(pre.children[chest]) == [arm_a, arm_b]
    turned[:, arm_b] = turned[:, arm_b] @ matrix_from_euler(np.radians([[0.0, 0.0, 0.5]] * 3), "ZYX")
    assert bvh_rotations(pre.replace(rotations=turned), chest) is None


def test_bvh_rotations_of_the_gmr_form_are_the_files(tmp_path):
    post, pre, _ = _leaf_and_fork(tmp_path)
    for name in ("Hips", "Chest", "ArmA"):  # the root, a child of the root, a grandchild
        j = pre.joint_index(name)
        np.testing.assert_allclose(bvh_rotations(pre, j), post.rotations[:, j], rtol=0, atol=1e-12)
        np.testing.assert_array_equal(bvh_rotations(post, j), post.rotations[:, j])
    assert bvh_rotations(pre, pre.joint_index("Tip")) is None  # a leaf turns no bone


def test_the_bvh_rotation_of_a_turned_root_is_its_rotation_then_its_childrens(rng):
    """A GMR root that turns, its children sharing one rotation: the BVH root's channels make
    the root's rotation followed by the children's (what post_from_pre writes)."""
    pre = random_motion(rng, [-1, 0, 0, 1], n_frames=4)
    rotations = pre.rotations.copy()
    rotations[:, 2] = rotations[:, 1]
    pre = pre.replace(rotations=rotations)
    expected = pre.rotations[:, 0] @ pre.rotations[:, 1]
    np.testing.assert_allclose(bvh_rotations(pre, 0), expected, rtol=0, atol=1e-15)
    post, _ = post_from_pre(pre)
    np.testing.assert_allclose(post.rotations[:, 0], expected, rtol=0, atol=1e-12)
    assert np.abs(expected - pre.rotations[:, 1]).max() > 0.1  # the root's own turn counts


def test_gmr_rotations_of_a_post_motion(tmp_path):
    post, pre, _ = _leaf_and_fork(tmp_path)
    root, chest = post.joint_index("Hips"), post.joint_index("Chest")
    rotations, order = gmr_rotations(post, root)
    np.testing.assert_array_equal(rotations, np.broadcast_to(np.eye(3), (3, 3, 3)))
    assert order == "ZYX"
    rotations, order = gmr_rotations(post, chest)  # a child of the root: the root's rotation
    np.testing.assert_array_equal(rotations, post.rotations[:, root])
    np.testing.assert_allclose(rotations, pre.rotations[:, chest], rtol=0, atol=1e-12)
    # a root's own order, whatever the default; the default for a root without one
    assert DEFAULT_ORDER != "XZY"
    assert gmr_rotations(post.replace(rotation_orders=("XZY", *post.rotation_orders[1:])), root)[1] == "XZY"
    assert gmr_rotations(post.replace(rotation_orders=("", *post.rotation_orders[1:])), root)[1] == DEFAULT_ORDER


def test_a_real_files_channels_are_its_values_bit_for_bit():
    motion, channels = read_motion_with_channels(shared_path("cmu/subject01/01_01.bvh"))
    for name, written in channels.angles.items():
        values = joint_curves(motion, name, "channels", file_channels=channels).values
        np.testing.assert_array_equal(values, written, err_msg=name)


def test_an_amc_motion_in_bvh_form_gives_the_files_dofs():
    """AMC dofs turn the bone ending at the joint (pre): on the motion converted to post
    rotation, that is the parent's rotation, and the values are still the file's."""
    pre, channels = read_motion_with_channels(shared_path("cmu/subject02/02_01.amc"))
    post, _ = post_from_pre(pre)
    for name in ("lfemur", "ltibia", "lradius"):
        curves = joint_curves(post, name, "channels", file_channels=channels)
        np.testing.assert_array_equal(curves.values, channels.angles[name], err_msg=name)


def test_a_joint_without_channels_has_no_columns_and_a_row_per_frame(tmp_path):
    post, pre, channels = _leaf_and_fork(tmp_path)
    end = post.children[post.joint_index("ArmA")][0]  # its End Site
    assert post.rotation_orders[end] == ""
    for curves in (
        joint_curves(post, end, "channels"),  # the motion's own (no order)
        joint_curves(pre, end, "channels", file_channels=channels),  # the file gives none
    ):
        assert curves.columns == () and curves.values.shape == (3, 0)


def test_curves_blocks_are_frozen_compared_by_identity_and_joined_under_the_first_unit():
    a = Curves(("a",), np.zeros((2, 1)), "deg")
    b = Curves(("b",), np.ones((2, 1)), "units")
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.unit = "rad"  # type: ignore[misc]
    assert a == a and a != Curves(("a",), np.zeros((2, 1)), "deg") and len({a, b}) == 2
    joined = a.concatenate([a, b])  # a static method: from an instance too
    assert joined.columns == ("a", "b") and joined.unit == "deg"
    np.testing.assert_array_equal(joined.values, [[0.0, 1.0], [0.0, 1.0]])
    empty = Curves.concatenate([])
    assert empty.columns == () and empty.values.shape == (0, 0) and empty.unit == ""
