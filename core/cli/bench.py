"""``gmr bench``: BVH parsing and forward kinematics, timed side by side in one run.

Prints figures, asserts nothing. The motion is CMU 01_01 (from ../shared/data) tiled to
``--frames`` frames.
"""

from __future__ import annotations

import argparse
import io
import tempfile
import time
from pathlib import Path

import numpy as np

from core.convert import pre_from_post
from core.errors import MotionFileError
from core.formats.bvh import read_bvh
from core.kinematics import forward_kinematics
from core.shared_data import shared_file

DEFAULT_BVH = "cmu/subject01/01_01.bvh"


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("bench", help="time BVH parsing and forward kinematics (prints, asserts nothing)")
    parser.add_argument("--frames", type=int, default=100_000, help="frames to tile the motion to (100000)")
    parser.add_argument("--bvh", default=None, help=f"the BVH file to tile (default ../shared/data/{DEFAULT_BVH})")
    parser.add_argument("--repeat", type=int, default=3, help="timings keep the best of this many runs (3)")
    parser.set_defaults(run=run)


def best_time(function, repeat: int) -> float:
    """The fastest of ``repeat`` calls, in seconds."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def tiled_bvh_bytes(source: Path, n_frames: int) -> tuple[bytes, bytes]:
    """A BVH file with the frames of ``source`` repeated to ``n_frames``; also its frame block."""
    data = source.read_bytes().replace(b"\r\n", b"\n")
    head, _, rest = data.partition(b"\nMOTION\n")
    lines = [line for line in rest.split(b"\n")[2:] if line.strip()]
    reps = -(-n_frames // len(lines))
    block = b"\n".join((lines * reps)[:n_frames]) + b"\n"
    header = head + b"\nMOTION\nFrames: %d\nFrame Time: 0.00833333\n" % n_frames
    return header + block, block


def run(args: argparse.Namespace) -> int:
    source = Path(args.bvh) if args.bvh else shared_file(DEFAULT_BVH)
    if not source.exists():
        raise MotionFileError(source, "benchmark input not found (the shared data folder is missing?)")
    data, block = tiled_bvh_bytes(source, args.frames)
    megabytes = len(data) / 1e6
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "tiled.bvh"
        path.write_bytes(data)
        parse = best_time(lambda: read_bvh(path), args.repeat)
        numpy_parse = best_time(lambda: np.loadtxt(io.BytesIO(block), comments=None, ndmin=2), args.repeat)
        post = read_bvh(path)
    gmr = pre_from_post(post)
    frames = post.n_frames
    positions = forward_kinematics(gmr, with_rotations=False)[0]
    rows = [
        ("BVH parse (ours, file -> motion)", parse, f"{megabytes / parse:8.1f} MB/s"),
        ("numpy.loadtxt of the same numbers", numpy_parse, f"{megabytes / numpy_parse:8.1f} MB/s"),
        (
            "post-rotation FK (BVH), positions",
            best_time(lambda: forward_kinematics(post, with_rotations=False), args.repeat),
            "",
        ),
        (
            "pre-rotation FK (GMR), positions",
            best_time(lambda: forward_kinematics(gmr, with_rotations=False), args.repeat),
            "",
        ),
        ("copy of the (F, J, 3) output (memory bound)", best_time(positions.copy, args.repeat), ""),
    ]
    print(f"{source.name} tiled to {frames} frames x {post.n_joints} joints ({megabytes:.1f} MB of BVH)")
    print(f"{'what':<46}{'total':>10}{'per frame':>14}  rate")
    for label, seconds, rate in rows:
        print(f"{label:<46}{seconds * 1e3:8.1f} ms{seconds / frames * 1e6:10.3f} us  {rate}")
    return 0
