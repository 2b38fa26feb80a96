"""A joint's angles as two named quantities (issue 21, items 5 and 6) and one clock (item 7)."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from gmr_studio.core.analysis.curves import joint_curves, values_at
from gmr_studio.core.cli import main
from gmr_studio.core.edits.mirror import mirror
from gmr_studio.core.formats import read_motion_with_channels
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.rigs import make_rig
from gmr_studio.core.rotations.euler import matrix_from_euler
from gmr_studio.core.table import csv_text
from gmr_studio.core.timebase.clock import duration_of, duration_seconds, frame_seconds
from tests.conftest import shared_path


def read_csv(path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array([[float(v) if v else np.nan for v in r] for r in rows[1:]])


def test_foot_channels_and_gmr_euler_mean_one_thing_in_either_convention(tmp_path, capsys):
    """Item 5: on the game rig, Foot_L's ``channels`` are its own BVH channels in the CLI (a
    BVH motion) and in the app's GMR form alike, and its ``gmr-euler`` is LowerLeg_L's
    rotation (the bone ending at the foot), not the foot's."""
    path = tmp_path / "W.bvh"
    write_bvh(make_rig("game_root"), path)
    post, channels = read_motion_with_channels(path)
    pre = pre_from_post(post)
    own = joint_curves(post, "Foot_L", "channels", file_channels=channels)
    assert own.columns == ("Foot_L.channels.Zrotation", "Foot_L.channels.Xrotation", "Foot_L.channels.Yrotation")
    np.testing.assert_array_equal(own.values, channels.angles["Foot_L"])  # the file's values, as written
    app = joint_curves(pre, "Foot_L", "channels", file_channels=channels)
    assert app.columns == own.columns and np.array_equal(app.values, own.values)
    gmr = joint_curves(pre, "Foot_L", "gmr-euler")
    assert gmr.columns == ("Foot_L.gmr-euler.Z", "Foot_L.gmr-euler.X", "Foot_L.gmr-euler.Y")
    np.testing.assert_allclose(gmr.values, channels.angles["LowerLeg_L"], atol=1e-9)
    np.testing.assert_array_equal(joint_curves(post, "Foot_L", "gmr-euler").values, gmr.values)
    assert not np.allclose(gmr.values, own.values)  # two quantities, two names
    assert joint_curves(pre, "Toes_L_End", "channels", file_channels=channels).columns == ()  # an End Site
    # the CLI writes the same columns; `euler` is channels' alias
    out = tmp_path / "c.csv"
    assert main(["curves", str(path), "--joints", "Foot_L", "--quantity", "euler", "-o", str(out)]) == 0
    header, table = read_csv(out)
    assert header[2:] == list(own.columns)
    np.testing.assert_allclose(table[:, 2:], own.values, rtol=1e-9, atol=1e-9)
    # the inspector's numbers (values_at) at a frame are the curves' at that frame
    columns, values = values_at(pre, "Foot_L", "channels", 123, file_channels=channels)
    assert columns == own.columns and np.array_equal(values, own.values[123])
    capsys.readouterr()


def test_amc_channels_are_the_files_dof_values_one_column_per_dof(capsys, tmp_path):
    """Item 6: CMU 02_01's lradius has `dof rx`: one column, 20.3824 at frame 0 as the file
    says; lfemur's three dofs in file order; the values make the motion's rotation."""
    amc = shared_path("cmu/subject02/02_01.amc")
    motion, channels = read_motion_with_channels(amc)
    elbow = joint_curves(motion, "lradius", "channels", file_channels=channels)
    assert elbow.columns == ("lradius.channels.rx",) and elbow.values[0, 0] == 20.3824
    hip = joint_curves(motion, "lfemur", "channels", file_channels=channels)
    assert hip.columns == ("lfemur.channels.rx", "lfemur.channels.ry", "lfemur.channels.rz")
    j = motion.joint_index("lradius")
    assert np.abs(channels.rotations("lradius") - motion.rotations[:, j]).max() < 1e-12
    out = tmp_path / "e.csv"
    assert main(["curves", str(amc), "--joints", "lradius", "--quantity", "channels", "-o", str(out)]) == 0
    header, table = read_csv(out)
    assert header == ["frame", "time", "lradius.channels.rx"] and table[0, 2] == 20.3824
    capsys.readouterr()


def test_after_an_edit_channels_come_from_the_motion_and_make_its_rotation():
    """Mirrored, the file's values no longer describe the motion: the columns are computed
    from its rotations (in the file's channel frames), and they rebuild those rotations."""
    motion, channels = read_motion_with_channels(shared_path("cmu/subject02/02_01.amc"))
    mirrored = mirror(motion)[0]
    hip = joint_curves(mirrored, "lfemur", "channels", file_channels=channels)
    assert not np.allclose(hip.values, channels.angles["lfemur"])
    c = channels.axes["lfemur"]
    rebuilt = c @ matrix_from_euler(np.radians(hip.values[:, ::-1]), "ZYX") @ c.T
    assert np.abs(rebuilt - mirrored.rotations[:, mirrored.joint_index("lfemur")]).max() < 1e-9


def test_one_clock_for_info_curves_and_the_timeline(capsys, tmp_path):
    """Item 7: an AMC of 597 frames at 120 Hz lasts 597 / 120 = 4.975 s everywhere."""
    amc = shared_path("cmu/subject01/01_01.amc")
    motion, _ = read_motion_with_channels(amc)
    assert duration_of(motion) == duration_seconds(motion.n_frames, motion.frame_time)
    assert main(["info", str(amc), "--json"]) == 0
    import json

    info = json.loads(capsys.readouterr().out)
    assert info["duration"] == duration_of(motion) == motion.n_frames / 120.0
    from gmr_studio.app.docks.timeline import time_text

    last = motion.n_frames - 1
    assert time_text(motion, last).split(" / ")[1].startswith(f"{duration_of(motion):.3f} s")
    assert time_text(motion, last).lstrip().startswith(f"{frame_seconds(last, motion.frame_time):.3f} s")
    out = tmp_path / "t.csv"
    assert main(["curves", str(amc), "--joints", "root", "--quantity", "world", "-o", str(out)]) == 0
    _, table = read_csv(out)
    np.testing.assert_allclose(table[:, 1], frame_seconds(np.arange(motion.n_frames), motion.frame_time), rtol=1e-9)


def test_one_csv_writer_quotes_names_with_commas_and_leaves_gaps_empty():
    text = csv_text(["frame", "a,b", 'say "x"'], np.array([[0, 1.5, np.nan], [1, np.nan, 2.0]]), ["%d", "%.10g"])
    rows = list(csv.reader(text.splitlines()))
    assert rows == [["frame", "a,b", 'say "x"'], ["0", "1.5", ""], ["1", "", "2"]]


@pytest.mark.parametrize("quantity", ["channels", "gmr-euler", "angle", "quaternion"])
def test_rotation_quantities_agree_between_the_bvh_and_its_gmr_form(quantity):
    path = shared_path("cmu/subject01/01_01.bvh")
    post, channels = read_motion_with_channels(path)
    pre = pre_from_post(post)
    for joint in ("Hips", "LeftUpLeg", "LeftFoot", "Head"):
        a = joint_curves(post, joint, quantity, file_channels=channels)
        b = joint_curves(pre, joint, quantity, file_channels=channels)
        assert a.columns == b.columns
        np.testing.assert_allclose(a.values, b.values, atol=1e-9)


def test_channels_say_whether_they_are_the_files_values_or_computed():
    """Issue 40.4: a joint's channels carry their origin. As read, a BVH's are the file's own
    values; after a split the split joint's are computed from the edited motion (they rebuild
    its rotation), the other joints' are still the file's; a glTF's, whose file stores
    quaternions, are always the motion's rotation as Euler angles."""
    from gmr_studio.core.analysis.curves import CHANNEL_ORIGINS, bvh_rotations
    from gmr_studio.core.edits.operations import split
    from gmr_studio.core.model.channels import FileChannels

    post, channels = read_motion_with_channels(shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh"))
    assert isinstance(channels, FileChannels)
    for name in ("Hips", "LeftArm", "Head", "Head_End"):
        curves = joint_curves(post, name, "channels", file_channels=channels)
        assert curves.origin == "file"
        if name != "Head_End":
            assert np.array_equal(curves.values, channels.angles[name])
    edited = split(pre_from_post(post), "LeftArm")
    arm = joint_curves(edited, "LeftArm", "channels", file_channels=channels)
    assert arm.origin == "edited" and not np.allclose(arm.values, channels.angles["LeftArm"])
    rebuilt = matrix_from_euler(np.radians(arm.values), channels.intrinsic_order("LeftArm"))
    assert np.abs(rebuilt - bvh_rotations(edited, edited.joint_index("LeftArm"))).max() < 1e-9
    head = joint_curves(edited, "Head", "channels", file_channels=channels)
    assert head.origin == "file" and np.array_equal(head.values, channels.angles["Head"])
    gltf, none = read_motion_with_channels(shared_path("gltf/bevy_Fox.glb"))
    assert none is None
    assert {joint_curves(gltf, j, "channels").origin for j in range(gltf.n_joints)} == {"motion"}
    assert set(CHANNEL_ORIGINS) == {"file", "edited", "motion", "none"}
