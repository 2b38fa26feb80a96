"""Comparison speed, printed (asserts nothing): two motions of CMU 01_01.bvh tiled to 100,000
frames (38 joints), B a perturbed copy of A, compared in every mode.

Two figures per mode: the comparison itself (tracks given: what the app does, its world
positions and rotations being cached already) and the whole of ``compare_motions`` (forward
kinematics of both motions included).

Run: ``.venv/bin/python -m gmr_studio.core.benchmark.compare_speed [--frames 100000]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gmr_studio.core.benchmark.timing import time_call
from gmr_studio.core.compare import ALIGN_KINDS, compare_motions, compare_tracks, track_of_motion
from gmr_studio.core.formats import read_motion
from gmr_studio.core.jointmap import match_joints
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import matrix_from_euler
from gmr_studio.core.shared_data import shared_file


def tiled(motion: Motion, n_frames: int) -> Motion:
    return motion.frame_slice(np.arange(n_frames) % motion.n_frames)


def perturbed(motion: Motion, seed: int = 1) -> Motion:
    """Every joint turned by up to ~2 degrees, frame by frame (a different motion, same skeleton)."""
    rng = np.random.default_rng(seed)
    noise = matrix_from_euler(rng.normal(scale=0.02, size=(*motion.rotations.shape[:2], 3)), "XYZ")
    return motion.replace(rotations=motion.rotations @ noise)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--skip-fk", action="store_true", help="time the comparison of tracks only")
    args = parser.parse_args()
    a = tiled(read_motion(shared_file("cmu/subject01/01_01.bvh")), args.frames)
    b = perturbed(a)
    print(f"two motions of {a.n_frames} frames x {a.n_joints} joints (CMU 01_01.bvh tiled; B perturbed)")
    track_a, track_b = track_of_motion(a), track_of_motion(b)
    match = match_joints(a.names, b.names)
    modes = [(kind, 0.0) for kind in ALIGN_KINDS] + [("rigid", "auto"), ("none", 0.5)]
    print(
        f"{'align':<11} {'offset':>6}  {'compare (s)':>11}  {'CPU (s)':>7}  {'with FK (s)':>11}  "
        f"{'MPJPE':>8}  {'max deg':>8}"
    )
    for kind, offset in modes:

        def run_tracks(kind=kind, offset=offset):
            result = compare_tracks(track_a, track_b, match, align=kind, offset=offset)
            return result, result.position, result.rotation  # the summaries are part of it

        result = run_tracks()[0]
        core = time_call(run_tracks, args.repeat)
        cpu = min(_cpu_seconds(run_tracks) for _ in range(args.repeat))
        total = float("nan")
        if not args.skip_fk:
            total = time_call(lambda kind=kind, offset=offset: compare_motions(a, b, align=kind, offset=offset), 1).best
        print(
            f"{kind:<11} {offset!s:>6}  {core.best:>11.3f}  {cpu:>7.3f}  {total:>11.3f}  "
            f"{result.position.mean:>8.4f}  {result.rotation.max:>8.3f}"
        )
    print("(offset 0.5: B between its frames, positions and rotations interpolated; CPU: process time,")
    print(" steadier than wall time on a shared machine; with FK: one run of compare_motions, wall)")


def _cpu_seconds(function) -> float:
    start = time.process_time()
    function()
    return time.process_time() - start


if __name__ == "__main__":
    main()
