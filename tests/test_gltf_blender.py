"""Blender's own glTF importer reads our export with every joint where FK puts it.

Runs ``tests/blender_gltf_positions.py`` with a Python that has ``bpy`` (Blender as a
module): ``$GMR_BPY_PYTHON``, else ``.venv-blender/bin/python`` of the checkout (make it with
``python3 -m venv .venv-blender && .venv-blender/bin/pip install bpy``, about 1 GB, or
``sh .ci/setup --tests``). Locally skipped, saying so, when neither exists; with
``GMR_REQUIRE_BLENDER=1`` (as ``.ci/run`` sets, where setup must have installed it) that fails.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.edits.operations import split
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.gltf import export_gltf
from gmr_studio.core.kinematics.convention import pre_from_post
from tests.conftest import shared_path
from tests.test_gltf import expected_positions

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "tests" / "blender_gltf_positions.py"
#: measured worst difference between Blender's positions and FK, relative to the size:
#: 2.3e-7 as empties, 4.0e-7 as an armature's pose bones (CMU 01_01, bpy 5.0.1); docs/gltf.md
BLENDER_RELATIVE_TOLERANCE = 2e-6


def bpy_python() -> Path:
    configured = os.environ.get("GMR_BPY_PYTHON")
    path = Path(configured) if configured else ROOT / ".venv-blender" / "bin" / "python"
    if not path.exists():
        why = f"no Python with bpy at {path} (set GMR_BPY_PYTHON or create .venv-blender: docs/gltf.md)"
        if os.environ.get("GMR_REQUIRE_BLENDER") == "1":
            pytest.fail(f"GMR_REQUIRE_BLENDER=1 but {why}; `sh .ci/setup --tests` installs it", pytrace=False)
        pytest.skip(why)
    return path


def blender_positions(glb: Path, n_frames: int, frame_time: float, tmp_path: Path) -> dict:
    out = tmp_path / "blender.json"
    done = subprocess.run(
        [str(bpy_python()), str(SCRIPT), str(glb), str(out), str(n_frames), repr(frame_time)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, f"Blender's script failed ({done.returncode}):\n{done.stderr[-3000:]}"
    return json.loads(out.read_text())


@pytest.mark.slow
@pytest.mark.parametrize("skin", [False, True], ids=["empties", "armature"])
def test_blender_reads_positions(tmp_path, skin):
    motion = pre_from_post(read_motion(shared_path("cmu/subject01/01_01.bvh"))).frame_slice(slice(0, 240, 3))
    motion = split(motion, "LeftUpLeg")  # a forest: two trees under the World root
    glb = tmp_path / "walk.glb"
    result = export_gltf(motion, glb, skin=skin)
    blender = blender_positions(glb, motion.n_frames, motion.frame_time, tmp_path)
    expected = expected_positions(motion, "y", result.metres_per_unit)
    got_blender = np.stack([np.asarray(blender["positions"][name]) for name in motion.names], axis=1)
    got = got_blender[..., [0, 2, 1]] * [1, 1, -1]  # Blender (x, y, z) is glTF (x, -z, y)
    error = float(np.abs(got - expected).max()) / (motion.size * result.metres_per_unit)
    print(f"Blender {blender['blender']}, skin={skin}: worst error {error:.2e} of the size")
    assert error <= BLENDER_RELATIVE_TOLERANCE
