"""``gmr convert`` with --asf, --frame-rate, --scale, --up, --from-up, --split-trees."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.edits.operations import split
from gmr_studio.core.edits.world import change_up_axis, scale_lengths
from gmr_studio.core.formats import load_gmr, read_motion, write_motion
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from gmr_studio.core.space.up_axis import Y_TO_Z, up_axis_of
from tests.conftest import random_motion, shared_path
from tests.test_export import validate_bvh


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_amc_to_gmr_with_scale_and_up_stated_in_the_header(capsys, tmp_path):
    source = shared_path("cmu/subject01/01_01.amc")
    output = tmp_path / "walk.gmr"
    code, out, _ = run(capsys, "convert", source, output, "--scale", "0.056444", "--up", "z", "--frame-rate", "60")
    assert code == 0
    assert "lengths scaled by 0.056444" in out and "to z up" in out
    converted = read_motion(output)
    assert converted.frame_time == pytest.approx(1 / 60)
    assert "lengths scaled by 0.056444" in converted.comments
    assert up_axis_of(converted) == "z" and converted.comments[-1] == "written by gmr convert from 01_01.amc"
    original = read_motion(source)
    expected = 0.056444 * world_positions(original) @ Y_TO_Z.T
    assert np.abs(world_positions(converted) - expected).max() <= 1e-9 * converted.size
    # Z up: the subject's height is along z now
    extent = np.ptp(world_positions(converted)[0], axis=0)
    assert extent[2] == extent.max()


def test_up_axis_round_trip_reads_the_header(capsys, tmp_path):
    source = shared_path("cmu/subject01/01_01.bvh")
    z_up, back = tmp_path / "z.gmr", tmp_path / "back.bvh"
    assert run(capsys, "convert", source, z_up, "--up", "z")[0] == 0
    code, out, _ = run(capsys, "convert", z_up, back, "--up", "y")
    assert code == 0 and "world turned from z up to y up" in out
    validate_bvh(back.read_text())
    original = read_bvh(source)
    again = read_bvh(back)
    assert again.names == original.names and again.rotation_orders == original.rotation_orders
    # measured 8.0e-16 of the size (the bound was 1e-6)
    assert np.abs(world_positions(again) - world_positions(original)).max() <= 5e-15 * original.size


def test_the_last_up_axis_a_file_states_is_its_up_axis(capsys, tmp_path):
    """A GMR header that states the up axis twice (edited by hand after a conversion to Z
    up): the later statement holds, for reading and for the next conversion."""
    source = shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh")
    z_up, edited = tmp_path / "z.gmr", tmp_path / "edited.gmr"
    assert run(capsys, "convert", source, z_up, "--up", "z")[0] == 0
    lines = z_up.read_text().splitlines()
    assert "# up axis: z" in lines
    lines.insert(lines.index("HIERARCHY"), "# up axis: y")
    edited.write_text("\n".join(lines) + "\n")
    assert up_axis_of(read_motion(edited)) == "y"
    code, out, _ = run(capsys, "convert", edited, tmp_path / "same.gmr", "--up", "y")
    assert code == 0 and "world turned" not in out  # already Y up, as it says last: nothing turned


def test_from_up_overrides_and_nothing_changes_when_axes_agree(capsys, tmp_path):
    source = shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh")
    output = tmp_path / "same.gmr"
    code, out, _ = run(capsys, "convert", source, output, "--up", "y")
    assert code == 0 and "up axis" not in out
    code, out, _ = run(capsys, "convert", source, output, "--from-up", "z", "--up", "y")
    assert code == 0 and "world turned from z up to y up" in out and "(x, y, z) -> (x, z, -y)" in out
    turned = read_motion(output)
    expected = world_positions(read_bvh(source)) @ Y_TO_Z
    assert np.abs(world_positions(turned) - expected).max() <= 1e-9 * turned.size


def test_up_axis_change_keeps_world_rotations_conjugated(rng):
    motion = random_motion(rng, [-1, 0, 1, 1, 3], n_frames=4)
    turned = change_up_axis(motion, "z", "y")
    positions, world = forward_kinematics(motion)
    turned_positions, turned_world = forward_kinematics(turned)
    np.testing.assert_allclose(turned_positions, positions @ Y_TO_Z.T, atol=1e-12)
    np.testing.assert_allclose(turned_world, Y_TO_Z @ world @ Y_TO_Z.T, atol=1e-12)
    assert turned.rotation_orders == tuple(o.translate(str.maketrans("YZ", "ZY")) for o in motion.rotation_orders)
    # the rest pose turns with the world
    np.testing.assert_allclose(
        world_positions(turned.rest_pose()), world_positions(motion.rest_pose()) @ Y_TO_Z.T, atol=1e-12
    )
    with pytest.raises(ValueError):
        scale_lengths(motion, 0)


def test_bvh_output_has_no_header_and_the_notes_are_printed(capsys, tmp_path):
    source = shared_path("cmu/subject02/02_01.amc")
    output = tmp_path / "walk.bvh"
    code, out, _ = run(capsys, "convert", source, output, "--scale", "2")
    assert code == 0 and f"{output}: lengths scaled by 2" in out
    assert "dummy joints" in out  # Acclaim siblings turn independently
    summary = validate_bvh(output.read_text())
    assert summary["frames"] == 343


def test_named_skeleton_for_an_amc_elsewhere(capsys, tmp_path):
    amc = tmp_path / "walk.amc"
    shutil.copy(shared_path("cmu/subject02/02_01.amc"), amc)
    output = tmp_path / "walk.gmr"
    code, _, err = run(capsys, "convert", amc, output)
    assert code == 2 and "name one with --asf" in err and not output.exists()
    code, _, _ = run(capsys, "convert", amc, output, "--asf", shared_path("cmu/subject02/02.asf"))
    assert code == 0 and read_motion(output).n_frames == 343
    code, out, _ = run(capsys, "info", amc, "--asf", shared_path("cmu/subject02/02.asf"))
    assert code == 0 and "AMC (Acclaim, with its ASF)" in out


def test_split_trees_writes_one_file_per_tree(capsys, tmp_path):
    forest = split(load_gmr(shared_path("cmu/subject01/01_01.bvh")), "LeftArm")
    gmr = tmp_path / "forest.gmr"
    write_motion(forest, gmr)
    code, _, _ = run(capsys, "convert", gmr, tmp_path / "trees.bvh", "--split-trees")
    assert code == 0
    assert sorted(p.name for p in tmp_path.glob("trees*.bvh")) == ["trees_Hips.bvh", "trees_LeftArm.bvh"]
    for path in tmp_path.glob("trees*.bvh"):
        validate_bvh(path.read_text())
    code, _, _ = run(capsys, "convert", shared_path("cmu/subject01/01_01.bvh"), tmp_path / "one.bvh", "--split-trees")
    assert code == 0 and (tmp_path / "one.bvh").exists()  # a single tree keeps the name asked for
    arm = read_bvh(tmp_path / "trees_LeftArm.bvh")
    assert arm.names[0] == "LeftArm"
    index = forest.names.index("LeftHand")
    np.testing.assert_allclose(
        world_positions(arm)[:, arm.names.index("LeftHand")], world_positions(forest)[:, index], atol=1e-9
    )


def test_bad_options_and_formats(capsys, tmp_path):
    source = shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh")
    with pytest.raises(SystemExit):
        main(["convert", str(source), str(tmp_path / "x.gmr"), "--scale", "-1"])
    assert "expected a positive number" in capsys.readouterr().err
    code, _, err = run(capsys, "convert", source, tmp_path / "x.c3d")
    assert code == 2 and "cannot write '.c3d' files" in err
    asf = shared_path("cmu/subject01/01.asf")
    code, _, err = run(capsys, "convert", asf, tmp_path / "x.gmr")
    assert code == 2 and "cannot convert '.asf' files" in err
