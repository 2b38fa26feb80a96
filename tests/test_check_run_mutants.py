"""Running the checks (core.checks.run) on the conditions the checks' tests left open
(mutation testing, docs/reliability.md): what each check reads with rest frames at both ends,
positions given by the caller, the findings' order, and which pops a flip explains."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.checks import CheckSettings, Finding, run_checks
from gmr_studio.core.checks.run import _without_flipped_pops, check_data
from gmr_studio.core.kinematics.fk import world_positions
from tests.checks_walk import clean_walk
from tests.test_checks import with_translation


def _walk_at_rest_at_both_ends():
    """The clean walk (30 Hz, metres, 30 frames) in the rest pose at frames 0-2 and 28-29."""
    motion = clean_walk(30.0, seconds=1.0)
    rotations = motion.rotations.copy()
    rotations[:3] = np.eye(3)
    rotations[-2:] = np.eye(3)
    return motion.replace(rotations=rotations)


def test_the_rest_frames_are_left_out_of_every_check_but_the_rest_pose():
    motion = _walk_at_rest_at_both_ends()
    positions = world_positions(motion)
    whole, inner = check_data(motion, CheckSettings(), positions)
    assert whole.positions is positions and (whole.n_frames, whole.first) == (30, 0)
    assert (inner.n_frames, inner.first, inner.motion.n_frames) == (25, 3, 25)
    np.testing.assert_array_equal(inner.positions, positions[3:28])
    np.testing.assert_array_equal(inner.motion.rotations, motion.rotations[3:28])
    assert inner.size == whole.size == motion.size
    found = [(f.kind, f.start, f.end, f.value) for f in run_checks(motion)]
    assert found == [("rest-pose", 0, 2, 3.0), ("rest-pose", 28, 29, 2.0)]  # the jumps into the rest pose not checked


def test_the_positions_given_are_the_ones_checked():
    motion = clean_walk(30.0, seconds=1.0)
    positions = world_positions(motion).copy()
    hand = motion.names.index("LeftHand")
    positions[12, hand, 1] += 0.05  # the caller's positions: a pop the motion has not
    settings = CheckSettings(kinds=("pop",))
    assert run_checks(motion, settings) == []
    (pop,) = run_checks(motion, settings, positions=positions)
    assert (pop.kind, pop.start, pop.names) == ("pop", 12, ("LeftHand",))
    whole, _inner = check_data(motion, settings)
    np.testing.assert_array_equal(whole.positions, world_positions(motion))


def test_findings_sorted_by_frame_then_in_the_kinds_order():
    """Two knocks of the hand (frames 20 and 12): each a pop and a stretched bone, listed by
    frame and, at one frame, pop before bone-length (the checks' order, not the alphabet's)."""
    motion = clean_walk(30.0, seconds=1.0)

    def knock(frames):
        shift = np.zeros((frames.size, 3))
        shift[frames == 20] = [0.05, 0.0, 0.0]
        shift[frames == 12] = [0.0, 0.05, 0.0]
        return shift

    found = run_checks(with_translation(motion, "LeftHand", knock))
    assert [(f.kind, f.start) for f in found] == [("pop", 12), ("bone-length", 12), ("pop", 20), ("bone-length", 20)]


def _finding(motion, kind: str, names: tuple[str, ...], start: int, end: int | None = None) -> Finding:
    joints = tuple(motion.names.index(n) for n in names)
    return Finding(kind, joints, names, start, start if end is None else end, "warning", 1.0, "m")


def test_the_pops_a_flip_explains_are_dropped():
    """A flip of LeftArm at frames 4-5 explains the pops of its subtree (arm, forearm, hand,
    hand end) at 4 and 5, not before or after, not of a joint outside it, not other kinds."""
    motion = clean_walk(30.0, seconds=0.2)
    subtree = ("LeftArm", "LeftForeArm", "LeftHand", "LeftHandEnd")
    flip = _finding(motion, "flip", ("LeftArm",), 4, 5)
    kept = [
        _finding(motion, "pop", ("LeftHand",), 3),
        flip,
        _finding(motion, "pop", ("LeftHand", "RightHand"), 4),
        _finding(motion, "bone-length", ("LeftHand",), 4),
        _finding(motion, "pop", ("LeftHand",), 6),
        _finding(motion, "pop", ("RightHand",), 5),
    ]
    dropped = [
        _finding(motion, "pop", ("LeftHand",), 4),
        _finding(motion, "pop", subtree, 5),
        _finding(motion, "pop", ("LeftForeArm", "LeftHand"), 5),
    ]
    found = [kept[0], kept[1], dropped[0], kept[2], kept[3], dropped[1], kept[4], dropped[2], kept[5]]
    assert _without_flipped_pops(found, motion) == kept


def test_the_flips_of_several_joints_explain_pops_of_all_their_subtrees():
    motion = clean_walk(30.0, seconds=0.2)
    flip = _finding(motion, "flip", ("LeftArm", "RightForeArm"), 2)
    both = _finding(motion, "pop", ("LeftHand", "RightHand"), 2)
    shoulder = _finding(motion, "pop", ("RightArm",), 2)  # above the flipped forearm
    assert _without_flipped_pops([flip, both, shoulder], motion) == [flip, shoulder]
    pops = [both, shoulder]
    assert _without_flipped_pops(pops, motion) == pops  # no flip: every pop kept
