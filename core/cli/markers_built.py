"""``gmr markers IN.c3d|IN.trc -o OUT.gmr`` without ``--skeleton``: a skeleton built from the markers.

The marker set is recognised from the labels (:mod:`core.markers.sets`), the joint centres
placed by the published methods and the bone lengths fitted (:mod:`core.markers.build`), the
paper's closed form run on it (``--refine``: then the least squares over the joint angles,
:mod:`core.markers.refine`), and with ``--against-file-model`` our joint centres and pelvis
frames are compared with the lab model's points in the file (:mod:`core.markers.file_model`).
Prints the set, how each joint was placed, the bone lengths with their spread, and the marker
residuals after a refinement.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import motion_suffix, write_motion
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.markerset import MarkerSet


def run_built(args: argparse.Namespace, markers: MarkerSet) -> int:
    from gmr_studio.core.cli.markers import refinement_text
    from gmr_studio.core.cli.output import write_json
    from gmr_studio.core.markers.built_motion import markers_to_built_motion
    from gmr_studio.core.markers.file_model import compare_with_file_model, file_model_text

    if args.map not in (None, "joints") or args.reference or args.truth or args.calibrate is not None:
        raise OperationError(
            "without --skeleton the skeleton is built from the markers: --map, --reference, --truth and "
            "--calibrate need --skeleton"
        )
    if args.frames is not None:
        markers = markers.frame_slice(args.frames)
    if args.fill_gaps:
        markers = markers.filled(args.fill_gaps)
    unknown = sorted(set(args.weights or {}) - set(markers.labels))
    if unknown:
        raise OperationError(f"--weights names markers the file does not have: {', '.join(unknown)}")
    root_at = args.root_at or "pelvis"
    built = markers_to_built_motion(
        markers, hip=args.hip, knee=args.knee, refine=args.refine, weights=args.weights, root_at=root_at
    )
    result, skeleton = built.result, built.built
    output = Path(args.output)
    motion = result.motion
    if motion_suffix(output) == ".bvh":
        from gmr_studio.core.formats.bvh_export import bvh_export

        motion = bvh_export(motion).motion
    write_motion(motion, output)
    comparison = None
    if args.against_file_model:
        comparison = compare_with_file_model(markers, result.motion, world_positions(result.motion))
    if args.json and comparison is not None:
        write_json(comparison, args.json, indent=2)
        if args.json == "-":
            return 0
    elif args.json:
        write_json(built_report(built, str(output)), args.json, indent=2)
        if args.json == "-":
            return 0
    print(
        f"{output}: {motion.n_frames} frames x {motion.n_joints} joints at {markers.rate:.6g} Hz, mm, the file's axes; "
        f"skeleton built from set {skeleton.set_match.summary()}"
    )
    for note in result.reasons:
        print(f"  note: {note}")
    print(lengths_text(built))
    if built.refinement is not None:
        print(refinement_text(built.refinement, built.labels, 1.0, "mm"))
    if comparison is not None:
        print(file_model_text(comparison))
    return 0


def lengths_text(built) -> str:
    skeleton = built.built
    lines = [f"  {'joint':<13} {'bone mm':>8} {'spread':>7} {'5%-95%':>15}  placed by"]
    for j, name in enumerate(skeleton.skeleton.names):
        if skeleton.skeleton.parents[j] < 0:
            lines.append(f"  {name:<13} {'root':>8} {'':>7} {'':>15}  {skeleton.methods[name]}")
            continue
        lo, hi = skeleton.span[j]
        lines.append(
            f"  {name:<13} {skeleton.lengths[j]:>8.1f} {skeleton.spread[j]:>7.1f} {lo:>7.1f}-{hi:<7.1f}  "
            f"{skeleton.methods[name]}"
        )
    return "\n".join(lines)


def built_report(built, output: str) -> dict:
    skeleton = built.built
    report = {
        "output": output,
        "marker_set": skeleton.set_match.definition.name,
        "notes": list(built.result.reasons),
        "bones": [
            {
                "joint": name,
                "method": skeleton.methods[name],
                "length_mm": None if np.isnan(skeleton.lengths[j]) else float(skeleton.lengths[j]),
                "spread_mm": None if np.isnan(skeleton.spread[j]) else float(skeleton.spread[j]),
            }
            for j, name in enumerate(skeleton.skeleton.names)
        ],
    }
    if built.refinement is not None:
        after = built.refinement.residuals
        report["residuals"] = [
            {
                "marker": label,
                "median_mm": float(np.nanmedian(after[:, m])),
                "p95_mm": float(np.nanpercentile(after[:, m], 95)),
            }
            for m, label in enumerate(built.labels)
            if np.isfinite(after[:, m]).any()
        ]
    return report
