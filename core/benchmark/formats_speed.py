"""Format speed, printed (asserts nothing), on CMU 01_01 tiled to many frames: the AMC
reader, Euler continuity, and BVH export (dummies back in, continuous angles, text).

Run: ``.venv/bin/python -m core.benchmark.formats_speed [--frames 100000]``.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from gmr_studio.core.edits.dummies import remove_dummies
from gmr_studio.core.formats.acclaim import read_amc, read_asf
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.bvh_export import bvh_export
from gmr_studio.core.rotations.continuity import continuous_euler
from gmr_studio.core.shared_data import shared_file


def tiled_amc(source: Path, n_frames: int) -> bytes:
    """The AMC's frames repeated (and renumbered) up to ``n_frames``."""
    lines = source.read_bytes().replace(b"\r\n", b"\n").split(b"\n")
    header = [line for line in lines if line.startswith((b":", b"#"))]
    frames: list[list[bytes]] = []
    for line in lines:
        if line.strip().isdigit():
            frames.append([])
        elif line.strip() and not line.startswith((b":", b"#")):
            frames[-1].append(line)
    out = list(header)
    for f in range(n_frames):
        out.append(b"%d" % (f + 1))
        out.extend(frames[f % len(frames)])
    return b"\n".join(out) + b"\n"


def best_of(function, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    skeleton = read_asf(shared_file("cmu/subject01/01.asf"))
    data = tiled_amc(shared_file("cmu/subject01/01_01.amc"), args.frames)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "tiled.amc"
        path.write_bytes(data)
        seconds = best_of(lambda: read_amc(path, skeleton), args.repeat)
    megabytes = len(data) / 1e6
    rate = megabytes / seconds
    print(f"AMC read, 01_01 tiled to {args.frames} frames ({megabytes:.1f} MB): {seconds:.2f} s, {rate:.1f} MB/s")
    bvh = read_bvh(shared_file("cmu/subject01/01_01.bvh"))
    tiled = bvh.frame_slice(np.arange(args.frames) % bvh.n_frames)
    seconds = best_of(lambda: continuous_euler(tiled.rotations, "ZYX"), args.repeat)
    print(f"continuous Euler angles, {args.frames} frames x {bvh.n_joints} joints: {seconds:.2f} s")
    cleaned, _ = remove_dummies(tiled)
    seconds = best_of(lambda: remove_dummies(tiled), args.repeat)
    print(f"remove_dummies, {args.frames} frames x {bvh.n_joints} joints: {seconds:.2f} s")
    export = bvh_export(cleaned)
    seconds = best_of(lambda: bvh_export(cleaned), args.repeat)
    print(f"BVH export (dummies back in), {args.frames} frames: {seconds:.2f} s")
    seconds = best_of(export.text, args.repeat)
    print(f"BVH text of that export ({export.motion.n_joints} joints, continuous angles): {seconds:.2f} s")


if __name__ == "__main__":
    main()
