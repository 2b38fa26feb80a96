"""``gmr convert IN OUT``: between .bvh and .gmr."""

from __future__ import annotations

import argparse
from pathlib import Path

from core.convert import post_from_pre, pre_from_post
from core.errors import OperationError
from core.formats import motion_suffix, read_motion, write_motion
from core.motion import Motion


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("convert", help="convert between .bvh and .gmr")
    parser.add_argument("input", help="a .bvh or .gmr file")
    parser.add_argument("output", help="the .bvh or .gmr file to write")
    parser.set_defaults(run=run)


def write_converted(motion: Motion, output: str | Path) -> None:
    """Write ``motion`` (either convention) in the format of ``output``'s suffix.

    BVH needs one tree: GMR siblings with independent rotations get dummy joints."""
    suffix = motion_suffix(output)
    if suffix == ".bvh":
        if motion.convention == "pre" and len(motion.roots) > 1:
            roots = ", ".join(motion.names[r] for r in motion.roots)
            raise OperationError(f"the motion has {len(motion.roots)} trees ({roots}): write .gmr, or join them first")
        motion, dummies = post_from_pre(motion)
        if dummies:
            print(f"{output}: added {len(dummies)} dummy joints for independent siblings: {', '.join(dummies)}")
    elif suffix == ".gmr":
        motion = pre_from_post(motion)
    else:
        raise OperationError(f"cannot write '{Path(output).suffix}' files: expected .bvh or .gmr")
    write_motion(motion, output)


def run(args: argparse.Namespace) -> int:
    write_converted(read_motion(args.input), args.output)
    return 0
