"""The reading options every ``gmr`` command that reads a motion takes, as one argument group.

``--asf S.asf`` (the skeleton of an ``.amc``; default: the single ``.asf`` beside it),
``--frame-rate HZ`` (frames per second of an ``.amc``, default 120; the rate a glTF
animation is sampled at, default its keys' spacing), ``--body-model M`` (the SMPL-family
model of an AMASS ``.npz``), ``--animation NAME|INDEX`` and ``--skin NAME|INDEX`` (which of
a glTF file's animations and skins; ``--animation`` also picks an FBX file's take; default the
first). Options that do not
apply to a file's format are ignored for it, so ``gmr info``, ``positions``, ``edit``,
``convert`` and ``markers`` read ``walk.amc --asf subject.asf`` alike. ``info``,
``positions``, ``edit`` and ``convert`` also take ``--scale S`` (lengths times S) and
``--up y|z [--from-up y|z]`` (turn the world so that axis is up), applied in that order
right after reading (``markers`` has its own ``--scale``, between marker and skeleton).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gmr_studio.core.edits.world import change_up_axis, scale_lengths
from gmr_studio.core.formats import motion_suffix, read_motion
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.up_axis import UP_AXES


def positive_number(text: str) -> float:
    """An argparse type: a finite number above zero."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, not {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a positive number, not {text!r}")
    return value


def add_reading_options(parser: argparse.ArgumentParser, *, transforms: bool = True) -> argparse._ArgumentGroup:
    """Add the shared group of reading options to a subcommand's parser (``transforms``:
    with ``--scale``, ``--up`` and ``--from-up``)."""
    group = parser.add_argument_group("reading motion files")
    group.add_argument("--asf", help="the skeleton of .amc inputs (default: the single .asf beside each AMC)")
    group.add_argument(
        "--frame-rate",
        type=positive_number,
        help="frames per second of .amc inputs (default 120); glTF: sample at this rate (default: the keys' spacing)",
    )
    group.add_argument("--body-model", help="the SMPL/SMPL-H/SMPL-X model (.npz/.pkl) of AMASS .npz inputs")
    add_gltf_options(group)
    if transforms:
        group.add_argument("--scale", type=positive_number, help="multiply every length by this factor")
        group.add_argument("--up", choices=UP_AXES, help="make this axis the up axis")
        group.add_argument(
            "--from-up", choices=UP_AXES, help="the input's up axis (default: what its file states, else its figure's)"
        )
    return group


def add_gltf_options(group) -> None:
    """``--animation`` and ``--skin``: which of a glTF file's animations and skins to read."""
    group.add_argument(
        "--animation", help="glTF and FBX inputs: the animation (take) to read, by name or index (default: the first)"
    )
    group.add_argument("--skin", help="glTF inputs: the skin whose joints make the skeleton (default: the first)")


def reader_options(
    path: str | Path,
    asf: str | None = None,
    frame_rate: float | None = None,
    body_model: str | None = None,
    *,
    animation: str | None = None,
    skin: str | None = None,
) -> dict:
    """The keyword arguments of :func:`core.formats.read_motion` for ``path``: the AMC
    options for an ``.amc``, the body model for an AMASS ``.npz`` (None: the reader says
    what to pass), the animation, skin and frame rate for glTF, the take for FBX, none for
    other formats."""
    suffix = motion_suffix(path)
    if suffix == ".npz":
        return {"body_model": body_model}
    if suffix in (".glb", ".gltf", ".vrma"):
        given = (("animation", animation), ("skin", skin), ("frame_rate", frame_rate))
        return {key: value for key, value in given if value is not None}
    if suffix == ".fbx":
        return {"animation": animation} if animation is not None else {}
    if suffix != ".amc":
        return {}
    return {key: value for key, value in (("asf", asf), ("frame_rate", frame_rate)) if value is not None}


def options_from_args(path: str | Path, args: argparse.Namespace) -> dict:
    """:func:`reader_options` from parsed arguments (of a parser with the reading group)."""
    return reader_options(
        path,
        getattr(args, "asf", None),
        getattr(args, "frame_rate", None),
        getattr(args, "body_model", None),
        animation=getattr(args, "animation", None),
        skin=getattr(args, "skin", None),
    )


def transformed_by_args(motion: Motion, args: argparse.Namespace) -> Motion:
    """The motion scaled (``--scale``) and turned (``--up``, ``--from-up``) as asked."""
    scale = getattr(args, "scale", None)
    if scale is not None and scale != 1:
        motion = scale_lengths(motion, scale)
    if getattr(args, "up", None) is not None:
        motion = change_up_axis(motion, args.up, getattr(args, "from_up", None))
    return motion


def read_with_args(path: str | Path, args: argparse.Namespace) -> Motion:
    """Read a motion in its own convention with the command line's reading options."""
    return transformed_by_args(read_motion(path, **options_from_args(path, args)), args)


def load_gmr_with_args(path: str | Path, args: argparse.Namespace) -> Motion:
    """Read a motion as GMR (pre-rotation) with the command line's reading options."""
    return pre_from_post(read_with_args(path, args))
