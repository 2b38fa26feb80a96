"""Quality checks' speed, printed (asserts nothing): CMU 01_01.bvh tiled to 100,000 frames
(38 joints), every check of :mod:`core.checks`.

Two figures: the checks with the world positions given (what the app does, its positions
being cached already) and the whole of ``run_checks`` (forward kinematics included); then
each check alone, positions given.

Run: ``.venv/bin/python -m gmr_studio.core.benchmark.checks_speed [--frames 100000]``.
"""

from __future__ import annotations

import argparse
from collections import Counter

from gmr_studio.core.benchmark.compare_speed import tiled
from gmr_studio.core.benchmark.timing import time_call
from gmr_studio.core.checks import CHECKS, KINDS, CheckSettings, run_checks
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics import world_positions
from gmr_studio.core.shared_data import shared_file


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    motion = tiled(read_motion(shared_file("cmu/subject01/01_01.bvh")), args.frames)
    positions = world_positions(motion)
    motion.size  # noqa: B018 - computed once, as the app has it
    print(f"{motion.n_frames} frames x {motion.n_joints} joints (CMU 01_01.bvh tiled), best of {args.repeat}")
    given = time_call(lambda: run_checks(motion, positions=positions), repeat=args.repeat)
    whole = time_call(lambda: run_checks(motion), repeat=args.repeat)
    findings = run_checks(motion, positions=positions)
    print(f"all checks, positions given:  {given.best:.3f} s  ({len(findings)} findings)")
    print(f"all checks with FK:           {whole.best:.3f} s")
    counts = Counter(f.kind for f in findings)
    for kind in KINDS:
        one = time_call(
            lambda kind=kind: run_checks(motion, CheckSettings(kinds=(kind,)), positions=positions),
            repeat=args.repeat,
        )
        print(f"  {kind:<12} {one.best:.3f} s  {counts[kind]:>5} findings")
    print(f"({len(CHECKS)} checks)")


if __name__ == "__main__":
    main()
