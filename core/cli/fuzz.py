"""``gmr fuzz``: attack every reader with mutated real files; print what happened.

Acceptable outcomes are a correct read or the project's error type with path, line and
message. Exit code 1 if any case ended otherwise (listed with how to replay it).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from gmr_studio.core.cli.progress import Progress
from gmr_studio.core.fuzz.runner import OUTCOMES, replay, run_fuzz
from gmr_studio.core.fuzz.targets import all_targets


def register(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--formats", default=None, help="comma-separated formats (default: all available)")
    parser.add_argument("--cases", type=int, default=10_000, help="cases per format (10000)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the run (0)")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds a case may take (10)")
    parser.add_argument("--memory-mb", type=int, default=2048, help="memory a case may allocate (2048 MB)")
    parser.add_argument("--jobs", type=int, default=None, help="worker processes (default: one per core)")
    parser.add_argument("--replay", metavar="FORMAT:INDEX", help="regenerate and read one case in-process")
    parser.add_argument("--save", metavar="FILE", help="with --replay: write the case's bytes to FILE")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.replay:
        name, _, index = args.replay.partition(":")
        case, result = replay(name, args.seed, int(index))
        print(f"case {name}:{index} (seed {args.seed}): {case.seed_file} + {', '.join(case.mutations)}")
        print(f"outcome: {result.outcome}  {result.detail}")
        if args.save:
            Path(args.save).write_bytes(case.data)
            print(f"wrote {args.save} ({len(case.data)} bytes)")
        return 0 if result.outcome in ("read", "clean") else 1
    names = args.formats.split(",") if args.formats else None
    if names:
        unknown = sorted(set(names) - set(all_targets()))
        if unknown:
            print(f"gmr: error: unknown or unavailable formats: {', '.join(unknown)}", file=sys.stderr)
            return 2
    bars: list[Progress] = []

    def show(done: int, total: int) -> None:
        if not bars:
            bars.append(Progress(total, unit="cases", label="fuzz"))
        bars[0].advance(count=done - bars[0].done)

    report = run_fuzz(names, args.cases, args.seed, args.timeout, args.memory_mb, args.jobs, show)
    for bar in bars:
        bar.close()
    print(f"fuzz run: seed {report.seed}, {report.cases_per_target} cases per format, {report.seconds:.0f} s")
    print(report.table())
    for name in report.unavailable:
        print(f"not run: {name}")
    if report.failures:
        print(f"\n{len(report.failures)} cases ended otherwise than {' or '.join(OUTCOMES[:2])}:")
        for failure in report.failures[:40]:
            print(
                f"  {failure.target}:{failure.index} [{failure.outcome}] {failure.seed_file} + "
                f"{', '.join(failure.mutations)}: {failure.detail}"
            )
        print(f"replay one with: gmr fuzz --seed {report.seed} --replay FORMAT:INDEX --save case.bin")
        return 1
    print("\nevery case was a correct read or a clean error")
    return 0
