"""The ``gmr`` command line: one subcommand per module in this package.

:data:`COMMANDS` names every subcommand and its one-line help; a subcommand's module (and the
numerical code it needs) is imported only when that command runs or its own ``--help`` is
asked, so ``gmr --help`` and a mistyped command answer at once. A module's ``register(parser)``
adds its arguments to the parser made for it here and sets ``run`` (``args.run(args)``).

Every bad input file ends as one line ``path:line:col: message`` on stderr and exit code
2, never a traceback; refused operations likewise (``gmr: error: ...``, exit 2).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Iterable, Sequence

from gmr_studio.core.errors import MotionFileError, OperationError

#: subcommand -> its one-line help, in the order ``gmr --help`` lists them; the command's module
#: is ``gmr_studio.core.cli.<subcommand>``
COMMANDS = {
    "info": "joints, roots, soft links, frames, frame rate and channels of a file",
    "positions": "world positions of all joints to a .npz file",
    "curves": "quantities of joints over time to CSV or PNG",
    "edit": "shift root, split, join, trim, resample, mirror, in the order given",
    "convert": "convert .bvh/.amc/.gmr/.npz/.glb/.gltf/.fbx to .gmr/.bvh/.glb, one file or a folder tree (--batch)",
    "dataset": "one .npz/.parquet table of every file's world positions or rotations",
    "markers": "marker data (.c3d, .trc) to a GMR motion of a skeleton",
    "compare": "per-joint position and rotation errors of motion B against motion A",
    "audit": "run a file through every round trip and check positions stay within tolerance",
    "check": "find foot skate, pops, jitter, flips, frozen frames... at their frames and joints",
    "library": "index folders of takes into one file; find, list and look at them",
    "bench": "time GMR forward kinematics for C_1..C_J roots against BVH, a copy, and other libraries",
    "fuzz": "mutate real files and check every reader fails cleanly",
    "stress": "load, convert and run FK on a very large motion; print peak memory",
}


def build_parser(commands: Iterable[str] | None = None) -> argparse.ArgumentParser:
    """The ``gmr`` parser, listing every subcommand; the arguments of ``commands`` (default:
    all of them) are added, which imports their modules."""
    loaded = set(COMMANDS if commands is None else commands)
    parser = argparse.ArgumentParser(
        prog="gmr",
        description="Inspect, edit and convert skeletal motion in the General Motion Representation.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, summary in COMMANDS.items():
        command = sub.add_parser(name, help=summary)
        if name in loaded:
            importlib.import_module(f"{__name__}.{name}").register(command)
    return parser


def command_named(argv: Sequence[str]) -> str | None:
    """The subcommand a ``gmr`` command line names: its first word not starting with ``-``
    (``gmr`` itself takes no option but ``--help``), or None."""
    return next((word for word in argv if not word.startswith("-")), None)


def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser([name for name in [command_named(argv)] if name in COMMANDS])
    args = parser.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except MotionFileError as exc:
        print(str(exc), file=sys.stderr)
        return 2
    except OperationError as exc:
        print(f"gmr: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("gmr: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `gmr info x.bvh | head`
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
