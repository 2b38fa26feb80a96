"""Euler curves of joints with fewer than three rotation channels, and a mirror whose left and
right joints turn in different orders."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.analysis.curves import euler_degrees, joint_curves
from gmr_studio.core.edits.mirror import mirror
from gmr_studio.core.formats import read_bvh
from gmr_studio.core.rotations.euler import matrix_from_euler


def test_two_channel_euler_curves_keep_the_first_channels():
    # planted bug: the last len(order) angles of the completed order taken (ZX: [35, 0], not [20, 35])
    angles = np.radians(np.array([[20.0, 35.0], [25.0, -10.0], [-40.0, 60.0]]))
    for order in ("ZX", "XY", "YZ"):
        rotations = matrix_from_euler(angles, order)
        np.testing.assert_allclose(euler_degrees(rotations, order), np.degrees(angles), rtol=0, atol=1e-12)
    one = matrix_from_euler(np.radians([[70.0], [100.0]]), "Y")
    np.testing.assert_allclose(euler_degrees(one, "Y"), [[70.0], [100.0]], rtol=0, atol=1e-12)


TWO_CHANNELS = b"""HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Knee
  {
    OFFSET 0 -1 0
    CHANNELS 2 Zrotation Xrotation
    End Site
    {
      OFFSET 0 -1 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.0333333
0 0 0 0 0 0 20 35
0 0 0 0 0 0 22 30
"""


def test_the_euler_curve_of_a_two_channel_joint_is_its_channels():
    motion = read_bvh("knee.bvh", TWO_CHANNELS)
    curves = joint_curves(motion, "Knee", "euler")  # euler: an alias of channels, the file's own
    assert curves.columns == ("Knee.channels.Zrotation", "Knee.channels.Xrotation")
    np.testing.assert_allclose(curves.values, [[20.0, 35.0], [22.0, 30.0]], rtol=0, atol=1e-12)


SIDES = b"""HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT LeftLeg
  {
    OFFSET 1 -1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -2 0
    }
  }
  JOINT RightLeg
  {
    OFFSET -1 -1 0
    CHANNELS 3 Yrotation Xrotation Zrotation
    End Site
    {
      OFFSET 0 -2 0
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.0333333
0 0 0 0 0 0 10 20 30 40 50 60
"""


def test_mirror_swaps_the_rotation_orders_with_the_sides():
    # planted bug: each joint keeps its own order while taking its partner's rotation
    motion = read_bvh("sides.bvh", SIDES)
    left, right = motion.joint_index("LeftLeg"), motion.joint_index("RightLeg")
    assert motion.rotation_orders[left] == "ZXY" and motion.rotation_orders[right] == "YXZ"
    mirrored, unmatched = mirror(motion)
    assert unmatched == ()
    assert mirrored.rotation_orders[left] == "YXZ" and mirrored.rotation_orders[right] == "ZXY"
    # the mirrored left leg's channels, in its new order, are the right leg's mirrored angles:
    # S R(a, b, c) S for S = diag(-1, 1, 1) keeps the X angle and negates the Y and Z ones
    got = euler_degrees(mirrored.rotations[:, left], mirrored.rotation_orders[left])
    np.testing.assert_allclose(got, [[-40.0, 50.0, -60.0]], rtol=0, atol=1e-12)
