"""Foot contacts measured along the motion's own up axis (issue 24: a Z-up walk)."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.contacts import foot_contacts
from gmr_studio.core.conversions import change_up_axis, up_axis_of
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics import world_positions


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
