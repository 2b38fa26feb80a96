"""What an indexing run has to do: the files of the folders against the library's rows.

:func:`plan_index` lists every file the library reads under each folder
(:func:`core.cli.batch.find_motion_files` with :func:`core.library.reading.library_suffixes`)
and sorts them by what the library holds:

- **new**: no row yet;
- **unchanged**: the row's stamp (size and modification time, with the AMC's ASF) and
  analysis tag are the file's: nothing to do;
- **changed**: another stamp, or a row made under another analysis tag (other check
  settings, another thumbnail size): the file is hashed again, and read again unless its
  hash is the row's (only the stamp is then updated);
- **removed**: a row under the folder whose file is gone: dropped.

Paths are absolute: the folder resolved, the files under it as found (a link inside the
folder keeps its own name).
"""

from __future__ import annotations

import dataclasses
import os
import sqlite3
from pathlib import Path

from gmr_studio.core.batch.files import find_motion_files
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import motion_suffix
from gmr_studio.core.library.reading import IndexOptions, file_stamp, library_suffixes


@dataclasses.dataclass
class Plan:
    """An indexing run's work.

    folders : the folders, resolved.
    tasks : (path, hash the library holds or None, folder) of every new or changed file.
    removed : ids of rows whose file is gone.
    """

    folders: list[str]
    tasks: list[tuple[str, str | None, str]] = dataclasses.field(default_factory=list)
    new: int = 0
    changed: int = 0
    unchanged: int = 0
    removed: list[int] = dataclasses.field(default_factory=list)

    @property
    def found(self) -> int:
        return self.new + self.changed + self.unchanged


def resolve_folders(folders: list[str | Path]) -> list[str]:
    """Each folder as an absolute path; OperationError for one that is not a folder."""
    resolved = []
    for folder in folders:
        path = Path(folder).expanduser()
        if not path.is_dir():
            raise OperationError(f"{folder} is not a folder")
        text = str(path.resolve())
        if text not in resolved:
            resolved.append(text)
    return resolved


def rows_under(connection: sqlite3.Connection, folder: str) -> dict[str, tuple[int, str, str, str]]:
    """path -> (id, stamp, hash, analysis) of the rows of files under ``folder``."""
    low, high = folder.rstrip(os.sep) + os.sep, folder.rstrip(os.sep) + chr(ord(os.sep) + 1)
    rows = connection.execute(
        "SELECT id, path, stamp, hash, analysis FROM files WHERE path >= ? AND path < ?", (low, high)
    )
    return {row["path"]: (row["id"], row["stamp"], row["hash"], row["analysis"]) for row in rows}


def plan_index(
    connection: sqlite3.Connection, folders: list[str | Path], options: IndexOptions, *, force: bool = False
) -> Plan:
    """The plan of indexing ``folders`` (module docstring); ``force``: read every file again."""
    plan = Plan(resolve_folders(folders))
    planned: set[str] = set()
    tags: dict[str, str] = {}  # suffix -> analysis tag
    for folder in plan.folders:
        held = rows_under(connection, folder)
        seen: set[str] = set()
        for found in find_motion_files(Path(folder), None, library_suffixes()):
            path = str(found)
            seen.add(path)
            if path in planned:  # under two of the folders given
                continue
            planned.add(path)
            try:
                _size, _mtime, stamp = file_stamp(path)
            except OSError:
                stamp = ""  # gone since it was listed: the worker says so
            row = held.get(path)
            suffix = motion_suffix(path)
            analysis = tags.get(suffix) or tags.setdefault(suffix, options.analysis(suffix))
            if row is None:
                plan.new += 1
                plan.tasks.append((path, None, folder))
            elif force or row[1] != stamp or row[3] != analysis:
                plan.changed += 1
                plan.tasks.append((path, row[2] if row[3] == analysis and not force else None, folder))
            else:
                plan.unchanged += 1
        plan.removed.extend(row[0] for path, row in held.items() if path not in seen)
    return plan
