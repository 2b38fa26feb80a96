"""Reading one file for the library: what it holds, what the checks find, its thumbnail.

:func:`describe_files` is the task a worker process runs (locally or on a Dask worker): it
takes a few files and returns one :class:`FileRecord` each, never raising. A file is
identified by its :func:`file_stamp` (size and modification time, with those of the files it
reads besides itself: an AMC's ASF) and its content hash (BLAKE2b of the same bytes); when
the hash is the one the library already holds the file is not read again
(:attr:`FileRecord.unchanged`).

Motions (every suffix of :data:`core.formats.READERS`, so a format registered there is
indexed too) are read with :func:`core.formats.read_motion` and checked by
:func:`core.checks.run_checks`; marker files (:data:`core.markers.MARKER_READERS`) by
:func:`core.markers.read_markers` and :func:`core.checks.markers.run_marker_checks`. A file
that cannot be read is a record with ``status`` ``"failed"`` and the reader's one line.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from gmr_studio.core.batch import workers
from gmr_studio.core.checks import SEVERITIES, CheckSettings, Finding, run_checks
from gmr_studio.core.checks.markers import run_marker_checks
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import READERS, motion_suffix, read_motion
from gmr_studio.core.formats.acclaim import asf_beside
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.library.skeletons import Skeleton
from gmr_studio.core.library.thumbnails import POSES, SIZE, marker_thumbnail, motion_thumbnail, png_bytes
from gmr_studio.core.markers import MARKER_READERS, read_markers
from gmr_studio.core.space.up_axis import detect_up_axis, up_axis_of
from gmr_studio.core.timebase.clock import duration_of

#: the version of what a record derives from a file: raised when the fields, the thumbnail
#: drawing or the way checks are summed up change, so that the next run reads every file again
RECORD_VERSION = 1
#: the stages of :func:`describe_file`, each timed: the file's stamp and content hash, reading
#: it (and its world positions), the checks, the thumbnail (drawn and encoded as PNG)
STAGES = ("hash", "read", "checks", "thumbnail")


def library_suffixes() -> tuple[str, ...]:
    """Every suffix the library indexes: the motion readers' and the marker readers'."""
    return tuple(sorted({*READERS, *MARKER_READERS}))


@dataclasses.dataclass(frozen=True)
class IndexOptions:
    """How files are read and summed up.

    body_model : the SMPL-family model AMASS ``.npz`` files are read with (None: such a
        file is a failed row saying so).
    settings : the checks' settings (:class:`core.checks.CheckSettings`), as its dict.
    size, poses : the thumbnail's size in pixels and how many poses it shows.
    """

    body_model: str | None = None
    settings: dict = dataclasses.field(default_factory=lambda: CheckSettings().to_dict())
    size: tuple[int, int] = SIZE
    poses: int = POSES

    def analysis(self, suffix: str) -> str:
        """The tag of what a file of ``suffix`` is summed up with: a record made under
        another tag is read again."""
        what = {"record": RECORD_VERSION, "settings": self.settings, "size": list(self.size), "poses": self.poses}
        if suffix == ".npz":
            what["body_model"] = self.body_model
        return hashlib.blake2b(json.dumps(what, sort_keys=True).encode(), digest_size=8).hexdigest()


@dataclasses.dataclass
class FileRecord:
    """Everything the library stores about one file (docs/library.md, the ``files`` table).

    ``problems`` holds ``(kind, level, count)`` (level 1 info, 2 warning, 3 error);
    ``seconds`` what each of :data:`STAGES` took (wall clock), ``cpu`` the CPU seconds
    of the thread that ran it; ``unchanged``: the content hash is the
    one the library holds, nothing else was read.
    """

    path: str
    size: int
    mtime_ns: int
    stamp: str
    hash: str
    analysis: str
    format: str
    kind: str
    status: str = "ok"
    message: str | None = None
    frames: int | None = None
    frame_rate: float | None = None
    duration: float | None = None
    joints: int | None = None
    roots: int | None = None
    markers: int | None = None
    units: str | None = None
    up_axis: str | None = None
    skeleton: Skeleton | None = None
    problems: tuple[tuple[str, int, int], ...] = ()
    findings: int | None = None
    infos: int | None = None
    warnings: int | None = None
    errors: int | None = None
    worst: str | None = None
    worst_level: int | None = None
    worst_frame: int | None = None
    thumbnail: bytes | None = None
    seconds: dict = dataclasses.field(default_factory=dict)
    cpu: dict = dataclasses.field(default_factory=dict)
    unchanged: bool = False

    def timed(self, stage: str, start: tuple[float, float]) -> tuple[float, float]:
        """Add the time since ``start`` (a :func:`clock` reading) to ``stage``; the clock now."""
        now = clock()
        self.seconds[stage] = self.seconds.get(stage, 0.0) + now[0] - start[0]
        self.cpu[stage] = self.cpu.get(stage, 0.0) + now[1] - start[1]
        return now


def clock() -> tuple[float, float]:
    """(wall clock, this thread's CPU time) in seconds."""
    return time.perf_counter(), time.thread_time()


def kind_of(suffix: str) -> str:
    """``markers`` (C3D, TRC), ``skeleton`` (an ASF alone) or ``motion``."""
    if suffix in MARKER_READERS:
        return "markers"
    return "skeleton" if suffix == ".asf" else "motion"


def companions(path: str | Path) -> list[Path]:
    """The files a file's reader reads besides it: an AMC's ASF (the one beside it, as the
    reader finds it); none for the others."""
    if motion_suffix(path) != ".amc":
        return []
    try:
        return [asf_beside(path)]
    except MotionFileError:
        return []


def file_stamp(path: str | Path) -> tuple[int, int, str]:
    """(size, modification time in ns, stamp): the stamp is ``size:mtime_ns`` of the file
    and of each of its :func:`companions`, joined by ``;``. OSError when it is gone."""
    info = os.stat(path)
    parts = [f"{info.st_size}:{info.st_mtime_ns}"]
    for other in companions(path):
        try:
            extra = os.stat(other)
        except OSError:
            continue
        parts.append(f"{extra.st_size}:{extra.st_mtime_ns}")
    return info.st_size, info.st_mtime_ns, ";".join(parts)


def content_hash(path: str | Path) -> str:
    """BLAKE2b (hex, 128 bits) of the file's bytes followed by its companions'."""
    digest = hashlib.blake2b(digest_size=16)
    for part in (Path(path), *companions(path)):
        try:
            with open(part, "rb") as stream:
                for block in iter(lambda: stream.read(1 << 20), b""):
                    digest.update(block)
        except OSError:
            if part == Path(path):
                raise
    return digest.hexdigest()


def describe_files(items: Sequence[tuple[str, str | None]], options: IndexOptions) -> list[FileRecord]:
    """:func:`describe_file` of each ``(path, hash the library holds or None)``: a worker's task."""
    return [describe_file(path, known, options) for path, known in items]


def describe_file(path: str, known_hash: str | None, options: IndexOptions) -> FileRecord:
    """The record of one file (never raises: a file that cannot be read is a failed record
    with the reader's one-line message)."""
    suffix = motion_suffix(path)
    start = clock()
    try:
        size, mtime_ns, stamp = file_stamp(path)
        digest = content_hash(path)
    except OSError as exc:
        return _failed_stat(path, suffix, options, f"{path}: cannot read the file: {exc.strerror or exc}")
    record = FileRecord(
        path=path,
        size=size,
        mtime_ns=mtime_ns,
        stamp=stamp,
        hash=digest,
        analysis=options.analysis(suffix),
        format=suffix.lstrip("."),
        kind=kind_of(suffix),
    )
    record.timed("hash", start)
    empty = dataclasses.replace(record, seconds={}, cpu={})
    if known_hash == digest:
        record.unchanged = True
        return record
    error, _ = workers.file_task(_fill, path, record, options)
    if error:  # the record as it was before reading, and the reader's line
        message = " ".join(error.split())
        return dataclasses.replace(empty, status="failed", message=message, seconds=record.seconds, cpu=record.cpu)
    return record


def _failed_stat(path: str, suffix: str, options: IndexOptions, message: str) -> FileRecord:
    return FileRecord(
        path=path,
        size=0,
        mtime_ns=0,
        stamp="",
        hash="",
        analysis=options.analysis(suffix),
        format=suffix.lstrip("."),
        kind=kind_of(suffix),
        status="failed",
        message=message,
    )


def _fill(path: str, record: FileRecord, options: IndexOptions) -> None:
    """Read the file into ``record`` (MotionFileError and others propagate to the caller)."""
    settings = CheckSettings.from_dict(options.settings)
    start = clock()
    if record.kind == "markers":
        markers = read_markers(path)
        start = record.timed("read", start)
        motion, findings = run_marker_checks(markers, settings)
        start = record.timed("checks", start)
        record.frames, record.frame_rate = markers.n_frames, float(markers.rate)
        record.duration = markers.duration
        record.markers, record.units = markers.n_markers, markers.units
        record.up_axis = detect_up_axis(markers.positions) if markers.n_frames else None
        _summarise(record, findings, markers.n_frames)
        start = record.timed("checks", start)
        picture = marker_thumbnail(markers.positions, options.size, options.poses) if markers.n_frames else None
    else:
        reading = {"body_model": options.body_model} if record.format == "npz" else {}
        motion = read_motion(path, **reading)
        positions = world_positions(motion)
        start = record.timed("read", start)
        findings = run_checks(motion, settings, positions, threads=1)  # the files are read side by side
        start = record.timed("checks", start)
        record.frames, record.frame_rate = motion.n_frames, float(motion.frame_rate)
        record.duration = duration_of(motion)
        record.joints, record.roots = motion.n_joints, len(motion.roots)
        record.units = None if motion.facts.unit is None else motion.facts.unit.name
        record.up_axis = up_axis_of(motion)
        record.skeleton = Skeleton.of(motion)
        _ = record.skeleton.signature, record.skeleton.topology  # hashed here, not by the process writing
        _summarise(record, findings, motion.n_frames)
        start = record.timed("checks", start)
        picture = motion_thumbnail(motion, positions, options.size, options.poses) if motion.n_frames else None
    record.thumbnail = png_bytes(picture) if picture is not None else None
    record.timed("thumbnail", start)


def _summarise(record: FileRecord, findings: list[Finding], n_frames: int) -> None:
    """Counts per kind and severity, per severity, the worst severity (and its level: 0
    for none, 1 info to 3 error) and its frame."""
    counts: dict[tuple[str, int], int] = {}
    for finding in findings:
        key = (finding.kind, finding.level)
        counts[key] = counts.get(key, 0) + 1
    record.problems = tuple((kind, level, count) for (kind, level), count in sorted(counts.items()))
    per_level = [sum(1 for f in findings if f.level == level) for level in (1, 2, 3)]
    record.findings = len(findings)
    record.infos, record.warnings, record.errors = per_level
    record.worst, record.worst_level, record.worst_frame = None, 0, None
    if findings:
        top = max(f.level for f in findings)
        record.worst, record.worst_level = SEVERITIES[top - 1], top
        record.worst_frame = worst_frame([f for f in findings if f.level == top], n_frames)


def worst_frame(findings: list[Finding], n_frames: int) -> int:
    """The frame most of ``findings`` cover (the first such)."""
    cover = np.zeros(max(n_frames, 1) + 1, np.int64)
    for finding in findings:
        cover[max(finding.start, 0)] += 1
        cover[min(finding.end, n_frames - 1) + 1] -= 1
    return int(np.argmax(np.cumsum(cover)[:-1]))
