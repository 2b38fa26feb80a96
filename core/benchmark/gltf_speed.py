"""glTF in, printed side by side with BVH (asserts nothing):

1. reading speed: CMU 01_01 (38 joints) tiled to ``--frames`` frames, written as BVH and as
   our ``.glb`` export, each read back (best of ``--repeat``); the goal is glTF within 2x
   the time of BVH;
2. round-trip precision: every motion of ../shared/data through ``gmr audit``'s glTF path
   (export to ``.glb`` in memory, read back, units and up axis undone) and, beside it, its
   BVH path: the worst joint distance relative to the size, against the glTF tolerance.

Run: ``.venv/bin/python -m gmr_studio.core.benchmark.gltf_speed [--frames 100000]``.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from gmr_studio.core.benchmark.formats_speed import best_of
from gmr_studio.core.compare.audit import GLTF_FILE_TOLERANCE, audit_motion
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.bvh import read_bvh, write_bvh
from gmr_studio.core.formats.gltf import export_gltf
from gmr_studio.core.formats.gltf_in import read_gltf
from gmr_studio.core.shared_data import shared_data_dir, shared_file

ROUND_TRIPS = {
    "glTF written and read": "glTF",
    "forest glTF after split all": "glTF forest",
    "BVH written and read": "BVH",
}


def reading_speed(frames: int, repeat: int) -> None:
    source = read_bvh(shared_file("cmu/subject01/01_01.bvh"))
    tiled = source.frame_slice(np.arange(frames) % source.n_frames)
    with tempfile.TemporaryDirectory() as folder:
        bvh, glb = Path(folder) / "tiled.bvh", Path(folder) / "tiled.glb"
        write_bvh(tiled, bvh)
        export_gltf(tiled, glb)
        bvh_seconds = glb_seconds = float("inf")
        for _ in range(repeat):  # interleaved, so that a change of the machine's load hits both
            bvh_seconds = min(bvh_seconds, best_of(lambda: read_bvh(bvh), 1))
            glb_seconds = min(glb_seconds, best_of(lambda: read_gltf(glb), 1))
        sizes = bvh.stat().st_size / 1e6, glb.stat().st_size / 1e6
    print(f"reading {frames} frames x {tiled.n_joints} joints (CMU 01_01 tiled), best of {repeat}, interleaved:")
    print(f"  {'format':<6} {'file MB':>8} {'seconds':>8} {'MB/s':>7}")
    print(f"  {'BVH':<6} {sizes[0]:>8.1f} {bvh_seconds:>8.2f} {sizes[0] / bvh_seconds:>7.1f}")
    print(f"  {'glb':<6} {sizes[1]:>8.1f} {glb_seconds:>8.2f} {sizes[1] / glb_seconds:>7.1f}")
    print(f"  glTF / BVH time: {glb_seconds / bvh_seconds:.2f} (goal: within 2)")


def round_trip_precision() -> None:
    folder = shared_data_dir()
    files = sorted(folder.glob("**/*.bvh")) + sorted(folder.glob("**/*.amc")) + sorted(folder.glob("gltf/**/*.gl*"))
    print(f"\nround trips, worst joint distance / size (glTF tolerance {GLTF_FILE_TOLERANCE:.0e}):")
    width = max([len(str(f.relative_to(folder))) for f in files] + [4])
    print(f"  {'file':<{width}} {'frames':>7} {'joints':>6}  " + "  ".join(f"{n:>11}" for n in ROUND_TRIPS.values()))
    worst = 0.0
    for path in files:
        motion = read_motion(path)
        paths = {p.name: p for p in audit_motion(motion, path, every=10**9) if p.name in ROUND_TRIPS}
        cells = [f"{paths[name].relative_error:>11.2e}" for name in ROUND_TRIPS]
        worst = max([worst] + [paths[name].relative_error for name in ROUND_TRIPS if "glTF" in name])
        relative = str(path.relative_to(folder))
        print(f"  {relative:<{width}} {motion.n_frames:>7} {motion.n_joints:>6}  " + "  ".join(cells))
    print(f"  worst glTF round trip: {worst:.2e} of the size ({len(files)} motions)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--skip-precision", action="store_true", help="only the reading speed")
    args = parser.parse_args()
    reading_speed(args.frames, args.repeat)
    if not args.skip_precision:
        round_trip_precision()


if __name__ == "__main__":
    main()
