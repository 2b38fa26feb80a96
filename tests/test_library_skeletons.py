"""Skeleton signatures and near matches: one rig one signature whatever the joint order,
renamed rigs matched through names and the shipped joint maps, groups that do not depend on
the order files come in."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.formats import read_motion
from gmr_studio.core.jointmap import JointMap, load_joint_map
from gmr_studio.core.library.skeletons import GROUP_MATCH, Skeleton, match_score, plain_name, skeleton_groups
from tests.conftest import shared_path

BVH = "cmu/subject01/01_01.bvh"
AMC = "cmu/subject01/01_01.amc"


def reordered(skeleton: Skeleton, order: list[int]) -> Skeleton:
    """The same skeleton with its joints listed in ``order`` (a permutation)."""
    new_index = {old: new for new, old in enumerate(order)}
    parents = tuple(new_index[skeleton.parents[old]] if skeleton.parents[old] >= 0 else -1 for old in order)
    return Skeleton(tuple(skeleton.names[old] for old in order), parents)


def test_one_rig_has_one_signature_whatever_order_its_joints_are_listed_in(rng):
    skeleton = Skeleton.of(read_motion(shared_path(BVH)))
    shuffled = reordered(skeleton, list(rng.permutation(skeleton.n_joints)))
    assert shuffled.names != skeleton.names
    assert shuffled.signature == skeleton.signature and shuffled.topology == skeleton.topology
    assert match_score(skeleton, shuffled) == 1.0


def test_a_renamed_rig_keeps_its_topology_and_matches_by_plain_names():
    skeleton = Skeleton.of(read_motion(shared_path(BVH)))
    prefixed = Skeleton(tuple(f"mixamorig:{n.upper()}" for n in skeleton.names), skeleton.parents)
    assert prefixed.signature != skeleton.signature and prefixed.topology == skeleton.topology
    assert match_score(skeleton, prefixed) == 1.0  # every joint paired by its plain name, every parent too
    assert plain_name("mixamorig:Left_Arm") == plain_name("LeftArm") == "leftarm"


def test_another_topology_is_another_topology_hash():
    chain = Skeleton(("a", "b", "c"), (-1, 0, 1))
    fork = Skeleton(("a", "b", "c"), (-1, 0, 0))
    assert chain.topology != fork.topology
    # b pairs with b, c with c; c's parent is b in one and a in the other: only a and b count
    assert match_score(chain, fork, maps=[]) == pytest.approx(2 * 2 / 6)


def test_cmus_bvh_and_asf_match_through_the_shipped_cmu_map():
    bvh, amc = (Skeleton.of(read_motion(shared_path(p))) for p in (BVH, AMC))
    assert match_score(bvh, amc, maps=[]) < GROUP_MATCH  # few names in common (lhipjoint, LHipJoint...)
    through_map = match_score(bvh, amc)
    assert through_map >= GROUP_MATCH
    assert through_map == pytest.approx(2 * 28 / (38 + 31))  # the 28 joints the CMU map pairs, all consistent
    assert match_score(bvh, amc, maps=[load_joint_map("cmu")]) == through_map
    # a map pairing the two roots and both hips only: the roots and hips count, with the
    # few plain names that pair (lhipjoint and LHipJoint sit at different places)
    small = JointMap.from_pairs({"Hips": "root", "LeftUpLeg": "lhipjoint", "RightUpLeg": "rhipjoint"})
    assert match_score(bvh, amc, maps=[small]) < GROUP_MATCH


def test_groups_do_not_depend_on_the_order_skeletons_come_in(rng):
    bvh, amc = (Skeleton.of(read_motion(shared_path(p))) for p in (BVH, AMC))
    mocap = Skeleton.of(read_motion(shared_path("bvh/bvh-python_test_mocapbank.bvh")))
    cesium = Skeleton.of(read_motion(shared_path("gltf/lab0_CesiumMan.glb")))
    skeletons = [bvh, amc, mocap, cesium]
    keys = ["b/01_01.bvh", "a/01_01.amc", "c/mocap.bvh", "d/cesium.glb"]
    groups, scores = skeleton_groups(skeletons, keys)
    assert groups == [1, 1, 2, 3]  # numbered by each group's first key: a/..., c/..., d/...
    assert scores[2] == scores[3] == 1.0 and scores[0] == scores[1] == pytest.approx(match_score(bvh, amc))
    for _ in range(5):
        order = list(rng.permutation(4))
        shuffled, _ = skeleton_groups([skeletons[k] for k in order], [keys[k] for k in order])
        assert shuffled == [groups[k] for k in order]


def test_skeletons_linked_through_a_third_share_a_group():
    a = Skeleton(("hips", "spine", "head", "arm", "hand", "leg"), (-1, 0, 1, 1, 3, 0))
    b = Skeleton(("hips", "spine", "head", "arm", "hand", "foot"), (-1, 0, 1, 1, 3, 0))
    c = Skeleton(("hips", "spine", "head", "wing", "claw", "foot"), (-1, 0, 1, 1, 3, 0))
    assert match_score(a, b) >= GROUP_MATCH and match_score(b, c) >= GROUP_MATCH > match_score(a, c)
    groups, _ = skeleton_groups([a, c, b], ["1", "2", "3"])
    assert len(set(groups)) == 1
    assert np.all(np.array(groups) == 1)
