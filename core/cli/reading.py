"""The reading options every ``gmr`` command that reads a motion takes, as one argument group.

``--asf S.asf`` (the skeleton of an ``.amc``; default: the single ``.asf`` beside it) and
``--frame-rate HZ`` (frames per second of an ``.amc``; default 120). Options that do not
apply to a file's format are ignored for it, so ``gmr info``, ``positions``, ``edit``,
``convert`` and ``markers`` read ``walk.amc --asf subject.asf`` alike.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gmr_studio.core.formats import load_gmr, motion_suffix, read_motion
from gmr_studio.core.motion import Motion


def positive_number(text: str) -> float:
    """An argparse type: a finite number above zero."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, not {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a positive number, not {text!r}")
    return value


def add_reading_options(parser: argparse.ArgumentParser) -> argparse._ArgumentGroup:
    """Add the shared group of reading options to a subcommand's parser."""
    group = parser.add_argument_group("reading motion files")
    group.add_argument("--asf", help="the skeleton of .amc inputs (default: the single .asf beside each AMC)")
    group.add_argument("--frame-rate", type=positive_number, help="frames per second of .amc inputs (default 120)")
    return group


def reader_options(path: str | Path, asf: str | None = None, frame_rate: float | None = None) -> dict:
    """The keyword arguments of :func:`core.formats.read_motion` for ``path``: the AMC
    options for an ``.amc``, none for other formats."""
    if motion_suffix(path) != ".amc":
        return {}
    return {key: value for key, value in (("asf", asf), ("frame_rate", frame_rate)) if value is not None}


def options_from_args(path: str | Path, args: argparse.Namespace) -> dict:
    """:func:`reader_options` from parsed arguments (of a parser with the reading group)."""
    return reader_options(path, getattr(args, "asf", None), getattr(args, "frame_rate", None))


def read_with_args(path: str | Path, args: argparse.Namespace) -> Motion:
    """Read a motion in its own convention with the command line's reading options."""
    return read_motion(path, **options_from_args(path, args))


def load_gmr_with_args(path: str | Path, args: argparse.Namespace) -> Motion:
    """Read a motion as GMR (pre-rotation) with the command line's reading options."""
    return load_gmr(path, **options_from_args(path, args))
