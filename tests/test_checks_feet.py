"""Foot skating (core.checks.feet): a slide forward, a foot creeping below the skate speed, a take
that starts with the foot in the air."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings, run_checks
from gmr_studio.core.rotations.euler import rotation_about_axis
from tests.checks_walk import clean_walk
from tests.test_checks import CM, with_translation

SKATE = CheckSettings(kinds=("foot-skate",))


def _slide(a: int, b: int, axis: int, distance: float):
    def slide(f):
        shift = np.zeros((f.size, 3))
        shift[:, axis] = distance * np.clip((f - a) / (b - a), 0.0, 1.0)
        return shift

    return slide


def test_a_foot_slid_forward():
    """2 cm along the walk (Z, the second horizontal axis of a Y-up take)."""
    motion = with_translation(clean_walk(120.0, unit=CM), "RightFoot", _slide(100, 120, 2, 2.0))
    (finding,) = run_checks(motion, SKATE)
    assert (finding.start, finding.end, finding.names[0]) == (100, 120, "RightFoot")
    assert finding.value == pytest.approx(2.0, rel=0.1)


def test_a_foot_creeping_below_the_skate_speed_does_not_slide():
    """3 cm/s, below the skate speed of 2% of the 173 cm size a second (3.46 cm/s), over
    the whole take: about 2 cm over each 0.66 s stance, and no finding."""
    motion = clean_walk(120.0, unit=CM)
    creep = 3.0 / 120.0  # cm a frame

    def drift(f):
        shift = np.zeros((f.size, 3))
        shift[:, 0] = creep * f
        return shift

    assert run_checks(with_translation(motion, "RightFoot", drift), SKATE) == []


def test_a_take_starting_with_the_foot_in_the_air():
    """From frame 30 of the walk the right foot swings at the first frame; slid 2 cm over
    its next stance (frames 70-90 of the take) it is found there."""
    motion = clean_walk(120.0, unit=CM).frame_slice(slice(30, None))
    motion = with_translation(motion, "RightFoot", _slide(70, 90, 0, 2.0))
    (finding,) = run_checks(motion, SKATE)
    assert (finding.start, finding.end, finding.names[0]) == (70, 90, "RightFoot")
    assert finding.value == pytest.approx(2.0, rel=0.1)


def test_a_slide_a_little_above_the_ground_is_a_slide():
    """Slid 2 cm while raised 1 cm (under the skate height, 1.5% of 173 cm = 2.6 cm)."""

    def slide(f):
        shift = _slide(100, 120, 0, 2.0)(f)
        shift[(f >= 100) & (f <= 120), 1] = 1.0
        return shift

    (finding,) = run_checks(with_translation(clean_walk(120.0, unit=CM), "RightFoot", slide), SKATE)
    assert (finding.start, finding.end, finding.names[0]) == (100, 120, "RightFoot")


def test_a_slide_to_the_last_frame_ends_there():
    motion = clean_walk(120.0, unit=CM).frame_slice(slice(0, 121))
    (finding,) = run_checks(with_translation(motion, "RightFoot", _slide(100, 120, 0, 2.0)), SKATE)
    assert (finding.start, finding.end) == (100, 120)


def test_a_take_as_short_as_the_window():
    """12 frames at 120 Hz, the right foot planted and slid 2 cm over them all: the window
    shrinks to the 11 steps of the take and finds it."""
    motion = clean_walk(120.0, unit=CM).frame_slice(slice(100, 112))
    (finding,) = run_checks(with_translation(motion, "RightFoot", _slide(0, 11, 0, 2.0)), SKATE)
    assert (finding.start, finding.end) == (0, 11)
    assert finding.value == pytest.approx(2.0, rel=0.1)


@pytest.mark.parametrize(("rate", "a"), [(4.0, 3), (10.0, 7)])
def test_slow_rates_take_a_window_of_one_frame(rate, a):
    """0.1 s is under a frame at 4 Hz and one frame at 10 Hz: windows of one step. A slide
    of 2 cm at one step of a stance of the right foot (planted at frames 3-4 at 4 Hz, 6-11
    at 10 Hz) is found at that step."""
    motion = clean_walk(rate, unit=CM)
    (finding,) = run_checks(with_translation(motion, "RightFoot", _slide(a, a + 1, 0, 2.0)), SKATE)
    assert (finding.start, finding.end) == (a, a + 1)


def test_depths_of_a_motion_without_feet_are_empty():
    from gmr_studio.core.checks.context import CheckData
    from gmr_studio.core.checks.feet import depths
    from gmr_studio.core.kinematics.fk import world_positions
    from gmr_studio.core.rigs import make_rig

    motion = make_rig("one_joint")
    joints, depth = depths(CheckData(motion, world_positions(motion), motion.size), CheckSettings())
    assert (joints.shape, depth.shape) == ((0,), (motion.n_frames, 0))


def test_a_foot_4_cm_below_its_contacts_is_an_info():
    """4 cm is 2.3% of the 173 cm walk: past the first limit (2%) only."""

    def sink(f):
        shift = np.zeros((f.size, 3))
        shift[(f >= 95) & (f <= 110), 1] = -4.0
        return shift

    motion = with_translation(clean_walk(120.0, unit=CM), "RightFoot", sink)
    findings = run_checks(motion, CheckSettings(kinds=("penetration",)))
    assert [f.severity for f in findings] == ["info", "info"]


def test_a_foot_slipping_in_jerks_slides():
    """0.2 cm at every third step from 99 -> 100 to 132 -> 133 (2.4 cm; the steps between
    still): each 0.1 s window moves 0.8 cm, past the skate speed: one slide, 99 to 133."""

    def jerks(f):
        shift = np.zeros((f.size, 3))
        shift[:, 0] = 0.2 * np.clip((f - 100) // 3 + 1, 0, 12)
        return shift

    (finding,) = run_checks(with_translation(clean_walk(120.0, unit=CM), "RightFoot", jerks), SKATE)
    assert (finding.start, finding.end) == (99, 133)
    assert finding.value == pytest.approx(2.4, rel=1e-6)


def test_a_take_of_two_frames():
    """Frames 3 and 4 of the walk at 4 Hz (the right foot planted at both), slid 2 cm
    between them: a slide of 2 cm at 2 cm a frame (8 cm/s, planted by the contacts' speed)."""
    motion = clean_walk(4.0, unit=CM).frame_slice(slice(3, 5))
    (finding,) = run_checks(with_translation(motion, "RightFoot", _slide(0, 1, 0, 2.0)), SKATE)
    assert (finding.start, finding.end, finding.value) == (0, 1, pytest.approx(2.0, rel=1e-9))


def test_a_toe_a_little_above_the_toe_end_still_touches():
    """The right toe turned 8 degrees down: its end lower than the toe by a few millimetres,
    under the skate height (2.6 cm): both touch, and a foot sunk 4 cm shows on both."""
    motion = clean_walk(120.0, unit=CM)
    j = motion.names.index("RightToe")
    rotations = motion.rotations.copy()
    rotations[:, j] = rotations[:, j] @ rotation_about_axis("X", np.array(np.radians(8.0)))

    def sink(f):
        shift = np.zeros((f.size, 3))
        shift[(f >= 95) & (f <= 110), 1] = -4.0
        return shift

    tilted = with_translation(motion.replace(rotations=rotations), "RightFoot", sink)
    findings = run_checks(tilted, CheckSettings(kinds=("penetration",)))
    assert [(f.start, f.end, f.names) for f in findings] == [(95, 110, ("RightToe",)), (95, 110, ("RightToeEnd",))]


@pytest.mark.parametrize(
    ("lift", "first"), [((117, 119), (95, 115, 2.0)), ((116, 118), (95, 114, pytest.approx(1.9, rel=1e-6)))]
)
def test_a_foot_lifted_between_two_slides(lift, first):
    """Slid 2 cm over frames 95-115 and 2 cm more over 121-136, lifted 10 cm in between
    (less than the 0.1 s window: the slides' steps make one run, cut where the foot is off
    the ground): two findings. Lifted from frame 116, the step 115 -> 116 has no end on the
    ground at 116 and frame 115 is no longer planted (the contacts' speed): the first ends at 114."""

    def move(f):
        shift = np.zeros((f.size, 3))
        shift[:, 0] = 2.0 * np.clip((f - 95) / 20, 0, 1) + 2.0 * np.clip((f - 121) / 15, 0, 1)
        shift[(f >= lift[0]) & (f <= lift[1]), 1] = 10.0
        return shift

    findings = run_checks(with_translation(clean_walk(120.0, unit=CM), "RightFoot", move), SKATE)
    assert [(f.start, f.end, f.value) for f in findings] == [first, (121, 136, pytest.approx(2.0, rel=1e-6))]
