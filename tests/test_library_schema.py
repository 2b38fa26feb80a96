"""The library file: what its header says, and what is done with an older, a newer or a
foreign file (rebuilt or refused, never misread)."""

from __future__ import annotations

import sqlite3

import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.library import schema
from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import select_rows
from tests import library_fixtures

takes = library_fixtures.takes


def header(path) -> tuple[int, int, str]:
    with sqlite3.connect(path) as connection:
        return (
            connection.execute("PRAGMA application_id").fetchone()[0],
            connection.execute("PRAGMA user_version").fetchone()[0],
            connection.execute("PRAGMA journal_mode").fetchone()[0],
        )


def test_a_new_library_says_what_it_is_and_which_version(tmp_path):
    db = tmp_path / "deep" / "folder" / "library.sqlite"
    with Library(db) as library:
        assert library.count() == 0 and library.folders() == []
    assert header(db) == (0x474D524C, schema.SCHEMA_VERSION, "wal")
    with sqlite3.connect(db) as connection:
        tables = {row[0] for row in connection.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        columns = [row[1] for row in connection.execute("PRAGMA table_info(files)")]
    assert tables == {"folders", "skeletons", "files", "problems", "thumbnails"}
    assert columns == ["id", *schema.FILE_COLUMNS]


#: the indexes of the files table in a library of version 1
VERSION_1_INDEXES = """
CREATE INDEX files_name ON files(name COLLATE NOCASE);
CREATE INDEX files_folder ON files(folder);
CREATE INDEX files_format ON files(format);
CREATE INDEX files_status ON files(status);
CREATE INDEX files_frames ON files(frames);
CREATE INDEX files_frame_rate ON files(frame_rate);
CREATE INDEX files_duration ON files(duration);
CREATE INDEX files_joints ON files(joints);
CREATE INDEX files_markers ON files(markers);
CREATE INDEX files_skeleton_id ON files(skeleton_id, path);
CREATE INDEX files_skeleton_group ON files(skeleton_group);
CREATE INDEX files_findings ON files(findings);
CREATE INDEX files_errors ON files(errors);
CREATE INDEX files_warnings ON files(warnings);
CREATE INDEX files_size ON files(size);
CREATE INDEX files_problems ON files(worst_level, errors, warnings, infos);
"""


def indexes(path) -> dict[str, str]:
    with sqlite3.connect(path) as connection:
        return dict(connection.execute("SELECT name, sql FROM sqlite_master WHERE type = 'index' AND sql IS NOT NULL"))


def test_a_library_of_version_1_is_migrated_in_place_its_rows_kept(takes, tmp_path):
    db, fresh = tmp_path / "library.sqlite", tmp_path / "fresh.sqlite"
    Library(fresh).close()
    with Library(db) as library:
        library.index([takes], jobs=1)
        rows = select_rows(library.connection)
    with sqlite3.connect(db) as connection:  # version 1: the same tables, other indexes
        for name in indexes(db):
            if name.startswith("files_"):
                connection.execute(f"DROP INDEX {name}")
        connection.executescript(VERSION_1_INDEXES)
        connection.execute("PRAGMA user_version = 1")
    with Library(db) as library:
        assert select_rows(library.connection) == rows
        assert library.index([takes], jobs=1).read == 0  # nothing to read again
    assert header(db)[1] == schema.SCHEMA_VERSION
    assert indexes(db) == indexes(fresh)


def test_an_older_library_with_no_way_to_this_version_is_rebuilt_and_indexed_again(takes, tmp_path):
    db = tmp_path / "library.sqlite"
    with Library(db) as library:
        library.index([takes], jobs=1)
        rows = len(select_rows(library.connection))
    # a library of a version before any this one migrates: another layout of the files table
    with sqlite3.connect(db) as connection:
        connection.execute("ALTER TABLE files RENAME COLUMN duration TO seconds")
        connection.execute("PRAGMA user_version = 0")
    with Library(db) as library:
        assert library.count() == 0 and library.folders() == [str(takes.resolve())]
        summary = library.index(library.folders(), jobs=1)
        assert summary.new == rows and len(select_rows(library.connection)) == rows
    assert header(db)[1] == schema.SCHEMA_VERSION


def test_a_newer_library_is_refused_and_left_as_it_is(tmp_path):
    db = tmp_path / "library.sqlite"
    Library(db).close()
    with sqlite3.connect(db) as connection:
        connection.execute(f"PRAGMA user_version = {schema.SCHEMA_VERSION + 1}")
    before = db.read_bytes()
    with pytest.raises(OperationError, match="newer GMR Studio"):
        Library(db)
    assert db.read_bytes() == before


def test_files_that_are_no_library_are_refused_and_left_as_they_are(tmp_path):
    other = tmp_path / "other.sqlite"
    with sqlite3.connect(other) as connection:
        connection.execute("CREATE TABLE files (path TEXT)")
    text = tmp_path / "notes.sqlite"
    text.write_text("not a database at all, but long enough to have a header " * 10)
    for path, words in ((other, "something else"), (text, "not an SQLite database")):
        before = path.read_bytes()
        with pytest.raises(OperationError, match=words):
            Library(path)
        assert path.read_bytes() == before


def test_reading_a_library_that_is_not_there_says_how_to_make_one(tmp_path):
    with pytest.raises(OperationError, match="gmr library index"):
        Library(tmp_path / "none.sqlite", create=False)
    assert not (tmp_path / "none.sqlite").exists()


def test_the_default_library_lives_in_the_users_data_folder(monkeypatch, tmp_path):
    monkeypatch.delenv("GMR_LIBRARY", raising=False)
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path))
    monkeypatch.setattr("sys.platform", "linux")
    assert schema.default_library_path() == tmp_path / "GMR Studio" / "library.sqlite"
    monkeypatch.setenv("GMR_LIBRARY", str(tmp_path / "mine.sqlite"))
    assert schema.default_library_path() == tmp_path / "mine.sqlite"
