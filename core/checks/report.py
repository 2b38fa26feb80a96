"""The checks' findings as ``gmr check`` writes them: the JSON document, the text table, one
summary row per file (``--batch``) and the ``--strict`` verdict.

JSON (stable; docs/checks.md)::

    {"file": str, "frames": int, "frame_rate": float, "units": str,
     "findings": [{"kind": str, "joints": [str], "start": int, "end": int,
                   "severity": "info" | "warning" | "error", "value": float, "units": str}],
     "skipped": [{"start": int, "end": int, "kinds": [str], "reason": str}]}

``units`` is the length unit the file states (``units: cm`` in a GMR header), else
``"file units"``; ``start`` and ``end`` are 0-based frames, both included; ``joints`` empty
means the whole pose. ``skipped``: the frames the checks of ``kinds`` did not look at and
why (:func:`core.checks.run.skipped_frames`; empty when every check saw every frame).
"""

from __future__ import annotations

from gmr_studio.core.checks.context import units_name
from gmr_studio.core.checks.model import KINDS, SEVERITIES, Finding, Skipped
from gmr_studio.core.model.motion import Motion

#: columns of the ``--batch`` table, in order (then one count column per kind)
SUMMARY_COLUMNS = ("file", "status", "frames", "frame_rate", "units", "findings", *SEVERITIES, "worst")


def check_document(file: str, motion: Motion, findings: list[Finding], skipped: list[Skipped] = ()) -> dict:
    """The JSON document of one file (module docstring)."""
    return {
        "file": str(file),
        "frames": motion.n_frames,
        "frame_rate": round(motion.frame_rate, 9),
        "units": units_name(motion),
        "findings": [f.to_dict() for f in findings],
        "skipped": [s.to_dict() for s in skipped],
    }


def frames_text(start: int, end: int) -> str:
    """``"frame 0"`` or ``"frames 1-60"``."""
    return f"frame {start}" if start == end else f"frames {start}-{end}"


def skipped_text(skipped: dict) -> str:
    """One ``skipped`` entry as a line: ``"frame 0 (the rest pose at the start) is left out
    of every check but rest-pose"``, or ``"... left out of foot-skate, pop"``."""
    kinds = skipped["kinds"]
    which = "every check but rest-pose" if set(kinds) == set(KINDS) - {"rest-pose"} else ", ".join(kinds)
    verb = "is" if skipped["start"] == skipped["end"] else "are"
    return f"{frames_text(skipped['start'], skipped['end'])} ({skipped['reason']}) {verb} left out of {which}"


def failing(findings: list[Finding] | list[dict], severity: str) -> list:
    """The findings (objects or their JSON) at ``severity`` or worse."""
    limit = SEVERITIES.index(severity)
    return [f for f in findings if SEVERITIES.index(f["severity"] if isinstance(f, dict) else f.severity) >= limit]


def _joints_text(names: list[str], width: int = 40) -> str:
    text = ", ".join(names) if names else "(whole pose)"
    return text if len(text) <= width else text[: width - 3] + "..."


def _value_text(value: float, units: str) -> str:
    if units in ("frames",):
        return f"{value:.0f} {units}"
    return f"{value:.4g} {units}"


def findings_text(document: dict) -> str:
    """The document as a terminal table: a heading line, then one row per finding."""
    findings = document["findings"]
    counts = {s: sum(1 for f in findings if f["severity"] == s) for s in SEVERITIES}
    heading = (
        f"{document['file']}: {document['frames']} frames at {document['frame_rate']:.6g} Hz, "
        f"lengths in {document['units']}; {len(findings)} finding{'s' * (len(findings) != 1)}"
    )
    if findings:
        heading += " (" + ", ".join(f"{counts[s]} {s}" for s in reversed(SEVERITIES) if counts[s]) + ")"
    lines = [heading]
    lines += [f"skipped: {skipped_text(s)}" for s in document.get("skipped", ())]
    if findings:
        lines.append(f"{'kind':<12} {'severity':<8} {'frames':>11}  {'joints':<40} value")
        for f in findings:
            frames = f"{f['start']}" if f["start"] == f["end"] else f"{f['start']}-{f['end']}"
            lines.append(
                f"{f['kind']:<12} {f['severity']:<8} {frames:>11}  {_joints_text(f['joints']):<40} "
                f"{_value_text(f['value'], f['units'])}"
            )
    return "\n".join(lines)


def summary_row(document: dict | None, file: str, status: str = "ok") -> dict:
    """One ``--batch`` row: file, status (``ok`` or the error), frames, frame rate, units,
    counts of findings in all, per severity and per kind, and the worst severity."""
    row: dict = dict.fromkeys((*SUMMARY_COLUMNS, *KINDS))
    row.update(file=file, status=status)
    if document is None:
        return row
    findings = document["findings"]
    row.update(frames=document["frames"], frame_rate=document["frame_rate"], units=document["units"])
    row["findings"] = len(findings)
    for severity in SEVERITIES:
        row[severity] = sum(1 for f in findings if f["severity"] == severity)
    for kind in KINDS:
        row[kind] = sum(1 for f in findings if f["kind"] == kind)
    worst = [s for s in SEVERITIES if row[s]]
    row["worst"] = worst[-1] if worst else ""
    return row
