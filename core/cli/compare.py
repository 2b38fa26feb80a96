"""``gmr compare A B``: per-joint errors of motion B against motion A (docs/compare.md).

Prints a table per matched joint (mean, max, frame of max; rotation mean and max where both
define orientations), the summary lines, the alignment used, the unmatched joints. Options
write the JSON document, a CSV of every frame and a plot (matplotlib). Errors are in A's
units, frames are A's 0-based indices. Exit 0; 2 for an unreadable input.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from gmr_studio.core.atomic import atomic_write_bytes, atomic_write_text
from gmr_studio.core.cli.reading import add_gltf_options, reader_options
from gmr_studio.core.compare import ALIGN_KINDS, Comparison, compare_motions
from gmr_studio.core.compare.clock import DEFAULT_OFFSET
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import read_motion


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = (
        "Compares B with A on A's frames and in A's units: joints matched by name or --map, "
        "B resampled by time, optionally shifted (--offset) and aligned (--align). Prints a table per "
        "joint, the MPJPE, median, 95th percentile and maximum, the alignment used and the unmatched joints."
    )
    parser.add_argument("a", help="the reference motion (any motion file the project reads)")
    parser.add_argument("b", help="the motion compared with it")
    parser.add_argument("--map", help="joint-name map: a shipped name (cmu) or a .toml file (docs/formats.md)")
    parser.add_argument("--asf", help="the .asf skeleton of .amc inputs (default: the one beside each AMC)")
    add_gltf_options(parser)
    parser.add_argument("--frames", help="A's frames, START:STOP (0-based, STOP excluded; either may be empty)")
    parser.add_argument("--align", choices=ALIGN_KINDS, default="none", help="fit B onto A over all frames")
    parser.add_argument(
        "--offset",
        default=DEFAULT_OFFSET,
        help=f"B's time minus A's, in A's frames (e.g. -1), or 'auto' to find it from the whole body "
        f"(default {DEFAULT_OFFSET}, as in the app)",
    )
    parser.add_argument("--scale", type=float, help="A units per B unit, when the files do not state their units")
    parser.add_argument("--up", choices=("y", "z"), help="B's up axis, when its file does not state it")
    parser.add_argument("--worst", type=int, default=3, help="joints drawn in the --plot error-over-time (default 3)")
    parser.add_argument("--json", metavar="OUT", help="write the comparison as JSON")
    parser.add_argument("--csv", metavar="OUT", help="write every frame's errors as CSV")
    parser.add_argument("--plot", metavar="OUT.png", help="write the error over time and per joint (matplotlib)")
    parser.set_defaults(run=run)


def parse_frames(text: str | None) -> tuple[int | None, int | None] | None:
    """``"10:200"`` -> (10, 200); ``":50"`` -> (None, 50); None -> None. OperationError if bad."""
    if text is None:
        return None
    parts = text.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        return tuple(int(p) if p.strip() else None for p in parts)  # type: ignore[return-value]
    except ValueError:
        raise OperationError(f"--frames must be START:STOP (whole numbers or empty), not {text!r}") from None


def parse_offset(text: str) -> float | str:
    if text == "auto":
        return "auto"
    try:
        return float(text)
    except ValueError:
        raise OperationError(f"--offset must be a number of A's frames or 'auto', not {text!r}") from None


def run(args: argparse.Namespace) -> int:
    a = read_motion(args.a, **_reading(args.a, args))
    b = read_motion(args.b, **_reading(args.b, args))
    try:
        result = compare_motions(
            a,
            b,
            joint_map=args.map,
            frames=parse_frames(args.frames),
            offset=parse_offset(args.offset),
            align=args.align,
            scale=args.scale,
            up_b=args.up,
            label_a=args.a,
            label_b=args.b,
        )
    except ValueError as exc:
        raise OperationError(str(exc)) from None
    print(comparison_text(result))
    for label, motion in (("A", a), ("B", b)):
        for note in reading_notes(motion):
            print(f"read {label}:   {note}")
    if args.json:
        atomic_write_text(args.json, json.dumps(result.to_json(), indent=1) + "\n")
        print(f"wrote {args.json}")
    if args.csv:
        atomic_write_text(args.csv, result.to_csv())
        print(f"wrote {args.csv}")
    if args.plot:
        write_plot(result, args.plot, worst=args.worst)
        print(f"wrote {args.plot}")
    return 0


def _reading(path: str, args: argparse.Namespace) -> dict:
    """The reader's options for one input: --asf for an AMC, --animation/--skin for glTF
    (sampled at its keys' spacing: the comparison resamples B on A's clock)."""
    return reader_options(path, args.asf, animation=args.animation, skin=args.skin)


#: the beginnings of the notes a reader adds that change what is compared (glTF: the
#: armature applied, the rest orientation taken out, scale folded, the sampling)
READING_NOTES = ("armature:", "rest pose:", "WARNING", "uniform scale", "animated uniform", "keys at", "sampled at")


def reading_notes(motion) -> list[str]:
    """The motion's reading notes that bear on a comparison (:data:`READING_NOTES`)."""
    return [c for c in motion.comments if c.startswith(READING_NOTES)]


def comparison_text(result: Comparison) -> str:
    """The table, summary, alignment and unmatched joints, as ``gmr compare`` prints them."""
    p, r = result.position, result.rotation
    unit = result.units_text
    width = max([len(f"{a} ~ {b}") for a, b in zip(result.names_a, result.names_b)] + [5])
    header = f"{'joint (A ~ B)':<{width}}  {'mean':>10}  {'max':>10}  {'at frame':>8}"
    if r is not None:
        header += f"  {'rot mean':>8}  {'rot max':>8}"
    lines = [f"A: {result.label_a}", f"B: {result.label_b}", f"errors in {unit} (A's); frames are A's", "", header]

    def cell(value: float, size: int, digits: int) -> str:
        return f"{'-':>{size}}" if not np.isfinite(value) else f"{value:>{size}.{digits}f}"

    for j, (name, match) in enumerate(zip(result.names_a, result.names_b)):
        frame = p.per_joint_max_frame[j]
        line = f"{name + ' ~ ' + match:<{width}}  {cell(p.per_joint_mean[j], 10, 5)}  {cell(p.per_joint_max[j], 10, 5)}"
        line += f"  {frame if frame >= 0 else '-':>8}"
        if r is not None:
            line += f"  {cell(r.per_joint_mean[j], 8, 3)}  {cell(r.per_joint_max[j], 8, 3)}"
        lines.append(line)
    first, last = (int(result.frames[0]), int(result.frames[-1])) if result.n_frames else (0, -1)
    lines += [
        "",
        f"frames:   {result.n_frames} of A ({first}-{last}); {p.count} joint samples compared "
        f"({result.n_frames * result.n_pairs - p.count} without B: outside its time range or gaps)",
        f"MPJPE:    {p.mean:.6g} {unit}   median {p.median:.6g}   p95 {p.p95:.6g}",
        f"max:      {p.max:.6g} {unit} at frame {p.max_frame}, joint {p.max_joint}",
    ]
    if r is not None and r.count:
        lines.append(f"rotation: mean {r.mean:.4g} deg   p95 {r.p95:.4g}   max {r.max:.4g} at frame {r.max_frame}, "
                     f"joint {r.max_joint} (world rotations, roots excluded)")  # fmt: skip
    lines += alignment_lines(result)
    lines.append(f"unmatched in A: {', '.join(result.unmatched_a) or 'none'}")
    lines.append(f"unmatched in B: {', '.join(result.unmatched_b) or 'none'}")
    return "\n".join(lines)


def alignment_lines(result: Comparison) -> list[str]:
    al = result.alignment
    how = "given"
    if al.offset_found:
        how = "found (--offset auto)"
        if al.offset_search is not None:
            how += f": {al.offset_search.text()}"
    default = " (the default)" if (al.offset_found and DEFAULT_OFFSET == "auto") else ""
    lines = [f"offset:   B = A {al.offset_frames:+g} frames ({al.offset_seconds:+.6g} s), {how}{default}"]
    lines += [f"space:    {note}" for note in al.notes]
    if al.kind == "none":
        lines.append(f"align:    none (RMS distance {al.rms_after:.6g} {result.units_text})")
    else:
        angle = np.degrees(np.arccos(np.clip((np.trace(al.fit.rotation) - 1) / 2, -1, 1)))
        lines.append(
            f"align:    {al.kind}: rotation {angle:.4g} deg, translation "
            f"({', '.join(f'{v:.6g}' for v in al.fit.translation)}), scale {al.fit.scale:.6g}; "
            f"RMS distance {al.rms_before:.6g} -> {al.rms_after:.6g} {result.units_text}"
        )
    return lines


def write_plot(result: Comparison, path: str, worst: int = 3) -> None:
    """Error over time (MPJPE and the ``worst`` joints by mean error) above a per-joint bar
    chart (mean, with the max as a tick), to a PNG (or any format matplotlib writes)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise OperationError("--plot needs matplotlib: pip install matplotlib") from None
    import io

    p = result.position
    unit = result.units_text
    figure, (over_time, per_joint) = plt.subplots(2, 1, figsize=(11, 8), gridspec_kw={"height_ratios": [1, 1.1]})
    over_time.plot(result.frames, p.per_frame, color="black", linewidth=1.5, label="MPJPE")
    order = np.argsort(np.where(np.isfinite(p.per_joint_max), p.per_joint_max, -np.inf))[::-1][:worst]
    for j in order:
        over_time.plot(result.frames, result.position_error[:, j], linewidth=0.8, label=result.names_a[j])
    over_time.set_xlabel("frame of A")
    over_time.set_ylabel(f"position error ({unit})")
    title = f"{Path(result.label_b).name} against {Path(result.label_a).name}: MPJPE {p.mean:.4g} {unit}"
    over_time.set_title(f"{title} (worst {worst} joints by max)")
    over_time.legend(loc="best", fontsize=8)
    over_time.grid(alpha=0.3)
    x = np.arange(result.n_pairs)
    per_joint.bar(x, p.per_joint_mean, color="#4c72b0", label="mean")
    per_joint.scatter(x, p.per_joint_max, marker="_", s=120, color="#c44e52", label="max", zorder=3)
    per_joint.set_xticks(x, result.names_a, rotation=70, fontsize=7)
    per_joint.set_ylabel(f"per joint ({unit})")
    per_joint.legend(loc="best", fontsize=8)
    per_joint.grid(axis="y", alpha=0.3)
    figure.tight_layout()
    buffer = io.BytesIO()
    suffix = path.rsplit(".", 1)[-1].lower() if "." in path else "png"
    figure.savefig(buffer, format=suffix, dpi=110)
    plt.close(figure)
    atomic_write_bytes(path, buffer.getvalue())
