"""The library's SQLite file: its tables, its version, and opening it safely.

One file (``sqlite3`` of the standard library), in WAL mode so that readers (the app's
table, ``gmr library list``) never wait for a writer and a writer killed mid-batch leaves
the last committed batch intact. Several processes may index into one file: each batch is
one ``BEGIN IMMEDIATE`` transaction, and a writer waits up to :data:`BUSY_SECONDS` for
another's to end.

The file says what it is in its header: ``PRAGMA application_id`` is :data:`APPLICATION_ID`
("GMRL") and ``PRAGMA user_version`` the schema version (:data:`SCHEMA_VERSION`).
:func:`open_library`:

- a new or empty file gets the tables below;
- a file of this version is used as it is;
- a library of an older version is rebuilt: its tables are dropped and made afresh, the
  list of folders kept (every other field is derived from the files, so the next
  ``gmr library index`` reads them again); it is never read with this version's queries;
- a library of a newer version, or an SQLite file of something else, or a file that is not
  SQLite, is refused (:class:`~core.errors.OperationError`) and left untouched.

Tables (docs/library.md describes every column):

- ``folders(path, indexed_at)``: the folders indexed into the library;
- ``skeletons(id, signature, topology, joints, roots, names, parents, skeleton_group,
  group_match)``: one row per distinct skeleton (:mod:`core.library.skeletons`);
- ``files(...)``: one row per file, read or failed (:data:`FILE_COLUMNS`);
- ``problems(file_id, kind, level, count)``: the checks' findings per kind and severity;
- ``thumbnails(file_id, png)``: the thumbnail of each file that has one.
"""

from __future__ import annotations

import os
import sqlite3
import sys
from pathlib import Path

from gmr_studio.core.errors import OperationError

SCHEMA_VERSION = 1
#: "GMRL" as a big-endian 32-bit number: PRAGMA application_id of a library
APPLICATION_ID = 0x474D524C
#: how long a writer waits for another process's transaction to end
BUSY_SECONDS = 120.0
#: at most this much of the file is read through a memory map (the operating system's
#: page cache, not the process's memory)
MMAP_BYTES = 1 << 30

#: the ``files`` table's columns after ``id``, in order, with their SQL types
FILE_COLUMNS: dict[str, str] = {
    "path": "TEXT NOT NULL UNIQUE",
    "name": "TEXT NOT NULL",
    "folder": "TEXT NOT NULL",
    "size": "INTEGER NOT NULL",
    "mtime_ns": "INTEGER NOT NULL",
    "stamp": "TEXT NOT NULL",
    "hash": "TEXT NOT NULL",
    "analysis": "TEXT NOT NULL",
    "format": "TEXT NOT NULL",
    "kind": "TEXT NOT NULL",
    "status": "TEXT NOT NULL",
    "message": "TEXT",
    "frames": "INTEGER",
    "frame_rate": "REAL",
    "duration": "REAL",
    "joints": "INTEGER",
    "roots": "INTEGER",
    "markers": "INTEGER",
    "units": "TEXT",
    "up_axis": "TEXT",
    "skeleton_id": "INTEGER REFERENCES skeletons(id)",
    "skeleton_group": "INTEGER",
    "findings": "INTEGER",
    "infos": "INTEGER",
    "warnings": "INTEGER",
    "errors": "INTEGER",
    "worst": "TEXT",
    "worst_level": "INTEGER",
    "worst_frame": "INTEGER",
    "indexed_at": "REAL NOT NULL",
}

#: the fields queries filter and sort on, each with its own index (the name's ignores case;
#: the skeleton's holds the path, a skeleton's first file found in the index)
INDEXED_FIELDS = (
    "name COLLATE NOCASE",
    "folder",
    "format",
    "status",
    "frames",
    "frame_rate",
    "duration",
    "joints",
    "markers",
    "skeleton_id, path",
    "skeleton_group",
    "findings",
    "errors",
    "warnings",
    "size",
)

TABLES = f"""
CREATE TABLE folders (
    path TEXT PRIMARY KEY,
    indexed_at REAL
);
CREATE TABLE skeletons (
    id INTEGER PRIMARY KEY,
    signature TEXT NOT NULL UNIQUE,
    topology TEXT NOT NULL,
    joints INTEGER NOT NULL,
    roots INTEGER NOT NULL,
    names TEXT NOT NULL,
    parents TEXT NOT NULL,
    skeleton_group INTEGER NOT NULL,
    group_match REAL NOT NULL
);
CREATE INDEX skeletons_group ON skeletons(skeleton_group);
CREATE TABLE files (
    id INTEGER PRIMARY KEY,
    {", ".join(f"{name} {kind}" for name, kind in FILE_COLUMNS.items())}
);
{"".join(f"CREATE INDEX files_{field.split()[0].strip(',')} ON files({field});" for field in INDEXED_FIELDS)}
CREATE INDEX files_problems ON files(worst_level, errors, warnings, infos);
CREATE TABLE problems (
    file_id INTEGER NOT NULL REFERENCES files(id) ON DELETE CASCADE,
    kind TEXT NOT NULL,
    level INTEGER NOT NULL,
    count INTEGER NOT NULL,
    PRIMARY KEY (file_id, kind, level)
) WITHOUT ROWID;
CREATE INDEX problems_kind ON problems(kind, level, file_id);
CREATE TABLE thumbnails (
    file_id INTEGER PRIMARY KEY REFERENCES files(id) ON DELETE CASCADE,
    png BLOB NOT NULL
);
"""


def default_library_path() -> Path:
    """Where a library lives when none is named: ``$GMR_LIBRARY`` if set, else
    ``library.sqlite`` in the user's data folder for GMR Studio (``$XDG_DATA_HOME/GMR Studio``
    on Linux, as the app's other data; ``~/Library/Application Support/GMR Studio`` on macOS,
    ``%LOCALAPPDATA%\\GMR Studio`` on Windows)."""
    override = os.environ.get("GMR_LIBRARY")
    if override:
        return Path(override).expanduser()
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Application Support"
    else:
        base = Path(os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share")
    return base / "GMR Studio" / "library.sqlite"


def open_library(path: str | Path, *, create: bool = True) -> sqlite3.Connection:
    """A connection to the library at ``path`` (module docstring for what is done with an
    older, newer or foreign file). ``create=False``: OperationError when there is no file.

    The connection is in autocommit mode (writers open their own transactions), with
    foreign keys on and WAL journaling; rows come back as :class:`sqlite3.Row`.
    """
    path = Path(path)
    if not path.exists():
        if not create:
            raise OperationError(
                f"no library at {path}: index a folder into it first (gmr library index DIR --db FILE)"
            )
        path.parent.mkdir(parents=True, exist_ok=True)
    try:
        connection = sqlite3.connect(path, timeout=BUSY_SECONDS, isolation_level=None, check_same_thread=False)
    except sqlite3.Error as exc:
        raise OperationError(f"cannot open the library {path}: {exc}") from None
    try:
        connection.row_factory = sqlite3.Row
        connection.execute(f"PRAGMA busy_timeout = {int(BUSY_SECONDS * 1000)}")
        try:
            application, version = _header(connection, path)
        except sqlite3.DatabaseError as exc:
            raise OperationError(f"{path} is not a library (not an SQLite database: {exc})") from None
        if application == APPLICATION_ID and version > SCHEMA_VERSION:
            raise OperationError(
                f"{path} is a library of a newer GMR Studio (schema version {version}; this one reads version "
                f"{SCHEMA_VERSION}): open it with that version, or index into another file"
            )
        connection.execute("PRAGMA journal_mode = WAL")
        connection.execute("PRAGMA synchronous = NORMAL")
        connection.execute(f"PRAGMA mmap_size = {MMAP_BYTES}")  # pages read in place, not copied
        _ensure_schema(connection, path)
        connection.execute("PRAGMA foreign_keys = ON")  # after a rebuild, which drops tables in any order
    except sqlite3.Error as exc:
        connection.close()
        raise OperationError(f"cannot open the library {path}: {exc}") from None
    except BaseException:
        connection.close()
        raise
    return connection


def _header(connection: sqlite3.Connection, path: Path) -> tuple[int, int]:
    """(application_id, user_version) of the file; OperationError for a database of
    something else."""
    application = connection.execute("PRAGMA application_id").fetchone()[0]
    version = connection.execute("PRAGMA user_version").fetchone()[0]
    if application not in (0, APPLICATION_ID) or (application == 0 and _tables(connection)):
        raise OperationError(f"{path} is an SQLite database of something else, not a GMR Studio library")
    return application, version


def _tables(connection: sqlite3.Connection) -> list[str]:
    rows = connection.execute("SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%'")
    return [row[0] for row in rows]


def _ensure_schema(connection: sqlite3.Connection, path: Path) -> None:
    """Create, keep or rebuild the tables in one write transaction (another process doing
    the same waits for it, then finds the tables made)."""
    version = connection.execute("PRAGMA user_version").fetchone()[0]
    if version == SCHEMA_VERSION:
        return
    connection.execute("BEGIN IMMEDIATE")
    try:
        application, version = _header(connection, path)  # again, inside the transaction
        if application == APPLICATION_ID and version > SCHEMA_VERSION:
            raise OperationError(f"{path} is a library of a newer GMR Studio (schema version {version})")
        if version != SCHEMA_VERSION:
            folders = _old_folders(connection) if application == APPLICATION_ID else []
            for table in _tables(connection):
                connection.execute(f'DROP TABLE "{table}"')
            for statement in TABLES.split(";"):
                if statement.strip():
                    connection.execute(statement)
            connection.executemany("INSERT INTO folders(path) VALUES (?)", [(f,) for f in folders])
            connection.execute(f"PRAGMA application_id = {APPLICATION_ID}")
            connection.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
        connection.execute("COMMIT")
    except BaseException:
        connection.execute("ROLLBACK")
        raise


def _old_folders(connection: sqlite3.Connection) -> list[str]:
    """The folder paths an older library lists (none if it has no such table or column)."""
    try:
        return [str(row[0]) for row in connection.execute("SELECT path FROM folders")]
    except sqlite3.Error:
        return []
