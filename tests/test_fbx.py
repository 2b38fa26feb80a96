"""FBX in: every animated FBX of the shared data reads with each joint where ufbx's own
evaluation puts it; the CLI reads every file and exits 0; takes are listed and chosen;
units and axes are the file's; bad files get the one-line error.

ufbx's evaluation (the oracle) runs in a child process, ``tests/ufbx_world_positions.py``:
world positions from ``evaluate_scene`` and ``node_to_world``, an independent route from the
reader's (which composes each node's local transform and runs the project's FK).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.fbx_in import fbx_contents, read_fbx
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import shared_files, shared_path

ROOT = Path(__file__).resolve().parent.parent
ORACLE = ROOT / "tests" / "ufbx_world_positions.py"
FBX_FILES = shared_files("fbx/*.fbx")
#: frames of each take compared (the shared takes have at most 120)
ORACLE_FRAMES = 150


def take_start(motion) -> float:
    """The time of the motion's first frame, as its take note states it."""
    note = next(c for c in motion.comments if c.startswith("take "))
    return float(note.split(": ", 1)[1].split(" to ")[0])


def ufbx_positions(
    path: Path, n_frames: int, tmp_path: Path, take: int = 0
) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """ufbx's world position of every node (name -> (F, 3)) at the first frames of a take,
    and the frames holding a key of every curve that changes (K,)."""
    out = tmp_path / "ufbx.npz"
    done = subprocess.run(
        [sys.executable, str(ORACLE), str(path), str(out), str(take), str(n_frames)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    with np.load(out) as archive:
        positions = {str(name): archive["positions"][:, k] for k, name in enumerate(archive["names"])}
        return positions, archive["keyed"]


@pytest.mark.parametrize("path", FBX_FILES)
def test_every_joint_is_where_ufbx_puts_it(path, tmp_path):
    motion = read_motion(path)
    n = min(motion.n_frames, ORACLE_FRAMES)
    expected, _ = ufbx_positions(path, n, tmp_path)
    got = world_positions(pre_from_post(motion.frame_slice(slice(0, n))))
    reference = np.stack([expected[name] for name in motion.names], axis=1)
    error = float(np.abs(got - reference).max()) / motion.size
    print(f"{path.name}: {motion.n_joints} joints, {n} frames, worst {error:.2e} of the size {motion.size:.4g}")
    assert error <= 1e-9


#: runs ``gmr info`` and ``gmr positions`` on each file given, in one process, and exits
#: with the first non-zero status (or 0): the CLI's own exit, after every file was read
CLI_RUN = """
import sys
from gmr_studio.core.cli import main
status = 0
for k, path in enumerate(sys.argv[2:]):
    for argv in (["info", path], ["positions", path, "-o", f"{sys.argv[1]}/{k}.npz"]):
        status = status or main(argv)
sys.exit(status)
"""


def test_cli_reads_every_file_and_exits_zero(tmp_path):
    files = [path for path in (p.values[0] for p in FBX_FILES) if path is not None]
    if not files:
        pytest.skip("no shared data")
    done = subprocess.run(
        [sys.executable, "-c", CLI_RUN, str(tmp_path), *map(str, files)], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.count("format:     FBX (read only)") == len(files)
    for k, path in enumerate(files):
        with np.load(tmp_path / f"{k}.npz") as archive:
            assert archive["positions"].shape[0] == read_motion(path).n_frames


def test_info_lists_the_takes_and_what_is_left_out():
    path = shared_path("fbx/ufbx_max_transformed_skin_7500_binary.fbx")
    done = subprocess.run(
        [sys.executable, "-m", "gmr_studio.core.cli", "info", str(path)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert "take:       0 'Take 001', 0 to 3.33333 s (--animation)" in done.stdout
    assert "nodes:      6 (5 bones); left out: 1 mesh" in done.stdout
    assert "units:      cm" in done.stdout and "up axis:    z (stated)" in done.stdout
    contents = fbx_contents(path)
    assert [take["name"] for take in contents["takes"]] == ["Take 001"]
    assert (contents["bones"], contents["meshes"], contents["frame_rate"]) == (5, 1, 30.0)


def test_a_take_is_its_time_span_at_the_files_rate():
    motion = read_fbx(shared_path("fbx/ufbx_maya_anim_layers_7500_binary.fbx"))
    assert motion.frame_rate == pytest.approx(24.0)
    assert motion.n_frames == 120  # 1/24 s to 5 s, both ends
    assert take_start(motion) == pytest.approx(1 / 24)
    assert any("3 layers blended" in c for c in motion.comments)


def test_the_take_is_chosen_by_name_or_index():
    path = shared_path("fbx/ufbx_maya_character_7500_binary.fbx")
    first = read_fbx(path)
    for wanted in (0, "0", "Take 001"):
        chosen = read_fbx(path, animation=wanted)
        assert np.array_equal(chosen.rotations, first.rotations)
    with pytest.raises(MotionFileError, match=r"no take of that name .*'Take 001'"):
        read_fbx(path, animation="Walk")
    with pytest.raises(MotionFileError, match=r"the file has 1 takes \(0..0\)"):
        read_fbx(path, animation=3)


def test_bones_make_the_skeleton_and_meshes_are_left_out():
    motion = read_fbx(shared_path("fbx/ufbx_maya_kenney_character_7700_binary.fbx"))
    assert "Hips" in motion.names and not any("Mesh" in name or "mesh" in name for name in motion.names)
    assert any(c.startswith("left out: 1 mesh") for c in motion.comments)


def test_node_animation_without_bones_makes_every_node_a_joint():
    motion = read_fbx(shared_path("fbx/ufbx_maya_transform_animation_7500_ascii.fbx"))
    assert motion.names == ("pCube1",)
    assert any("no bones: every node is a joint" in c for c in motion.comments)
    assert np.ptp(motion.translations[:, 0], axis=0).max() > 0  # the cube moves


def test_units_and_up_axis_are_the_files():
    z_up = read_fbx(shared_path("fbx/ufbx_max_transformed_skin_7500_binary.fbx"))
    y_up = read_fbx(shared_path("fbx/ufbx_maya_character_7500_binary.fbx"))
    assert (z_up.facts.unit.name, z_up.facts.up_axis) == ("cm", "z")
    assert (y_up.facts.unit.name, y_up.facts.up_axis) == ("cm", "y")


# --------------------------------------------------------------------------- bad files
def bad_files(tmp_path: Path) -> dict[str, Path]:
    source = shared_path("fbx/ufbx_maya_character_7500_binary.fbx").read_bytes()
    ascii_source = shared_path("fbx/ufbx_maya_transform_animation_7500_ascii.fbx").read_bytes()
    rng = np.random.default_rng(41)
    corrupt = bytearray(source)
    corrupt[2000:6000] = rng.integers(0, 256, 4000, dtype=np.uint8).tobytes()
    cases = {
        "truncated": source[: len(source) // 3],
        "header only": source[:27],
        "corrupt": bytes(corrupt),
        "ascii cut": ascii_source[: len(ascii_source) // 2],
        "not fbx": b"HIERARCHY\nROOT Hips\n{\n",
        "empty": b"",
    }
    paths = {}
    for name, data in cases.items():
        paths[name] = tmp_path / f"{name.replace(' ', '_')}.fbx"
        paths[name].write_bytes(data)
    return paths


def test_bad_files_get_one_line_naming_the_file(tmp_path):
    for name, path in bad_files(tmp_path).items():
        try:
            read_fbx(path)
        except MotionFileError as exc:
            text = str(exc)
            assert text.startswith(str(path)) and "\n" not in text, f"{name}: {text!r}"
        # a corrupt file that ufbx still reads is fine, as long as it reads a valid motion
    with pytest.raises(MotionFileError, match="not an FBX file"):
        read_fbx(bad_files(tmp_path)["not fbx"])
    with pytest.raises(MotionFileError, match="empty"):
        read_fbx(bad_files(tmp_path)["empty"])


def test_cli_says_one_line_for_a_bad_file(tmp_path):
    path = bad_files(tmp_path)["truncated"]
    done = subprocess.run(
        [sys.executable, "-m", "gmr_studio.core.cli", "info", str(path)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert done.stderr.strip().count("\n") == 0 and str(path) in done.stderr


def test_file_facts_name_the_unit_or_convert_to_metres():
    from gmr_studio.core.formats.fbx_in.skeleton import file_facts

    factor, turn, facts, lines = file_facts(0.01, [0, 4, 3])  # 3ds Max: right +x, up +z, front -y
    assert factor == 1.0 and np.array_equal(turn, np.eye(3))
    assert (facts.unit.name, facts.up_axis) == ("cm", "z") and lines == ["axes: right +x, up +z, front -y (the file's)"]
    factor, turn, facts, lines = file_facts(0.05, [0, 2, 4])
    assert factor == 0.05 and facts.unit.scaled(factor).name == "m" and facts.up_axis == "y"
    _, turn, facts, lines = file_facts(0.01, [1, 4, 2])  # Blender's Z up export: right -x, front +y
    assert np.array_equal(turn, np.diag([-1.0, -1.0, 1.0])) and facts.up_axis == "z"
    _, turn, facts, lines = file_facts(1.0, [2, 0, 4])  # X up: turned to Y up
    assert np.array_equal(turn @ [1, 0, 0], [0, 1, 0]) and facts.up_axis == "y"


def test_json_info_is_plain_data(tmp_path):
    path = shared_path("fbx/ufbx_maya_anim_interpolation_7700_binary.fbx")
    done = subprocess.run(
        [sys.executable, "-m", "gmr_studio.core.cli", "info", str(path), "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    info = json.loads(done.stdout)
    assert info["format"] == "FBX (read only)" and info["fbx"]["takes"][0]["name"] == "Take 001"
