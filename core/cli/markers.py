"""``gmr markers IN.c3d|IN.trc [--skeleton S --map NAME|FILE] -o OUT.gmr``: markers to GMR.

Without ``--skeleton`` the marker set is recognised from its labels and a skeleton is built
from the markers (joint centres by the published methods, constant bone lengths), then the
same closed form runs on it; ``--refine`` adds the per-frame least squares over the joint
angles; ``--against-file-model`` compares with the lab model's points stored in the file.

The marker map places each joint centre (``joints``: markers labelled with the joint names
are the joint centres; ``cmu``: the CMU 41-marker set on the CMU ASF skeleton), the pelvis
comes by Procrustes, the limbs by their bone directions, the twists from ``--reference``
(or least change from frame to frame). Prints what was missing and a per-joint table: the
share of frames each joint was measured, its distance from its virtual marker and, with
``--truth`` (a motion of the same trial, put on the markers' clock by the comparison
engine: ``--truth-offset``, found when the frame counts differ), its position and angle errors.

``--calibrate A:B --save-map FILE`` first fits the map's clusters on those frames against
``--reference`` (the same trial, or a one-frame static pose) and writes the calibrated map.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from gmr_studio.core.cli.output import write_json as write_json_file
from gmr_studio.core.cli.reading import add_reading_options, reader_options
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr, motion_suffix, write_motion
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.build import HIP_METHODS, KNEE_METHODS
from gmr_studio.core.markers.markermap import load_marker_map, save_marker_map
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.similarity import Similarity


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = __doc__.split("\n\n", 1)[1]
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("input", help="a .c3d or .trc marker file")
    parser.add_argument(
        "--skeleton", help="the skeleton: .asf, .bvh or .gmr (default: built from the markers of a known set)"
    )
    parser.add_argument(
        "--refine",
        action="store_true",
        help="after the closed form, least squares over the joint angles of every frame (residuals printed)",
    )
    parser.add_argument(
        "--weights",
        type=marker_weights,
        metavar="LABEL=W,...",
        help="the refinement's weight of markers (built skeleton; default 1; 0 leaves one out)",
    )
    parser.add_argument(
        "--hip", choices=HIP_METHODS, default="harrington", help="hip centre regression (built skeleton)"
    )
    parser.add_argument(
        "--knee",
        choices=KNEE_METHODS,
        default="functional",
        help="knee centre (built skeleton): on the flexion axis of the thigh and shank clusters where they allow it "
        "(functional, default), or between the condyles / by the chord as Plug-in Gait places it (anatomical)",
    )
    parser.add_argument(
        "--against-file-model",
        action="store_true",
        help="compare the joint centres and pelvis frames with the lab model's stored in the file (built skeleton)",
    )
    parser.add_argument("--map", default="joints", help="marker map: joints, cmu, or a .toml file (default joints)")
    parser.add_argument("--reference", help="a motion of the same skeleton whose best-matching poses give the twists")
    parser.add_argument(
        "--truth", help="the true motion of the same trial (any skeleton form, e.g. .amc, .bvh): errors are printed"
    )
    parser.add_argument(
        "--truth-offset",
        type=truth_offset,
        metavar="N|auto",
        help="truth frame minus marker frame (default 0 for as many frames as the markers, else auto)",
    )
    parser.add_argument("--truth-map", help="joint-name map between skeleton and truth (cmu, or .toml; default names)")
    parser.add_argument("--roots", default="", help="joints that stay roots at their measured positions: J1,J2")
    parser.add_argument("--frames", type=frame_slice, help="marker frames A:B to convert (from 0, B excluded)")
    parser.add_argument(
        "--exclude-within", type=float, metavar="SECONDS", help="do not match reference frames this close in time"
    )
    parser.add_argument("--fill-gaps", type=int, default=0, metavar="N", help="interpolate marker gaps of <= N frames")
    parser.add_argument(
        "--axes",
        help="skeleton axes as marker axes, overriding the map's alignment: e.g. yzx (CMU C3D to ASF), x,z,-y",
    )
    parser.add_argument("--scale", type=float, help="skeleton units per marker unit, overriding the map's")
    parser.add_argument("--aim", choices=("markers", "chain"), default="markers", help="bone directions from")
    parser.add_argument("--pelvis-fit", choices=("note", "points"), default="note", help="Procrustes variant")
    parser.add_argument(
        "--root-at",
        choices=("fit", "pelvis"),
        help="the closed form's root: by the least-squares translation of all joints (fit; the default with "
        "--skeleton) or at the pelvis markers' root (pelvis: the paper's; the default for a built skeleton)",
    )
    parser.add_argument("--calibrate", type=frame_slice, metavar="A:B", help="calibrate the map on these frames")
    parser.add_argument("--save-map", help="write the calibrated map here (.toml)")
    parser.add_argument(
        "--json",
        nargs="?",
        const="-",
        metavar="OUT",
        help="the report as JSON: printed, or written to OUT (with --against-file-model: the comparison)",
    )
    parser.add_argument("-o", "--output", required=True, help="the .gmr (or .bvh) file to write")
    add_marker_options(parser)
    add_reading_options(parser, transforms=False)  # its --scale is the marker-to-skeleton one
    parser.set_defaults(run=run)


def positive_rate(text: str) -> float:
    """``--rate HZ``: a positive number of frames per second."""
    try:
        rate = float(text)
    except ValueError:
        rate = -1.0
    if not (np.isfinite(rate) and rate > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number of frames per second, not {text!r}")
    return rate


def add_marker_options(parser: argparse.ArgumentParser) -> None:
    """``--drop-computed`` and ``--rate``: how marker files (.c3d, .trc) are read, for every
    command that reads them (:func:`marker_options` gives the reader's keywords)."""
    group = parser.add_argument_group("reading marker files (.c3d, .trc)")
    group.add_argument(
        "--drop-computed",
        action="store_true",
        help="read the samples the capture software computed (C3D residual 0: its gap filling) as gaps; "
        "by default they are kept and counted as computed",
    )
    group.add_argument(
        "--rate",
        type=positive_rate,
        metavar="HZ",
        help="the marker file's frame rate, for a file that states none (a C3D whose POINT:RATE is 0)",
    )


def marker_options(args: argparse.Namespace) -> dict:
    """The keywords of :func:`core.markers.read_markers` the options of :func:`add_marker_options` ask for."""
    computed = "drop" if getattr(args, "drop_computed", False) else "keep"
    return {"computed": computed, "rate": getattr(args, "rate", None)}


def frame_slice(text: str) -> slice:
    """``"A:B"``, ``"A:"``, ``":B"`` -> slice (frame indices from 0)."""
    start, sep, stop = text.partition(":")
    try:
        if not sep:
            raise ValueError
        return slice(int(start) if start.strip() else None, int(stop) if stop.strip() else None)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected frames as A:B, not {text!r}") from None


def marker_weights(text: str) -> dict[str, float]:
    """``"LKNE=2,RKNE=2,SACR=0"`` -> {label: weight >= 0}."""
    out: dict[str, float] = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        label, sep, value = part.partition("=")
        try:
            weight = float(value)
        except ValueError:
            weight = -1.0
        if not sep or not label.strip() or not weight >= 0:
            raise argparse.ArgumentTypeError(f"expected LABEL=WEIGHT (a number >= 0), not {part!r}")
        out[label.strip()] = weight
    return out


def truth_offset(text: str) -> int | str:
    """``"auto"`` or a whole number of frames."""
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number of frames or auto, not {text!r}") from None


def parse_axes(text: str) -> np.ndarray:
    """``"yzx"`` or ``"x,z,-y"``: skeleton x, y, z as (signed) marker axes -> rotation (3, 3)."""
    parts = text.split(",") if "," in text else list(text)
    rows = []
    for part in parts:
        part = part.strip().lower()
        sign = -1.0 if part.startswith("-") else 1.0
        axis = part.lstrip("+-")
        if axis not in ("x", "y", "z"):
            raise OperationError(f"--axes {text!r}: expected three of x, y, z, each maybe signed")
        row = np.zeros(3)
        row["xyz".index(axis)] = sign
        rows.append(row)
    matrix = np.array(rows)
    if matrix.shape != (3, 3) or not np.isclose(abs(np.linalg.det(matrix)), 1.0):
        raise OperationError(f"--axes {text!r}: name each axis once")
    if np.linalg.det(matrix) < 0:
        raise OperationError(f"--axes {text!r} mirrors the markers: flip the sign of one axis")
    return matrix


def load_skeleton(path: str) -> Motion:
    return load_gmr(path)


def load_motion_of(path: str, skeleton_path: str, args: argparse.Namespace | None = None) -> Motion:
    """A motion of the skeleton, read with the reading options (an .amc reads with --asf,
    else with the --skeleton .asf)."""
    asf = getattr(args, "asf", None) or (skeleton_path if motion_suffix(skeleton_path) == ".asf" else None)
    return load_gmr(path, **reader_options(path, asf, getattr(args, "frame_rate", None)))


def run(args: argparse.Namespace) -> int:
    from gmr_studio.core.markers.report import conversion_table, conversion_text
    from gmr_studio.core.markers.solve import markers_to_motion
    from gmr_studio.core.markers.virtual import resolve_map

    markers = read_markers(args.input, **marker_options(args))
    if not args.skeleton:
        from gmr_studio.core.cli.markers_built import run_built

        return run_built(args, markers)
    if args.against_file_model:
        raise OperationError("--against-file-model compares the skeleton built from the markers: leave out --skeleton")
    skeleton = load_skeleton(args.skeleton)
    marker_map = load_marker_map(args.map)
    if args.axes or args.scale:
        old = marker_map.alignment
        marker_map = marker_map.replace(
            alignment=Similarity(
                parse_axes(args.axes) if args.axes else old.rotation, args.scale or old.scale, old.translation
            )
        )
    reference = load_motion_of(args.reference, args.skeleton, args) if args.reference else None
    if args.calibrate is not None:
        marker_map = _calibrate(args, markers, skeleton, marker_map, reference)
    roots = [r.strip() for r in args.roots.split(",") if r.strip()]
    result = markers_to_motion(
        markers,
        skeleton,
        marker_map,
        reference=reference,
        exclude_within=args.exclude_within,
        roots=roots,
        frames=args.frames,
        fill_gaps=args.fill_gaps,
        pelvis_method=args.pelvis_fit,
        aim=args.aim,
        root_at=args.root_at or "fit",
    )
    refinement = None
    if args.refine:
        from gmr_studio.core.markers.refine import refine_joints

        refinement = refine_joints(result.motion, result.refine_targets(), weights=result.weights)
        result = dataclasses.replace(result, motion=refinement.motion)
    output = Path(args.output)
    motion = result.motion
    if motion_suffix(output) == ".bvh":
        from gmr_studio.core.formats.bvh_export import bvh_export

        motion = bvh_export(motion).motion  # dummies where GMR siblings turn independently
    write_motion(motion, output)
    truth_positions = truth_rotations = truth_note = None
    if args.truth:
        truth = load_motion_of(args.truth, args.skeleton, args)
        truth_positions, truth_rotations, truth_note = truth_on_markers_clock(
            result.motion, truth, markers.n_frames, args.frames, args.truth_offset, args.truth_map
        )
    resolved = resolve_map(marker_map, markers, skeleton=skeleton)
    unit = resolved.units or markers.units  # errors are printed in the markers' unit
    rows = conversion_table(result, 1.0 / resolved.alignment.scale, truth_positions, truth_rotations)
    if args.json:
        report = {"output": str(output), "pelvis": result.pelvis_note, "reasons": list(result.reasons), "joints": rows}
        if truth_note:
            report["truth"] = truth_note
        write_json_file(report, args.json, indent=2)
        return 0
    print(
        f"{output}: {motion.n_frames} frames x {motion.n_joints} joints at {1 / motion.frame_time:.6g} Hz, "
        f"roots {', '.join(motion.names[r] for r in motion.roots)}; map {resolved.name}, "
        f"twists {'from ' + args.reference if reference is not None else 'changing least from frame to frame'}"
    )
    if resolved.renamed:
        print(f"  joints: {resolved.renamed}")
    if result.pelvis_note:
        print(f"  pelvis: {result.pelvis_note}")
    for reason in result.reasons:
        print(f"  note: {reason}")
    if truth_note:
        print(f"  truth: {truth_note}")
    print(conversion_text(rows, unit))
    if refinement is not None:
        print(refinement_text(refinement, motion.names, 1.0 / resolved.alignment.scale, unit))
    if resolved.pelvis:
        from gmr_studio.core.markers.pelvis import recover_pelvis
        from gmr_studio.core.markers.report import pelvis_fit_summary, pelvis_fit_text

        shown = markers.frame_slice(args.frames) if args.frames is not None else markers
        print(pelvis_fit_text(pelvis_fit_summary(recover_pelvis(shown, resolved, skeleton=skeleton))))
    return 0


def refinement_text(refinement, names, factor: float, unit: str) -> str:
    """Per marker: median and 95% residual over the frames, before and after the refinement."""
    before, after = refinement.residuals_before * factor, refinement.residuals * factor
    lines = [f"refinement ({refinement.iterations} Levenberg-Marquardt iterations), residual per marker in {unit}:"]
    lines.append(f"  {'marker':<12} {'median before':>13} {'median after':>12} {'95% after':>9}")
    for m, name in enumerate(names):
        if np.isfinite(after[:, m]).any():
            lines.append(
                f"  {name:<12} {np.nanmedian(before[:, m]):>13.2f} {np.nanmedian(after[:, m]):>12.2f} "
                f"{np.nanpercentile(after[:, m], 95):>9.2f}"
            )
    rms = np.sqrt(np.nanmean(after**2))
    lines.append(f"  overall RMS after: {rms:.2f} {unit}")
    return "\n".join(lines)


def truth_on_markers_clock(
    motion: Motion,
    truth: Motion,
    n_marker_frames: int,
    frames: slice | None,
    offset: int | str | None,
    joint_map: str | None,
) -> tuple[np.ndarray, np.ndarray | None, str | None]:
    """The truth sampled on the converted motion's frames, through the comparison engine.

    motion : the converted motion (F frames: marker frames ``frames`` of ``n_marker_frames``).
    offset : truth frame minus marker frame; None: 0 when the truth has as many frames as
    the markers (the same trial frame for frame, as an AMC), else found (``auto``: the lag
    found from the whole body, as ``gmr compare --offset auto``; a BVH adds a
    T-pose frame, +1). joint_map : pairs the skeleton's joints with the truth's (None: names).
    Returns truth positions (F, J, 3) and local rotations (F, J, 3, 3) in the motion's joint
    order (NaN where unmatched or outside the truth; rotations None when the truth is on
    another skeleton or clock), and a note for the report (None when the offset is 0 as
    assumed). Raises OperationError when too little of the truth overlaps.
    """
    from gmr_studio.core.compare import compare_motions
    from gmr_studio.core.timebase.clock import common_rate

    start = (frames or slice(None)).indices(n_marker_frames)[0]
    if offset is None:
        offset = 0 if truth.n_frames == n_marker_frames else "auto"
    try:
        comparison = compare_motions(
            motion,
            truth,
            joint_map=joint_map,
            with_rotations=False,
            offset="auto" if offset == "auto" else start + offset,
        )
    except ValueError as error:
        raise OperationError(f"--truth: {error}") from None
    lag = comparison.alignment.offset_frames - start  # truth frame minus marker frame
    positions = np.full((motion.n_frames, motion.n_joints, 3), np.nan)
    positions[:, comparison.index_a] = comparison.positions_b
    overlap = int(np.isfinite(positions[:, comparison.index_a[0], 0]).sum())
    if overlap < max(1, motion.n_frames // 2):
        raise OperationError(
            f"--truth ({truth.n_frames} frames) overlaps {overlap} of the {motion.n_frames} converted frames "
            f"at offset {lag:g}: it must be the same trial (or give --truth-offset)"
        )
    rotations = None
    same_skeleton = [motion.names[i] for i in comparison.index_a] == [truth.names[j] for j in comparison.index_b]
    if same_skeleton and lag == round(lag) and common_rate(motion.frame_rate, truth.frame_rate) == motion.frame_rate:
        rows = np.arange(motion.n_frames) + start + round(lag)
        inside = (rows >= 0) & (rows < truth.n_frames)
        rotations = np.full((motion.n_frames, motion.n_joints, 3, 3), np.nan)
        rotations[np.ix_(inside, comparison.index_a)] = truth.rotations[rows[inside]][:, comparison.index_b]
    note = None
    if lag != 0 or offset == "auto":
        how = "found from the whole body" if comparison.alignment.offset_found else "given"
        note = f"truth frame = marker frame {lag:+g} ({how}); {comparison.n_pairs} joints matched" + (
            f", unmatched {', '.join(comparison.unmatched_a)}" if comparison.unmatched_a else ""
        )
    return positions, rotations, note


def _calibrate(args, markers: MarkerSet, skeleton: Motion, marker_map, reference: Motion | None):
    from gmr_studio.core.kinematics.fk import forward_kinematics
    from gmr_studio.core.markers.pelvis import rest_positions
    from gmr_studio.core.markers.virtual import calibrate_marker_map, resolve_map

    if reference is None:
        raise OperationError("--calibrate needs --reference: the pose of the calibration frames")
    order = [reference.joint_index(n) for n in skeleton.names]
    positions = forward_kinematics(reference, with_rotations=False)[0][:, order]
    resolved = resolve_map(marker_map, markers, skeleton=skeleton)
    calibrated = calibrate_marker_map(
        resolved,
        markers,
        positions,
        skeleton.names,
        args.calibrate,
        pelvis_home=rest_positions(skeleton, resolved.pelvis) if resolved.pelvis else None,
        note={
            "markers": Path(args.input).name,
            "reference": Path(args.reference).name,
            "skeleton": Path(args.skeleton).name,
            "frames": f"{args.calibrate.start or 0}:{'' if args.calibrate.stop is None else args.calibrate.stop}",
        },
    )
    if args.save_map:
        save_marker_map(calibrated, args.save_map)
        print(f"{args.save_map}: map {calibrated.name} calibrated on frames {calibrated.calibration['frames']}")
        for v in calibrated.virtual:
            if v.rms is not None:
                print(f"  {v.name}: calibration RMS {v.rms:.2f} {calibrated.units or markers.units}")
    return calibrated
