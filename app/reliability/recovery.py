"""Recovery files: unsaved work written where a crash cannot take it.

A recovery file is a GMR file (``.gmr``) in the ``recovery`` folder of the app's data folder
(Qt's ``AppDataLocation``: ``$XDG_DATA_HOME/GMR Studio/recovery`` on Linux, so the XDG
variables move it). It is named after the document (``01_01.3f2a9c1b.gmr``: the file's stem
and a hash of its full path, ``untitled`` for the demo) and holds, in a ``#`` comment line
right after ``GMR 1``, what the start-up dialog shows: the original file, when it was
written, how many edits it holds and the process that wrote it. Any GMR reader reads it as
an ordinary motion.

This module is free of widgets: :mod:`app.autosave` writes the files, the dialog
(:mod:`app.recovery_dialog`) and ``gmr-studio --recover`` list them.
"""

from __future__ import annotations

import dataclasses
import datetime
import hashlib
import itertools
import json
import os
from collections.abc import Iterator
from pathlib import Path

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.formats.textmotion import format_text_motion
from gmr_studio.core.model.motion import Motion

APP_NAME = "GMR Studio"
#: the comment line that carries the record, right after ``GMR 1``
MARKER = "# gmr-studio recovery "
#: bytes read from the start of a file to find its record
_HEAD_BYTES = 4096


@dataclasses.dataclass(frozen=True)
class RecoveryRecord:
    """One recovery file and what it says about itself.

    Attributes
    ----------
    path : the recovery file (.gmr).
    original : the document's file, or None for the demo or an unsaved motion.
    saved_at : when it was written (local time, ISO 8601 to the second).
    edits : edits made to the document since it was opened or last saved.
    pid : the process that wrote it.
    """

    path: Path
    original: Path | None
    saved_at: str
    edits: int
    pid: int

    @property
    def display_name(self) -> str:
        return self.original.name if self.original is not None else "untitled motion"

    def describe(self) -> str:
        """One line: original file, time, edits."""
        where = str(self.original) if self.original is not None else "untitled motion (no file)"
        plural = "" if self.edits == 1 else "s"
        return f"{where}  saved {self.saved_at.replace('T', ' ')}  {self.edits} edit{plural}  ({self.path})"


def recovery_folder() -> Path:
    """``<AppDataLocation>/recovery`` (not created here)."""
    from PyQt6.QtCore import QCoreApplication, QStandardPaths

    if QCoreApplication.applicationName() != APP_NAME:
        QCoreApplication.setApplicationName(APP_NAME)
    location = QStandardPaths.writableLocation(QStandardPaths.StandardLocation.AppDataLocation)
    return (Path(location) if location else Path.home() / ".local" / "share" / APP_NAME) / "recovery"


def recovery_path(original: str | Path | None, folder: Path | None = None) -> Path:
    """The recovery file of a document: its stem and a hash of its full path."""
    folder = folder if folder is not None else recovery_folder()
    if original is None:
        return folder / "untitled.gmr"
    resolved = str(Path(original).resolve())
    digest = hashlib.sha256(resolved.encode("utf-8", "surrogateescape")).hexdigest()[:8]
    return folder / f"{Path(resolved).stem}.{digest}.gmr"


def write_recovery(motion: Motion, path: Path, original: str | Path | None, edits: int) -> RecoveryRecord:
    """Write ``motion`` (pre-rotation) as a GMR recovery file, atomically; its record."""
    record = RecoveryRecord(
        path=path,
        original=Path(original).resolve() if original is not None else None,
        saved_at=datetime.datetime.now().isoformat(timespec="seconds"),
        edits=int(edits),
        pid=os.getpid(),
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, _with_record(format_text_motion(motion, "gmr"), record))
    return record


def _with_record(chunks: Iterator[str], record: RecoveryRecord) -> Iterator[str]:
    """The GMR text with the record's comment after its first line."""
    first = next(chunks)
    head, newline, rest = first.partition("\n")
    fields = {
        "original": None if record.original is None else str(record.original),
        "saved_at": record.saved_at,
        "edits": record.edits,
        "pid": record.pid,
    }
    line = MARKER + json.dumps(fields, ensure_ascii=True) + "\n"
    return itertools.chain([head + newline + line + rest], chunks)


def read_record(path: Path) -> RecoveryRecord | None:
    """The record of a recovery file, or None if it is not one (or unreadable)."""
    try:
        with path.open("rb") as handle:
            head = handle.read(_HEAD_BYTES).decode("utf-8", "replace")
    except OSError:
        return None
    for line in head.splitlines()[1:3]:
        if line.startswith(MARKER):
            try:
                fields = json.loads(line[len(MARKER) :])
                original = fields["original"]
                return RecoveryRecord(
                    path=path,
                    original=Path(original) if original else None,
                    saved_at=str(fields["saved_at"]),
                    edits=int(fields["edits"]),
                    pid=int(fields["pid"]),
                )
            except (ValueError, KeyError, TypeError):
                return None
    return None


def process_alive(pid: int) -> bool:
    """A live GMR Studio process has this id (its recovery files are in use, not orphaned)."""
    if pid == os.getpid():
        return True
    try:
        command = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return False
    return b"gmr" in command and Path(f"/proc/{pid}/stat").read_text().split(") ")[-1][:1] not in ("Z", "X")


def list_recoveries(folder: Path | None = None, *, include_live: bool = False) -> list[RecoveryRecord]:
    """Recovery files left behind (newest first). Files of a running GMR Studio are left
    out unless ``include_live``; files that are not recovery files are ignored."""
    folder = folder if folder is not None else recovery_folder()
    if not folder.is_dir():
        return []
    records = [r for r in (read_record(p) for p in sorted(folder.glob("*.gmr"))) if r is not None]
    if not include_live:
        records = [r for r in records if not process_alive(r.pid)]
    return sorted(records, key=lambda r: r.saved_at, reverse=True)


def discard(record: RecoveryRecord) -> None:
    """Delete a recovery file (gone already is fine)."""
    record.path.unlink(missing_ok=True)


def print_recoveries(folder: Path | None = None) -> int:
    """``gmr-studio --recover``: list the recovery files; exit status 0."""
    records = list_recoveries(folder, include_live=True)
    if not records:
        print(f"no recovery files in {folder if folder is not None else recovery_folder()}")
        return 0
    print(f"{len(records)} recovery file(s); start gmr-studio to restore or discard them:")
    for record in records:
        live = "  [in use by a running GMR Studio]" if process_alive(record.pid) else ""
        print(record.describe() + live)
    return 0
