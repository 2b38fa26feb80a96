"""``gmr edit IN -o OUT [--shift-root J] [--split J] [--join J] [--split-all] [--join-all]
[--remove-dummies] [--frames A:B] [--rate HZ] [--mirror] ...``: apply the operations in the
order given, then write ``.gmr`` or ``.bvh`` (a forest under one World root). ``--frames``
trims to ``A:B`` (0-based, B excluded), ``--rate`` resamples (:mod:`core.edits.clip`), ``--mirror``
swaps left and right (:mod:`core.edits.mirror`): it says how many left/right pairs it swapped (and
which, with ``--list-pairs``); names that look sided but have no partner are listed on stderr."""

from __future__ import annotations

import argparse
import sys

from gmr_studio.core.cli.convert import write_converted
from gmr_studio.core.cli.curves import parse_frames
from gmr_studio.core.cli.reading import add_reading_options, load_gmr_with_args, positive_number
from gmr_studio.core.edits.clip import resample, trim
from gmr_studio.core.edits.dummies import remove_dummies
from gmr_studio.core.edits.mirror import mirror, mirror_pairs, pairs_text
from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.edits.steps import AppendStep, add_edit_arguments
from gmr_studio.core.model.motion import Motion


def _mirrored(motion: Motion, list_pairs: bool) -> Motion:
    result, unmatched = mirror(motion)
    pairs = mirror_pairs(motion).pairs
    if list_pairs:
        print(f"gmr edit --mirror: swapped {pairs_text(motion.names, pairs)}")
    else:
        print(f"gmr edit --mirror: swapped {pairs_text(motion.names, pairs, 0)} (--list-pairs names them)")
    if unmatched:
        print(f"gmr edit --mirror: no partner for {', '.join(unmatched)} (left as they are)", file=sys.stderr)
    return result


OPERATIONS = {
    "shift_root": lambda m, j: shift_root(m, j),
    "split": lambda m, j: split(m, j),
    "join": lambda m, j: join(m, j),
    "split_all": lambda m, _: split_all(m),
    "join_all": lambda m, _: join_all(m),
    "remove_dummies": lambda m, _: remove_dummies(m)[0],
    "frames": lambda m, frames: trim(m, *frames),
    "rate": lambda m, rate: resample(m, rate),
    "mirror": lambda m, list_pairs: _mirrored(m, list_pairs),
}


def register(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("input", help="a .bvh, .gmr or .amc file (an AMC's skeleton: --asf, else the .asf beside it)")
    parser.add_argument("-o", "--output", required=True, help="a .gmr or .bvh file (forests: a World root)")
    add_edit_arguments(parser)
    parser.add_argument(
        "--frames", metavar="A:B", type=parse_frames, action=AppendStep, const="frames", help="keep frames A to B-1"
    )
    parser.add_argument(
        "--rate", metavar="HZ", type=positive_number, action=AppendStep, const="rate", help="resample to HZ"
    )
    parser.add_argument("--mirror", nargs=0, action=AppendStep, const="mirror", help="swap left and right")
    parser.add_argument("--list-pairs", action="store_true", help="with --mirror: name the left/right pairs swapped")
    add_reading_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    motion = load_gmr_with_args(args.input, args)
    for operation, joint in args.steps:  # a mirror step takes --list-pairs instead of a joint
        motion = OPERATIONS[operation](motion, args.list_pairs if operation == "mirror" else joint)
    write_converted(motion, args.output)
    return 0
