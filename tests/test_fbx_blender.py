"""FBX against Blender: Blender's own FBX importer puts every joint of the shared binary FBX
files where the reader does, and Blender's own FBX export of shared BVH files reads back as
the BVH.

Blender runs as a module (``bpy``) in a child process, as in tests/test_gltf_blender.py
(``$GMR_BPY_PYTHON`` or ``.venv-blender``; skipped, saying so, without it, failed with
``GMR_REQUIRE_BLENDER=1``). Times: Blender's FBX importer puts FBX time ``t`` on Blender
frame ``1 + t * fps`` (fps the scene's whole frame rate it sets from the file), where
tests/blender_fbx_positions.py evaluates each of the reader's frame times; Blender's FBX
exporter writes BVH frame ``f`` (Blender frame ``1 + f``) at time ``f / (fps / fps_base)``,
which is the reader's frame ``f`` at the file's rate (120.00048 Hz for CMU's 120 Hz BVH:
Blender keeps 120 fps with ``fps_base`` 0.999996), so FBX frame ``f`` is BVH frame ``f``.
"""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.compare import compare_motions
from gmr_studio.core.formats import read_motion, write_motion
from gmr_studio.core.formats.bvh import read_bvh, write_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import UNITS
from tests.conftest import shared_path
from tests.test_fbx import take_start, ufbx_positions
from tests.test_gltf_blender import bpy_python

ROOT = Path(__file__).resolve().parent.parent
IMPORT_SCRIPT = ROOT / "tests" / "blender_fbx_positions.py"
EXPORT_SCRIPT = ROOT / "tests" / "blender_bvh_to_fbx.py"
#: binary files compared with Blender's import. Left out: the Maya animation layers file
#: (Blender's importer makes one action per layer and plays only the first: it does not
#: blend layers, which the reader does as the file says)
BINARY_FILES = [
    "fbx/ufbx_max_transformed_skin_7500_binary.fbx",
    "fbx/ufbx_maya_anim_interpolation_7700_binary.fbx",
    "fbx/ufbx_maya_character_7500_binary.fbx",
    "fbx/ufbx_maya_kenney_character_7700_binary.fbx",
]
#: frames of a BVH exported through Blender in the round trip
ROUND_TRIP_FRAMES = 240


def run_blender(script: Path, *args: str) -> str:
    done = subprocess.run([str(bpy_python()), str(script), *args], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"Blender's script failed ({done.returncode}):\n{done.stderr[-3000:]}"
    return done.stdout


def to_blender(motion) -> np.ndarray:
    """(3, 3) from the motion's axes (the project's: Y up with front +Z, or Z up with front
    -Y) to Blender's (Z up, front -Y): Blender's importer turns the file's axes to its own."""
    if motion.facts.up_axis == "z":
        return np.eye(3)
    return np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # (x, y, z) -> (x, -z, y)


@pytest.mark.slow
@pytest.mark.parametrize("relative", BINARY_FILES)
def test_blender_import_puts_every_joint_where_the_reader_does(relative, tmp_path):
    path = shared_path(relative)
    motion = read_motion(path)
    # at the frames where every changing curve has a key: between keys Blender's own curves
    # (Bezier handles made from FBX's tangents) differ from FBX's cubic interpolation
    frames = ufbx_positions(path, motion.n_frames, tmp_path)[1]
    times = take_start(motion) + frames * motion.frame_time
    out = tmp_path / "blender.json"
    run_blender(IMPORT_SCRIPT, str(path), str(out), json.dumps(times.tolist()))
    blender = json.loads(out.read_text())["positions"]
    metres = 0.01  # every shared file is in cm (test_fbx checks the units note)
    assert motion.facts.unit.name == "cm"
    ours = world_positions(pre_from_post(motion.frame_slice(frames))) @ to_blender(motion).T * metres
    theirs = np.stack([np.asarray(blender[name]) for name in motion.names], axis=1)
    error = float(np.abs(ours - theirs).max()) / (motion.size * metres)
    print(f"{path.name}: {len(frames)} frames with keys, worst {error:.2e} of the size")
    assert error <= 1e-5


def bvh_through_blender(relative: str, tmp_path: Path, up: str = "Y"):
    """(the BVH trimmed to ROUND_TRIP_FRAMES, the FBX Blender exported of it)."""
    source = read_bvh(shared_path(relative))
    trimmed = source.frame_slice(slice(0, min(source.n_frames, ROUND_TRIP_FRAMES)))
    bvh, fbx = tmp_path / "in.bvh", tmp_path / f"out_{up}.fbx"
    write_bvh(trimmed, bvh)
    run_blender(EXPORT_SCRIPT, str(bvh), str(fbx), up)
    return trimmed, read_motion(fbx)


@pytest.mark.slow
@pytest.mark.parametrize("relative", ["cmu/subject01/01_01.bvh", "bvh/bvh-python_test_mocapbank.bvh"])
def test_blender_fbx_export_of_a_bvh_reads_back_as_the_bvh(relative, tmp_path):
    bvh, fbx = bvh_through_blender(relative, tmp_path)
    assert fbx.n_frames == bvh.n_frames and (fbx.facts.unit.name, fbx.facts.up_axis) == ("cm", "y")
    expected = world_positions(pre_from_post(bvh))
    got = world_positions(pre_from_post(fbx)) / 100  # Blender's metres (the BVH's units) written as cm
    joints = [name for name in fbx.names if name in bvh.names]  # End Sites have no bone
    assert len(joints) == sum(not name.endswith("_End") for name in bvh.names)
    error = np.abs(got[:, [fbx.names.index(n) for n in joints]] - expected[:, [bvh.names.index(n) for n in joints]])
    relative_error = float(error.max()) / bvh.size
    print(f"{relative}: {len(joints)} joints, {bvh.n_frames} frames, worst {relative_error:.2e} of the size")
    assert relative_error <= 1e-5


@pytest.mark.slow
def test_a_blender_export_read_in_bulk_puts_every_joint_where_ufbx_does(tmp_path):
    """Blender bakes a key on every frame, so the reader takes the keys as the file holds them
    and composes FBX's transform stack itself rather than asking ufbx frame by frame: the
    joints are still where ufbx's own evaluation puts them, to rounding, with the float32
    scale Blender writes on every bone and the bones' rest orientations."""
    _, fbx = bvh_through_blender("cmu/subject01/01_01.bvh", tmp_path)
    expected, _ = ufbx_positions(tmp_path / "out_Y.fbx", fbx.n_frames, tmp_path)
    got = world_positions(pre_from_post(fbx))
    reference = np.stack([expected[name] for name in fbx.names], axis=1)
    error = float(np.abs(got - reference).max()) / fbx.size
    print(f"01_01 through Blender: {fbx.n_joints} joints, {fbx.n_frames} frames, worst {error:.2e} of the size")
    assert error <= 1e-9


@pytest.mark.slow
def test_an_fbx_in_cm_z_up_compares_with_metres_y_up_without_flags(tmp_path):
    bvh, fbx = bvh_through_blender("cmu/subject01/01_01.bvh", tmp_path, up="Z")
    assert (fbx.facts.unit.name, fbx.facts.up_axis) == ("cm", "z")
    stated = tmp_path / "walk.gmr"  # the BVH's units are Blender's metres; a GMR file states them
    write_motion(pre_from_post(bvh).replace(facts=FileFacts(unit=UNITS["m"])), stated)
    comparison = compare_motions(read_motion(stated), fbx)
    worst = float(np.nanmax(comparison.position_error))
    print(f"gmr compare walk.gmr out_Z.fbx: worst {worst / bvh.size:.2e} of the size")
    assert worst <= 1e-5 * bvh.size


@pytest.mark.slow
def test_the_benchmark_prints_its_figures(capsys):
    from gmr_studio.core.benchmark.fbx_speed import reading_speed

    shared_path("cmu/subject01/01_01.bvh")
    reading_speed(300, 1, bpy_python())  # the figures themselves: gmr bench --fbx
    out = capsys.readouterr().out
    assert "reading 300 frames" in out and "FBX / glTF:" in out and "ufbx's load alone" in out
    rows = {line.split()[0]: line.split() for line in out.splitlines() if re.match(r"  (FBX|glb) +[0-9.]+ ", line)}
    assert float(rows["glb"][-1]) == 1.0 and float(rows["FBX"][-1]) > 0  # each read as a multiple of glTF's
