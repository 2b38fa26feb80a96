"""``gmr curves`` (CSV layout, values from an independent reading) and ``gmr edit`` clip flags."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.edits.clip import resample, trim
from gmr_studio.core.edits.mirror import mirror
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from gmr_studio.core.rigs import make_rig
from tests.conftest import shared_path
from tests.test_curves import bvh_channels


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def read_csv(path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array(rows[1:], dtype=np.float64)


def test_euler_csv_has_the_issues_layout_and_the_files_channels(capsys, tmp_path):
    path = shared_path("cmu/subject01/01_01.bvh")
    out = tmp_path / "euler.csv"
    code, stdout, _ = run(
        capsys, "curves", path, "--joints", "LeftLeg,Hips", "--quantity", "euler", "--frames", "10:20", "-o", out
    )
    assert code == 0 and "6 columns x 10 frames" in stdout
    header, table = read_csv(out)
    rotations = ("Zrotation", "Yrotation", "Xrotation")
    assert header == ["frame", "time", *(f"{j}.channels.{a}" for j in ("LeftLeg", "Hips") for a in rotations)]
    np.testing.assert_array_equal(table[:, 0], np.arange(10, 20))
    np.testing.assert_allclose(table[:, 1], np.arange(10, 20) * 0.0083333, rtol=1e-9)
    channels = bvh_channels(path)
    expected = np.hstack([channels["LeftLeg"][1][10:20], channels["Hips"][1][10:20, 3:]])
    np.testing.assert_allclose(table[:, 2:], expected, rtol=1e-9, atol=1e-7)  # 10 significant digits


def test_world_speed_and_local_csv_columns(capsys, tmp_path):
    path = shared_path("cmu/subject02/02_01.amc")
    motion = load_gmr(path)
    reference, _ = reference_forward_kinematics(motion)
    j = motion.joint_index("lfoot")
    out = tmp_path / "world.csv"
    assert run(capsys, "curves", path, "--joints", "lfoot", "--quantity", "world", "-o", out)[0] == 0
    header, table = read_csv(out)
    assert header == ["frame", "time", "lfoot.world.x", "lfoot.world.y", "lfoot.world.z"]
    np.testing.assert_allclose(table[:, 2:], reference[:, j], rtol=1e-9, atol=1e-9 * motion.size)
    assert run(capsys, "curves", path, "--joints", "lfoot", "--quantity", "speed", "-o", out)[0] == 0
    header, table = read_csv(out)
    assert header == ["frame", "time", "lfoot.speed"]
    step = np.linalg.norm(reference[2, j] - reference[0, j]) / (2 * motion.frame_time)
    assert table[1, 2] == pytest.approx(step, rel=1e-9)
    for quantity in ("local-pre", "local-post"):
        assert run(capsys, "curves", path, "--joints", "ltibia", "--quantity", quantity, "-o", out)[0] == 0
        header, table = read_csv(out)
        assert header[2:] == [f"ltibia.{quantity}.{a}" for a in "xyz"]
    # the bone's length: |R t| = |t|
    assert np.linalg.norm(table[:, 2:], axis=1) == pytest.approx(
        np.linalg.norm(motion.offsets[motion.joint_index("ltibia")])
    )


def test_contacts_csv_and_png(capsys, tmp_path):
    path = shared_path("cmu/subject02/02_01.amc")
    out = tmp_path / "contacts.csv"
    assert run(capsys, "curves", path, "--quantity", "contacts", "-o", out)[0] == 0
    header, table = read_csv(out)
    assert header == ["frame", "time", "lfoot.contact", "ltoes.contact", "rfoot.contact", "rtoes.contact"]
    assert set(np.unique(table[:, 2:])) == {0.0, 1.0}
    png = tmp_path / "contacts.png"
    assert run(capsys, "curves", path, "--quantity", "euler", "--joints", "lfemur", "-o", png)[0] == 0
    from matplotlib.image import imread

    image = imread(png)
    assert image.shape[:2] == (450, 1000)
    assert np.unique(image.reshape(-1, image.shape[-1]), axis=0).shape[0] > 20  # curves, not a blank


def test_curves_refusals_are_one_line_and_exit_2(capsys, tmp_path):
    path = shared_path("cmu/subject02/02_01.amc")
    code, _, err = run(
        capsys,
        "curves",
        path,
        "--joints",
        "lfoot",
        "--quantity",
        "world",
        "--frames",
        "50:10",
        "-o",
        tmp_path / "a.csv",
    )
    assert code == 2 and "frame range 50:10" in err
    code, _, err = run(capsys, "curves", path, "--quantity", "world", "-o", tmp_path / "a.csv")
    assert code == 2 and "--joints is required" in err
    code, _, err = run(capsys, "curves", path, "--joints", "nose", "--quantity", "world", "-o", tmp_path / "a.csv")
    assert code == 2 and "unknown joint 'nose'" in err
    assert not (tmp_path / "a.csv").exists()


def test_edit_mirror_says_how_many_pairs_it_swapped_and_names_them_on_request(capsys, tmp_path):
    source = tmp_path / "second_life.bvh"
    write_bvh(make_rig("second_life"), source)
    code, out, err = run(capsys, "edit", source, "-o", tmp_path / "m.bvh", "--mirror")
    assert code == 0 and err == ""
    assert out == "gmr edit --mirror: swapped 10 left/right pairs (--list-pairs names them)\n"
    code, out, _ = run(capsys, "edit", source, "-o", tmp_path / "m.bvh", "--mirror", "--list-pairs")
    assert code == 0 and out.startswith("gmr edit --mirror: swapped 10 left/right pairs: lCollar/rCollar, ")
    assert out.endswith(", mToeLeft/mToeRight, mToeLeft_End/mToeRight_End\n")


def test_edit_trims_resamples_and_mirrors_in_the_order_given(capsys, tmp_path):
    source = shared_path("cmu/subject01/01_01.bvh")
    out = tmp_path / "edited.gmr"
    code, _, err = run(capsys, "edit", source, "-o", out, "--frames", "100:341", "--rate", "30", "--mirror")
    assert code == 0 and err == ""
    edited = read_motion(out)
    expected = mirror(resample(trim(load_gmr(source), 100, 341), 30.0))[0]
    # frames 100 to 340 span 2 s at 120 Hz ('Frame Time: .0083333', 120 Hz to seven digits):
    # 61 frames at 30 Hz, the last at 2 s
    assert edited.n_frames == expected.n_frames == 61 and edited.frame_rate == pytest.approx(30.0)
    np.testing.assert_allclose(
        reference_forward_kinematics(edited)[0], reference_forward_kinematics(expected)[0], atol=1e-6 * edited.size
    )
    other = tmp_path / "other.gmr"
    assert run(capsys, "edit", source, "-o", other, "--rate", "30", "--frames", "100:141")[0] == 0
    assert read_motion(other).n_frames == 41  # resampled first: frames 100 to 140 of 30 Hz
