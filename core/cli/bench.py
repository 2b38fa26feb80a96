"""``gmr bench``: the paper's benchmark (section 6, Figure 4), reproduced in one run.

Prints tables, asserts nothing; the machinery is in :mod:`core.benchmark`.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gmr_studio.core.shared_data import shared_data_dir


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = (
        "Real BVH files (../shared/data and --data folders), tiled to --frames frames at 120 fps; "
        "configurations C_k with k random roots, --instances each; BVH baseline, memory-bound yardstick, "
        "parse throughput, operations, peers. Prints figures, asserts nothing."
    )
    parser.add_argument("--frames", type=int, default=100_000, help="frames to tile the motion to (100000)")
    parser.add_argument("--seed", type=int, default=6, help="seed for the random root sets (6)")
    parser.add_argument("--json", type=Path, default=None, metavar="OUT", help="write the results as JSON")
    parser.add_argument("--plot", type=Path, default=None, metavar="OUT.png", help="write the Figure-4-style plot")
    parser.add_argument("--markdown", type=Path, default=None, metavar="OUT.md", help="write the tables as Markdown")
    parser.add_argument(
        "--data", type=Path, action="append", default=[], metavar="DIR", help="another folder of BVH files (repeatable)"
    )
    parser.add_argument("--instances", type=int, default=10, help="random instances per configuration (10)")
    parser.add_argument("--repeat", type=int, default=5, help="timings keep the best of this many runs (5)")
    parser.add_argument("--peer-frames", type=int, default=1000, help="frames for per-frame peers (bvhio) (1000)")
    parser.add_argument("--no-peers", action="store_true", help="skip the other libraries")
    parser.add_argument(
        "--fbx",
        action="store_true",
        help="instead: FBX reading against glTF (Blender's FBX export of 01_01 tiled to --frames; needs bpy)",
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from gmr_studio.core.atomic import atomic_write_text
    from gmr_studio.core.benchmark.report import markdown_tables, summary_lines, write_json, write_plot
    from gmr_studio.core.benchmark.runner import BenchOptions, run_benchmark

    if args.frames < 1 or args.instances < 1 or args.repeat < 1:
        raise SystemExit("gmr bench: --frames, --instances and --repeat must be positive")
    if args.fbx:  # core/benchmark/fbx_speed.py
        from gmr_studio.core.benchmark.fbx_speed import default_bpy, reading_speed

        reading_speed(args.frames, args.repeat, default_bpy())
        return 0
    options = BenchOptions(
        folders=(shared_data_dir(), *args.data),
        frames=args.frames,
        seed=args.seed,
        instances=args.instances,
        repeat=args.repeat,
        peer_frames=args.peer_frames,
        peers=not args.no_peers,
    )
    result = run_benchmark(options, log=lambda line: print(line, flush=True))
    for line in summary_lines(result):
        print(line)
    if args.json:
        write_json(result, args.json)
        print(f"wrote {args.json}")
    if args.plot and write_plot(result, args.plot):
        print(f"wrote {args.plot}")
    if args.markdown:
        atomic_write_text(args.markdown, markdown_tables(result))
        print(f"wrote {args.markdown}")
    return 0
