"""Marker maps apply through joint-name maps: the CMU marker map (made on CMU's ASF) on CMU's
BVH skeleton of the same take (01_01.bvh with 01_01.c3d), as the AMC workflow does."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.jointmap import load_joint_map
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import markers_to_motion, read_markers, recover_pelvis
from tests.conftest import shared_path
from tests.test_markers_pelvis_guess import write_rig

MM = 25.4 / 0.45  # millimetres per CMU length unit
TEST = slice(1100, None)  # the cmu map was calibrated on frames 0:1100


@functools.cache
def cmu_take():
    folder = shared_path("cmu/subject01")
    markers = read_markers(folder / "01_01.c3d")
    bvh = load_gmr(folder / "01_01.bvh")
    asf = load_gmr(folder / "01.asf")
    return markers, bvh, asf


def test_the_bvh_workflow_is_the_amc_one():
    markers, bvh, asf = cmu_take()
    # the root at X1 (the paper's): the fitted root averages over each skeleton's own joints
    through_bvh = markers_to_motion(markers, bvh, "cmu", frames=TEST, root_at="pelvis")
    through_asf = markers_to_motion(markers, asf, "cmu", frames=TEST, root_at="pelvis")
    assert through_bvh.frame_valid.all() and through_bvh.motion.names == bvh.names
    # every paired joint is placed by the same virtual marker, bit for bit
    pairs = load_joint_map("cmu").a_to_b
    for bvh_name, asf_name in pairs.items():
        np.testing.assert_array_equal(
            through_bvh.measured[:, bvh.joint_index(bvh_name)], through_asf.measured[:, asf.joint_index(asf_name)]
        )
    # against the BVH itself (its frame 0 is an added T-pose): legs, spine and head as the AMC's
    error = np.linalg.norm(world_positions(through_bvh.motion) - world_positions(bvh)[1:][TEST], axis=2) * MM
    per_joint = dict(zip(bvh.names, error.mean(axis=0)))
    body = [n for n in bvh.names if not any(k in n for k in ("Arm", "Hand", "Finger", "Thumb", "LFing", "RFing"))]
    assert np.mean([per_joint[n] for n in body]) < 20.0  # measured 14.9
    amc = load_gmr(shared_path("cmu/subject01/01_01.amc"), asf=shared_path("cmu/subject01/01.asf"))
    asf_error = np.linalg.norm(world_positions(through_asf.motion) - world_positions(amc)[TEST], axis=2) * MM
    asf_per_joint = dict(zip(asf.names, asf_error.mean(axis=0)))
    for bvh_name in ("Hips", "LeftUpLeg", "LeftLeg", "RightFoot", "Spine", "Spine1"):
        assert per_joint[bvh_name] == pytest.approx(asf_per_joint[pairs[bvh_name]], abs=0.2)


def test_gmr_markers_on_the_bvh(tmp_path, capsys):
    folder = shared_path("cmu/subject01")
    code = main(["markers", str(folder / "01_01.c3d"), "--skeleton", str(folder / "01_01.bvh"), "--map", "cmu",
                 "--frames", "0:200", "-o", str(tmp_path / "out.bvh")])  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0, out
    assert "joints: joint names through joint map 'cmu'; thorax, lwrist, rwrist unpaired" in out
    assert load_gmr(tmp_path / "out.bvh").n_frames == 200


def test_recover_pelvis_on_the_bvh_and_a_skeleton_no_map_pairs(tmp_path):
    markers, bvh, _ = cmu_take()
    pelvis = recover_pelvis(markers, "cmu", skeleton=bvh)
    assert pelvis.labels == ("Hips", "LeftUpLeg", "RightUpLeg") and pelvis.valid.sum() == 2751
    rig = write_rig(tmp_path / "rig.bvh", root="pelvis", left="l_hip", right="r_hip", back="belly")
    with pytest.raises(OperationError, match="marker map 'cmu' places the joints of another skeleton"):
        recover_pelvis(markers, "cmu", skeleton=rig)
    assert recover_pelvis(markers, "cmu").labels == ("root", "lhipjoint", "rhipjoint")  # no skeleton: as named
