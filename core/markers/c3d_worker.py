"""The child process of :func:`core.markers.c3d.read_c3d`: ezc3d decodes one file.

``python -m gmr_studio.core.markers.c3d_worker FILE [MEMORY_BYTES]`` writes the decoded file to stdout
as an .npz archive, or its error to stderr with exit status 3. Nothing in the package
imports this module at import time, so ``-m`` runs it without a second copy.
"""

from __future__ import annotations

import io
import json
import os
import sys
from pathlib import Path

import numpy as np

#: exit status when ezc3d raised (the same number as core.markers.c3d.REJECTED)
REJECTED = 3
#: POINT parameters that list analysis outputs stored as points (the C3D standard's groups;
#: POINT:TYPE_GROUPS may name more)
OUTPUT_GROUPS = ("ANGLES", "FORCES", "MOMENTS", "POWERS", "SCALARS", "REACTIONS")
#: POINT parameters that are never output groups, whatever TYPE_GROUPS says
_NOT_GROUPS = ("LABELS", "DESCRIPTIONS", "UNITS", "TYPE_GROUPS")


#: what the worker prints before a message of the project's own (not ezc3d's)
OWN_PREFIX = "gmr: "


class OwnError(ValueError):
    """A reason of the project's own for refusing the file (printed after OWN_PREFIX)."""


def output_groups(point) -> tuple[dict[str, list[str]], dict[str, str]]:
    """The analysis-output groups of ezc3d's POINT parameters: group name -> the point labels
    it lists, and group name -> its unit (``POINT:ANGLE_UNITS`` for ANGLES...).

    The groups are :data:`OUTPUT_GROUPS` and every POINT parameter that ``POINT:TYPE_GROUPS``
    names (pairs such as ``Angles ANGLES``; names are compared upper-case) and that holds text.
    """
    names = list(OUTPUT_GROUPS)
    if "TYPE_GROUPS" in point:
        for entry in np.asarray(point["TYPE_GROUPS"]["value"]).reshape(-1):
            name = str(entry).strip().upper()
            if name and name not in names and not name.startswith(_NOT_GROUPS) and not name.endswith("_UNITS"):
                names.append(name)
    groups: dict[str, list[str]] = {}
    units: dict[str, str] = {}
    for name in names:
        if name not in point or point[name]["type"] != -1:  # ezc3d type -1: text
            continue
        labels = [str(label).strip() for label in np.asarray(point[name]["value"]).reshape(-1) if str(label).strip()]
        if labels:
            groups[name] = labels
            unit = point.get(f"{name.removesuffix('S')}_UNITS")
            values = np.asarray(unit["value"]).reshape(-1) if unit is not None else []
            units[name] = str(values[0]).strip() if len(values) else ""
    return groups, units


def processing_parameters(parameters) -> dict[str, float]:
    """The numbers of the PROCESSING group (the subject measurements Vicon Nexus and pyCGM2
    store there: KneeWidth, LAnkleWidth, MarkerDiameter, LegLength... in mm)."""
    out: dict[str, float] = {}
    for name, entry in parameters.get("PROCESSING", {}).items():
        value = entry.get("value") if isinstance(entry, dict) else None
        try:
            numbers = np.asarray(value, dtype=np.float64).ravel()
        except (TypeError, ValueError):
            continue
        if numbers.size == 1 and np.isfinite(numbers[0]):
            out[str(name)] = float(numbers[0])
    return out


def decode_c3d(path: Path) -> dict:
    """What this module needs from ezc3d, as plain arrays and a JSON-ready ``meta`` dict.

    Returns ``points`` (F, M, 3) float64 (NaN where ezc3d flags the sample), ``residuals``
    (F, M) float64 and ``meta`` (labels, units, rate, first_frame, and ``long_frames``
    when the parameters announce more frames than ezc3d read: then every frame is decoded
    by :func:`core.markers.c3d_frames.read_points`).
    """
    from gmr_studio.core.markers.c3d_frames import parameter_frame_count, read_points

    c3d, notes = _ezc3d_read(path)
    point = c3d["parameters"]["POINT"]
    data = c3d["data"]
    xyz = np.ascontiguousarray(np.asarray(data["points"], dtype=np.float64)[:3].transpose(2, 1, 0))
    residuals = np.asarray(data["meta_points"]["residuals"], dtype=np.float64)
    residuals = residuals[0].T if residuals.size else np.zeros(xyz.shape[:2])
    labels: list[str] = []
    for key in ["LABELS"] + [f"LABELS{k}" for k in range(2, 100)]:
        if key not in point:
            break
        labels += [str(label) for label in point[key]["value"]]
    header = c3d["header"]["points"]
    units = point["UNITS"]["value"] if "UNITS" in point else []
    rate = point["RATE"]["value"] if "RATE" in point else []
    groups, group_units = output_groups(point)
    meta = {
        "output_groups": groups,
        "output_units": group_units,
        "labels": labels,
        "units": str(units[0]) if len(units) else "",
        "rate": float(rate[0]) if len(rate) else float(header["frame_rate"]),
        "first_frame": int(header["first_frame"]),
    }
    counted = parameter_frame_count(c3d["parameters"])
    if counted is not None and counted[0] > xyz.shape[0]:  # past 65,535 frames: ezc3d stops there
        xyz, residuals, read = read_points(path, c3d["parameters"], counted[0])
        meta["long_frames"] = {"announced": counted[0], "where": counted[1], "read": read}
    elif (layout := _analog_layout_note(path, c3d)) is not None:
        xyz, residuals, _ = read_points(path, c3d["parameters"], xyz.shape[0])
        notes.append(layout)
    meta["parameters"] = processing_parameters(c3d["parameters"])
    meta["notes"] = notes
    return {"points": xyz, "residuals": residuals, "meta": meta}


def _ezc3d_read(path: Path):
    """ezc3d's reading of the file and what was done to make it readable: an SGI/MIPS file,
    which ezc3d refuses, is rewritten in Intel byte order first (:mod:`core.markers.c3d_byteorder`)."""
    import tempfile

    import ezc3d  # imported here: the parent process of an isolated read never loads it

    from gmr_studio.core.markers.c3d_byteorder import SGI, C3DLayoutError, intel_from_sgi, processor_of

    data = path.read_bytes()
    try:
        sgi = processor_of(data) == SGI
    except C3DLayoutError:
        sgi = False  # ezc3d says what is wrong
    if not sgi:
        return ezc3d.c3d(str(path)), []
    try:
        intel = intel_from_sgi(data)
    except C3DLayoutError as exc:
        raise OwnError(
            f"this SGI/MIPS (big-endian) C3D is damaged: {exc}; export the trial again from the capture software"
        ) from None
    with tempfile.TemporaryDirectory(prefix="gmr-c3d-") as folder:
        copy = Path(folder) / "intel.c3d"
        copy.write_bytes(intel)
        c3d = ezc3d.c3d(str(copy))
    return c3d, ["written on an SGI/MIPS machine (big-endian): read in Intel byte order, numbers unchanged"]


def _analog_layout_note(path: Path, c3d) -> str | None:
    """A note when ezc3d's frame layout disagrees with the header's, else None.

    ezc3d sizes a frame's analog block as ANALOG:USED x (ANALOG:RATE / POINT:RATE, rounded
    down); the header's word 3 holds the analog values per 3D frame that the writer used.
    Where they differ (Motion Analysis' EVaRT sample 11: ANALOG:RATE 1000 at 60 Hz gives
    ezc3d 16 samples, the header and the file's size say 17), ezc3d reads every frame after
    the first from the wrong place; the points are then decoded by the header's layout
    (:func:`core.markers.c3d_frames.read_points`), which the file's size confirms."""
    from gmr_studio.core.markers.c3d_frames import analog_values_per_frame

    analogs = c3d["header"]["analogs"]
    point_rate = float(c3d["header"]["points"]["frame_rate"])
    if not analogs["size"] or point_rate <= 0:
        return None
    ezc3d_values = int(analogs["size"]) * round(float(analogs["frame_rate"]) / point_rate)
    header_values = analog_values_per_frame(path)
    if ezc3d_values == header_values:
        return None
    return (
        f"the header stores {header_values} analog values per frame, ezc3d expected {ezc3d_values} "
        "(from ANALOG:RATE / POINT:RATE): points decoded by the header's layout"
    )


def _die_with_parent(parent: int | None) -> None:
    """Ask Linux to kill this process when its parent dies (a reader killed in the middle of
    a read must not leave ezc3d spinning), and leave at once if the parent is already gone."""
    try:
        import ctypes
        import signal

        libc = ctypes.CDLL(None)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        return
    if parent is not None and os.getppid() != parent:
        os._exit(REJECTED)


def _worker(argv: list[str]) -> int:
    """``python -m gmr_studio.core.markers.c3d_worker FILE [MEMORY_BYTES [SECONDS [PARENT_PID]]]``: the
    decoded file as .npz on stdout."""
    _die_with_parent(int(argv[3]) if len(argv) > 3 else None)
    try:
        import resource

        if len(argv) > 1:
            limit = int(argv[1])
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        if len(argv) > 2:  # CPU seconds: a backstop should the parent's timeout never come
            seconds = int(float(argv[2])) + 2
            resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 1))
    except (ImportError, ValueError, OSError):  # pragma: no cover - platform without rlimits
        pass
    try:
        decoded = decode_c3d(Path(argv[0]))
    except MemoryError:
        print("the file asks for more memory than any C3D needs", file=sys.stderr)
        return REJECTED
    except OwnError as exc:
        print(OWN_PREFIX + str(exc), file=sys.stderr)
        return REJECTED
    except Exception as exc:  # ezc3d raises OSError, RuntimeError, ValueError...
        print(str(exc), file=sys.stderr)
        return REJECTED
    buffer = io.BytesIO()
    np.savez(
        buffer, points=decoded["points"], residuals=decoded["residuals"], meta=np.array(json.dumps(decoded["meta"]))
    )
    sys.stdout.buffer.write(buffer.getvalue())
    sys.stdout.buffer.flush()
    return 0


if __name__ == "__main__":
    sys.exit(_worker(sys.argv[1:]))
