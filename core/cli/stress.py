"""``gmr stress``: a very large motion (default 1,000,000 frames of CMU 01_01's 38-joint
skeleton) read from BVH, converted to GMR, forward kinematics, written as GMR; prints the
time of each stage and the process's peak memory after it.
"""

from __future__ import annotations

import argparse
import contextlib
import resource
import sys
import tempfile
import time
from pathlib import Path

from gmr_studio.core.benchmark.data import tile_bvh
from gmr_studio.core.cli.progress import Progress
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.gmr import write_gmr
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.shared_data import shared_file

DEFAULT_BVH = "cmu/subject01/01_01.bvh"


def register(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--frames", type=int, default=1_000_000, help="frames (1000000)")
    parser.add_argument("--bvh", default=None, help=f"BVH to tile (default ../shared/data/{DEFAULT_BVH})")
    parser.add_argument("--keep", metavar="DIR", help="write the big files here instead of a temporary folder")
    parser.set_defaults(run=run)


def peak_gib() -> float:
    """Peak resident memory of this process so far, GiB (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def run(args: argparse.Namespace) -> int:
    source = Path(args.bvh) if args.bvh else shared_file(DEFAULT_BVH)
    if not source.exists():
        raise MotionFileError(source, "stress input not found (the shared data folder is missing?)")
    if args.keep:
        Path(args.keep).mkdir(parents=True, exist_ok=True)
    bar = Progress(5, unit="stages", label="stress")
    with contextlib.nullcontext(args.keep) if args.keep else tempfile.TemporaryDirectory() as folder:

        def stage(label, function, *arguments):
            start = time.perf_counter()
            value = function(*arguments)
            line = f"{label:<44}{time.perf_counter() - start:8.1f} s   peak {peak_gib():6.2f} GiB"
            bar.message(line, sys.stdout)
            bar.advance()
            return value

        path = Path(folder) / "large.bvh"
        data = stage("tile the BVH text", tile_bvh, source, args.frames)
        path.write_bytes(data)
        size_mb = len(data) / 1e6
        del data
        post = stage(f"read the BVH ({size_mb:.0f} MB)", read_bvh, path)
        print(f"  {post.n_frames} frames x {post.n_joints} joints")
        gmr = stage("convert to GMR", pre_from_post, post)
        del post
        positions, rotations = stage("forward kinematics (positions, rotations)", forward_kinematics, gmr)
        del positions, rotations
        stage("write the GMR file", write_gmr, gmr, Path(folder) / "large.gmr")
    bar.close()
    print(f"peak resident memory of the whole run: {peak_gib():.2f} GiB")
    return 0
