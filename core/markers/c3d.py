"""C3D marker files through ezc3d, in a child process so that no file can crash the caller.

ezc3d reads every C3D flavour (Intel, DEC and SGI byte orders; integer and float samples;
``LABELS2``... for more than 255 markers). It is a C++ extension, and on corrupt files it
does not always raise: random bytes in a real file's parameter section can make it hang
for minutes or die with a segmentation fault. A reader in a desktop app must not take the
app down with it, so by default the decoding runs in a child Python process
(``python -m gmr_studio.core.markers.c3d_worker FILE``) with a time and memory limit, at the
cost of starting that process. A C3D that ezc3d rejects, or that makes it crash or hang,
becomes a :class:`~core.errors.MotionFileError` naming the file.

Gaps and computed samples. A sample whose residual is negative is invalid in every C3D
(ezc3d gives NaN): a gap. A residual of zero marks a point the cameras did not measure but
the capture software computed (its gap filling, an interpolation or a filter), *when the
file records residuals at all* (some sample has a positive one, as CMU's files do): such
samples are kept, marked in :attr:`MarkerSet.computed <core.markers.markerset.MarkerSet>`
(CMU 01_01's 859, 0.7%, are continuous with the measured samples around them), and
``computed="drop"`` makes them gaps. Many writers (Qualisys, Vicon Nexus exports, the
Plug-in Gait sample) write a zero residual for every sample: there it means "no residual
recorded", and the samples are kept as measured. Only the evidence makes a gap of a sample
with residual 0: at exactly (0, 0, 0) (older writers mark missing markers that way), or a
computed sample farther from the measured samples before and after it than a marker can
move in the time between (:data:`MAX_MARKER_SPEED`).

Analysis outputs: joint angles, forces, moments, powers and scalars that a model (Vicon Plug-in
Gait, pyCGM2) stores among the POINT entries are named in ``POINT:ANGLES``, ``FORCES``,
``MOMENTS``, ``POWERS``, ``SCALARS`` (and any group ``POINT:TYPE_GROUPS`` names): they are
kept out of the markers, in ``MarkerSet.outputs`` (:class:`~core.markers.markerset.PointOutputs`,
only invalid samples are gaps there), and a note counts them.

Long captures: past 65,535 frames ezc3d stops at the 16-bit count; the worker then reads the
real count from the parameters and decodes every frame (:mod:`core.markers.c3d_frames`).
"""

from __future__ import annotations

import io
import json
import os
import signal
import struct
import subprocess
import sys
from pathlib import Path
from typing import Literal

import numpy as np

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers.markerset import MarkerSet, PointOutputs, gap_runs, split_subject
from gmr_studio.core.space.units import parse_unit, unit_named

#: exit status of the worker when ezc3d raised (its message is on stderr); see c3d_worker
REJECTED = 3

Computed = Literal["keep", "drop"]

#: metres per second no marker on a body reaches (a hand in a pitch or a punch peaks near
#: 20, a golf club's head near 50): a computed sample that far from the measured ones is no
#: position of its marker
MAX_MARKER_SPEED = 60.0

_PROCESSORS = {84: "Intel", 85: "DEC", 86: "SGI/MIPS"}
#: the module run in the child process
WORKER_MODULE = "gmr_studio.core.markers.c3d_worker"
#: the worker's address-space limit, in bytes (a C3D needs a few times its size)
_MEMORY_FLOOR = 4 << 30


def read_c3d(
    path: str | Path,
    *,
    computed: Computed = "keep",
    rate: float | None = None,
    isolate: bool = True,
    timeout: float | None = None,
) -> MarkerSet:
    """Read the 3D points of a C3D file into a :class:`MarkerSet`.

    Parameters
    ----------
    path : the file.
    computed : ``"keep"`` the samples the capture software computed (residual 0 in a file
        that records residuals), marked in ``MarkerSet.computed``, or ``"drop"`` them (gaps);
        see the module docstring.
    rate : frames per second, for a file whose POINT:RATE is 0 or wrong (None: the file's).
    isolate : decode in a child process (default); ``False`` calls ezc3d in this process,
        which is faster but trusts the file.
    timeout : seconds the child may take (default: 10 s plus 1 s per MB of file).

    Returns
    -------
    MarkerSet with positions (F, M, 3) in the file's POINT:UNITS and axes, gaps NaN,
    ``computed`` (F, M), the subject prefix split off each label, ``first_frame`` from the
    header, and ``notes`` saying what was tolerated (computed samples kept or dropped,
    renamed labels, a file shorter than its header).

    Raises
    ------
    MotionFileError : the file is missing, is not a C3D, ezc3d rejects it, or it gives no
        frame rate and ``rate`` is None.
    """
    if computed not in ("keep", "drop"):
        raise ValueError(f"computed must be 'keep' or 'drop', not {computed!r}")
    if rate is not None and not (np.isfinite(rate) and rate > 0):
        raise ValueError(f"the frame rate must be a positive number, not {rate}")
    where = str(path)
    size, announced = _check_header(Path(path), where)
    if isolate:
        decoded = _decode_in_child(Path(path), where, size, timeout)
    else:
        from gmr_studio.core.markers.c3d_worker import decode_c3d  # not at import: see c3d_worker

        try:
            decoded = decode_c3d(Path(path))
        except (OSError, RuntimeError, ValueError, MemoryError, IndexError) as exc:
            from gmr_studio.core.markers.c3d_worker import OWN_PREFIX, OwnError

            text = OWN_PREFIX + str(exc) if isinstance(exc, OwnError) else str(exc)
            raise MotionFileError(where, rejection(_clean(text))) from None
    decoded["meta"]["announced_frames"] = announced
    return _marker_set(decoded, where, computed, rate)


def _check_header(path: Path, where: str) -> tuple[int, int]:
    """The cheap checks of the 512-byte header, with clear messages.

    Returns the file size and the number of frames the header announces (0 when its 16-bit
    frame numbers cannot tell: ezc3d rewrites them to what it read, so they are taken here).
    """
    try:
        with path.open("rb") as stream:
            header = stream.read(512)
            size = os.fstat(stream.fileno()).st_size
    except OSError as exc:
        raise MotionFileError(where, f"cannot read the file: {exc.strerror or exc}") from None
    if size == 0:
        raise MotionFileError(where, "the file is empty: expected a C3D header of 512 bytes")
    if len(header) < 512:
        raise MotionFileError(where, f"the file has {size} bytes: a C3D starts with a header of 512 bytes")
    if header[1] != 0x50:
        raise MotionFileError(where, f"byte 2 is {header[1]}, not 80 (0x50): this is not a C3D file")
    start = (header[0] - 1) * 512
    if header[0] < 1 or start + 4 > size:
        raise MotionFileError(where, f"the parameter section (block {header[0]}) lies outside the file")
    with path.open("rb") as stream:
        stream.seek(start)
        section = stream.read(4)
    if section[3] not in _PROCESSORS:
        known = ", ".join(f"{code} ({name})" for code, name in _PROCESSORS.items())
        raise MotionFileError(where, f"unknown processor type {section[3]} in the parameters: expected {known}")
    first, last = struct.unpack(">HH" if section[3] == 86 else "<HH", header[6:10])
    return size, (last - first + 1 if first <= last < 0xFFFF else 0)


#: how many times the CPU budget a child may take on the clock: a busy machine slows the
#: child's start and its reading, while a file that makes ezc3d spin uses up its CPU budget
WALL_CLOCK_FACTOR = 6


def _decode_in_child(path: Path, where: str, size: int, timeout: float | None) -> dict:
    limit = timeout if timeout is not None else 10.0 + size / 1e6  # CPU seconds
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = env["OPENBLAS_NUM_THREADS"] = "1"
    memory = str(max(_MEMORY_FLOOR, 64 * size))
    command = [sys.executable, "-m", WORKER_MODULE, str(path.resolve()), memory, f"{limit:.0f}", str(os.getpid())]
    try:
        done = subprocess.run(
            command, capture_output=True, timeout=WALL_CLOCK_FACTOR * limit, env=env, stdin=subprocess.DEVNULL
        )
    except subprocess.TimeoutExpired:
        raise MotionFileError(
            where,
            f"ezc3d did not finish reading the file in {WALL_CLOCK_FACTOR * limit:.0f} s: the file is probably corrupt",
        ) from None
    message = _clean(done.stderr.decode("utf-8", "replace"))
    if done.returncode == REJECTED:
        raise MotionFileError(where, rejection(message))
    if done.returncode == -signal.SIGXCPU:
        raise MotionFileError(
            where, f"ezc3d did not finish reading the file in {limit:.0f} s of CPU time: the file is probably corrupt"
        )
    if done.returncode != 0:
        cause = f"signal {-done.returncode}" if done.returncode < 0 else f"exit status {done.returncode}"
        detail = f" ({message})" if done.stderr.strip() else ""
        raise MotionFileError(where, f"ezc3d crashed reading the file ({cause}){detail}: the file is corrupt")
    with np.load(io.BytesIO(done.stdout), allow_pickle=False) as archive:
        decoded = {key: archive[key] for key in archive.files}
    decoded["meta"] = json.loads(str(decoded["meta"]))
    return decoded


def rejection(message: str) -> str:
    """The error message for a file the worker refused: the project's own reasons as they
    are; ezc3d's prefixed with its name, and, where ezc3d asks its user to report a missing
    feature, what the user can do instead."""
    own = "gmr: "  # c3d_worker.OWN_PREFIX (the worker module is not imported here)
    if message.startswith(own):
        return message[len(own) :]
    if "github issue" in message.lower():
        what = message.split(",")[0].split(". ")[0].strip().rstrip(".")
        return (
            f"this kind of C3D cannot be read here (ezc3d: {what}); export the trial again from the "
            "capture software as a PC (Intel) C3D, or convert it with a C3D editor such as Mokka"
        )
    return f"ezc3d rejects the file: {message}"


def _clean(message: str) -> str:
    lines = [line.strip() for line in message.strip().splitlines() if line.strip()]
    text = lines[-1] if lines else "no reason given"
    return text.removesuffix(": iostream error")


def _marker_set(decoded: dict, where: str, computed: Computed = "keep", given_rate: float | None = None) -> MarkerSet:
    meta = decoded["meta"]
    points = np.array(decoded["points"], dtype=np.float64)
    residuals = np.asarray(decoded["residuals"], dtype=np.float64)
    n_frames, n_points = points.shape[:2]
    notes: list[str] = list(meta.get("notes", []))
    rate = _rate(meta["rate"], given_rate, where, notes)
    unit = parse_unit(meta["units"])
    units = None if unit is None else unit.name
    if units is None:
        units = "mm"
        notes.append(f"POINT:UNITS is '{meta['units'].strip()}', not a length unit known here: read as mm")
    kinds = _output_kinds(meta["labels"], n_points, meta.get("output_groups", {}))
    is_marker = np.array([not kind for kind in kinds], dtype=bool)
    gaps = (residuals < 0) | ~np.isfinite(points).all(axis=2)
    # the residual rules are the markers': analysis outputs are computed, never measured
    zero = (residuals == 0) & ~gaps & is_marker
    origin = zero & (points == 0).all(axis=2)
    if origin.any():
        notes.append(f"{int(origin.sum())} samples at exactly (0, 0, 0) with no residual read as gaps")
        gaps |= origin
    recorded = bool((residuals[:, is_marker] > 0).any())
    made = zero & ~gaps if recorded else np.zeros_like(zero)
    jumps = _jumps(points, (residuals > 0) & ~gaps, made, rate, unit_named(units).metres)
    if jumps.any():
        notes.append(
            f"{int(jumps.sum())} computed samples (residual 0) farther from the measured ones around them than a "
            f"marker moves at {MAX_MARKER_SPEED:g} m/s read as gaps"
        )
        gaps |= jumps
        made &= ~jumps
    if made.any():
        share = 100.0 * made.sum() / max(int(is_marker.sum()) * n_frames, 1)
        what = f"{int(made.sum())} samples with residual 0 ({share:.2g}% of the markers' samples"
        what += ": computed by the capture software, not measured)"
        notes.append(what + (" read as gaps" if computed == "drop" else " kept and marked computed"))
        if computed == "drop":
            gaps |= made
            made = np.zeros_like(made)
    points[gaps] = np.nan
    long_frames = meta.get("long_frames")
    if long_frames:
        notes.append(
            f"{long_frames['where']} gives {long_frames['announced']} frames, more than the header's 16-bit "
            f"frame numbers hold: {long_frames['read']} frames read"
            + ("" if long_frames["read"] == long_frames["announced"] else " (the file ends there: it may be truncated)")
        )
    elif meta["announced_frames"] != n_frames and meta["announced_frames"] > 0:
        notes.append(
            f"the header announces {meta['announced_frames']} frames, the file holds {n_frames}: it may be truncated"
        )
    subjects, labels = _labels(meta["labels"], n_points, notes)
    outputs = None
    if not is_marker.all():
        index = np.flatnonzero(~is_marker)
        outputs = PointOutputs(
            labels=tuple(labels[m] for m in index),
            subjects=tuple(subjects[m] for m in index),
            kinds=tuple(kinds[m] for m in index),
            values=points[:, index],
            units={group.lower(): unit for group, unit in meta.get("output_units", {}).items()},
        )
        counts = ", ".join(f"{len(group)} {kind}" for kind, group in outputs.by_kind().items())
        notes.append(f"{outputs.n_outputs} analysis outputs ({counts}) kept out of the markers")
        keep = np.flatnonzero(is_marker)
        points, subjects, labels = points[:, keep], [subjects[m] for m in keep], [labels[m] for m in keep]
        made = made[:, keep]
    return MarkerSet(
        labels=labels,
        subjects=subjects,
        positions=points,
        computed=made,
        rate=rate,
        units=units,
        first_frame=meta["first_frame"],
        source=where,
        notes=notes,
        outputs=outputs,
        parameters=dict(meta.get("parameters", {})),
    )


def _rate(stated: float, given: float | None, where: str, notes: list[str]) -> float:
    """The frame rate: ``given`` (``--rate``) when there is one, noted where the file states
    another; else the file's, which must be positive."""
    if given is not None:
        if np.isfinite(stated) and stated > 0 and stated != given:
            notes.append(f"POINT:RATE is {stated:g} Hz: read at {given:g} Hz as asked")
        return float(given)
    if not np.isfinite(stated) or stated <= 0:
        raise MotionFileError(
            where,
            f"the point rate is {stated:g}: the file does not say how many frames per second it holds; "
            "give the rate it was captured at with --rate HZ",
        )
    return float(stated)


def _jumps(points: np.ndarray, measured: np.ndarray, computed: np.ndarray, rate: float, metres: float) -> np.ndarray:
    """(F, M) bool: the computed samples farther from the measured sample before them and
    from the one after them (each that exists) than a marker moves at
    :data:`MAX_MARKER_SPEED` in the time between. ``points`` (F, M, 3) in units of
    ``metres``; ``measured``, ``computed`` (F, M) bool."""
    out = np.zeros_like(computed)
    frames, markers = np.nonzero(computed)
    if not frames.size:
        return out
    per_frame = MAX_MARKER_SPEED / metres / rate  # file units a marker can move in a frame
    too_far = np.ones(frames.size, bool)
    anchored = np.zeros(frames.size, bool)
    for anchor in gap_runs(measured):
        at = anchor[frames, markers]
        inside = (at >= 0) & (at < points.shape[0])
        distance = np.linalg.norm(points[frames, markers] - points[np.where(inside, at, 0), markers], axis=1)
        too_far &= ~inside | (distance > per_frame * np.abs(frames - at))
        anchored |= inside
    out[frames, markers] = too_far & anchored
    return out


def _output_kinds(raw: list[str], n_points: int, groups: dict[str, list[str]]) -> list[str]:
    """Per point, the analysis-output group that lists it (lower case), "" for markers.

    A group may name a point with or without its subject prefix."""
    kind_of: dict[str, str] = {}
    for group, members in groups.items():
        for member in members:
            kind_of.setdefault(member, group.lower())
    kinds = []
    for m in range(n_points):
        text = raw[m].strip() if m < len(raw) else ""
        kinds.append((kind_of.get(text) or kind_of.get(split_subject(text)[1], "")) if text else "")
    return kinds


def _labels(raw: list[str], n_markers: int, notes: list[str]) -> tuple[list[str], list[str]]:
    """Subjects and bare labels for the M points: blanks named, duplicates made unique."""
    if len(raw) < n_markers:
        notes.append(f"POINT:LABELS names {len(raw)} of the {n_markers} points: the others are named M001...")
    subjects, labels = [], []
    seen: set[tuple[str, str]] = set()
    for m in range(n_markers):
        text = raw[m].strip() if m < len(raw) else ""
        subject, label = split_subject(text) if text else ("", f"M{m + 1:03d}")
        if (subject, label) in seen:
            copy = 2
            while (subject, f"{label}~{copy}") in seen:
                copy += 1
            notes.append(f"point {m + 1} repeats the label '{text}': renamed '{label}~{copy}'")
            label = f"{label}~{copy}"
        seen.add((subject, label))
        subjects.append(subject)
        labels.append(label)
    return subjects, labels
