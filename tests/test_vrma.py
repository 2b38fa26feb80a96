"""VRM animation (``.vrma``: a glTF binary with the ``VRMC_vrm_animation`` extension) reads
through the glTF reader: its humanoid bones are the skeleton, its expression and lookAt
nodes are not joints, and each bone is where the file's node transforms put it."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from tests.gltf_builder import GltfBuilder, quaternion


def build_vrma(path):
    """A .vrma: hips -> spine -> head, a lookAt node under the head, an expression node at
    the top; the hips move up and the spine turns over three keys (1/30 s apart)."""
    gltf = GltfBuilder()
    head = gltf.node(name="J_Head", translation=[0, 0.3, 0])
    look = gltf.node(name="LookAt", translation=[0, 0.1, 0.2])
    gltf.doc["nodes"][head]["children"] = [look]
    spine = gltf.node(name="J_Spine", translation=[0, 0.2, 0], children=[head])
    hips = gltf.node(name="J_Hips", translation=[0, 1.0, 0], children=[spine])
    happy = gltf.node(name="Expression_happy", translation=[0, 0, 0])
    gltf.doc["scenes"] = [{"nodes": [hips, happy]}]
    times = np.array([0.0, 1 / 30, 2 / 30])
    turns = np.stack([quaternion([0, 0, 1], d) for d in (0, 20, 40)])
    gltf.animation(
        [
            (hips, "translation", times, [[0, 1.0, 0], [0, 1.1, 0], [0, 1.2, 0]], "LINEAR"),
            (spine, "rotation", times, turns, "LINEAR"),
            (happy, "translation", times, [[0, 0, 0], [1, 0, 0], [0, 0, 0]], "LINEAR"),  # an expression's weight
        ]
    )
    gltf.doc["extensionsUsed"] = ["VRMC_vrm_animation"]
    gltf.doc["extensions"] = {
        "VRMC_vrm_animation": {
            "specVersion": "1.0",
            "humanoid": {"humanBones": {"hips": {"node": hips}, "spine": {"node": spine}, "head": {"node": head}}},
            "expressions": {"preset": {"happy": {"node": happy}}},
            "lookAt": {"node": look},
        }
    }
    return gltf.save(path)


def test_humanoid_bones_are_the_skeleton(tmp_path):
    motion = read_motion(build_vrma(tmp_path / "wave.vrma"))
    assert motion.names == ("J_Hips", "J_Spine", "J_Head")  # no LookAt, no Expression_happy
    assert motion.n_frames == 3 and abs(motion.frame_rate - 30) < 1e-3
    assert any("VRM animation: its humanoid bones are the joints" in c for c in motion.comments)
    positions = world_positions(pre_from_post(motion))
    turned = np.radians(40)
    head = [0, 1.2, 0] + 0.3 * np.array([-np.sin(turned), np.cos(turned), 0]) + [0, 0.2, 0]
    np.testing.assert_allclose(positions[2, 2], head, atol=1e-6)  # float32 keys


def test_gmr_info_reads_a_vrma(tmp_path):
    path = build_vrma(tmp_path / "wave.vrma")
    done = subprocess.run(
        [sys.executable, "-m", "gmr_studio.core.cli", "info", str(path)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert "VRM animation (glTF 2.0 binary)" in done.stdout and "joints:     3" in done.stdout
