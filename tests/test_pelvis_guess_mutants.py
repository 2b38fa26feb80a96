"""Which three joints give the pelvis (core/markers/pelvis_guess.py): sides from names, the
pelvis joints, the candidates in order, a triangle's quality against values worked by hand, the
choice and its limits, its description, the motion's samples (the mutation run's blind spots,
docs/reliability.md)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from gmr_studio.core.markers import pelvis_guess as guess
from gmr_studio.core.markers.pelvis_guess import PelvisChoice, candidates, choose_pelvis, side, triangle_quality
from gmr_studio.core.model.motion import Motion, identity_rotations

NOTE, NAMED, ANY = (
    "the technical note's: root, left femur, lower back",
    "root and both hips, by their names",
    "a triple of pelvis joints that is not collinear",
)


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("LeftUpLeg", "left"), ("RightUpLeg", "right"), ("lfemur", "left"), ("rfemur", "right"),
        ("L_Thigh", "left"), ("thigh.R", "right"), ("LHipJoint", "left"), ("RHipJoint", "right"),
        ("LArm", "left"), ("RArm", "right"), ("LK", "left"), ("RK", "right"),
        ("Spine", None), ("HIPS", None), ("Lumbar", None), ("LowerBack", None), ("L", None), ("R", None),
    ],
)  # fmt: skip
def test_side_of_a_name(name, expected):
    assert side(name) == expected


def test_pelvis_joints_follow_bones_of_length_zero_only():
    # 0 root; 1 a zero-length bone at the root (its child 2 moves with the pelvis); 3 a real
    # bone (its child 4 does not); 5 a child of 2
    parents = [-1, 0, 1, 0, 3, 2]
    offsets = np.array([[0.0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1]])
    assert guess.pelvis_joints(parents, offsets, 0) == [1, 2, 3]


#: a rig: Hips with LeftUpLeg, RightUpLeg and Spine (each with a child)
NAMES = ("Hips", "LeftUpLeg", "LeftKnee", "RightUpLeg", "RightKnee", "Spine", "Neck")
PARENTS = [-1, 0, 1, 0, 3, 0, 5]
OFFSETS = np.array([[0.0, 0, 0], [9, -3, 0], [0, -40, 1], [-9, -3, 0], [0, -40, 1], [0, 10, -1], [0, 40, 0]])


def test_candidates_come_in_order_each_once():
    assert candidates(NAMES, PARENTS, OFFSETS) == [
        (("Hips", "LeftUpLeg", "Spine"), NOTE),
        (("Hips", "LeftUpLeg", "RightUpLeg"), NAMED),
        (("Hips", "RightUpLeg", "Spine"), ANY),
    ]
    assert candidates(("x", "HIPS", "leftupleg", "RightUpLeg")) == [(("HIPS", "leftupleg", "RightUpLeg"), NAMED)]


def test_the_root_is_a_joint_without_parent_even_under_a_busier_child():
    """Root -> Hips (a real bone) -> three children: the pelvis joints are the root's."""
    names = ("Root", "Hips", "LeftUpLeg", "RightUpLeg", "Spine", "Other")
    parents = [-1, 0, 1, 1, 1, 0]
    offsets = np.ones((6, 3))
    assert candidates(names, parents, offsets) == [
        (("Hips", "LeftUpLeg", "RightUpLeg"), NAMED),
        (("Root", "Hips", "Other"), ANY),
    ]
    # two roots: the one with more pelvis joints (a lone marker root has none)
    names, parents = ("Marker", *NAMES), [-1, *[p + 1 if p >= 0 else -1 for p in PARENTS]]
    assert candidates(names, parents, np.ones((8, 3)))[0] == (("Hips", "LeftUpLeg", "Spine"), NOTE)


def frames_of(*triangles):
    return np.array(triangles, dtype=np.float64)


def test_triangle_quality_against_values_worked_by_hand():
    # X1 at 0, X2 along x growing from 3 to 3.2 over 21 frames, X3 at (1, 4, 0): the angle at
    # X1 is about 76 degrees, its sine 4 / sqrt(17) whatever X2's length
    k = np.arange(21.0)
    points = np.zeros((21, 3, 3))
    points[:, 1, 0] = 3.0 + 0.01 * k
    points[:, 2] = [1.0, 4.0, 0.0]
    sine, change = triangle_quality(points)
    assert sine == pytest.approx(4 / np.sqrt(17), rel=1e-12)
    # sides |X1X2| = 3 + 0.01 k (spread from the 5th to the 95th percentile, frames 1 and 19:
    # 3.19 - 3.01), |X1X3| = sqrt(17) fixed, |X2X3| = sqrt((2 + 0.01 k)^2 + 16) (spread under
    # 0.08), the longest: the size is its median, frame 10's
    assert change == pytest.approx(0.18 / np.sqrt(2.1**2 + 16), rel=1e-9)
    # in metres: a small triangle (products of lengths below 1) has the same sine
    assert triangle_quality(points / 100)[0] == pytest.approx(4 / np.sqrt(17), rel=1e-12)


def test_triangle_quality_ignores_missing_frames_and_degenerate_ones_without_warnings():
    good = [[0.0, 0, 0], [1.0, 0, 0], [0.5, 0.5, 0]]  # longest side 1 exactly, sine of 45 degrees
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sine, change = triangle_quality(frames_of(good, good, [[np.nan] * 3] * 3))
        assert sine == pytest.approx(np.sqrt(0.5), rel=1e-12) and change == 0.0
        # X2 on X1 in two frames of three: their sine counts as 0, the median with them
        sine, _ = triangle_quality(frames_of(good, [[0.0, 0, 0], [0.0, 0, 0], [0.5, 0.5, 0]], [[0.0] * 3] * 3))
        assert sine == 0.0
        assert triangle_quality(np.full((2, 3, 3), np.nan)) == (0.0, np.inf)
        assert triangle_quality(np.zeros((3, 3, 3))) == (0.0, np.inf)  # all three on one point


def test_the_sine_may_round_above_one_in_the_description():
    choice = PelvisChoice(("a", "b", "c"), "how", 1.0 + 2.0**-52, 0.0099)
    assert choice.describe() == "pelvis triple a, b, c (how; angle at a 90 deg, shape kept to 0.99%)"
    half = dataclasses.replace(choice, sine=0.5, triple=("root", "lhip", "back"))
    assert half.describe() == "pelvis triple root, lhip, back (how; angle at root 30 deg, shape kept to 0.99%)"
    with pytest.raises(dataclasses.FrozenInstanceError):
        choice.sine = 0.0  # type: ignore[misc]


def rig_positions(n_frames, bend=0.0, seed=1):
    """(F, 7, 3) positions of NAMES: the rig turned at random, the spine leaning by ``bend``
    (a fraction of its offset) more each frame, so the note's triangle changes shape."""
    rng = np.random.default_rng(seed)
    rest = np.array([[0.0, 0, 0], [9, -3, 0], [9, -43, 1], [-9, -3, 0], [-9, -43, 1], [0, 10, -1], [0, 50, -1]])
    out = np.empty((n_frames, 7, 3))
    for f in range(n_frames):
        pose = rest.copy()
        pose[5:] += [bend * f * 10, 0, 0]
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        out[f] = pose @ (q * np.sign(np.linalg.det(q))).T + rng.normal(size=3) * 100
    return out


def test_choices_measured_on_the_markers_or_on_the_motion():
    rigid, leaning = rig_positions(20), rig_positions(20, bend=0.02)
    # on the markers: the note's triple keeps its shape (2% allowed)
    choice = choose_pelvis(NAMES, rigid, PARENTS, OFFSETS)
    assert choice.triple == ("Hips", "LeftUpLeg", "Spine") and choice.how == NOTE and choice.shape_change < 1e-12
    # the spine leaning 0.2 of its bone over 20 frames: the note's triangle changes too much
    choice = choose_pelvis(NAMES, leaning, PARENTS, OFFSETS)
    assert choice.triple == ("Hips", "LeftUpLeg", "RightUpLeg") and choice.how == NAMED
    # one marker frame: the motion's two frames decide, exactly (1e-6): the lean is seen there
    choice = choose_pelvis(NAMES, rigid[:1], PARENTS, OFFSETS, motion_positions=leaning[:2])
    assert choice.triple == ("Hips", "LeftUpLeg", "RightUpLeg") and choice.shape_change < 1e-12
    choice = choose_pelvis(NAMES, rigid[:1], PARENTS, OFFSETS, motion_positions=rigid[:2])
    assert choice.triple == ("Hips", "LeftUpLeg", "Spine") and choice.how == NOTE and choice.shape_change < 1e-12
    # a motion of one frame measures nothing: the markers decide
    choice = choose_pelvis(NAMES, leaning, PARENTS, OFFSETS, motion_positions=rigid[:1])
    assert choice.triple == ("Hips", "LeftUpLeg", "RightUpLeg")


def test_markers_within_two_percent_pass_and_a_motion_within_a_millionth():
    leaning = rig_positions(20, bend=0.0015)  # the note's triangle changes by about 1%
    _, change = triangle_quality(leaning[:, [0, 1, 5]])
    assert 0.005 < change < 0.02
    assert choose_pelvis(NAMES, leaning, PARENTS, OFFSETS).triple == ("Hips", "LeftUpLeg", "Spine")
    # measured on an exact motion the same lean is too much
    choice = choose_pelvis(NAMES, leaning[:1], PARENTS, OFFSETS, motion_positions=leaning)
    assert choice.triple == ("Hips", "LeftUpLeg", "RightUpLeg")


def test_when_no_triple_keeps_its_shape_the_least_changing_is_taken():
    names = ("Hips", "A", "B", "C")
    parents, offsets = [-1, 0, 0, 0], np.ones((4, 3))
    f = np.arange(20.0)[:, None]
    points = np.zeros((20, 4, 3))  # A, B, C along x, y, z from Hips, moving away
    points[:, 1] = [10.0, 0, 0] + f * [0.3, 0, 0]  # 0.3 a frame
    points[:, 2] = [0.0, 10, 0] + f * [0, 0.1, 0]  # 0.1
    points[:, 3] = [0.0, 0, 10] + f * [0, 0, 0.2]  # 0.2
    choice = choose_pelvis(names, points, parents, offsets)
    # a triangle changes as its fastest point: (A, B) and (A, C) by A's 0.3, (B, C) by C's 0.2
    assert choice.triple == ("Hips", "B", "C")
    assert choice.how == f"{ANY}; no triple keeps its shape, this one changes least"
    # the three moving alike (each triangle the others with axes swapped): the first is kept
    points[:, 1:] = np.eye(3) * (10 + 0.1 * f[:, :, None])
    assert choose_pelvis(names, points, parents, offsets).triple == ("Hips", "A", "B")


def test_a_triangle_with_the_smallest_sine_accepted():
    names, parents, offsets = ("Hips", "A", "B"), [-1, 0, 0], np.ones((3, 3))
    x = 1.0
    while True:  # X3 = (x, 0.05, 0): the sine at X1 is 0.05 to rounding; find it exactly
        sine = triangle_quality(np.array([[[0.0, 0, 0], [1.0, 0, 0], [x, 0.05 * x / np.sqrt(1 - 0.0025), 0]]]))[0]
        if sine == guess.MIN_SINE:
            break
        x = np.nextafter(x, 2.0 if sine > guess.MIN_SINE else 0.0)
    points = np.array([[[0.0, 0, 0], [1.0, 0, 0], [x, 0.05 * x / np.sqrt(1 - 0.0025), 0]]])
    assert choose_pelvis(names, points, parents, offsets).triple == ("Hips", "A", "B")
    points[0, 2, 1] *= 0.99
    assert choose_pelvis(names, points, parents, offsets) is None


def flat_motion(n_frames: int) -> Motion:
    return Motion(
        names=["root", "child"],
        parents=[-1, 0],
        offsets=np.array([[0.0, 0, 0], [1.0, 0, 0]]),
        rotation_orders=["XYZ", "XYZ"],
        has_translation=np.array([True, False]),
        rotations=identity_rotations(n_frames, 2),
        translations=np.stack(
            [np.arange(n_frames)[:, None] * [1.0, 0, 0], np.broadcast_to([1.0, 0, 0], (n_frames, 3))], 1
        ),
        frame_time=1 / 30,
    )


@pytest.mark.parametrize(("n_frames", "samples"), [(3, 3), (1999, 1999), (2000, 1000), (4001, 1334)])
def test_the_motion_is_sampled_to_at_most_2000_frames_evenly(n_frames, samples):
    positions = guess.sampled_positions(flat_motion(n_frames))
    assert positions.shape == (samples, 2, 3)
    step = -(-n_frames // samples)
    np.testing.assert_array_equal(positions[:, 0, 0], np.arange(0, n_frames, step, dtype=float))


def test_a_triangle_changing_by_exactly_the_limit_keeps_its_shape():
    """X2 moving away from X1 along y, X3 fixed on x: base and step found so that the change,
    computed, is MAX_SHAPE_CHANGE to the bit (a search over bases, kept here)."""
    names, parents, offsets = ("Hips", "A", "B"), [-1, 0, 0], np.ones((3, 3))
    points = np.zeros((21, 3, 3))
    points[:, 1, 1] = 6.069 + 0.01307323536979031 * np.arange(21.0)
    points[:, 2] = [10.0, 0.0, 0.0]
    assert triangle_quality(points)[1] == guess.MAX_SHAPE_CHANGE == 0.02
    choice = choose_pelvis(names, points, parents, offsets)
    assert choice.triple == ("Hips", "A", "B") and choice.how == ANY and choice.shape_change == 0.02
