"""Text and JSON descriptions of marker sets and of marker conversions (for ``gmr``)."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.solve import SOURCE_NAMES, MarkerMotion
from gmr_studio.core.rotations.euler import rotation_angle


def describe_markers(markers: MarkerSet, path: str) -> dict:
    """A JSON-ready description: format, frames, rate, units, subjects, per-marker gaps and
    computed samples (present but computed by the capture software: ``computed_fraction``
    of all samples, ``computed`` per marker)."""
    table = markers.gap_table()
    return {
        "path": path,
        "format": "C3D" if path.lower().endswith(".c3d") else "TRC",
        "frames": markers.n_frames,
        "frame_rate": markers.rate,
        "duration": markers.duration,
        "first_frame": markers.first_frame,
        "units": markers.units,
        "subjects": sorted({s for s in markers.subjects if s}),
        "markers": table,
        "missing_fraction": float((~markers.present).mean()) if markers.present.size else 0.0,
        "computed_fraction": float(markers.computed.mean()) if markers.computed.size else 0.0,
        "notes": list(markers.notes),
        "outputs": _outputs(markers),
        "marker_set": marker_set_info(markers),
    }


def marker_set_info(markers: MarkerSet) -> dict:
    """The known marker set the labels fit (:func:`core.markers.sets.identify_marker_set`):
    ``{"name", "title", "missing", "with"}``, or ``{"name": None, "note": what a map would need}``."""
    from gmr_studio.core.markers.sets import identify_marker_set, no_match_text

    match = identify_marker_set(markers)
    if match is None:
        seen = markers.present.any(axis=0) if markers.n_frames else np.zeros(markers.n_markers, bool)
        labels = [label for label, s in zip(markers.labels, seen) if s]
        return {"name": None, "note": no_match_text(labels, [label for label, s in zip(markers.labels, seen) if not s])}
    return {
        "name": match.definition.name,
        "title": match.definition.title,
        "missing": list(match.missing),
        "with": list(match.optional),
        "summary": match.summary(),
    }


def _outputs(markers: MarkerSet) -> dict:
    """Analysis outputs by kind: ``{kind: {"units": ..., "labels": [...]}}`` (empty if none)."""
    if markers.outputs is None:
        return {}
    units = markers.outputs.units
    return {
        kind: {"units": units.get(kind, ""), "labels": labels} for kind, labels in markers.outputs.by_kind().items()
    }


def markers_text(info: dict) -> str:
    lines = [
        f"file:       {info['path']}",
        f"format:     {info['format']} markers",
        f"frames:     {info['frames']} at {info['frame_rate']:.6g} Hz ({info['duration']:.3f} s), "
        f"first frame {info['first_frame']}",
        f"units:      {info['units']} (axes as in the file)",
        f"markers:    {len(info['markers'])}",
        f"subjects:   {', '.join(info['subjects']) or 'none (no prefix on the labels)'}",
        f"gaps:       {100 * info['missing_fraction']:.2f}% of all samples",
    ]
    if info.get("computed_fraction"):
        count = sum(m["computed"] for m in info["markers"])
        lines.append(
            f"computed:   {100 * info['computed_fraction']:.2f}% of all samples ({count}, kept): filled in by the "
            "capture software, not measured (--drop-computed reads them as gaps)"
        )
    marker_set = info.get("marker_set") or {}
    if marker_set.get("name"):
        lines.append(f"set:        {marker_set['summary']}")
    elif marker_set:
        lines.append(f"set:        {marker_set['note']}")
    lines += [f"note:       {n}" for n in info["notes"]]
    for kind, group in info.get("outputs", {}).items():  # not markers: listed, never drawn
        unit = f" ({group['units']})" if group["units"] else ""
        lines.append(f"output:     {len(group['labels'])} {kind}{unit}: {', '.join(group['labels'])}")
    width = max([len(m["label"]) for m in info["markers"]] + [6])
    lines += ["", f"{'marker':<{width}}  {'missing':>8}  {'gaps':>5}  {'longest':>7}  {'computed':>8}"]
    for m in info["markers"]:
        lines.append(
            f"{m['label']:<{width}}  {m['missing']:>8}  {m['gaps']:>5}  {m['longest']:>7}  {m.get('computed', 0):>8}"
        )
    return "\n".join(lines)


def conversion_table(
    result: MarkerMotion, unit_mm: float | None, truth_positions=None, truth_rotations=None
) -> list[dict]:
    """Per joint: how its rotation was found, its distance from its virtual marker (mean,
    max) and, given the true motion of the same frames, position and angle errors.

    ``unit_mm``: the unit errors are given in, per skeleton unit (e.g. millimetres; None:
    skeleton units).
    ``truth_positions`` (F, J, 3), ``truth_rotations`` (F, J, 3, 3) local, skeleton order.
    """
    factor = unit_mm or 1.0
    motion = result.motion
    positions = world_positions(motion)
    to_marker = np.linalg.norm(positions - result.measured, axis=2) * factor
    rows = []
    for j, name in enumerate(motion.names):
        counts = np.bincount(result.sources[:, j], minlength=len(SOURCE_NAMES))
        row = {
            "joint": name,
            "measured": float((counts[0] + counts[3]) / len(result.sources)),  # measured, or the root
            "source": SOURCE_NAMES[int(np.argmax(counts))],
            "marker_mean": _mean(to_marker[:, j]),
            "marker_max": _max(to_marker[:, j]),
        }
        if truth_positions is not None:
            row["position_error"] = _mean(np.linalg.norm(positions[:, j] - truth_positions[:, j], axis=1) * factor)
        if truth_rotations is not None and motion.parents[j] >= 0:
            angle = rotation_angle(np.swapaxes(motion.rotations[:, j], -1, -2) @ truth_rotations[:, j])
            row["angle_error_deg"] = _mean(np.degrees(angle))
        rows.append(row)
    return rows


def _mean(values: np.ndarray) -> float | None:
    finite = values[np.isfinite(values)]
    return float(finite.mean()) if finite.size else None


def _max(values: np.ndarray) -> float | None:
    finite = values[np.isfinite(values)]
    return float(finite.max()) if finite.size else None


def conversion_text(rows: list[dict], unit: str) -> str:
    """The per-joint table of :func:`conversion_table` as text."""
    width = max([len(r["joint"]) for r in rows] + [len("overall")])  # the header and the last row fit too
    has_truth = any("position_error" in r for r in rows)
    has_angles = any("angle_error_deg" in r for r in rows)
    header = f"{'joint':<{width}}  {'measured':>8}  {'to marker (mean/max ' + unit + ')':>28}"
    if has_truth:
        header += f"  {'vs truth ' + unit:>12}"
    if has_angles:
        header += f"  {'angle deg':>9}"
    lines = [header]

    def cell(value, size, digits=1):
        return f"{'-':>{size}}" if value is None else f"{value:>{size}.{digits}f}"

    for r in rows:
        line = f"{r['joint']:<{width}}  {100 * r['measured']:>7.1f}%  "
        line += f"{cell(r['marker_mean'], 13)} {cell(r['marker_max'], 14)}"
        if has_truth:
            line += f"  {cell(r.get('position_error'), 12)}"
        if has_angles:
            line += f"  {cell(r.get('angle_error_deg'), 9, 2)}"
        lines.append(line)
    if has_truth:
        values = [r["position_error"] for r in rows if r.get("position_error") is not None]
        lines.append(f"{'overall':<{width}}  {'':>8}  {'':>28}  {np.mean(values):>12.1f}")
    return "\n".join(lines)


def pelvis_fit_summary(pelvis) -> dict:
    """Min, median, 95th percentile and max over the valid frames (``pelvis.units``) of the
    pelvis fit: ``procrustes`` (the three points fitted, ``fit_labels``), ``markers`` (the
    real markers against their cluster templates) and each virtual marker's distance from
    its fitted home (``virtual``: name -> figures)."""

    def figures(values) -> dict | None:
        if values is None:
            return None
        finite = np.asarray(values)[np.isfinite(values)]
        if not finite.size:
            return None
        quantiles = np.percentile(finite, [0, 50, 95, 100])
        return dict(zip(("min", "median", "p95", "max"), (float(q) for q in quantiles)))

    virtual = {}
    for k, name in enumerate(pelvis.labels):
        virtual[name] = {
            "residual": figures(None if pelvis.virtual_residuals is None else pelvis.virtual_residuals[:, k]),
            "cluster_fit": figures(None if pelvis.virtual_fit is None else pelvis.virtual_fit[:, k]),
        }
    return {
        "units": pelvis.units,
        "fit_labels": list(pelvis.fit_labels or pelvis.labels),
        "procrustes": figures(pelvis.residuals),
        "markers": figures(pelvis.marker_fit),
        "virtual": virtual,
        "note": pelvis.note,
    }


def pelvis_fit_text(summary: dict) -> str:
    """:func:`pelvis_fit_summary` as lines of text."""

    def cells(values: dict | None) -> str:
        if values is None:
            return "-"
        return " / ".join(f"{values[key]:.2f}" for key in ("min", "median", "p95", "max"))

    unit = summary["units"]
    lines = [f"pelvis fit ({unit}, min / median / 95% / max over the frames):"]
    lines.append(f"  Procrustes on {', '.join(summary['fit_labels'])}: {cells(summary['procrustes'])}")
    if summary["markers"] is not None:
        lines.append(f"  real markers to the cluster template: {cells(summary['markers'])}")
    for name, values in summary["virtual"].items():
        lines.append(
            f"  {name}: from its fitted home {cells(values['residual'])}; cluster fit {cells(values['cluster_fit'])}"
        )
    if summary["note"]:
        lines.append(f"  ({summary['note']})")
    return "\n".join(lines)
