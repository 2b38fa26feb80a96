"""Blender's own glTF export of a CMU BVH reads back, and ``gmr compare`` finds every joint
within 1e-5 of the size of the BVH's.

Blender imports ``01_01.bvh`` (its BVH importer, scale 1: BVH units become metres) and
exports ``.glb`` (its glTF exporter, every frame sampled): bones named as the joints, an
armature object above them, and each bone's rest orientation (along the limb) in its
node's frame. The reader takes the armature's transform into the root and the rest
orientations (from the inverse bind matrices) out of the frames, so both positions and
world rotations compare with the BVH's; the BVH's End Sites have no bone and stay
unmatched. Runs ``tests/blender_bvh_to_gltf.py`` with the Python that has ``bpy``
(:func:`tests.test_gltf_blender.bpy_python`; skipped, saying so, without one).
"""

from __future__ import annotations

import subprocess

import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.formats import read_motion
from tests.conftest import shared_path
from tests.test_gltf_blender import ROOT, bpy_python

SCRIPT = ROOT / "tests" / "blender_bvh_to_gltf.py"
#: measured (Blender 5.0.1, CMU 01_01): positions 1.2e-6 of the size, rotations 7.8e-5 deg
RELATIVE_TOLERANCE = 1e-5
ROTATION_TOLERANCE_DEGREES = 1e-3


@pytest.mark.slow
def test_blender_export_of_a_cmu_bvh_compares_within_1e5_of_the_size(tmp_path, capsys):
    bvh = shared_path("cmu/subject01/01_01.bvh")
    glb = tmp_path / "blender.glb"
    subprocess.run([str(bpy_python()), str(SCRIPT), str(bvh), str(glb)], check=True, capture_output=True, timeout=600)
    a, b = read_motion(bvh), read_motion(glb)
    assert any(c.startswith("rest pose: the skin's bind pose") for c in b.comments)
    assert any(c.startswith("armature: the transform of") for c in b.comments)
    result = compare_motions(a, b)
    end_sites = {name for name in a.names if name.endswith("_End")}
    assert set(result.unmatched_a) == end_sites and not result.unmatched_b
    assert result.n_frames == a.n_frames and result.position.count == a.n_frames * result.n_pairs
    print(f"Blender glb against 01_01.bvh: positions {result.position.max / a.size:.1e} of the size, "
          f"rotations {result.rotation.max:.1e} deg")  # fmt: skip
    assert result.position.max <= RELATIVE_TOLERANCE * a.size
    assert result.rotation.max <= ROTATION_TOLERANCE_DEGREES
    assert main(["compare", str(bvh), str(glb)]) == 0
    out = capsys.readouterr().out
    assert "read B:   rest pose: the skin's bind pose" in out and "read B:   armature:" in out
