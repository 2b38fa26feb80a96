"""Joint-name maps (core/jointmap.py) and the shipped CMU map, checked on the real files."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.jointmap import JointMap, available_joint_maps, load_joint_map, match_joints
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import shared_path

#: bones the cgspeed BVH dropped (docs/formats.md): their lengths on subject 01's ASF
THORAX = 2.06488
BVH_DUMMIES = {
    "LHipJoint", "RHipJoint", "LowerBack", "Neck", "LeftShoulder", "RightShoulder",
    "LeftFingerBase", "LThumb", "RightFingerBase", "RThumb",
}  # fmt: skip


@pytest.fixture(scope="module")
def cmu_pair():
    bvh = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    amc = read_motion(shared_path("cmu/subject01/01_01.amc"))
    return bvh, amc


def test_cmu_map_ships_and_names_joints_of_both_files(cmu_pair):
    bvh, amc = cmu_pair
    assert "cmu" in available_joint_maps()
    cmu = load_joint_map("cmu")
    assert set(cmu.a_to_b) <= set(bvh.names)
    assert set(cmu.b_to_a) <= set(amc.names)
    match = match_joints(bvh.names, amc.names, cmu)
    assert len(match.pairs) == len(cmu.pairs) == 28
    # what is left over is exactly what the map's comments say: BVH dummies, dropped ASF bones
    assert set(match.unmatched_a) == BVH_DUMMIES
    assert match.unmatched_b == ["thorax", "lwrist", "rwrist"]
    assert not match.reversed_map


def test_cmu_pairs_sit_at_the_same_place(cmu_pair):
    """Lower body and spine agree to the BVH's 5 decimals; above the dropped thorax every pair
    is that bone apart for the whole trial; the hands differ more (dropped wrist), but measured
    from the wrist the fingers agree."""
    bvh, amc = cmu_pair
    pb, pa = world_positions(bvh)[1:], world_positions(amc)  # BVH frame 0 is an added T-pose
    n = min(len(pa), len(pb))
    pb, pa = pb[:n], pa[:n]
    match = match_joints(bvh.names, amc.names, "cmu")
    distance = {bvh.names[i]: np.linalg.norm(pb[:, i] - pa[:, j], axis=-1) for i, j in match.pairs}
    lower = ["Hips", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase", "LeftToeBase_End", "Spine", "Spine1"]
    lower += [n.replace("Left", "Right") for n in lower if "Left" in n]
    assert max(distance[n].max() for n in lower) < 1.5e-4
    upper = ["Neck1", "Head", "Head_End", "LeftArm", "LeftForeArm", "LeftHand", "RightArm", "RightForeArm", "RightHand"]
    for name in upper:
        assert np.abs(distance[name] - THORAX).max() < 1e-4, name
    hands = ["LFingers", "LFingers_End", "LThumb_End", "RFingers", "RFingers_End", "RThumb_End"]
    for name in hands:  # 0.38 to 3.80 apart, but the same seen from the (BVH hand, ASF wrist)
        assert distance[name].max() < 3.9 and distance[name].min() > 0.3, name
        hand, wrist = ("LeftHand", "lwrist") if name[0] == "L" else ("RightHand", "rwrist")
        seen_from_bvh = pb[:, bvh.names.index(name)] - pb[:, bvh.names.index(hand)]
        seen_from_amc = pa[:, amc.names.index(match_b(match, bvh, amc, name))] - pa[:, amc.names.index(wrist)]
        assert np.abs(seen_from_bvh - seen_from_amc).max() < 1e-5, name
    assert set(distance) == {*lower, *upper, *hands}


def match_b(match, bvh, amc, name: str) -> str:
    return amc.names[dict(match.pairs)[bvh.names.index(name)]]


def test_the_map_reads_both_ways(cmu_pair):
    bvh, amc = cmu_pair
    forward = match_joints(bvh.names, amc.names, "cmu")
    backward = match_joints(amc.names, bvh.names, "cmu")
    assert backward.reversed_map
    assert sorted((b, a) for a, b in backward.pairs) == forward.pairs
    assert backward.unmatched_a == forward.unmatched_b and backward.unmatched_b == forward.unmatched_a
    cmu = load_joint_map("cmu")
    assert cmu.reversed().reversed() == cmu
    assert cmu.reversed().a_to_b == cmu.b_to_a


def test_without_a_map_equal_names_pair():
    match = match_joints(["Hips", "Spine", "Head", "Tail"], ["Head", "Hips", "Arm"])
    assert match.pairs == [(0, 1), (2, 0)]
    assert match.unmatched_a == ["Spine", "Tail"] and match.unmatched_b == ["Arm"]


def test_map_pairs_first_then_names_each_joint_once():
    """A joint the map pairs is not paired again by name, and names fill in what the map lacks."""
    a = ["Hips", "root", "Knee"]
    b = ["root", "Knee", "pelvis"]
    match = match_joints(a, b, {"Hips": "root", "root": "pelvis"})
    assert match.pairs == [(0, 0), (1, 2), (2, 1)]
    assert match.unmatched_a == [] and match.unmatched_b == []
    # a BVH against itself through the CMU map: everything by name
    names = ["Hips", "LeftUpLeg", "Head_End"]
    assert match_joints(names, names, "cmu").pairs == [(0, 0), (1, 1), (2, 2)]


def test_explicit_pairs_and_one_to_one():
    assert load_joint_map({"A": "x"}).pairs == (("A", "x"),)
    assert JointMap.from_pairs([("A", "x"), ("B", "y")]).b_to_a == {"x": "A", "y": "B"}
    with pytest.raises(ValueError, match="paired twice on side b"):
        JointMap.from_pairs({"A": "x", "B": "x"})


def test_bad_map_files(tmp_path):
    with pytest.raises(MotionFileError, match="known maps are cmu"):
        load_joint_map("no-such-map")
    bad = tmp_path / "bad.toml"
    bad.write_text('format = "gmr-jointmap 1"\n[pairs]\nHips = root\n')
    with pytest.raises(MotionFileError) as info:
        load_joint_map(bad)
    assert info.value.line == 3 and "not valid TOML" in info.value.message
    bad.write_text("[pairs]\nHips = 3\n")
    with pytest.raises(MotionFileError, match="'Hips' must be a joint name"):
        load_joint_map(bad)
    bad.write_text('[pairs]\nHips = "root"\nPelvis = "root"\n')
    with pytest.raises(MotionFileError, match="paired twice"):
        load_joint_map(bad)
    bad.write_text('format = "gmr-jointmap 9"\n[pairs]\nA = "b"\n')
    with pytest.raises(MotionFileError, match="expected 'gmr-jointmap 1'"):
        load_joint_map(bad)
    bad.write_text('name = "x"\n')
    with pytest.raises(MotionFileError, match=r"needs a \[pairs\] table"):
        load_joint_map(bad)
    own = tmp_path / "mine.toml"
    own.write_text('[pairs]\nHips = "root"\n')
    assert load_joint_map(own).name == "mine" and load_joint_map(str(own)).source == str(own)
