"""Frozen, duplicated and rest-pose frames (core.checks.frames): takes of two frames or none,
near copies, a hold of exactly the frozen limit, the joints that move, a take at rest
throughout."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings, run_checks
from gmr_studio.core.checks.context import CheckData
from gmr_studio.core.checks.frames import rest_fractions, rest_frames, same_pose_runs
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.rotations.euler import rotation_about_axis
from tests.checks_walk import clean_walk
from tests.test_checks import CM

HELD = CheckSettings(kinds=("frozen", "duplicate"))


def test_a_take_of_two_equal_frames_is_a_duplicate():
    motion = clean_walk(120.0, unit=CM).frame_slice(np.array([5, 5]))
    assert [(f.kind, f.start, f.end, f.value) for f in run_checks(motion, HELD)] == [("duplicate", 1, 1, 1.0)]


def test_same_pose_runs_of_one_frame_are_none():
    motion = clean_walk(120.0, unit=CM).frame_slice(slice(0, 1))
    runs = same_pose_runs(CheckData(motion, world_positions(motion), motion.size), CheckSettings())
    assert runs.shape == (0, 2)


def test_a_copy_moved_by_a_hundredth_of_a_millimetre_is_no_duplicate():
    """The root moved 0.001 cm at the copy: 1e-3 / 173 = 5.8e-6 of the size, beyond the
    same-pose tolerance (1e-7 of it); moved 1e-6 cm it is within it, still a copy."""
    motion = clean_walk(120.0, unit=CM).frame_slice(np.concatenate([np.arange(251), [250], np.arange(251, 600)]))
    assert [f.kind for f in run_checks(motion, HELD)] == ["duplicate"]
    translations = motion.translations.copy()
    translations[251, 0, 0] += 1e-3
    assert run_checks(motion.replace(translations=translations), HELD) == []
    translations[251, 0, 0] = translations[250, 0, 0] + 1e-6  # 5.8e-9 of the size: a copy rounded
    assert [f.kind for f in run_checks(motion.replace(translations=translations), HELD)] == ["duplicate"]


def test_a_hold_of_exactly_the_frozen_limit_is_frozen_only():
    """At 10 Hz two frames of one pose last 0.2 s, the frozen limit: frozen, not a duplicate."""
    motion = clean_walk(10.0, unit=CM)
    index = np.arange(motion.n_frames)
    index[21] = 20
    assert [(f.kind, f.start, f.end) for f in run_checks(motion.frame_slice(index), HELD)] == [("frozen", 20, 21)]


def test_a_frame_shown_three_times_is_a_warning():
    """Two copies: the duplicate limits (1, 1, 3) frames give a warning, not an error."""
    motion = clean_walk(120.0, unit=CM)
    index = np.concatenate([np.arange(251), [250, 250], np.arange(251, motion.n_frames)])
    (finding,) = run_checks(motion.frame_slice(index), HELD)
    assert (finding.start, finding.end, finding.value, finding.severity) == (251, 252, 2.0, "warning")


def _turned_once(motion, joint: int, frame: int):
    """``motion`` with every joint but the root still (the identity) but ``joint`` at
    ``frame``, turned 0.1 rad about X: the one joint that moves."""
    rotations = motion.rotations.copy()
    rotations[:, 1:] = np.eye(3)
    rotations[frame, joint] = rotation_about_axis("X", np.array(0.1))
    return motion.replace(rotations=rotations)


@pytest.mark.parametrize("name", ["Head", "Spine", "LeftUpLeg"])
def test_a_joint_turned_at_any_one_frame_is_the_joint_that_moves(name):
    """The rest fraction counts the joints that move (the root's children too): with one joint
    turned at one frame of 64, every other frame is at rest and that one is not."""
    motion = clean_walk(120.0, unit=CM).frame_slice(slice(0, 64))
    j = motion.names.index(name)
    for frame in range(64):
        expected = np.ones(64)
        expected[frame] = 0.0
        np.testing.assert_array_equal(rest_fractions(_turned_once(motion, j, frame), CheckSettings()), expected)


def test_a_joint_turned_at_the_first_frame_only_moves():
    motion = clean_walk(120.0, unit=CM)
    fractions = rest_fractions(_turned_once(motion, motion.names.index("Head"), 0), CheckSettings())
    assert fractions[0] == 0.0 and (fractions[1:] == 1.0).all()


def test_a_turning_root_is_not_counted_for_the_rest_pose():
    """Rest frames with every joint but the root (turning about the vertical) at rest: all
    of the moving non-root joints, so rest frames even when all (1.0) are asked for."""
    motion = clean_walk(120.0, unit=CM)
    rotations = motion.rotations.copy()
    rotations[:, 0] = rotation_about_axis("Y", np.linspace(0.0, 1.0, motion.n_frames))
    rotations[:12, 1:] = np.eye(3)
    turning = motion.replace(rotations=rotations)
    assert rest_frames(turning, CheckSettings(rest_fraction=1.0)) == (12, 0)


def test_no_frames_and_all_frames_at_rest_have_no_rest_frames():
    """Without frames, or in the rest pose throughout (the joints wobbling 0.1 degree around
    it, so they move): (0, 0), and no finding."""
    motion = clean_walk(120.0, unit=CM)
    assert rest_frames(motion.frame_slice(slice(0, 0)), CheckSettings()) == (0, 0)
    wobble = np.radians(0.1) * np.sin(np.arange(motion.n_frames))[:, None]
    rotations = rotation_about_axis("X", np.broadcast_to(wobble, (motion.n_frames, motion.n_joints)))
    still = motion.replace(rotations=rotations)
    assert rest_frames(still, CheckSettings()) == (0, 0)
    assert run_checks(still, CheckSettings(kinds=("rest-pose",))) == []


def test_a_step_where_only_an_inner_joint_moves_keeps_no_pose():
    """Leaves and roots screen the steps; every joint decides: the Spine (neither) moved at
    frame 1 of three equal frames breaks the pose there."""
    motion = clean_walk(120.0, unit=CM).frame_slice(np.array([5, 5, 5]))
    positions = world_positions(motion)
    data = CheckData(motion, positions, motion.size)
    np.testing.assert_array_equal(same_pose_runs(data, CheckSettings()), [[0, 2]])
    positions = positions.copy()
    positions[1, motion.names.index("Spine"), 0] += 1.0
    data = CheckData(motion, positions, motion.size)
    assert same_pose_runs(data, CheckSettings()).shape == (0, 2)


def test_rest_fractions_without_moving_joints_are_0_per_frame():
    motion = clean_walk(120.0, unit=CM).frame_slice(slice(0, 40))
    still = motion.replace(rotations=np.broadcast_to(np.eye(3), motion.rotations.shape).copy())
    np.testing.assert_array_equal(rest_fractions(still, CheckSettings()), np.zeros(40))


def test_duplicates_come_with_their_kind_only():
    motion = clean_walk(120.0, unit=CM)
    copied = motion.frame_slice(np.concatenate([np.arange(251), [250], np.arange(251, motion.n_frames)]))
    assert [f.kind for f in run_checks(copied, CheckSettings(kinds=("duplicate",)))] == ["duplicate"]
    assert run_checks(copied, CheckSettings(kinds=("frozen",))) == []


def test_rest_frames_at_the_end():
    motion = clean_walk(120.0, unit=CM)
    rotations = motion.rotations.copy()
    rotations[-10:] = np.eye(3)
    assert rest_frames(motion.replace(rotations=rotations), CheckSettings()) == (0, 10)
    (finding,) = run_checks(motion.replace(rotations=rotations), CheckSettings(kinds=("rest-pose",)))
    assert (finding.start, finding.end, finding.value) == (590, 599, 10.0)
