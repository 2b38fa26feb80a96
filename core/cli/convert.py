"""``gmr convert IN OUT``: .bvh, .amc (+ASF), .gmr, AMASS .npz (+``--body-model``), glTF and
FBX in; .gmr, .bvh, .glb/.gltf out (FBX is read only); or ``--batch``.

Options, applied in this order: ``--remove-dummies`` (fold zero-offset joints into their
children), ``--scale S`` (lengths times S), ``--up y|z`` (turn the world so that axis is
up; the source's up axis is what its header says, else Y, or ``--from-up``). GMR outputs
state the conversions in their ``#`` header; BVH has no comment syntax (Blender's importer,
for one, reads lines at fixed offsets), so for a BVH they are printed instead.

BVH output is standard whatever the motion holds (:mod:`core.formats.bvh_export`): dummy joints for
independent siblings, a forest under one ``World`` root, or one file per tree with
``--split-trees``. ``--batch IN_DIR OUT_DIR`` converts a folder tree (:mod:`core.cli.batch`). glTF output is
Y up in metres (:mod:`core.formats.gltf`; ``--metres-per-unit``, else inferred).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

from gmr_studio.core.batch.files import MOTION_SUFFIXES
from gmr_studio.core.cli.reading import add_reading_options, positive_number, reader_options
from gmr_studio.core.edits.dummies import remove_dummies
from gmr_studio.core.edits.world import change_up_axis, scale_lengths
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import motion_suffix, read_motion, write_motion
from gmr_studio.core.formats.bvh_export import bvh_export, bvh_export_trees, tree_file_name
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.model.motion import Motion

#: formats ``convert`` reads and writes
INPUT_SUFFIXES = MOTION_SUFFIXES
OUTPUT_SUFFIXES = (".bvh", ".gmr", ".glb", ".gltf")


@dataclasses.dataclass(frozen=True)
class ConvertOptions:
    """What to do to each motion on its way from one file to another."""

    asf: str | None = None
    frame_rate: float | None = None
    scale: float | None = None
    up: str | None = None
    from_up: str | None = None
    remove_dummies: bool = False
    split_trees: bool = False
    metres_per_unit: float | None = None
    body_model: str | None = None
    animation: str | None = None
    skin: str | None = None

    @classmethod
    def from_args(cls, args: argparse.Namespace) -> ConvertOptions:
        return cls(**{field.name: getattr(args, field.name, None) for field in dataclasses.fields(cls)})


@dataclasses.dataclass
class ConversionReport:
    """What one conversion did: files written and one-line notes."""

    input: str
    outputs: list[str]
    frames: int
    joints: int
    notes: list[str]


def add_conversion_options(parser: argparse.ArgumentParser) -> None:
    """The options shared by single and batch conversion."""
    add_reading_options(parser)  # --asf, --frame-rate, --scale, --up, --from-up
    parser.add_argument(
        "--remove-dummies", action="store_true", help="fold zero-offset joints into their children (GMR needs none)"
    )
    parser.add_argument(
        "--split-trees",
        action="store_true",
        help="BVH output: one file per tree (OUT_<root>.bvh) instead of a World root",
    )
    parser.add_argument(
        "--metres-per-unit",
        type=positive_number,
        help="glTF output: metres per length unit (default: inferred from the skeleton's size)",
    )


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = __doc__.split("\n\n")[0] if __doc__ else None
    parser.usage = (
        "gmr convert IN OUT [options]\n"
        "       gmr convert --batch IN_DIR OUT_DIR [--to gmr|bvh|glb] [--jobs N | --scheduler S] [options]"
    )
    parser.add_argument("input", help="a .bvh, .amc, .gmr, AMASS .npz or glTF file (with --batch: a folder)")
    parser.add_argument("output", help="the .gmr or .bvh file to write (with --batch: a folder)")
    parser.add_argument("--batch", action="store_true", help="convert every motion file in the folder tree IN_DIR")
    parser.add_argument("--to", choices=("gmr", "bvh", "glb"), default="gmr", help="with --batch: output format (gmr)")
    parser.add_argument("--jobs", type=int, default=None, help="with --batch: parallel processes (default: all cores)")
    parser.add_argument(
        "--scheduler",
        metavar="tcp://HOST:8786|local:N",
        help="with --batch: run on a Dask cluster (extra 'cluster'; docs/cluster.md) instead of local processes",
    )
    add_conversion_options(parser)
    parser.set_defaults(run=run)


def read_for_conversion(path: str | Path, options: ConvertOptions) -> Motion:
    """Read any input file, passing the AMC, AMASS and glTF options to their readers."""
    return read_motion(
        path,
        **reader_options(
            path, options.asf, options.frame_rate, options.body_model, animation=options.animation, skin=options.skin
        ),
    )


def transformed(motion: Motion, options: ConvertOptions) -> tuple[Motion, list[str]]:
    """The motion after the options' conversions, with notes saying what happened; the
    GMR form (pre-rotation) whenever dummies are removed, the input's convention otherwise."""
    notes = []
    if options.remove_dummies:
        motion, removed = remove_dummies(motion)
        note = f"removed {len(removed)} dummy joints" + (f": {', '.join(removed)}" if removed else "")
        notes.append(note)
        motion = motion.replace(comments=(*motion.comments, f"{note} (gmr convert --remove-dummies)"))
    if options.scale is not None and options.scale != 1:
        motion = scale_lengths(motion, options.scale)
        notes.append(motion.comments[-1])
    if options.up is not None:
        turned = change_up_axis(motion, options.up, options.from_up)
        if len(turned.comments) > len(motion.comments):
            notes.append(turned.comments[-1])
        motion = turned
    return motion, notes


def write_converted(
    motion: Motion,
    output: str | Path,
    *,
    split_trees: bool = False,
    quiet: bool = False,
    metres_per_unit: float | None = None,
) -> list[str]:
    """Write ``motion`` (either convention) in the format of ``output``'s suffix; return
    the files written. BVH: the standard form of :func:`core.formats.bvh_export.bvh_export` (dummy
    joints where siblings differ, a World root over a forest), or one file per tree."""
    suffix = motion_suffix(output)
    if suffix not in OUTPUT_SUFFIXES:
        raise OperationError(f"cannot write '{Path(output).suffix}' files: expected .bvh, .gmr, .glb or .gltf")
    if suffix in (".glb", ".gltf"):
        from gmr_studio.core.formats.gltf import export_gltf

        result = export_gltf(motion, output, metres_per_unit=metres_per_unit)
        if not quiet:
            print(f"{output}: glTF, Y up ({result.up_note}); {result.unit_note}")
        return [str(output)]
    if suffix == ".gmr":
        gmr = pre_from_post(motion)
        write_motion(gmr, output)
        return [str(output)]
    exports = (
        [(tree_file_name(output, root), export) for root, export in bvh_export_trees(motion)]
        if split_trees and len(motion.roots) > 1
        else [(Path(output), bvh_export(motion))]
    )
    written = []
    for path, export in exports:
        export.write(path)
        written.append(str(path))
        if not quiet and export.dummies:
            shown = ", ".join(export.dummies)
            print(f"{path}: added {len(export.dummies)} dummy joints for independent siblings: {shown}")
        if not quiet and export.world_root:
            print(f"{path}: {len(motion.roots)} trees under the synthetic root '{export.world_root}'")
    return written


def convert_file(
    source: str | Path, output: str | Path, options: ConvertOptions, *, quiet: bool = True
) -> ConversionReport:
    """Read, convert and write one file (outputs written atomically)."""
    suffix = motion_suffix(source)
    if suffix not in INPUT_SUFFIXES:
        raise OperationError(f"cannot convert '{Path(source).suffix}' files: expected {', '.join(INPUT_SUFFIXES)}")
    motion = read_for_conversion(source, options)
    motion, notes = transformed(motion, options)
    if motion_suffix(output) == ".gmr":
        motion = motion.replace(comments=(*motion.comments, f"written by gmr convert from {Path(source).name}"))
    written = write_converted(
        motion, output, split_trees=options.split_trees, quiet=quiet, metres_per_unit=options.metres_per_unit
    )
    return ConversionReport(str(source), written, motion.n_frames, motion.n_joints, notes)


def run(args: argparse.Namespace) -> int:
    options = ConvertOptions.from_args(args)
    if args.batch:
        from gmr_studio.core.cli.batch import run_batch

        return run_batch(Path(args.input), Path(args.output), args.to, options, args.jobs, scheduler=args.scheduler)
    report = convert_file(args.input, args.output, options, quiet=False)
    for note in report.notes:
        for path in report.outputs:
            print(f"{path}: {note}")
    return 0
