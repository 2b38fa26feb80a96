"""The ``gmr`` command line: info, positions, edit, convert, bench, and its error contract."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.core.cli import COMMANDS, main
from gmr_studio.core.edits.operations import join, shift_root, split
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import shared_path
from tests.test_bvh_reader import SMALL


@pytest.fixture
def small_bvh(tmp_path):
    path = tmp_path / "small.bvh"
    path.write_text(SMALL)
    return path


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_info_text_and_json(capsys, small_bvh):
    code, out, _ = run(capsys, "info", small_bvh)
    assert code == 0
    assert "frames:     2 at 2 Hz" in out and "roots:      1 (Hips)" in out
    assert "Spine_End" in out and "Xposition Yposition Zposition Zrotation Xrotation Yrotation" in out
    code, out, _ = run(capsys, "info", small_bvh, "--json")
    info = json.loads(out)
    assert info["frames"] == 2 and info["frame_rate"] == 2.0 and info["roots"] == ["Hips"]
    assert [j["name"] for j in info["joints"]] == ["Hips", "Spine", "Spine_End"]
    assert info["joints"][1] == {
        "name": "Spine",
        "parent": "Hips",
        "soft_parent": None,
        "offset": [0.0, 1.0, 0.0],
        "channels": ["Zrotation", "Xrotation", "Yrotation"],
    }


def test_positions_match_forward_kinematics(capsys, small_bvh, tmp_path):
    out = tmp_path / "p.npz"
    code, _, _ = run(capsys, "positions", small_bvh, "-o", out)
    assert code == 0
    data = np.load(out)
    assert list(data["names"]) == ["Hips", "Spine", "Spine_End"]
    np.testing.assert_array_equal(data["positions"], world_positions(read_bvh(small_bvh)))


def test_edit_applies_operations_in_the_order_given(capsys, tmp_path):
    source = shared_path("cmu/subject01/01_01.bvh")
    out = tmp_path / "edited.gmr"
    code, _, _ = run(
        capsys,
        "edit",
        source,
        "-o",
        out,
        "--split",
        "LeftArm",
        "--shift-root",
        "Head",
        "--join",
        "LeftArm",
        "--split",
        "RightFoot",
    )
    assert code == 0
    expected = split(
        join(shift_root(split(pre_from_post(read_bvh(source)), "LeftArm"), "Head"), "LeftArm"), "RightFoot"
    )
    edited = read_motion(out)
    assert sorted(edited.names[r] for r in edited.roots) == ["Head", "RightFoot"]
    index = [edited.names.index(n) for n in expected.names]
    original = world_positions(read_bvh(source))
    assert np.abs(world_positions(edited)[:, index] - original).max() <= 1e-9 * expected.size


def test_edit_to_bvh_one_tree_and_a_forest(capsys, tmp_path):
    source = shared_path("cmu/subject01/01_01.bvh")
    code, out, _ = run(capsys, "edit", source, "-o", tmp_path / "e.bvh", "--shift-root", "LeftFoot")
    assert code == 0 and "dummy joints" in out
    edited = read_bvh(tmp_path / "e.bvh")
    assert edited.names[0] == "LeftFoot"
    # a forest goes under one synthetic World root (issue 3: BVH export of any forest)
    code, out, _ = run(capsys, "edit", source, "-o", tmp_path / "f.bvh", "--split", "LeftArm")
    assert code == 0 and "2 trees under the synthetic root 'World'" in out
    forest = read_bvh(tmp_path / "f.bvh")
    assert forest.names[0] == "World" and len(forest.roots) == 1


def test_convert_bvh_to_gmr_and_back(capsys, small_bvh, tmp_path):
    gmr, bvh = tmp_path / "s.gmr", tmp_path / "s.bvh"
    assert run(capsys, "convert", small_bvh, gmr)[0] == 0
    assert gmr.read_text().startswith("GMR 1\n")
    assert run(capsys, "convert", gmr, bvh)[0] == 0
    np.testing.assert_allclose(world_positions(read_bvh(bvh)), world_positions(read_bvh(small_bvh)), atol=1e-12)


def test_bad_file_is_one_line_and_exit_code_2(capsys, small_bvh):
    small_bvh.write_text(SMALL.replace("4 5 6", "4 5 x"))
    code, out, err = run(capsys, "info", small_bvh)
    assert code == 2 and out == ""
    assert err == f"{small_bvh}:20:5: frame 2, value 3: expected a number, found 'x'\n"


def test_refused_operation_is_one_line_and_exit_code_2(capsys, small_bvh, tmp_path):
    code, _, err = run(capsys, "edit", small_bvh, "-o", tmp_path / "o.gmr", "--join", "Spine")
    assert code == 2 and err == "gmr: error: cannot join 'Spine': it is not a root\n"


def test_unknown_format_and_missing_file(capsys, tmp_path):
    code, _, err = run(capsys, "info", tmp_path / "motion.xyz")
    assert code == 2 and "unknown motion format '.xyz'" in err
    code, _, err = run(capsys, "info", tmp_path / "missing.bvh")
    assert code == 2 and "cannot read the file" in err


def test_installed_command_prints_no_traceback(small_bvh):
    small_bvh.write_text(SMALL.replace("Frames: 2", "Frames: 9"))
    result = subprocess.run(
        [sys.executable, "-m", "gmr_studio.core.cli", "info", str(small_bvh)], capture_output=True, text=True
    )
    assert result.returncode == 2
    expected = f"{small_bvh}:21:1: the file ends after 2 frames, but 'Frames:' on line 17 promised 9"
    assert result.stderr.strip() == expected
    assert "Traceback" not in result.stderr


def modules_loaded_by(entry: str, *argv: str) -> tuple[str, str, set[str]]:
    """What ``entry``'s ``main`` prints for ``argv`` in a new interpreter (stdout, stderr), and
    every module it had imported by then."""
    code = (
        "import sys\n"
        f"from {entry} import main\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\n"
        "print('MODULES', *sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, check=True)
    out, _, modules = result.stdout.rpartition("MODULES ")
    return out, result.stderr, set(modules.split())


def test_help_lists_every_command_without_loading_the_numerical_code():
    out, _, loaded = modules_loaded_by("gmr_studio.core.cli", "--help")
    for name, summary in COMMANDS.items():
        assert f"    {name}" in out and summary[:30] in out
    assert not {"numba", "scipy", "gmr_studio.core.formats", "gmr_studio.core.kinematics"} & loaded
    assert not {f"gmr_studio.core.cli.{name}" for name in COMMANDS} & loaded


def test_a_command_loads_its_own_module_and_no_other_commands():
    out, _, loaded = modules_loaded_by("gmr_studio.core.cli", "edit", "--help")
    assert "--shift-root J" in out and "--mirror" in out
    assert "gmr_studio.core.cli.edit" in loaded
    assert not {"gmr_studio.core.cli.bench", "gmr_studio.core.cli.fuzz", "gmr_studio.core.cli.dataset"} & loaded


def test_a_mistyped_command_is_named_with_the_choices():
    _, err, loaded = modules_loaded_by("gmr_studio.core.cli", "conver", "a.bvh")
    assert "invalid choice: 'conver'" in err and "'convert'" in err
    assert "gmr_studio.core.formats" not in loaded


def test_bench_prints_side_by_side_figures(capsys):
    shared_path("cmu/subject01/01_01.bvh")
    code, out, _ = run(capsys, "bench", "--frames", "1000", "--instances", "1", "--repeat", "1", "--no-peers")
    assert code == 0
    for label in ("MB/s", "numpy.loadtxt", "BVH, rotations cached", "BVH, from Euler", "copy of the"):
        assert label in out


def test_stress_runs_on_a_small_motion(capsys):
    shared_path("cmu/subject01/01_01.bvh")
    code, out, _ = run(capsys, "stress", "--frames", "500")
    assert code == 0 and "500 frames x 38 joints" in out and "peak resident memory" in out
