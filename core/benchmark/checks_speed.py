"""Quality checks' speed, printed (asserts nothing): CMU 01_01.bvh tiled to 100,000 frames
(38 joints), every check of :mod:`core.checks`.

Two figures: the checks with the world positions given (what the app does, its positions
being cached already) and the whole of ``run_checks`` (forward kinematics included); then
each check alone, positions given.

Run: ``.venv/bin/python -m gmr_studio.core.benchmark.checks_speed [--frames 100000]``.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

from gmr_studio.core.benchmark.compare_speed import tiled
from gmr_studio.core.checks import CHECKS, KINDS, CheckSettings, run_checks
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.shared_data import shared_file


def _timed(function, repeat: int) -> tuple[float, float]:
    """Best wall-clock and best CPU seconds of ``repeat`` runs."""
    walls, cpus = [], []
    for _ in range(max(1, repeat)):
        wall, cpu = time.perf_counter(), time.process_time()
        function()
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return min(walls), min(cpus)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    motion = tiled(read_motion(shared_file("cmu/subject01/01_01.bvh")), args.frames)
    positions = world_positions(motion)
    motion.size  # noqa: B018 - computed once, as the app has it
    print(f"{motion.n_frames} frames x {motion.n_joints} joints (CMU 01_01.bvh tiled), best of {args.repeat}")
    given, given_cpu = _timed(lambda: run_checks(motion, positions=positions), args.repeat)
    whole, whole_cpu = _timed(lambda: run_checks(motion), args.repeat)
    findings = run_checks(motion, positions=positions)
    print("best wall-clock and CPU seconds (on a loaded machine the CPU time is what an idle one takes)")
    print(f"all checks, positions given:  {given:.3f} s  CPU {given_cpu:.3f} s  ({len(findings)} findings)")
    print(f"all checks with FK:           {whole:.3f} s  CPU {whole_cpu:.3f} s")
    counts = Counter(f.kind for f in findings)
    for kind in KINDS:
        settings = CheckSettings(kinds=(kind,))
        wall, cpu = _timed(lambda s=settings: run_checks(motion, s, positions=positions), args.repeat)
        print(f"  {kind:<12} {wall:.3f} s  CPU {cpu:.3f} s  {counts[kind]:>5} findings")
    print(f"({len(CHECKS)} checks)")


if __name__ == "__main__":
    main()
