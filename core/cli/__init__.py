"""The ``gmr`` command line: one subcommand per module in this package.

Every bad input file ends as one line ``path:line:col: message`` on stderr and exit code
2, never a traceback; refused operations likewise (``gmr: error: ...``, exit 2).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from gmr_studio.core.errors import MotionFileError, OperationError

#: subcommand modules, in the order ``gmr --help`` lists them
COMMANDS = (
    "info",
    "positions",
    "curves",
    "edit",
    "convert",
    "dataset",
    "markers",
    "compare",
    "audit",
    "check",
    "library",
    "bench",
    "fuzz",
    "stress",
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="gmr",
        description="Inspect, edit and convert skeletal motion in the General Motion Representation.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        module = importlib.import_module(f"gmr_studio.core.cli.{name}")
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
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
