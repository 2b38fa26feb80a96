"""glTF everywhere a motion is read: positions, convert (glTF to BVH and GMR), compare (units
from both files), batch conversion and the dataset, with --animation/--skin/--frame-rate."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import shared_path


def positions_by_name(motion) -> dict[str, np.ndarray]:
    return dict(zip(motion.names, np.moveaxis(world_positions(motion), 1, 0)))


def test_positions_with_the_animation_chosen(tmp_path, capsys):
    fox = shared_path("gltf/bevy_Fox.glb")
    out = tmp_path / "walk.npz"
    assert main(["positions", str(fox), "--animation", "Walk", "-o", str(out)]) == 0
    with np.load(out) as data:
        np.testing.assert_array_equal(data["positions"], world_positions(read_motion(fox, animation="Walk")))
    assert main(["positions", str(fox), "--frame-rate", "10", "-o", str(out)]) == 0
    with np.load(out) as data:
        assert data["positions"].shape[0] == 36  # Survey: 3.5 s at 10 Hz, last frame on its last key
    csv = tmp_path / "walk.csv"
    arguments = ["--animation", "Walk", "--quantity", "speed", "--joints", "b_Head_05", "-o", str(csv)]
    assert main(["curves", str(fox), *arguments]) == 0
    assert len(csv.read_text().splitlines()) == 1 + read_motion(fox, animation="Walk").n_frames


@pytest.mark.parametrize("suffix", [".bvh", ".gmr"])
def test_convert_gltf_to_bvh_and_gmr_keeps_every_joint(tmp_path, suffix):
    source = shared_path("gltf/mediaplusarchi_RobotExpressive.glb")
    out = tmp_path / f"robot{suffix}"
    assert main(["convert", str(source), str(out), "--animation", "Walking"]) == 0
    original, converted = (
        positions_by_name(read_motion(source, animation="Walking")),
        positions_by_name(read_motion(out)),
    )
    size = read_motion(source).size
    worst = max(float(np.abs(converted[name] - value).max()) for name, value in original.items())
    assert worst <= (1e-6 if suffix == ".bvh" else 1e-12) * size  # docs/formats.md: BVH 1e-6, GMR 15 digits


def test_compare_bvh_with_its_glb_on_its_clock_in_its_units(tmp_path, capsys):
    bvh = shared_path("cmu/subject01/01_01.bvh")
    glb = tmp_path / "walk.glb"
    assert main(["convert", str(bvh), str(glb)]) == 0
    capsys.readouterr()
    assert main(["compare", str(bvh), str(glb)]) == 0
    out = capsys.readouterr().out
    assert "B in m, exported from ASF unit (in / 0.45) (its file facts); A states no unit" in out
    assert "unmatched in A: none" in out and "unmatched in B: none" in out
    mpjpe = float(out.split("MPJPE:")[1].split()[0])
    assert mpjpe < 2e-7 * read_motion(bvh).size  # float32: docs/gltf.md
    rotation_max = float(out.split("rotation:")[1].split("max")[1].split()[0])
    assert rotation_max < 1e-3  # our pre-rotation export read back as pre-rotation: same joint frames


def test_batch_and_dataset_read_gltf(tmp_path, capsys):
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(shared_path("gltf/bevy_Fox.glb"), folder / "fox.glb")
    external = shared_path("gltf/blenderio_03_skinned_cylinder/03_skinned_cylinder.gltf")
    shutil.copytree(external.parent, folder / "cylinder")
    assert main(["convert", "--batch", str(folder), str(tmp_path / "out"), "--to", "gmr", "--jobs", "1"]) == 0
    converted = read_motion(tmp_path / "out" / "cylinder" / "03_skinned_cylinder.gmr")
    np.testing.assert_allclose(world_positions(converted), world_positions(read_motion(external)), atol=1e-12)
    table = tmp_path / "positions.npz"
    assert main(["dataset", str(folder), "-o", str(table), "--jobs", "1", "--animation", "0"]) == 0
    with np.load(table) as data:
        files = list(data["files"])
        assert files == ["cylinder/03_skinned_cylinder.gltf", "fox.glb"]
        np.testing.assert_allclose(data["values_1"], world_positions(read_motion(folder / "fox.glb")), rtol=1e-6)


def test_gltf_to_gltf_keeps_metres(tmp_path, capsys):
    fox = shared_path("gltf/bevy_Fox.glb")  # 100 m tall: the unit inference would take it for cm
    out = tmp_path / "fox.glb"
    assert main(["convert", str(fox), str(out), "--animation", "Run"]) == 0
    assert "lengths in m as the motion states, times 1" in capsys.readouterr().out
    before, after = read_motion(fox, animation="Run"), read_motion(out)
    worst = float(np.abs(world_positions(before) - world_positions(after)).max())
    assert worst <= 2e-7 * before.size  # float32


def test_the_benchmark_prints_its_figures(capsys):
    from gmr_studio.core.benchmark.gltf_speed import reading_speed

    shared_path("cmu/subject01/01_01.bvh")
    reading_speed(300, 1)  # the figures themselves: python -m gmr_studio.core.benchmark.gltf_speed
    out = capsys.readouterr().out
    assert "reading 300 frames x 38 joints" in out and "glTF / BVH time:" in out
