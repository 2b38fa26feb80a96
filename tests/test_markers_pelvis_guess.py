"""Which three joints give the pelvis (core/markers/pelvis_guess.py): on BVH rigs whose hips sit
level with the root, the technical note's root, left femur and lower back, else any
non-collinear triple of pelvis joints, and which one was used is said; sides from names, the
candidates in order, a triangle's quality against values worked by hand, the choice and its
limits, the motion's samples."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.markers import markers_to_motion
from gmr_studio.core.markers import pelvis_guess as guess
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.pelvis_guess import PelvisChoice, candidates, choose_pelvis, side, triangle_quality
from gmr_studio.core.markers.trc import write_trc
from gmr_studio.core.model.motion import Motion, identity_rotations
from tests.conftest import shared_path
from tests.test_markers_solve import assert_exact, joint_markers

#: a game-style rig: both hips level with the root (root and hips collinear), a spine above
RIG = """HIERARCHY
ROOT {root}
{{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT {left}
  {{
    OFFSET 9 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT {left}Knee
    {{
      OFFSET 0 -40 1
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {{
        OFFSET 0 -40 0
      }}
    }}
  }}
  JOINT {right}
  {{
    OFFSET -9 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT {right}Knee
    {{
      OFFSET 0 -40 1
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {{
        OFFSET 0 -40 0
      }}
    }}
  }}
  JOINT {back}
  {{
    OFFSET 0 10 -1
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Neck
    {{
      OFFSET 0 40 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {{
        OFFSET 0 10 0
      }}
    }}
  }}
}}
MOTION
Frames: {n}
Frame Time: 0.0333333
{rows}
"""


def write_rig(path, root="Hips", left="LeftUpLeg", right="RightUpLeg", back="Spine", n=40):
    rng = np.random.default_rng(7)
    values = rng.uniform(-60, 60, (n, 6 + 3 * 6))
    values[:, :3] = rng.normal(size=(n, 3)) * 20
    rows = "\n".join(" ".join(f"{v:.6f}" for v in row) for row in values)
    path.write_text(RIG.format(root=root, left=left, right=right, back=back, n=n, rows=rows))
    return load_gmr(path)


@pytest.mark.parametrize(
    ("names", "expected", "how"),
    [
        ({}, ("Hips", "LeftUpLeg", "Spine"), "technical note"),
        (
            {"root": "pelvis", "left": "l_hip", "right": "r_hip", "back": "belly"},
            ("pelvis", "l_hip", "belly"),
            "not collinear",
        ),
    ],
)
def test_rigs_with_level_hips_convert_and_say_which_triple(tmp_path, names, expected, how):
    truth = write_rig(tmp_path / "rig.bvh", **names)
    markers = joint_markers(truth)
    result = markers_to_motion(markers, truth, "joints", reference=truth)
    assert_exact(result.motion, truth)
    assert result.pelvis.labels == expected
    assert f"pelvis triple {', '.join(expected)} (" in result.pelvis_note and how in result.pelvis_note
    free = markers_to_motion(markers, truth, "joints")  # without a reference, positions are still exact
    assert_exact(free.motion, truth, angles=False)


def test_gmr_markers_prints_the_triple(tmp_path, capsys):
    truth = write_rig(tmp_path / "rig.bvh")
    write_trc(joint_markers(truth).replace(source="rig.trc"), tmp_path / "rig.trc", digits=17)
    code = main(["markers", str(tmp_path / "rig.trc"), "--skeleton", str(tmp_path / "rig.bvh"), "--map", "joints",
                 "-o", str(tmp_path / "out.gmr")])  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0 and "pelvis: pelvis triple Hips, LeftUpLeg, Spine (the technical note's" in out


def test_cmu_skeletons_keep_rigid_triples():
    """CMU ASF: the note's lower back turns with the spine (its triangle with root and left hip
    changes by 5%), so root and both hips are used; CMU BVH: LowerBack sits on Hips (a dummy)
    and Spine turns with it, so again the hips."""
    amc = load_gmr(shared_path("cmu/subject01/01_01.amc"), asf=shared_path("cmu/subject01/01.asf")).frame_slice(
        slice(0, 600)
    )
    bvh = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 600))
    for motion, expected in ((amc, ("root", "lhipjoint", "rhipjoint")), (bvh, ("Hips", "LeftUpLeg", "RightUpLeg"))):
        markers = joint_markers(motion)
        choice = choose_pelvis(motion.names, markers.positions, motion.parents, motion.offsets)
        assert choice.triple == expected, choice
    assert [side(n) for n in ("LeftUpLeg", "lfemur", "L_Thigh", "thigh.L", "LHipJoint", "RightArm", "Spine")] == [
        "left", "left", "left", "left", "left", "right", None,
    ]  # fmt: skip


def test_collinear_everywhere_is_refused_with_the_reason(tmp_path):
    positions = np.zeros((3, 3, 3))
    positions[:, 1, 0], positions[:, 2, 0] = 1.0, -1.0  # three points on a line
    markers = MarkerSet(labels=["Hips", "LeftUpLeg", "RightUpLeg"], positions=positions, rate=30, units="cm")
    assert choose_pelvis(markers.labels, markers.positions) is None


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


@pytest.mark.parametrize("n_frames", [3, 4001])
def test_the_motion_is_sampled_evenly_from_its_first_frame_to_its_end(n_frames):
    """A short take is measured at every frame, a long one at evenly spaced frames from the
    first, at most MOTION_SAMPLES of them (the root moves one unit a frame: x is the frame)."""
    frames = guess.sampled_positions(flat_motion(n_frames))[:, 0, 0]
    step = frames[1] - frames[0]
    assert frames[0] == 0.0 and len(frames) <= guess.MOTION_SAMPLES
    np.testing.assert_array_equal(np.diff(frames), step)
    assert frames[-1] + step >= n_frames
    assert n_frames > 3 or step == 1.0


def test_a_triangle_changing_by_exactly_the_limit_keeps_its_shape():
    """X2 moving away from X1 along y, X3 fixed on x: base and step found so that the change,
    computed, is MAX_SHAPE_CHANGE to the bit (a search over bases, kept here)."""
    names, parents, offsets = ("Hips", "A", "B"), [-1, 0, 0], np.ones((3, 3))
    points = np.zeros((21, 3, 3))
    points[:, 1, 1] = 6.069 + 0.01307323536979031 * np.arange(21.0)
    points[:, 2] = [10.0, 0.0, 0.0]
    assert triangle_quality(points)[1] == guess.MAX_SHAPE_CHANGE
    choice = choose_pelvis(names, points, parents, offsets)
    assert choice.triple == ("Hips", "A", "B") and choice.how == ANY and choice.shape_change == guess.MAX_SHAPE_CHANGE
