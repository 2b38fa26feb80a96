"""Quality checks (core.checks): each planted defect found at its frames and joint with its
size within 10%; nothing found on the clean synthetic walk at 24 to 240 Hz in m, cm, in. Running
them: the rest frames left out of every check but the rest pose's, the positions given by the
caller, the findings' order, and the pops a flip explains dropped."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.checks import KINDS, CheckSettings, Skipped, joint_flags, run_checks, skipped_frames
from gmr_studio.core.checks.run import check_data
from gmr_studio.core.kinematics.fk import world_positions, world_rotations
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rigs import RIGS, make_rig
from gmr_studio.core.rotations.euler import rotation_about_axis
from tests.checks_walk import clean_walk, reference_frame_crouch

CM = 0.01
INCH = 0.0254
#: (rate, unit): the defects are planted at 120 Hz frame numbers scaled to the rate
SETUPS = [(120.0, CM), (30.0, 1.0), (240.0, INCH)]


def frames(frame: int, rate: float) -> int:
    return round(frame * rate / 120.0)


def cm(value: float, unit: float) -> float:
    """A length given in centimetres, in the motion's unit."""
    return value * 0.01 / unit


def with_translation(motion: Motion, joint: str, change) -> Motion:
    """The motion with ``joint`` given translation channels and its world position moved by
    ``change(frames) -> (F, 3)`` world displacements (post convention: P_j = P_p + W_p t_j)."""
    j = motion.names.index(joint)
    parent = motion.parents[j]
    world = world_rotations(motion)[:, parent]  # (F, 3, 3)
    shift = change(np.arange(motion.n_frames))
    translations = motion.translations.copy()
    translations[:, j] += np.einsum("fba,fb->fa", world, shift)  # W_p^T shift
    flags = motion.has_translation.copy()
    flags[j] = True
    return motion.replace(translations=translations, has_translation=flags)


def only(findings, kind):
    found = [f for f in findings if f.kind == kind]
    assert found, f"no {kind} finding among {[(f.kind, f.start, f.end) for f in findings]}"
    return found


@pytest.mark.parametrize(("rate", "unit"), [*SETUPS, (24.0, CM), (60.0, INCH), (240.0, 1.0)])
def test_nothing_on_the_clean_walk(rate, unit):
    motion = clean_walk(rate, unit=unit)
    assert run_checks(motion) == []


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_foot_slid_2_cm_over_frames_100_to_120(rate, unit):
    a, b = frames(100, rate), frames(120, rate)

    def slide(f):
        shift = np.zeros((f.size, 3))
        shift[:, 0] = cm(2.0, unit) * np.clip((f - a) / (b - a), 0.0, 1.0)
        return shift

    motion = with_translation(clean_walk(rate, unit=unit), "RightFoot", slide)
    (finding,) = only(run_checks(motion), "foot-skate")
    assert (finding.start, finding.end) == (a, b)
    assert finding.names[0] == "RightFoot"
    assert finding.value == pytest.approx(cm(2.0, unit), rel=0.1)


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_one_frame_pop_of_5_cm_on_one_joint(rate, unit):
    at = frames(200, rate)

    def knock(f):
        shift = np.zeros((f.size, 3))
        shift[f == at] = np.array([3.0, 4.0, 0.0]) * cm(1.0, unit)
        return shift

    motion = with_translation(clean_walk(rate, unit=unit), "LeftHand", knock)
    findings = run_checks(motion)
    (finding,) = only(findings, "pop")
    assert (finding.start, finding.end, finding.names) == (at, at, ("LeftHand",))
    assert finding.value == pytest.approx(cm(5.0, unit), rel=0.1)
    assert {f.kind for f in findings} == {"pop", "bone-length"}  # the hand's bone stretched that frame


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_180_degree_flip(rate, unit):
    motion = clean_walk(rate, unit=unit)
    at, j = frames(300, rate), motion.names.index("RightForeArm")
    rotations = motion.rotations.copy()
    rotations[at, j] = rotations[at, j] @ rotation_about_axis("Y", np.array(np.pi))
    findings = run_checks(motion.replace(rotations=rotations))
    (finding,) = only(findings, "flip")
    assert (finding.start, finding.end, finding.names) == (at, at, ("RightForeArm",))
    assert finding.value == pytest.approx(180.0, rel=0.1)
    assert finding.severity == "error"


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_bone_stretched_by_3_percent(rate, unit):
    motion = clean_walk(rate, unit=unit)
    a, b = frames(150, rate), frames(200, rate)
    j = motion.names.index("LeftForeArm")
    translations = motion.translations.copy()
    translations[a : b + 1, j] *= 1.03
    flags = motion.has_translation.copy()
    flags[j] = True
    findings = run_checks(motion.replace(translations=translations, has_translation=flags))
    (finding,) = only(findings, "bone-length")
    assert (finding.start, finding.end, finding.names) == (a, b, ("LeftForeArm",))
    assert finding.value == pytest.approx(3.0, rel=0.1)
    assert finding.units == "%"


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_frozen_stretch(rate, unit):
    motion = clean_walk(rate, unit=unit)
    a, b = frames(400, rate), frames(440, rate)
    index = np.arange(motion.n_frames)
    index[a : b + 1] = a
    findings = run_checks(motion.frame_slice(index))
    (finding,) = only(findings, "frozen")
    assert (finding.start, finding.end, finding.joints) == (a, b, ())
    assert finding.value == pytest.approx((b - a + 1) / rate, rel=1e-12)
    # the take resumes where the walk has gone on: the root jumps after the hold
    assert [(f.start, f.end) for f in only(findings, "teleport")] == [(b, b + 1)]


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_duplicated_frames(rate, unit):
    motion = clean_walk(rate, unit=unit)
    at = frames(250, rate)
    index = np.concatenate([np.arange(at + 1), [at, at], np.arange(at + 1, motion.n_frames)])
    (finding,) = run_checks(motion.frame_slice(index))
    assert (finding.kind, finding.start, finding.end, finding.value) == ("duplicate", at + 1, at + 2, 2.0)
    assert finding.units == "frames"


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_teleport(rate, unit):
    at = frames(350, rate)

    def jump(f):
        shift = np.zeros((f.size, 3))
        shift[f >= at, 0] = cm(50.0, unit)
        return shift

    motion = clean_walk(rate, unit=unit)
    translations = motion.translations.copy()
    translations[:, 0] += jump(np.arange(motion.n_frames))
    (finding,) = run_checks(motion.replace(translations=translations))
    assert (finding.kind, finding.start, finding.end, finding.names) == ("teleport", at - 1, at, ("Hips",))
    assert finding.value == pytest.approx(cm(50.0, unit), rel=0.1)


#: world (x, y, z) of a Y-up motion -> (x, -z, y): the same motion Z up
Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def turned_z_up(motion: Motion) -> Motion:
    """A post-convention motion of one root turned Z up (its root's frame and path turned,
    every other joint unchanged), its comments saying so."""
    rotations = motion.rotations.copy()
    rotations[:, 0] = Y_UP_TO_Z_UP @ rotations[:, 0]
    translations = motion.translations.copy()
    translations[:, 0] = motion.translations[:, 0] @ Y_UP_TO_Z_UP.T
    offsets = motion.offsets.copy()
    offsets[0] = Y_UP_TO_Z_UP @ motion.offsets[0]
    return motion.replace(rotations=rotations, translations=translations, offsets=offsets, comments=("up axis: z",))


@pytest.mark.parametrize("up", ["y", "z"])
def test_a_foot_sliding_forward_is_found_whichever_axis_is_up(up):
    """The right foot slid 2 cm forward (along the walk) over frames 100-120: found, with
    its size, in the Y-up walk and in the same walk turned Z up (its forward the -Y axis,
    the slide measured across the up axis the file states)."""

    def slide(f):
        shift = np.zeros((f.size, 3))
        shift[:, 2] = 2.0 * np.clip((f - 100) / 20, 0.0, 1.0)
        return shift

    motion = with_translation(clean_walk(120.0, unit=CM), "RightFoot", slide)
    if up == "z":
        motion = turned_z_up(motion)
    (finding,) = run_checks(motion, CheckSettings(kinds=("foot-skate",)))
    assert (finding.start, finding.end, finding.names[0]) == (100, 120, "RightFoot")
    assert finding.value == pytest.approx(2.0, rel=0.1)


def test_a_teleport_of_the_hips_under_a_pinned_root():
    """core.rigs' origin_root: a Root pinned at the world origin, the hips below it carrying
    the walk. The hips moved 50 cm sideways from frame 150 on: a teleport of the hips (the
    root that carries the figure), not of the Root, which never moves."""
    motion = make_rig("origin_root")
    hips = motion.names.index("Hips")
    assert motion.parents[hips] == motion.names.index("Root") and motion.anchors[motion.parents[hips]]
    translations = motion.translations.copy()
    translations[150:, hips, 0] += 0.5
    (finding,) = run_checks(motion.replace(translations=translations), CheckSettings(kinds=("teleport",)))
    assert (finding.kind, finding.start, finding.end, finding.names) == ("teleport", 149, 150, ("Hips",))
    assert finding.value == pytest.approx(0.5, rel=0.1)


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_rest_pose_at_start(rate, unit):
    motion = clean_walk(rate, unit=unit)
    n = frames(10, rate)
    rotations = motion.rotations.copy()
    rotations[:n] = np.eye(3)
    (finding,) = run_checks(motion.replace(rotations=rotations))
    assert (finding.kind, finding.start, finding.end, finding.value) == ("rest-pose", 0, n - 1, n)


def test_a_reference_frame_before_a_crouch_is_the_rest_pose_alone():
    """A Second Life take of 150 joints: frame 0 the reference pose (the body in the T-pose,
    the 125 face and finger joints turned a few degrees to mark them driven), frames 1-60 a
    crouch in which they sit at zero while the hips sink 44 cm and the knees bend to 125
    degrees. Most joints change only between frames 0 and 1, yet the crouch is no rest pose:
    the rest pose is frame 0 alone, and the right foot's slide over frames 1-11 is found,
    with every check and with foot-skate alone, frame 0 said to be left out."""
    motion = reference_frame_crouch("t-pose")
    found = [(f.kind, f.start, f.end, f.names) for f in run_checks(motion)]
    assert found == [
        ("rest-pose", 0, 0, ()),
        ("foot-skate", 1, 11, ("RightFoot", "RightToe", "RightToeEnd")),
    ]
    skate = CheckSettings(kinds=("foot-skate",))
    (finding,) = run_checks(motion, skate)
    assert (finding.kind, finding.start, finding.end) == ("foot-skate", 1, 11)
    assert finding.value == pytest.approx(8.0, rel=0.1)  # 8 cm
    assert skipped_frames(motion, skate) == [Skipped(0, 0, ("foot-skate",), "the rest pose at the start")]
    assert skipped_frames(motion, CheckSettings(kinds=("rest-pose",))) == []  # nothing the rest pose skips


def test_a_reference_frame_of_turned_joints_is_no_rest_pose():
    """The same take with every joint of frame 0 turned a few degrees (no T-pose): no frame
    is in the rest pose, none is left out."""
    motion = reference_frame_crouch("marked")
    assert [f for f in run_checks(motion) if f.kind == "rest-pose"] == []
    assert skipped_frames(motion, CheckSettings()) == []


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_foot_below_its_contact_level(rate, unit):
    a, b = frames(95, rate), frames(110, rate)

    def sink(f):
        shift = np.zeros((f.size, 3))
        shift[(f >= a) & (f <= b), 1] = -cm(4.0, unit)
        return shift

    motion = with_translation(clean_walk(rate, unit=unit), "RightFoot", sink)
    findings = only(run_checks(motion), "penetration")
    assert {f.names[0] for f in findings} == {"RightToe", "RightToeEnd"}  # the ankle is above them
    for finding in findings:
        assert (finding.start, finding.end) == (a, b)
        assert finding.value == pytest.approx(cm(4.0, unit), rel=0.1)


@pytest.mark.parametrize(("rate", "unit"), SETUPS)
def test_jitter_on_one_joint(rate, unit):
    a, b = frames(60, rate), frames(540, rate)
    rng = np.random.default_rng(7)

    def shake(f):
        shift = np.zeros((f.size, 3))
        inside = (f >= a) & (f <= b)
        shift[inside] = rng.normal(scale=cm(0.5, unit), size=(inside.sum(), 3))
        return shift

    motion = with_translation(clean_walk(rate, unit=unit), "RightHand", shake)
    findings = [f for f in run_checks(motion) if f.names[:1] == ("RightHand",) and f.kind == "jitter"]
    assert len(findings) == 1
    block = max(6, round(0.2 * rate))
    assert abs(findings[0].start - a) <= block and abs(findings[0].end - b) <= block
    assert findings[0].value == pytest.approx(cm(0.5, unit) * np.sqrt(3), rel=0.15)


def test_settings_round_trip_through_json():
    settings = CheckSettings(kinds=("pop", "flip"), pop_mad=6.0, rest_limits=(2.0, 3.0, float("inf")))
    text = json.dumps(settings.to_dict())
    assert CheckSettings.from_dict(json.loads(text)) == settings
    assert json.loads(text)["rest_limits"] == [2.0, 3.0, None]
    with pytest.raises(ValueError, match="unknown check 'pops'"):
        CheckSettings(kinds=("pops",))
    with pytest.raises(ValueError, match="increasing"):
        CheckSettings(pop_limits=(0.1, 0.05, 0.2))
    with pytest.raises(ValueError, match="unknown check setting"):
        CheckSettings.from_dict({"pop_max": 3})
    with pytest.raises(ValueError, match="positive"):
        CheckSettings(pop_mad=-1.0)
    assert CheckSettings.from_dict({"pop_mad": "6"}).pop_mad == 6.0


def test_only_the_kinds_asked_for_run():
    motion = clean_walk(120.0, unit=CM)
    index = np.arange(motion.n_frames)
    index[400:441] = 400
    held = motion.frame_slice(index)
    assert {f.kind for f in run_checks(held)} == {"frozen", "teleport"}
    assert {f.kind for f in run_checks(held, CheckSettings(kinds=("frozen",)))} == {"frozen"}
    assert run_checks(held, CheckSettings(kinds=("pop", "flip"))) == []
    assert set(KINDS) == set(CheckSettings().kinds)


def test_joint_flags_mark_the_frames_and_joints():
    motion = clean_walk(120.0, unit=CM)
    rotations = motion.rotations.copy()
    j = motion.names.index("RightForeArm")
    rotations[300, j] = rotations[300, j] @ rotation_about_axis("Y", np.array(np.pi))
    index = np.concatenate([np.arange(251), [250], np.arange(251, motion.n_frames)])
    flipped = motion.replace(rotations=rotations).frame_slice(index)
    findings = run_checks(flipped)
    flags = joint_flags(findings, flipped.n_frames, flipped.n_joints)
    assert flags.shape == (flipped.n_frames, flipped.n_joints)
    expected = np.zeros_like(flags)
    expected[251, :] = 2  # the duplicate: a warning on the whole pose
    expected[301, j] = 3  # the flip (one frame later after the copy): an error on the forearm
    np.testing.assert_array_equal(flags, expected)


@pytest.mark.parametrize("name", [n for n in RIGS if n != "long_take"])
def test_the_convention_rigs_have_no_warning(name):
    """core.rigs: a Root pinned at the origin (its hips translate), Z-up millimetres, six
    channels on every joint, 250 joints, one joint, one frame: infos at most (the rigs'
    knee curves have kinks, small pops)."""
    findings = run_checks(make_rig(name))
    assert [f for f in findings if f.severity != "info"] == []
    assert {f.kind for f in findings} <= {"pop", "foot-skate"}


def test_a_flip_in_the_gmr_form_names_the_children_together():
    """In GMR (pre) form each child carries its BVH parent's rotation: a flip of the BVH's
    Hips is one finding on the three bones that hang from them."""
    from gmr_studio.core.kinematics.convention import pre_from_post

    motion = clean_walk(120.0, unit=CM)
    rotations = motion.rotations.copy()
    rotations[300, 0] = rotations[300, 0] @ rotation_about_axis("Y", np.array(np.pi / 2))
    turned = motion.replace(rotations=rotations)
    (post,) = run_checks(turned)
    (pre,) = run_checks(pre_from_post(turned))
    assert (post.kind, post.start, post.end, post.names) == ("flip", 300, 300, ("Hips",))
    assert (pre.kind, pre.start, pre.end, set(pre.names)) == ("flip", 300, 300, {"Spine", "LeftUpLeg", "RightUpLeg"})
    assert pre.value == pytest.approx(post.value) == pytest.approx(90.0)


@pytest.mark.parametrize("relative", ["cmu/subject01/01_01.bvh", "bvh/assimp_Boxing_Toes.bvh"])
def test_the_gmr_form_of_a_real_file_gets_the_same_findings(relative):
    """The app holds the GMR form; the checks say the same of it as of the BVH."""
    from gmr_studio.core.formats import read_motion
    from gmr_studio.core.kinematics.convention import pre_from_post
    from tests.conftest import shared_path

    motion = read_motion(shared_path(relative))
    post, pre = run_checks(motion), run_checks(pre_from_post(motion))
    assert post and [f.to_dict() | {"value": 0} for f in pre] == [f.to_dict() | {"value": 0} for f in post]
    np.testing.assert_allclose([f.value for f in pre], [f.value for f in post], rtol=1e-9)  # FK's rounding


def test_defects_planted_in_a_real_take_are_found_among_its_own():
    """CMU 01_01.bvh (units of 1/0.45 inch): a 5 cm pop of the left hand at 1500, the root
    moved 50 cm from 1800 on, frame 1300 shown twice (later frames one further): each found
    where planted, its size within 10%, beside the take's own findings."""
    from gmr_studio.core.formats import read_motion
    from tests.conftest import shared_path

    motion = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    unit = 0.0254 / 0.45  # metres per CMU unit

    def knock(f):
        shift = np.zeros((f.size, 3))
        shift[f == 1500] = np.array([0.0, 0.05, 0.0]) / unit
        return shift

    planted = with_translation(motion, "LeftHand", knock)
    translations = planted.translations.copy()
    translations[1800:, 0, 0] += 0.5 / unit
    index = np.concatenate([np.arange(1301), [1300], np.arange(1301, motion.n_frames)])
    planted = planted.replace(translations=translations).frame_slice(index)
    before = {(f.kind, f.start) for f in run_checks(motion)}
    found = [f for f in run_checks(planted) if (f.kind, f.start - (f.start > 1300)) not in before]
    assert [(f.kind, f.start, f.end, f.names[:1]) for f in found] == [
        ("duplicate", 1301, 1301, ()),
        ("pop", 1501, 1501, ("LeftHand",)),
        ("bone-length", 1501, 1501, ("LeftHand",)),  # the knock stretches the hand's bone
        ("teleport", 1800, 1801, ("Hips",)),
    ]
    assert found[1].value == pytest.approx(0.05 / unit, rel=0.1)
    assert found[3].value == pytest.approx(0.5 / unit, rel=0.1)


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


def turned_for_a_frame(motion, joints, frame: int = 300):
    """``motion`` with each of ``joints`` turned 120 degrees about Y at ``frame`` only: a flip
    that moves the joints below it (their pop, where flips are not checked)."""
    rotations = motion.rotations.copy()
    for name in joints:
        j = motion.names.index(name)
        rotations[frame, j] = rotations[frame, j] @ rotation_about_axis("Y", np.array(np.radians(120.0)))
    return motion.replace(rotations=rotations)


def knocked(motion, joint: str, frame: int):
    def knock(frames):
        shift = np.zeros((frames.size, 3))
        shift[frames == frame, 0] = 0.05
        return shift

    return with_translation(motion, joint, knock)


def found(motion, kinds):
    return [(f.kind, f.start, f.names) for f in run_checks(motion, CheckSettings(kinds=kinds))]


def test_the_pops_a_flip_explains_are_dropped():
    """A flip of the left arm for one frame moves its forearm: a pop when flips are not
    checked, explained by the flip when they are. A pop of another frame stays."""
    flipped = turned_for_a_frame(clean_walk(120.0), ["LeftArm"])
    assert found(flipped, ("pop",)) == [("pop", 300, ("LeftForeArm",))]
    assert found(flipped, ("pop", "flip")) == [("flip", 300, ("LeftArm",))]
    elsewhere = knocked(flipped, "LeftHand", 200)
    assert found(elsewhere, ("pop", "flip")) == [("pop", 200, ("LeftHand",)), ("flip", 300, ("LeftArm",))]


def test_a_pop_of_a_joint_outside_the_flipped_subtree_is_kept():
    """The right hand knocked at the frame the left arm flips: one pop of both (the forearm's
    and the hand's), which the flip does not explain whole."""
    motion = knocked(turned_for_a_frame(clean_walk(120.0), ["LeftArm"]), "RightHand", 300)
    assert found(motion, ("pop", "flip")) == [
        ("pop", 300, ("LeftForeArm", "RightHand")),
        ("flip", 300, ("LeftArm",)),
    ]


def test_the_flips_of_several_joints_explain_the_pops_of_all_their_subtrees():
    flipped = turned_for_a_frame(clean_walk(120.0), ["LeftArm", "RightArm"])
    ((kind, frame, names),) = found(flipped, ("pop",))
    assert (kind, frame, set(names)) == ("pop", 300, {"LeftForeArm", "RightForeArm"})
    assert found(flipped, ("pop", "flip")) == [("flip", 300, ("LeftArm",)), ("flip", 300, ("RightArm",))]


def test_the_checks_find_the_same_on_one_thread_or_several():
    from gmr_studio.core.demo import demo_motion

    walk = demo_motion()
    take = walk.frame_slice(np.tile(np.arange(walk.n_frames), 18))  # 8,640 frames: two threads' worth
    one = run_checks(take, threads=1)
    assert one and {f.kind for f in one} >= {"teleport"}  # every seam of the tiling is a jump
    assert run_checks(take, threads=2) == one
