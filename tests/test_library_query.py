"""Queries over a library of a few thousand rows give the rows that filtering and sorting
every row by hand gives, in the same order, whichever index answers them; a page is that
order's slice, and a row's place in it is where the order puts it; and a library without its
indexes answers the same."""

from __future__ import annotations

import shutil
import sqlite3

import numpy as np
import pytest

from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import Query, count, first_ids, positions, select_ids, select_rows
from tests.library_fixtures import made_up_records as records
from tests.library_fixtures import write_records

N_FILES = 2000


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """(path of a library of :func:`records`, path of a copy without its indexes)."""
    folder = tmp_path_factory.mktemp("query")
    db, bare = folder / "library.sqlite", folder / "bare.sqlite"
    with Library(db) as made:
        written = records(N_FILES)
        write_records(made, written)
    shutil.copyfile(db, bare)
    with sqlite3.connect(bare) as connection:
        names = connection.execute("SELECT name FROM sqlite_master WHERE type = 'index' AND sql IS NOT NULL")
        for (name,) in names.fetchall():
            connection.execute(f"DROP INDEX {name}")
    return db, bare


QUERIES = {
    "every row": Query(),
    "one format": Query(formats=("bvh",)),
    "two formats": Query(formats=("bvh", "c3d")),
    "at least 5 s": Query(min_duration=5),
    "2 to 10 s": Query(min_duration=2, max_duration=10),
    "bvh, 2 to 10 s": Query(formats=("bvh",), min_duration=2, max_duration=10),
    "3 joints": Query(joints=3),
    "bvh with 3 joints": Query(formats=("bvh",), joints=3),
    "one group": Query(groups=(1,)),
    "two groups": Query(groups=(1, 2)),
    "failed": Query(failed=True),
    "a pop, info or worse": Query(has=(("pop", 1),)),
    "an error of any kind": Query(has=(("any", 3),)),
    "a word of the name": Query(words=("take00",)),
    "a pattern of the name": Query(name="*7?.BVH"),
}
SORTS = ("path", "name", "format", "duration", "frames", "rate", "joints", "group", "problems", "modified")


def by_hand(rows: list[dict], query: Query) -> list[str]:
    """The paths of the rows ``query`` lets through, in its order, by plain Python."""
    import fnmatch

    def passes(row: dict) -> bool:
        quality = row["quality"] or {}
        kinds = quality.get("kinds", {})
        levels = {"info": 1, "warning": 2, "error": 3}
        return (
            (not query.formats or row["format"] in query.formats)
            and (query.min_duration is None or (row["duration"] is not None and row["duration"] >= query.min_duration))
            and (query.max_duration is None or (row["duration"] is not None and row["duration"] <= query.max_duration))
            and (query.joints is None or row["joints"] == query.joints)
            and (not query.groups or (row["skeleton"] or {}).get("group") in query.groups)
            and (not query.failed or row["status"] == "failed")
            and all(word.lower() in row["name"].lower() for word in query.words)
            and (query.name is None or fnmatch.fnmatchcase(row["name"].lower(), query.name.lower()))
            and all(
                any(levels[s] >= level for k, counts in kinds.items() if kind in ("any", k) for s in counts)
                for kind, level in query.has
            )
        )

    def key(row: dict) -> tuple:
        quality = row["quality"] or {}
        worst = {None: 0, "info": 1, "warning": 2, "error": 3}[quality.get("worst")] if quality else None
        values = {
            "path": (),
            "name": (row["name"].lower(),),
            "format": (row["format"],),
            "duration": (row["duration"],),
            "frames": (row["frames"],),
            "rate": (row["frame_rate"],),
            "joints": (row["joints"],),
            "group": ((row["skeleton"] or {}).get("group"),),
            "problems": (worst, *(quality.get(s) for s in ("error", "warning", "info"))),
            "modified": (row["mtime_ns"],),
        }[query.sort]
        return (*((v is not None, v if v is not None else 0) for v in values), row["path"])  # no value first

    return [row["path"] for row in sorted(filter(passes, rows), key=key, reverse=query.descending)]


@pytest.mark.parametrize("what", QUERIES)
def test_a_query_gives_the_rows_a_filter_and_sort_by_hand_gives(library, what):
    from dataclasses import replace

    db, bare = library
    with Library(db) as indexed, Library(bare) as plain:
        rows = select_rows(indexed.connection)
        path_of = {row["id"]: row["path"] for row in rows}
        row_of = {row["path"]: row for row in rows}
        found = select_rows(indexed.connection, QUERIES[what])  # whole rows, their problems included
        assert found == [row_of[path] for path in by_hand(rows, QUERIES[what])]
        for sort in SORTS:
            for descending in (False, True):
                query = replace(QUERIES[what], sort=sort, descending=descending)
                expected = by_hand(rows, query)
                ids = select_ids(indexed.connection, query)
                assert [path_of[i] for i in ids] == expected, (sort, descending)
                assert count(indexed.connection, query) == len(expected)
                for block in (64, len(expected) + 1):  # a block smaller than the result, one larger
                    total, first = first_ids(indexed.connection, query, block)
                    assert total == len(expected) and np.array_equal(first, ids[:block])
                assert np.array_equal(select_ids(plain.connection, query), ids)  # the same without indexes
                third = len(expected) // 3
                page = select_rows(indexed.connection, query, limit=40, offset=third)
                assert [r["path"] for r in page] == expected[third:][:40]
                assert np.array_equal(select_ids(indexed.connection, query, limit=100, offset=third), ids[third:][:100])
                some = [int(i) for i in ids[::97]] + [-1]  # and an id of no row
                assert positions(indexed.connection, query, some) == {i: 97 * k for k, i in enumerate(some[:-1])}
    assert {len(by_hand(rows, q)) for q in QUERIES.values()} - {0, N_FILES}  # the filters filter


def test_a_query_finds_every_row_as_the_library_holds_it(library):
    db, _bare = library
    with Library(db) as indexed:
        rows = select_rows(indexed.connection)
        failed = select_rows(indexed.connection, Query(failed=True, sort="name"))
    assert len(rows) == N_FILES and len({r["id"] for r in rows}) == N_FILES
    by_path = {r["path"]: r for r in rows}
    for record in records(N_FILES):
        row = by_path[record.path]
        assert (row["format"], row["frames"], row["duration"], row["joints"]) == (
            record.format,
            record.frames,
            record.duration,
            record.joints,
        )
        if record.problems:
            assert {k: sum(c.values()) for k, c in row["quality"]["kinds"].items()} == {
                kind: number for kind, _level, number in record.problems
            }
    assert {r["path"] for r in failed} == {r.path for r in records(N_FILES) if r.status == "failed"}
    assert row["modified"] == "2001-09-09T01:46:40Z"  # 10**18 ns after 1970, in UTC
