"""Dummy joints out (remove_dummies) and back in (BVH export), positions unchanged."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.edits.dummies import find_dummies, remove_dummies
from gmr_studio.core.edits.operations import split
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.bvh_export import bvh_export
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import random_motion, shared_path
from tests.test_export import assert_round_trip

CMU_DUMMIES = [
    "LHipJoint",
    "RHipJoint",
    "LowerBack",
    "Neck",
    "LeftShoulder",
    "LeftFingerBase",
    "LThumb",
    "RightShoulder",
    "RightFingerBase",
    "RThumb",
]


def positions_by_name(motion, names):
    return world_positions(motion)[:, [motion.names.index(n) for n in names]]


def test_cmu_01_01_has_exactly_the_ten_dummies():
    bvh = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    assert [bvh.names[j] for j in find_dummies(bvh)] == CMU_DUMMIES
    cleaned, removed = remove_dummies(bvh)
    assert sorted(removed) == sorted(CMU_DUMMIES) and len(removed) == 10
    assert bvh.n_joints == 38 and cleaned.n_joints == 28
    assert cleaned.names == tuple(n for n in bvh.names if n not in CMU_DUMMIES)
    assert cleaned.convention == "pre" and find_dummies(cleaned) == []
    error = np.abs(world_positions(cleaned) - positions_by_name(bvh, cleaned.names)).max()
    assert error <= 1e-9 * bvh.size
    # the children of a dummy now hang from the dummy's parent
    assert cleaned.names[cleaned.parents[cleaned.names.index("LeftUpLeg")]] == "Hips"
    assert cleaned.names[cleaned.parents[cleaned.names.index("LFingers")]] == "LeftHand"
    cleaned.check_invariants()


def test_dummies_go_back_in_on_export():
    bvh = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    cleaned, _ = remove_dummies(bvh)
    export = bvh_export(cleaned)
    # Hips' three children now turn independently: one dummy each, named after the child
    assert {"LeftUpLeg_dummy", "RightUpLeg_dummy", "Spine_dummy"} <= set(export.dummies)
    assert_round_trip(cleaned, export, tolerance=1e-9)
    # a tip whose parent changed keeps its name (a JOINT, not an End Site named after its parent)
    names = dict(zip(cleaned.names, export.names))
    assert names["LThumb_End"] == "LThumb_End" and names["Head_End"] == "Head_End"
    again = read_bvh("again.bvh", export.text().encode())
    in_file = [names[n] for n in cleaned.names]
    error = np.abs(positions_by_name(again, in_file) - positions_by_name(bvh, cleaned.names)).max()
    assert error <= 1e-9 * bvh.size


def test_chains_of_dummies_and_a_relative_tolerance(rng):
    # 0 -> 1 (dummy) -> 2 (dummy) -> {3, 4}; 5 has a tiny offset; 6 is a dummy leaf (no child)
    motion = random_motion(rng, [-1, 0, 1, 2, 2, 0, 5, 3], n_frames=4)
    offsets = motion.offsets.copy()
    scale = 1000.0
    offsets *= scale
    offsets[[1, 2]] = 0.0
    offsets[5] = 1e-7  # 1e-7 < 1e-9 * size (size ~ 1000s): counts as zero
    offsets[7] = 0.0  # a zero-offset leaf is not a dummy (no child)
    translations = np.broadcast_to(offsets, motion.translations.shape).copy()
    translations[:, 0] = motion.translations[:, 0]
    motion = motion.replace(offsets=offsets, translations=translations)
    assert motion.size > 100
    assert find_dummies(motion) == [1, 2, 5]
    cleaned, removed = remove_dummies(motion)
    assert removed == ["j1", "j2", "j5"] and cleaned.names == ("j0", "j3", "j4", "j6", "j7")
    assert list(cleaned.parents) == [-1, 0, 0, 0, 1]
    # R''_c = R_d R_c composes along the chain: j3 absorbs R_1 R_2
    np.testing.assert_allclose(
        cleaned.rotations[:, 1], motion.rotations[:, 1] @ motion.rotations[:, 2] @ motion.rotations[:, 3], atol=1e-12
    )
    # j5's tiny offset is dropped with it: positions move by at most that much
    error = np.abs(world_positions(cleaned) - positions_by_name(motion, cleaned.names)).max()
    assert error <= 1e-9 * motion.size
    strict, removed_strict = remove_dummies(motion, tolerance=0.0)
    assert removed_strict == ["j1", "j2"] and "j5" in strict.names


def test_joints_with_translation_channels_or_soft_links_stay(rng):
    motion = random_motion(rng, [-1, 0, 1, 2, 3], n_frames=3, translation_joints=(1,))
    offsets = motion.offsets.copy()
    offsets[[1, 2, 3]] = 0.0
    translations = motion.translations.copy()
    translations[:, [2, 3]] = 0.0
    motion = motion.replace(offsets=offsets, translations=translations)
    assert find_dummies(motion) == [2, 3]  # j1 has translation channels
    forest = split(motion, 4)  # j4 now holds a soft link to j3
    assert find_dummies(forest) == [2]
    cleaned, removed = remove_dummies(forest)
    assert removed == ["j2"] and cleaned.soft_parents[cleaned.names.index("j4")] == cleaned.names.index("j3")
    error = np.abs(world_positions(cleaned) - positions_by_name(forest, cleaned.names)).max()
    assert error <= 1e-9 * forest.size


def test_no_dummies_gives_the_motion_back(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=2)
    same, removed = remove_dummies(motion)
    assert same is motion and removed == []
    post = random_motion(rng, [-1, 0, 1], n_frames=2, convention="post")
    converted, _ = remove_dummies(post)
    assert converted.convention == "pre"
    np.testing.assert_allclose(world_positions(converted), world_positions(pre_from_post(post)), atol=1e-12)


def test_command_line_reports_and_removes_dummies(capsys, tmp_path):
    source = shared_path("cmu/subject01/01_01.bvh")
    assert main(["info", str(source)]) == 0
    out = capsys.readouterr().out
    assert "dummies:    10 (LHipJoint, RHipJoint, LowerBack, Neck, LeftShoulder" in out
    assert main(["info", str(source), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["dummies"] == CMU_DUMMIES
    output = tmp_path / "clean.gmr"
    assert main(["convert", str(source), str(output), "--remove-dummies"]) == 0
    assert "removed 10 dummy joints: LHipJoint, RHipJoint" in capsys.readouterr().out
    cleaned = read_motion(output)
    assert cleaned.n_joints == 28 and any("removed 10 dummy joints" in c for c in cleaned.comments)
    original = read_bvh(source)
    error = np.abs(world_positions(cleaned) - positions_by_name(original, cleaned.names)).max()
    assert error <= 1e-9 * original.size
    assert main(["info", str(output)]) == 0
    assert "dummies:    0\n" in capsys.readouterr().out


@pytest.mark.parametrize("target", [".bvh", ".gmr"])
def test_remove_dummies_then_any_output(tmp_path, target, capsys):
    source = shared_path("cmu/subject01/01_01.bvh")
    output = tmp_path / f"out{target}"
    assert main(["convert", str(source), str(output), "--remove-dummies"]) == 0
    capsys.readouterr()
    again = read_motion(output)
    original = read_bvh(source)
    # every joint with children keeps its name (the tips are End Sites, named by the reader)
    kept = [n for j, n in enumerate(original.names) if n not in CMU_DUMMIES and original.children[j]]
    error = np.abs(positions_by_name(again, kept) - positions_by_name(original, kept)).max()
    assert error <= 1e-6 * original.size
