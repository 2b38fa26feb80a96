"""FBX in, printed side by side with glTF (asserts nothing).

CMU 01_01 (38 joints) tiled to ``--frames`` frames is written as BVH, imported and exported
as FBX by Blender (its own BVH importer and FBX exporter, every frame baked, curve
simplification off: Blender must be installed as a Python module, ``--bpy PYTHON``, by
default ``$GMR_BPY_PYTHON`` or ``.venv-blender/bin/python``), and exported as ``.glb`` by
this project; both are read back (best of ``--repeat``, interleaved). The goal: the FBX
within 2x the time of the glTF.

Run: ``gmr bench --fbx [--frames 100000]`` or
``.venv/bin/python -m gmr_studio.core.benchmark.fbx_speed [--frames 100000]``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from gmr_studio.core.benchmark.formats_speed import best_of
from gmr_studio.core.formats.bvh import read_bvh, write_bvh
from gmr_studio.core.formats.fbx_in import read_fbx
from gmr_studio.core.formats.gltf import export_gltf
from gmr_studio.core.formats.gltf_in import read_gltf
from gmr_studio.core.shared_data import shared_file

#: Blender's BVH import and FBX export, run by the Python that has ``bpy`` (argv: IN OUT)
BLENDER_EXPORT = """
import sys, bpy
source, output = sys.argv[-2], sys.argv[-1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_anim.bvh(filepath=source, global_scale=1.0, update_scene_fps=True, update_scene_duration=True)
bpy.ops.export_scene.fbx(filepath=output, bake_anim=True, bake_anim_simplify_factor=0.0, add_leaf_bones=False)
"""


def default_bpy() -> Path:
    configured = os.environ.get("GMR_BPY_PYTHON")
    return Path(configured) if configured else Path(".venv-blender") / "bin" / "python"


def reading_speed(frames: int, repeat: int, bpy: Path) -> None:
    source = read_bvh(shared_file("cmu/subject01/01_01.bvh"))
    tiled = source.frame_slice(np.arange(frames) % source.n_frames)
    with tempfile.TemporaryDirectory() as folder:
        bvh, fbx, glb = Path(folder) / "tiled.bvh", Path(folder) / "tiled.fbx", Path(folder) / "tiled.glb"
        write_bvh(tiled, bvh)
        start = time.perf_counter()
        subprocess.run([str(bpy), "-c", BLENDER_EXPORT, str(bvh), str(fbx)], check=True, capture_output=True)
        export_seconds = time.perf_counter() - start
        export_gltf(tiled, glb)
        fbx_seconds = glb_seconds = float("inf")
        for _ in range(repeat):  # interleaved, so that a change of the machine's load hits both
            fbx_seconds = min(fbx_seconds, best_of(lambda: read_fbx(fbx), 1))
            glb_seconds = min(glb_seconds, best_of(lambda: read_gltf(glb), 1))
        motion = read_fbx(fbx)
        sizes = fbx.stat().st_size / 1e6, glb.stat().st_size / 1e6
    print(f"reading {frames} frames x {tiled.n_joints} joints (CMU 01_01 tiled), best of {repeat}, interleaved:")
    print(f"  (Blender exported the FBX in {export_seconds:.1f} s: {motion.n_frames} frames, {motion.n_joints} joints)")
    print(f"  {'format':<6} {'file MB':>8} {'seconds':>8} {'MB/s':>7}")
    print(f"  {'FBX':<6} {sizes[0]:>8.1f} {fbx_seconds:>8.2f} {sizes[0] / fbx_seconds:>7.1f}")
    print(f"  {'glb':<6} {sizes[1]:>8.1f} {glb_seconds:>8.2f} {sizes[1] / glb_seconds:>7.1f}")
    print(f"  FBX / glTF time: {fbx_seconds / glb_seconds:.2f} (goal: within 2)")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--bpy", type=Path, default=None, help="a Python with Blender's bpy module")
    args = parser.parse_args(argv)
    reading_speed(args.frames, args.repeat, args.bpy or default_bpy())


if __name__ == "__main__":
    main()
