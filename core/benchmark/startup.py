"""Start-up of the command lines, printed (asserts nothing): ``gmr --help`` and
``gmr-studio --help`` beside ``python -c "import numpy"``, each a whole new process.

The commands run in turn (numpy, gmr, gmr-studio, numpy, gmr, ...) so that a machine whose
speed drifts slows them alike; each figure is the fastest of ``--runs`` runs (the least
disturbed), and the ratio is each command's over numpy's. A ratio near 1 means printing the
usage costs about what starting Python and importing numpy does: nothing numerical is loaded
to print it (``gmr --help`` lists the subcommands without importing them,
:mod:`core.cli`).

Run: ``python -m gmr_studio.core.benchmark.startup [--runs 10]``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from collections.abc import Sequence

#: label -> command line; the first is the yardstick the others are divided by
COMMANDS = {
    'python -c "import numpy"': [sys.executable, "-c", "import numpy"],
    "gmr --help": [sys.executable, "-m", "gmr_studio.core.cli", "--help"],
    "gmr-studio --help": [sys.executable, "-m", "gmr_studio.app.main", "--help"],
}


def process_seconds(command: Sequence[str]) -> float:
    """Wall seconds from starting ``command`` to its exit (its output thrown away)."""
    start = time.perf_counter()
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - start


def startup_seconds(runs: int, commands: dict[str, list[str]] = COMMANDS) -> dict[str, list[float]]:
    """Every run's seconds of each command, the commands interleaved, after one unrecorded
    warm-up run of each (which fills the file cache and Python's bytecode cache)."""
    for command in commands.values():
        process_seconds(command)
    seconds: dict[str, list[float]] = {label: [] for label in commands}
    for _ in range(max(1, runs)):
        for label, command in commands.items():
            seconds[label].append(process_seconds(command))
    return seconds


def report_lines(seconds: dict[str, list[float]]) -> list[str]:
    """One line per command: its fastest and median run, and its fastest over the yardstick's."""
    yardstick = min(next(iter(seconds.values())))
    lines = []
    for label, runs in seconds.items():
        ordered = sorted(runs)
        best, median = ordered[0], ordered[len(ordered) // 2]
        lines.append(
            f"{label:28s} min {best * 1e3:7.1f} ms  median {median * 1e3:7.1f} ms  ratio {best / yardstick:5.2f}"
        )
    return lines


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=10, help="runs of each command (10)")
    args = parser.parse_args(argv)
    seconds = startup_seconds(args.runs)
    print(f"start-up, fastest of {args.runs} runs each, interleaved; ratio: over the first line's")
    for line in report_lines(seconds):
        print(line)


if __name__ == "__main__":
    main()
