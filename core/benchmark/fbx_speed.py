"""FBX in, printed side by side with glTF (asserts nothing).

CMU 01_01 (38 joints) tiled to ``--frames`` frames is written as BVH, imported and exported
as FBX by Blender (its own BVH importer and FBX exporter, every frame baked, curve
simplification off: Blender must be installed as a Python module, ``--bpy PYTHON``, by
default ``$GMR_BPY_PYTHON`` or ``.venv-blender/bin/python``), and exported as ``.glb`` by
this project; both are read back (best of ``--repeat``, interleaved). The goal: the FBX
within 2x the time of the glTF. Each read is timed in wall seconds and in CPU seconds (this
process and its children: the FBX reader's child process), and the load average is printed,
since on a shared machine the wall time moves with the other jobs. Timed with them: ufbx
loading the file in a new process and doing nothing else, the floor of a reader on ufbx.

``--keep DIR`` keeps the three files in DIR and reuses them when they are there for the
same number of frames (Blender's export of 100,000 frames takes minutes).

Run: ``gmr bench --fbx [--frames 100000]`` or
``.venv/bin/python -m gmr_studio.core.benchmark.fbx_speed [--frames 100000] [--keep DIR]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

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


#: ufbx's load of the file alone, as the reader's child process loads it, and nothing else
#: (argv: FILE): the floor under any reader built on ufbx
UFBX_LOAD_ONLY = """
import os, sys, ufbx
ufbx.load_file(sys.argv[1], retain_dom=True, no_format_from_extension=True)
os._exit(0)
"""


def default_bpy() -> Path:
    configured = os.environ.get("GMR_BPY_PYTHON")
    return Path(configured) if configured else Path(".venv-blender") / "bin" / "python"


def cpu_seconds() -> float:
    """CPU seconds (user and system) of this process and of its children that have ended."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed(function) -> tuple[float, float]:
    """(wall seconds, CPU seconds) of one call."""
    wall, cpu = time.perf_counter(), cpu_seconds()
    function()
    return time.perf_counter() - wall, cpu_seconds() - cpu


def made_files(frames: int, folder: Path, bpy: Path) -> tuple[Path, Path, float | None]:
    """(FBX, glb) of CMU 01_01 tiled to ``frames`` in ``folder`` and the seconds Blender took
    to export the FBX (None: the files of an earlier run with as many frames were reused)."""
    fbx, glb, stamp = folder / "tiled.fbx", folder / "tiled.glb", folder / "frames.txt"
    if fbx.exists() and glb.exists() and stamp.exists() and stamp.read_text().strip() == str(frames):
        return fbx, glb, None
    source = read_bvh(shared_file("cmu/subject01/01_01.bvh"))
    tiled = source.frame_slice(np.arange(frames) % source.n_frames)
    bvh = folder / "tiled.bvh"
    write_bvh(tiled, bvh)
    start = time.perf_counter()
    subprocess.run([str(bpy), "-c", BLENDER_EXPORT, str(bvh), str(fbx)], check=True, capture_output=True)
    export_seconds = time.perf_counter() - start
    export_gltf(tiled, glb)
    stamp.write_text(f"{frames}\n")
    return fbx, glb, export_seconds


def reading_speed(frames: int, repeat: int, bpy: Path, keep: Path | None = None) -> None:
    with tempfile.TemporaryDirectory() as scratch:
        folder = keep or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        fbx, glb, export_seconds = made_files(frames, folder, bpy)
        load_before = os.getloadavg()[0]
        load_only = [sys.executable, "-c", UFBX_LOAD_ONLY, str(fbx)]
        readers = {
            "FBX": lambda: read_fbx(fbx),
            "glb": lambda: read_gltf(glb),
            "ufbx load": lambda: subprocess.run(load_only, check=True),
        }
        best = {name: (float("inf"), float("inf")) for name in readers}
        for _ in range(repeat):  # interleaved, so that a change of the machine's load hits both
            for name, read in readers.items():
                wall, cpu = timed(read)
                best[name] = (min(best[name][0], wall), min(best[name][1], cpu))
        load_after = os.getloadavg()[0]
        motion = read_fbx(fbx)
        sizes = {"FBX": fbx.stat().st_size / 1e6, "glb": glb.stat().st_size / 1e6}
    made = "reused from --keep" if export_seconds is None else f"Blender exported the FBX in {export_seconds:.1f} s"
    sizes["ufbx load"] = sizes["FBX"]
    print(f"reading {frames} frames (CMU 01_01 tiled), best of {repeat}, interleaved:")
    print(f"  ({made}: {motion.n_frames} frames, {motion.n_joints} joints)")
    print(f"  {'read':<10} {'file MB':>8} {'wall s':>8} {'CPU s':>8} {'MB/s':>7} {'x glTF':>7}")
    for name, (wall, cpu) in best.items():
        ratio = wall / best["glb"][0]
        print(f"  {name:<10} {sizes[name]:>8.1f} {wall:>8.2f} {cpu:>8.2f} {sizes[name] / wall:>7.1f} {ratio:>7.2f}")
    wall_ratio = best["FBX"][0] / best["glb"][0]
    cpu_ratio = best["FBX"][1] / best["glb"][1]
    print(f"  FBX / glTF: {wall_ratio:.2f} in wall time, {cpu_ratio:.2f} in CPU time (goal: within 2)")
    floor = best["ufbx load"][0] / best["glb"][0], best["ufbx load"][1] / best["glb"][1]
    print(f"  ufbx's load alone (a new process, no reading): {floor[0]:.2f} x glTF in wall, {floor[1]:.2f} in CPU time")
    print(f"  load average: {load_before:.1f} before the reads, {load_after:.1f} after ({os.cpu_count()} cores)")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--bpy", type=Path, default=None, help="a Python with Blender's bpy module")
    parser.add_argument("--keep", type=Path, default=None, metavar="DIR", help="keep the files there and reuse them")
    args = parser.parse_args(argv)
    reading_speed(args.frames, args.repeat, args.bpy or default_bpy(), args.keep)


if __name__ == "__main__":
    main()
