"""Flips and bone lengths (core.checks.joints): angles of known turns, a turn that stays, flips
that do not come back, bones stretched twice in a short while or by little."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings, run_checks
from gmr_studio.core.checks.joints import rotation_steps
from gmr_studio.core.rotations.euler import rotation_about_axis
from tests.checks_walk import clean_walk
from tests.test_checks import CM

FLIPS = CheckSettings(kinds=("flip",))


def test_rotation_steps_are_the_angles_between_frames():
    """Four joints, from the identity to turns of 0, 30, 120 and 180 degrees."""
    turns = rotation_about_axis("Y", np.radians([0.0, 30.0, 120.0, 180.0]))  # (4, 3, 3)
    steps = rotation_steps(np.stack([np.broadcast_to(np.eye(3), turns.shape), turns]))
    np.testing.assert_allclose(steps, [[0.0, 30.0, 120.0, 180.0]], atol=1e-6)


def test_a_half_turn_rounded_past_minus_one_is_180_degrees():
    """A trace a rounding below -1 (not a rotation to the last bit): 180 degrees, not NaN."""
    turned = np.diag([1.0 + 1e-15, -1.0 - 1e-15, -1.0 - 1e-15])
    steps = rotation_steps(np.stack([np.eye(3), turned])[:, None])
    assert steps[0, 0] == 180.0


def _turned(motion, joint: str, frames, degrees: float, axis: str = "Y"):
    j = motion.names.index(joint)
    rotations = motion.rotations.copy()
    rotations[frames, j] = rotations[frames, j] @ rotation_about_axis(axis, np.array(np.radians(degrees)))
    return motion.replace(rotations=rotations)


def test_a_turn_that_stays_is_one_flip_of_its_two_frames():
    motion = _turned(clean_walk(120.0, unit=CM), "RightForeArm", slice(300, None), 180.0)
    (finding,) = run_checks(motion, FLIPS)
    assert (finding.start, finding.end, finding.names) == (299, 300, ("RightForeArm",))
    assert finding.value == pytest.approx(180.0, abs=1.0)


def test_two_turns_far_apart_are_two_flips():
    """Turned 100 degrees from frame 300 and 100 more from frame 400 (more than 0.5 s later)."""
    motion = _turned(clean_walk(120.0, unit=CM), "RightForeArm", slice(300, None), 100.0)
    motion = _turned(motion, "RightForeArm", slice(400, None), 100.0)
    assert [(f.start, f.end) for f in run_checks(motion, FLIPS)] == [(299, 300), (399, 400)]


def test_a_second_turn_that_does_not_come_back_is_no_return():
    """Turned 100 degrees at frame 300 and 60 degrees back at 310: 40 degrees from where it
    was, within the limit (45): one flip of frames 300-309. Turned 100 then 150 back: 50
    from where it was: two flips of their own."""
    walk = clean_walk(120.0, unit=CM)
    back = _turned(_turned(walk, "RightForeArm", slice(300, None), 100.0), "RightForeArm", slice(310, None), -60.0)
    assert [(f.start, f.end) for f in run_checks(back, FLIPS)] == [(300, 309)]
    apart = _turned(_turned(walk, "RightForeArm", slice(300, None), 100.0), "RightForeArm", slice(310, None), -150.0)
    assert [(f.start, f.end) for f in run_checks(apart, FLIPS)] == [(299, 300), (309, 310)]


def test_a_return_beyond_90_degrees_with_a_limit_of_100():
    """Limits from 100 degrees: turned 150 about Y at frame 300 and 120 about X at 310 (both
    steps flips): frame 310 is 165 degrees from frame 299, beyond the limit: two flips."""
    settings = CheckSettings(kinds=("flip",), flip_limits=(100.0, 120.0, 170.0))
    walk = clean_walk(120.0, unit=CM)
    away = _turned(_turned(walk, "RightForeArm", slice(300, None), 150.0), "RightForeArm", slice(310, None), 120.0, "X")
    assert [(f.start, f.end) for f in run_checks(away, settings)] == [(299, 300), (309, 310)]


def test_a_flip_of_one_frame_then_a_turn_that_stays():
    """Turned 180 degrees at frame 300 only, then again from 302 on: the one-frame flip
    (300), then a flip of 301 -> 302."""
    motion = _turned(clean_walk(120.0, unit=CM), "RightForeArm", [300], 180.0)
    motion = _turned(motion, "RightForeArm", slice(302, None), 180.0)
    assert [(f.start, f.end) for f in run_checks(motion, FLIPS)] == [(300, 300), (301, 302)]


def _stretched(motion, joint: str, runs, factor: float):
    j = motion.names.index(joint)
    translations = motion.translations.copy()
    for a, b in runs:
        translations[a : b + 1, j] *= factor
    flags = motion.has_translation.copy()
    flags[j] = True
    return motion.replace(translations=translations, has_translation=flags)


def test_a_bone_stretched_twice_within_0_1_s_is_one_finding():
    """Frames 150-160 and 166-180 (5 frames apart, under the 12 of 0.1 s): one finding."""
    motion = _stretched(clean_walk(120.0, unit=CM), "LeftForeArm", [(150, 160), (166, 180)], 1.03)
    (finding,) = run_checks(motion, CheckSettings(kinds=("bone-length",)))
    assert (finding.start, finding.end) == (150, 180)


def test_a_bone_stretched_by_1_5_percent_is_an_info():
    motion = _stretched(clean_walk(120.0, unit=CM), "LeftForeArm", [(150, 200)], 1.015)
    (finding,) = run_checks(motion, CheckSettings(kinds=("bone-length",)))
    assert (finding.start, finding.end, finding.severity) == (150, 200, "info")
    assert finding.value == pytest.approx(1.5, rel=0.05)


def test_a_split_roots_soft_link_stretched():
    """The Spine split from the Hips (a root linked to joint 0), moved 3% of its link away
    from them over frames 150-200: a bone-length finding of the link, 3%."""
    from gmr_studio.core.edits.operations import split
    from gmr_studio.core.kinematics.convention import pre_from_post
    from gmr_studio.core.kinematics.fk import world_positions

    motion = split(pre_from_post(clean_walk(120.0, unit=CM)), "Spine")
    s = motion.names.index("Spine")
    assert (motion.parents[s], motion.soft_parents[s]) == (-1, 0)
    positions = world_positions(motion)
    link = positions[:, s] - positions[:, 0]
    translations = motion.translations.copy()
    translations[150:201, s] += 0.03 * link[150:201]
    (finding,) = run_checks(motion.replace(translations=translations), CheckSettings(kinds=("bone-length",)))
    assert (finding.start, finding.end, finding.names) == (150, 200, ("Spine",))
    assert finding.value == pytest.approx(3.0, rel=1e-6)


def test_a_bone_in_a_take_of_two_frames():
    """Two frames, the forearm 6% longer at the second: each 2.9% from their median."""
    motion = _stretched(clean_walk(120.0, unit=CM).frame_slice(slice(0, 2)), "LeftForeArm", [(1, 1)], 1.06)
    (finding,) = run_checks(motion, CheckSettings(kinds=("bone-length",)))
    assert (finding.start, finding.end, finding.value) == (0, 1, pytest.approx(300 / 103, rel=1e-9))


def test_a_bone_too_short_to_compare():
    """A hand end with translation channels 1e-4 cm from the hand (under 1e-6 of the 173 cm
    size), its length varying by half: no length to compare, no finding."""
    motion = clean_walk(120.0, unit=CM)
    j = motion.names.index("LeftHandEnd")
    translations = motion.translations.copy()
    translations[:, j] = [0.0, 1e-4, 0.0]
    translations[::2, j] *= 1.5
    flags = motion.has_translation.copy()
    flags[j] = True
    tiny = motion.replace(translations=translations, has_translation=flags)
    assert run_checks(tiny, CheckSettings(kinds=("bone-length",))) == []


def test_a_child_of_the_root_stretched():
    motion = _stretched(clean_walk(120.0, unit=CM), "Spine", [(150, 200)], 1.03)
    (finding,) = run_checks(motion, CheckSettings(kinds=("bone-length",)))
    assert (finding.start, finding.end, finding.names) == (150, 200, ("Spine",))
    assert finding.value == pytest.approx(3.0, rel=1e-9)


@pytest.mark.parametrize(("second", "expected"), [((7, 8), [(4, 8)]), ((8, 9), [(4, 5), (8, 9)])])
def test_bone_runs_joined_across_one_frame_at_4_hz(second, expected):
    """At 4 Hz 0.1 s is under a frame: runs one frame apart join, two frames apart do not."""
    motion = _stretched(clean_walk(4.0, unit=CM), "LeftForeArm", [(4, 5), second], 1.03)
    findings = run_checks(motion, CheckSettings(kinds=("bone-length",)))
    assert [(f.start, f.end) for f in findings] == expected


def test_rotations_a_rounding_off_are_0_degrees_not_nan():
    """A product whose trace rounds above 3 (the identity to the last bit or past it): a
    step of 0 degrees; a held rotation flipped for one frame pairs with its return though
    its trace with itself rounds past 3."""
    steps = rotation_steps(np.stack([np.eye(3), np.diag([1.0 + 1e-15] * 3)])[:, None])
    assert steps[0, 0] == 0.0
    held = rotation_about_axis("X", np.array(0.1)) @ rotation_about_axis("X", np.array(0.7))
    assert np.sum(held * held) > 3.0  # 3.0000000000000004
    motion = clean_walk(120.0, unit=CM)
    rotations = motion.rotations.copy()
    rotations[:, motion.names.index("Head")] = held
    motion = _turned(motion.replace(rotations=rotations), "Head", [300], 180.0)
    assert [(f.start, f.end, f.names) for f in run_checks(motion, FLIPS)] == [(300, 300, ("Head",))]


def test_a_flip_in_a_take_of_two_frames():
    motion = _turned(clean_walk(120.0, unit=CM).frame_slice(slice(0, 2)), "RightForeArm", [1], 180.0)
    (finding,) = run_checks(motion, FLIPS)
    assert (finding.start, finding.end) == (0, 1)


def test_a_flip_back_after_exactly_0_5_s_is_one_flip():
    """At 120 Hz: turned at frame 300 and back at 360 (steps 299 and 359, 60 frames apart,
    0.5 s): one flip of frames 300-359; back at 361 it is two."""
    walk = clean_walk(120.0, unit=CM)
    assert [(f.start, f.end) for f in run_checks(_turned(walk, "RightForeArm", slice(300, 360), 180.0), FLIPS)] == [
        (300, 359)
    ]
    assert [(f.start, f.end) for f in run_checks(_turned(walk, "RightForeArm", slice(300, 361), 180.0), FLIPS)] == [
        (299, 300),
        (360, 361),
    ]
