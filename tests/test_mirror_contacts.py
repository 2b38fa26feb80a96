"""Mirror (name rules, Second Life's among them, reflection, twice = identity) and foot
contacts on real walks."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.analysis.contacts import contact_runs, foot_contacts, foot_joints
from gmr_studio.core.edits.mirror import mirror, pairs_text, side_partners
from gmr_studio.core.edits.operations import shift_root, split
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.kinematics.fk import reference_forward_kinematics, world_positions
from gmr_studio.core.rigs import make_rig, second_life_name
from tests.conftest import random_motion, shared_path


def test_side_rules_cover_the_usual_conventions():
    names = [
        "Hips", "LeftArm", "RightArm", "mixamorig:LeftHand", "mixamorig:RightHand", "lfemur", "rfemur",
        "lowerback", "LHipJoint", "RHipJoint", "LowerBack", "hand_L", "hand_R", "foot.l", "foot.r",
        "LeftEye", "thigh.L", "shin_r",
    ]  # fmt: skip
    sides = side_partners(names)
    partner = {names[j]: names[k] for j, k in enumerate(sides.partner)}
    for left, right in [("LeftArm", "RightArm"), ("mixamorig:LeftHand", "mixamorig:RightHand"), ("lfemur", "rfemur"),
                        ("LHipJoint", "RHipJoint"), ("hand_L", "hand_R"), ("foot.l", "foot.r")]:  # fmt: skip
        assert partner[left] == right and partner[right] == left
    for central in ("Hips", "lowerback", "LowerBack"):
        assert partner[central] == central
    assert sides.unmatched == ("LeftEye", "thigh.L", "shin_r")
    assert sides.pairs.shape == (6, 2)


def test_second_life_and_poser_names_pair_up():
    names = [
        "hip", "abdomen", "lCollar", "rCollar", "lShldr", "rShldr", "lThigh", "rThigh", "lShin", "rShin",
        "mHandIndex1Left", "mHandIndex1Right", "mEyeLeft", "mEyeRight", "mHipLeft", "mHipRight",
        "mFaceNoseCenter", "mFaceEar1Left", "lEye", "lowerback",
    ]  # fmt: skip
    sides = side_partners(names)
    assert pairs_text(names, sides.pairs) == (
        "7 left/right pairs: lCollar/rCollar, lShldr/rShldr, lThigh/rThigh, lShin/rShin, "
        "mHandIndex1Left/mHandIndex1Right, mEyeLeft/mEyeRight, mHipLeft/mHipRight"
    )
    partner = {names[j]: names[k] for j, k in enumerate(sides.partner)}
    for central in ("hip", "abdomen", "mFaceNoseCenter", "lEye", "lowerback"):  # lEye: a loose rule, no rEye
        assert partner[central] == central
    assert sides.unmatched == ("mFaceEar1Left",)  # a ...Left name says its side: reported
    assert pairs_text(names, sides.pairs, 2) == "7 left/right pairs: lCollar/rCollar, lShldr/rShldr, and 5 more"
    assert pairs_text(names, sides.pairs, 0) == "7 left/right pairs"


def test_a_second_life_bvh_mirrors_every_joint_onto_its_partner(tmp_path):
    """The walk named as a Second Life BVH (core.rigs), written and read back: ten pairs, and
    every world position reflected onto the partner's, as the walk with its own names."""
    write_bvh(make_rig("second_life"), tmp_path / "crouch.bvh")
    motion = read_motion(tmp_path / "crouch.bvh")
    sides = side_partners(motion.names, motion.parents)
    assert pairs_text(motion.names, sides.pairs) == (
        "10 left/right pairs: lCollar/rCollar, lShldr/rShldr, lForeArm/rForeArm, lHand/rHand, "
        "mHandIndex1Left/mHandIndex1Right, lThigh/rThigh, lShin/rShin, lFoot/rFoot, mToeLeft/mToeRight, "
        "mToeLeft_End/mToeRight_End"
    )
    mirrored, unmatched = mirror(motion)
    assert unmatched == () and mirrored.names == motion.names
    before, after = world_positions(motion), world_positions(mirrored)
    centre = before[0, :, 0].mean()  # arms out along x: the lateral axis
    expected = before[:, sides.partner] * np.array([-1.0, 1.0, 1.0]) + np.array([2 * centre, 0.0, 0.0])
    np.testing.assert_allclose(after, expected, rtol=0, atol=1e-12 * motion.size)
    walk = make_rig("metres")  # the same walk with its Left/Right names mirrors to the same positions
    order = [motion.names.index(second_life_name(name)) for name in walk.names]
    np.testing.assert_allclose(after[:, order], world_positions(mirror(walk)[0]), rtol=0, atol=1e-12 * motion.size)


@pytest.mark.parametrize(
    ("relative", "count", "unmatched"),
    [
        ("bvh/assimp_Boxing_Toes.bvh", 10, ()),
        ("bvh/bvh-python_test_freebvh.bvh", 31, ()),
        ("bvh/bvh-python_test_mocapbank.bvh", 9, ()),
        ("bvh/cmu_cgspeed_npybvh_example_75f.bvh", 15, ()),
        ("cmu/subject01/01_01.bvh", 15, ()),
        ("cmu/subject01/01_01.amc", 12, ()),
        ("gltf/bevy_Fox.glb", 0, ()),
        ("gltf/lab0_CesiumMan.glb", 6, ("Skeleton_arm_joint_L__4_", "Skeleton_arm_joint_R")),
        ("gltf/mediaplusarchi_RobotExpressive.glb", 18, ()),
    ],
)
def test_real_files_pair_as_they_did_before_the_second_life_rules(relative, count, unmatched):
    motion = read_motion(shared_path(relative))
    sides = side_partners(motion.names, motion.parents)
    assert (sides.pairs.shape[0], sides.unmatched) == (count, unmatched)


@pytest.mark.parametrize("relative", ["cmu/subject01/01_01.bvh", "cmu/subject02/02_01.amc"])
def test_mirror_reflects_every_world_position_onto_the_partner(relative):
    motion = load_gmr(shared_path(relative))
    mirrored, unmatched = mirror(motion)
    assert unmatched == ()
    sigma = side_partners(motion.names).partner
    assert np.count_nonzero(sigma != np.arange(motion.n_joints)) >= 16
    before, _ = reference_forward_kinematics(motion)
    after, _ = reference_forward_kinematics(mirrored)
    # an independent statement: the lateral axis is X for both files; the plane sits at the
    # mean x of the first frame
    centre = before[0, :, 0].mean()
    expected = before[:, sigma] * np.array([-1.0, 1.0, 1.0]) + np.array([2 * centre, 0.0, 0.0])
    np.testing.assert_allclose(after, expected, rtol=0, atol=1e-12 * motion.size)
    mirrored.check_invariants()


@pytest.mark.parametrize("convention", ["pre", "post"])
def test_mirror_twice_is_the_identity(convention):
    if convention == "pre":
        walk = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 600))
        motion = shift_root(split(walk, "RightArm"), "LeftFoot")
    else:
        motion = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    twice, _ = mirror(mirror(motion)[0])
    np.testing.assert_array_equal(twice.parents, motion.parents)
    np.testing.assert_array_equal(twice.soft_parents, motion.soft_parents)
    assert twice.rotation_orders == motion.rotation_orders
    np.testing.assert_array_equal(twice.rotations, motion.rotations)  # sign flips only: exact
    np.testing.assert_allclose(twice.translations, motion.translations, rtol=0, atol=1e-13 * motion.size)
    once, _ = mirror(motion)
    assert not np.allclose(once.translations, motion.translations)


def test_mirror_refuses_a_skeleton_without_sides(rng):
    with pytest.raises(OperationError, match="left/right"):
        mirror(random_motion(rng, [-1, 0, 1]))


def _stance_order(contacts, left: str, right: str, bridge: int = 3) -> list[str]:
    """Which foot starts each stance, in time order: a stance is a run of planted frames of
    one foot, runs less than ``bridge`` frames apart counted as one (a one-frame flicker)."""
    starts = []
    for side, name in (("L", left), ("R", right)):
        runs = contact_runs(contacts.planted[:, contacts.names.index(name)])
        separate = np.concatenate([[True], runs[1:, 0] - runs[:-1, 1] >= bridge])
        starts += [(int(start), side) for start in runs[separate, 0]]
    return [side for _, side in sorted(starts)]


def test_contacts_on_a_walk_alternate_between_the_feet():
    motion = load_gmr(shared_path("cmu/subject02/02_01.amc"))
    contacts = foot_contacts(motion)
    assert {"lfoot", "rfoot", "ltoes", "rtoes"} <= set(contacts.names)
    assert contacts.planted.shape == (motion.n_frames, len(contacts.names))
    phases = _stance_order(contacts, "lfoot", "rfoot")
    assert phases == ["R", "L", "R", "L", "R", "L"]  # 02_01 walks three steps with each foot
    for k in range(len(contacts.names)):
        runs = contact_runs(contacts.planted[:, k])
        assert np.all(runs[:, 1] > runs[:, 0])
    # stricter thresholds plant fewer frames
    strict = foot_contacts(motion, height=0.005, speed=0.05)
    assert strict.planted.sum() < contacts.planted.sum()
    assert np.all(~strict.planted | contacts.planted)


def test_foot_joints_of_a_bvh_and_planted_means_low_and_slow():
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    names = [motion.names[j] for j in foot_joints(motion)]
    assert {"LeftFoot", "RightFoot", "LeftToeBase", "RightToeBase"} <= set(names)
    positions, _ = reference_forward_kinematics(motion)
    contacts = foot_contacts(motion, positions)
    j = contacts.names.index("LeftFoot")
    p = positions[:, contacts.joints[j]]
    height = p[:, 1] - p[:, 1].min()
    speed = np.linalg.norm(np.gradient(p, motion.frame_time, axis=0), axis=1)
    expected = (height < 0.03 * motion.size) & (speed < 0.4 * motion.size)
    np.testing.assert_array_equal(contacts.planted[:, j], expected)
    assert 0 < expected.sum() < motion.n_frames
