"""Foot contacts measured along the motion's own up axis (issue 24: a Z-up walk)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.analysis.contacts import foot_contacts
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.edits.world import change_up_axis
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.space.up_axis import up_axis_of


def test_a_z_up_walk_has_the_same_planted_frames_as_its_y_up_original():
    # planted bug: heights always read along Y (a Z-up walk gets its sideways-forward axis)
    walk = load_gmr(demo_folder() / MOTION_FILE)
    z_up = change_up_axis(walk, "z")
    assert up_axis_of(walk) == "y" and up_axis_of(z_up) == "z"
    y_contacts, z_contacts = foot_contacts(walk), foot_contacts(z_up)
    assert z_contacts.names == y_contacts.names and len(y_contacts.names) == 4
    np.testing.assert_array_equal(z_contacts.planted, y_contacts.planted)
    # and they are the frames where each foot is low (along Z here) and slow, computed by hand
    positions = world_positions(z_up)[:, z_contacts.joints]
    height = positions[..., 2] - positions[..., 2].min(axis=0)
    speed = np.linalg.norm(np.gradient(positions, z_up.frame_time, axis=0), axis=-1)
    expected = (height < 0.03 * z_up.size) & (speed < 0.4 * z_up.size)
    np.testing.assert_array_equal(z_contacts.planted, expected)
    assert (z_contacts.planted.sum(axis=0) >= 30).all()
    # heights along Y (forward, in this world) would plant other frames: the case is telling
    sideways = positions[..., 1] - positions[..., 1].min(axis=0)
    assert ((sideways < 0.03 * z_up.size) & (speed < 0.4 * z_up.size)).sum() != expected.sum()


FEET = (
    b"""HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT LeftFoot
  {
    OFFSET 0 -1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 0 0
    }
  }
  JOINT RightFoot
  {
    OFFSET 0 -1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 0 0
    }
  }
}
MOTION
Frames: 7
Frame Time: 1
"""
    + b"0 0 0 0 0 0 0 0 0 0 0 0\n" * 7
)


def test_planted_means_strictly_below_both_thresholds():
    # planted bugs: `<=` for either threshold; the thresholds and joints not given by keyword
    from gmr_studio.core.formats import read_bvh

    motion = read_bvh("feet.bvh", FEET)
    assert motion.size == 1.0 and motion.frame_time == 1.0
    left, right = motion.joint_index("LeftFoot"), motion.joint_index("RightFoot")
    positions = np.zeros((7, motion.n_joints, 3))
    positions[:, left, 1] = [0, 0, 0, 0.25, 0.25, 0.25, 0.25]  # rests exactly at the height threshold
    positions[:, right, 2] = 0.5 * np.arange(7)  # slides exactly at the speed threshold (0.5 / s)
    contacts = foot_contacts(motion, positions=positions, joints=["LeftFoot", "RightFoot"], height=0.25, speed=0.5)
    assert contacts.height_threshold == 0.25 and contacts.speed_threshold == 0.5
    assert contacts.names == ("LeftFoot", "RightFoot")
    # left: low and slow on frames 0-2 (0.125 / s on 2), at the height threshold (not below) on 3-6
    np.testing.assert_array_equal(contacts.planted[:, 0], [True, True, True, False, False, False, False])
    np.testing.assert_array_equal(contacts.planted[:, 1], False)  # never slower than the threshold
    with pytest.raises(TypeError):
        foot_contacts(motion, positions, ["LeftFoot"], 0.25)  # thresholds are keyword-only


def test_contacts_are_frozen_and_compared_by_identity():
    # planted bugs: the dataclass made mutable, or compared field by field (arrays: ambiguous)
    walk = load_gmr(demo_folder() / MOTION_FILE)
    contacts = foot_contacts(walk)
    with pytest.raises(dataclasses.FrozenInstanceError):
        contacts.speed_threshold = 0.0
    again = foot_contacts(walk)
    assert contacts == contacts and contacts != again and len({contacts, again}) == 2


def test_a_motion_without_frames_has_no_contacts():
    # the empty case of the ground (each joint's lowest point): nothing planted, no error
    walk = load_gmr(demo_folder() / MOTION_FILE)
    empty = foot_contacts(walk, positions=np.zeros((0, walk.n_joints, 3)))
    assert empty.planted.shape == (0, 4)
