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
- a library of an older version is migrated in place, its rows kept, when this version
  knows the way (:data:`MIGRATIONS`: version 1's indexes are made again as version 2's);
  else rebuilt: its tables are dropped and made afresh, the list of folders kept (every
  other field is derived from the files, so the next ``gmr library index`` reads them
  again). Either way its tables are this version's before a query reads them;
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

SCHEMA_VERSION = 2
#: "GMRL" as a big-endian 32-bit number: PRAGMA application_id of a library
APPLICATION_ID = 0x474D524C
#: how long a writer waits for another process's transaction to end
BUSY_SECONDS = 120.0
#: at most this much of the file is read through a memory map (the operating system's
#: page cache, not the process's memory)
MMAP_BYTES = 1 << 30
#: the connection's page cache (KiB): what a query's sort holds before it spills
CACHE_KIB = 32 << 10

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

#: the ``files`` table's indexes (``files_<name>``), each on the fields that queries filter and
#: sort on, then the path: the index alone answers a filter on its fields (the rows in the
#: path's order, the default sort) and a sort by them (ties in the path's order) without
#: reading the rows. The name's ignores case; ``format_duration`` answers the two filters at once.
FILE_INDEXES: dict[str, str] = {
    "name": "name COLLATE NOCASE",
    "format": "format",
    "format_duration": "format, duration",
    "status": "status",
    "frames": "frames",
    "frame_rate": "frame_rate",
    "duration": "duration",
    "joints": "joints",
    "markers": "markers",
    "skeleton_id": "skeleton_id",
    "skeleton_group": "skeleton_group",
    "findings": "findings",
    "errors": "errors",
    "warnings": "warnings",
    "size": "size",
    "problems": "worst_level, errors, warnings, infos",
}
_FILE_INDEXES_SQL = "".join(
    f"CREATE INDEX files_{name} ON files({fields}, path);\n" for name, fields in FILE_INDEXES.items()
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
{_FILE_INDEXES_SQL}CREATE TABLE problems (
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
        connection.execute(f"PRAGMA cache_size = -{CACHE_KIB}")
        connection.execute("PRAGMA temp_store = MEMORY")  # a query's sort in memory, never a temporary file
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
    """Create, keep, migrate or rebuild the tables in one write transaction (another process
    doing the same waits for it, then finds the tables made)."""
    version = connection.execute("PRAGMA user_version").fetchone()[0]
    if version == SCHEMA_VERSION:
        return
    connection.execute("BEGIN IMMEDIATE")
    try:
        application, version = _header(connection, path)  # again, inside the transaction
        if application == APPLICATION_ID and version > SCHEMA_VERSION:
            raise OperationError(f"{path} is a library of a newer GMR Studio (schema version {version})")
        if application == APPLICATION_ID and _migrates(version):
            for step in range(version, SCHEMA_VERSION):
                MIGRATIONS[step](connection)
        elif version != SCHEMA_VERSION:
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


def _migrates(version: int) -> bool:
    """Whether a library of ``version`` can be brought to this version in place."""
    return 0 < version < SCHEMA_VERSION and all(step in MIGRATIONS for step in range(version, SCHEMA_VERSION))


def _indexes_end_in_the_path(connection: sqlite3.Connection) -> None:
    """Version 1 to 2: the ``files`` table's indexes dropped and made as :data:`FILE_INDEXES`
    (the rows are the same)."""
    names = connection.execute(
        "SELECT name FROM sqlite_master WHERE type = 'index' AND tbl_name = 'files' AND sql IS NOT NULL"
    ).fetchall()
    for (name,) in names:
        connection.execute(f'DROP INDEX "{name}"')
    for statement in _FILE_INDEXES_SQL.split(";"):
        if statement.strip():
            connection.execute(statement)


#: version -> the function that takes a library of that version to the next, in place
MIGRATIONS = {1: _indexes_end_in_the_path}


def _old_folders(connection: sqlite3.Connection) -> list[str]:
    """The folder paths an older library lists (none if it has no such table or column)."""
    try:
        return [str(row[0]) for row in connection.execute("SELECT path FROM folders")]
    except sqlite3.Error:
        return []
