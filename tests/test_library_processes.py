"""The library under several processes: a run killed halfway leaves the file intact and the
next one goes on; two processes indexing into one file at once; a Dask cluster writes the
rows a local run writes."""

from __future__ import annotations

import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import select_rows
from tests import library_fixtures
from tests.conftest import shared_path

takes = library_fixtures.takes


def copies(folder, relative: str, count: int):
    """``count`` copies of a shared file in ``folder`` (take000.bvh, ...)."""
    folder.mkdir(parents=True)
    source = shared_path(relative)
    for k in range(count):
        shutil.copyfile(source, folder / f"take{k:03d}{source.suffix}")
    return folder


def index_command(db, *folders, workers: int = 1) -> list[str]:
    command = [sys.executable, "-m", "gmr_studio.core.cli", "library", "index", *map(str, folders)]
    return [*command, "--db", str(db), "--workers", str(workers)]


def rows_written(db) -> int:
    """Rows committed so far, read as another process would (0 while there is no table)."""
    try:
        with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=30) as connection:
            return connection.execute("SELECT count(*) FROM files").fetchone()[0]
    except sqlite3.Error:
        return 0


def intact(db) -> bool:
    with sqlite3.connect(db) as connection:
        return connection.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def whole_rows(db) -> bool:
    """Every row of a file read is whole: its numbers, its quality and its thumbnail."""
    with Library(db) as library:
        rows = select_rows(library.connection)
    return all(r["status"] == "ok" and r["frames"] and r["quality"] is not None and r["thumbnail"] for r in rows)


@pytest.mark.slow
def test_a_run_killed_halfway_leaves_its_batches_and_the_next_run_goes_on(tmp_path):
    folder = copies(tmp_path / "takes", "bvh/cmu_cgspeed_npybvh_example_75f.bvh", 150)
    db = tmp_path / "library.sqlite"
    process = subprocess.Popen(index_command(db, folder), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while rows_written(db) == 0 and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    process.send_signal(signal.SIGKILL)
    process.wait()
    written = rows_written(db)
    assert process.returncode == -signal.SIGKILL and 0 < written < 150, "killed after the first batch, before the end"
    assert intact(db) and whole_rows(db)
    with Library(db) as library:
        summary = library.index([folder], jobs=1)
        assert (summary.new, summary.unchanged) == (150 - written, written)
        assert library.count() == 150
    assert intact(db) and whole_rows(db)


@pytest.mark.slow
def test_two_processes_indexing_into_one_file_at_once(tmp_path):
    first = copies(tmp_path / "first", "bvh/cmu_cgspeed_npybvh_example_75f.bvh", 24)
    second = copies(tmp_path / "second", "bvh/bvh-python_test_mocapbank.bvh", 16)
    db = tmp_path / "library.sqlite"
    both = [subprocess.Popen(index_command(db, a, b), stderr=subprocess.PIPE) for a, b in ((first, second),) * 2]
    results = [p.communicate(timeout=300) for p in both]
    assert [p.returncode for p in both] == [0, 0], [err.decode() for _, err in results]
    assert intact(db) and whole_rows(db)
    with Library(db) as library:
        rows = select_rows(library.connection)
        assert len(rows) == 40 and len({r["path"] for r in rows}) == 40
        assert sorted(library.folders()) == sorted([str(first.resolve()), str(second.resolve())])
        again = library.index([first, second], jobs=1)
    assert again.read == 0 and again.unchanged == 40


@pytest.mark.slow
def test_a_dask_cluster_writes_the_rows_a_local_run_writes(takes, tmp_path):
    pytest.importorskip("distributed", reason="the 'cluster' extra (dask[distributed]) is not installed")
    local, cluster = tmp_path / "local.sqlite", tmp_path / "cluster.sqlite"
    with Library(local) as library:
        library.index([takes], jobs=1)
        expected = {r["path"]: {k: v for k, v in r.items() if k != "id"} for r in select_rows(library.connection)}
    with Library(cluster) as library:
        summary = library.index([takes], scheduler="local:2")
        found = {r["path"]: {k: v for k, v in r.items() if k != "id"} for r in select_rows(library.connection)}
    assert summary.workers == "Dask local:2" and found == expected
    assert os.path.getsize(cluster) > 0
