"""The demo files are made by core/demo.py: regenerating them reproduces the committed ones."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.demo import (
    GAPS,
    MARKERS_FILE,
    MOTION_FILE,
    SURFACE_MARKERS,
    demo_folder,
    demo_markers,
    demo_motion,
    write_demo,
)
from gmr_studio.core.formats.gmr import read_gmr
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.markerset import Z_UP_TO_Y_UP
from gmr_studio.core.markers.trc import trc_text

CMU_NAMES = {"root", "lhipjoint", "lfemur", "ltibia", "lfoot", "ltoes", "lowerback", "upperback", "thorax", "head"}


#: the committed walk.gmr against a fresh one: its numbers are written to 15 significant
#: digits, and the last digit of 14 of its 480 frame lines differs (libm and numba rounding):
#: measured 4.5e-13 cm in positions (the figure is 155 cm) and 8.9e-16 in rotations
POSITION_TOLERANCE_CM = 2e-12
ROTATION_TOLERANCE = 4e-15


def test_regenerating_reproduces_the_committed_files(tmp_path):
    motion_path, markers_path = write_demo(tmp_path)
    committed_motion = read_gmr(demo_folder() / MOTION_FILE)
    fresh_motion = read_gmr(motion_path)
    assert committed_motion.names == fresh_motion.names
    np.testing.assert_array_equal(committed_motion.parents, fresh_motion.parents)
    np.testing.assert_allclose(
        world_positions(committed_motion), world_positions(fresh_motion), rtol=0, atol=POSITION_TOLERANCE_CM
    )
    # the header (everything but the numbers of the frames) is the same text
    committed_text = (demo_folder() / MOTION_FILE).read_text()
    assert committed_text.split("MOTION")[0] == motion_path.read_text().split("MOTION")[0]
    # the markers' text (mm to 5 decimals) comes out byte for byte
    assert markers_path.read_bytes() == (demo_folder() / MARKERS_FILE).read_bytes()


def test_the_demo_in_memory_is_the_committed_one():
    committed = read_gmr(demo_folder() / MOTION_FILE)
    motion = demo_motion()
    assert motion.names == committed.names and motion.rotation_orders == committed.rotation_orders
    np.testing.assert_array_equal(motion.parents, committed.parents)
    np.testing.assert_array_equal(motion.has_translation, committed.has_translation)
    np.testing.assert_allclose(motion.rotations, committed.rotations, rtol=0, atol=ROTATION_TOLERANCE)
    np.testing.assert_allclose(world_positions(motion), world_positions(committed), rtol=0, atol=POSITION_TOLERANCE_CM)
    assert trc_text(demo_markers(motion)) == (demo_folder() / MARKERS_FILE).read_text()


def test_the_demo_is_a_standing_walking_humanoid_with_cmu_bone_names():
    motion = demo_motion()
    assert CMU_NAMES <= set(motion.names) and motion.n_joints == 31
    assert motion.frame_rate == 120 and motion.n_frames == 480
    positions = world_positions(motion)
    head, toes = positions[:, motion.joint_index("head"), 1], positions[:, motion.joint_index("ltoes"), 1]
    assert (head > 150).all() and (toes < 30).all()  # Y up, centimetres
    lowest = positions[..., 1].min(axis=1)
    assert np.abs(lowest).max() < 6  # feet on the ground, give or take a few cm
    travel = positions[-1, 0, 2] - positions[0, 0, 2]
    assert 450 < travel < 550  # walks about 5 m along +Z in 4 s
    left_knee = positions[:, motion.joint_index("lfemur")]
    right_knee = positions[:, motion.joint_index("rfemur")]
    swing = left_knee[:, 2] - right_knee[:, 2]
    assert swing.max() > 20 and swing.min() < -20  # the legs alternate
    left_hand = positions[:, motion.joint_index("lwrist"), 2] - positions[:, 0, 2]
    assert np.corrcoef(left_hand, swing)[0, 1] < -0.5  # arms swing against the legs


def test_the_markers_follow_the_joints_with_gaps():
    motion = demo_motion()
    markers = demo_markers(motion)
    assert markers.units == "mm" and markers.rate == motion.frame_rate
    assert markers.labels[: motion.n_joints] == motion.names
    assert set(markers.labels[motion.n_joints :]) == set(SURFACE_MARKERS)
    # back to the motion's axes and units: virtual markers sit on their joints (0.5 mm noise)
    in_motion = np.einsum("ab,fmb->fma", Z_UP_TO_Y_UP, markers.positions) / 10.0
    error = np.linalg.norm(in_motion[:, : motion.n_joints] - world_positions(motion), axis=-1)
    assert np.nanmax(error) < 0.5 and np.nanmean(error) < 0.15
    for label, first, last in GAPS:
        m = markers.labels.index(label)
        assert not markers.present[first : last + 1, m].any()
        assert markers.present[last + 1, m] and markers.present[first - 1, m]
    assert markers.present.mean() > 0.99
