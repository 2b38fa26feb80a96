"""The library: index folders of takes into one SQLite file, incrementally and in parallel.

:class:`Library` holds the connection (:func:`core.library.schema.open_library`) and writes
records; :meth:`Library.index` is what ``gmr library index`` and the app's background
indexing run:

1. plan (:func:`core.library.scan.plan_index`): new, changed, unchanged and removed files;
2. drop the removed rows (one transaction) and list the folders;
3. read the new and changed files in worker processes (:func:`core.batch.workers.results`:
   ``jobs`` local processes, or a Dask cluster with ``scheduler``), a few files a task
   (:func:`core.library.reading.describe_files`);
4. write the records as they come, :data:`BATCH_FILES` files or :data:`BATCH_SECONDS`
   seconds to a transaction: a run killed halfway leaves every batch written before intact,
   and the next run reads only the files not yet written; a run stopped by ``stop()``
   does the same.

Several processes may index into one library at once (each batch waits for the others'):
the rows are the same as one process would write.
"""

from __future__ import annotations

import dataclasses
import json
import sqlite3
import time
from collections.abc import Callable, Iterable
from pathlib import Path

from gmr_studio.core.batch import workers
from gmr_studio.core.library import schema
from gmr_studio.core.library.reading import STAGES, FileRecord, IndexOptions, clock, describe_files
from gmr_studio.core.library.scan import Plan, plan_index
from gmr_studio.core.library.skeletons import Skeleton, best_match, skeleton_groups

#: a batch is written when it holds this many files, or ...
BATCH_FILES = 64
#: ... when this many seconds have passed since the last one was written
BATCH_SECONDS = 1.0
#: at most this many files a task
CHUNK_FILES = 16

#: the ``files`` columns a record fills (the others: name, folder, skeleton and time, by :meth:`Library.write`)
_RECORD_COLUMNS = tuple(c for c in schema.FILE_COLUMNS if c in {f.name for f in dataclasses.fields(FileRecord)})


@dataclasses.dataclass
class IndexSummary:
    """What an indexing run did: files found, read (new and changed), unchanged, removed,
    failed (of those read), touched (changed stamp, same content: not read again), and
    time; ``stage_seconds`` and ``stage_cpu``: the wall-clock and CPU seconds of each stage
    of reading a file (:data:`core.library.reading.STAGES`) summed over the files, wherever
    they ran; ``database`` and ``database_cpu``: the same of writing the rows (in this
    process); ``stopped``: ``stop()`` ended it."""

    folders: list[str]
    found: int = 0
    new: int = 0
    changed: int = 0
    unchanged: int = 0
    removed: int = 0
    read: int = 0
    failed: int = 0
    touched: int = 0
    seconds: float = 0.0
    workers: str = ""
    stage_seconds: dict = dataclasses.field(default_factory=lambda: dict.fromkeys(STAGES, 0.0))
    stage_cpu: dict = dataclasses.field(default_factory=lambda: dict.fromkeys(STAGES, 0.0))
    database: float = 0.0
    database_cpu: float = 0.0
    stopped: bool = False

    def text(self) -> str:
        """The summary line ``gmr library index`` prints."""
        line = (
            f"{self.found} files in {len(self.folders)} folder{'s' * (len(self.folders) != 1)}: "
            f"{self.read} read ({self.new} new, {self.changed} changed), {self.unchanged} unchanged, "
            f"{self.removed} removed, {self.failed} failed in {self.seconds:.1f} s ({self.workers})"
        )
        if self.touched:
            line += f"; {self.touched} with a new time but the same content, not read again"
        if self.stopped:
            line += "; stopped before the end (the next run goes on)"
        return line


class Library:
    """An open library file (``with Library(path) as library: ...`` closes it)."""

    def __init__(self, path: str | Path, *, create: bool = True) -> None:
        self.path = Path(path)
        self.connection = schema.open_library(self.path, create=create)

    def close(self) -> None:
        self.connection.close()

    def __enter__(self) -> Library:
        return self

    def __exit__(self, *_exc) -> None:
        self.close()

    # -------------------------------------------------------------------- reading
    def folders(self) -> list[str]:
        """The folders indexed into the library, in the order they were added."""
        return [row[0] for row in self.connection.execute("SELECT path FROM folders ORDER BY rowid")]

    def count(self) -> int:
        return self.connection.execute("SELECT count(*) FROM files").fetchone()[0]

    def thumbnail(self, file_id: int) -> bytes | None:
        """The PNG bytes of a row's thumbnail, None if it has none."""
        row = self.connection.execute("SELECT png FROM thumbnails WHERE file_id = ?", (file_id,)).fetchone()
        return bytes(row[0]) if row is not None else None

    # -------------------------------------------------------------------- writing
    def add_folders(self, folders: Iterable[str]) -> None:
        with self._transaction() as connection:
            connection.executemany("INSERT OR IGNORE INTO folders(path) VALUES (?)", [(f,) for f in folders])

    def remove(self, ids: list[int]) -> None:
        """Drop rows (their problems and thumbnails go with them)."""
        if ids:
            with self._transaction() as connection:
                connection.executemany("DELETE FROM files WHERE id = ?", [(i,) for i in ids])

    def write(self, records: list[tuple[FileRecord, str]]) -> None:
        """Write ``(record, folder)`` pairs in one transaction: a row per file (replacing
        the one it had), its problems and its thumbnail; an ``unchanged`` record only
        updates the row's stamp."""
        now = time.time()
        with self._transaction() as connection:
            for record, folder in records:
                if record.unchanged:
                    connection.execute(
                        "UPDATE files SET size = ?, mtime_ns = ?, stamp = ?, indexed_at = ? WHERE path = ?",
                        (record.size, record.mtime_ns, record.stamp, now, record.path),
                    )
                    continue
                skeleton_id, group = self._skeleton(connection, record.skeleton)
                values = {c: getattr(record, c) for c in _RECORD_COLUMNS}
                values.update(
                    name=Path(record.path).name,
                    folder=folder,
                    skeleton_id=skeleton_id,
                    skeleton_group=group,
                    indexed_at=now,
                )
                columns = list(values)
                file_id = connection.execute(
                    f"INSERT INTO files({', '.join(columns)}) VALUES ({', '.join('?' * len(columns))}) "
                    f"ON CONFLICT(path) DO UPDATE SET {', '.join(f'{c} = excluded.{c}' for c in columns)} "
                    "RETURNING id",
                    [values[c] for c in columns],
                ).fetchone()[0]
                connection.execute("DELETE FROM problems WHERE file_id = ?", (file_id,))
                connection.executemany(
                    "INSERT INTO problems(file_id, kind, level, count) VALUES (?, ?, ?, ?)",
                    [(file_id, kind, level, count) for kind, level, count in record.problems],
                )
                if record.thumbnail is not None:
                    connection.execute(
                        "INSERT OR REPLACE INTO thumbnails(file_id, png) VALUES (?, ?)", (file_id, record.thumbnail)
                    )
                else:
                    connection.execute("DELETE FROM thumbnails WHERE file_id = ?", (file_id,))

    def _skeleton(self, connection: sqlite3.Connection, skeleton: Skeleton | None) -> tuple[int | None, int | None]:
        """(id, group) of a skeleton's row, made (and put in a group) if new."""
        if skeleton is None:
            return None, None
        row = connection.execute(
            "SELECT id, skeleton_group FROM skeletons WHERE signature = ?", (skeleton.signature,)
        ).fetchone()
        if row is not None:
            return row[0], row[1]
        known = connection.execute("SELECT skeleton_group, names, parents FROM skeletons ORDER BY id").fetchall()
        others = [Skeleton(tuple(json.loads(r[1])), tuple(json.loads(r[2]))) for r in known]
        nearest, score = best_match(skeleton, others)  # for now: the final groups come from regroup()
        group = known[nearest][0] if nearest is not None else max((r[0] for r in known), default=0) + 1
        score = score if nearest is not None else 1.0
        cursor = connection.execute(
            "INSERT INTO skeletons(signature, topology, joints, roots, names, parents, skeleton_group, group_match) "
            "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
            (
                skeleton.signature,
                skeleton.topology,
                skeleton.n_joints,
                skeleton.n_roots,
                json.dumps(list(skeleton.names)),
                json.dumps(list(skeleton.parents)),
                group,
                round(score, 6),
            ),
        )
        return cursor.lastrowid, group

    def regroup(self) -> None:
        """Drop skeletons no file uses, and number the skeleton groups afresh
        (:func:`core.library.skeletons.skeleton_groups`, numbered by their first file's
        path): the same groups whatever order the files were read in, by one process or several."""
        with self._transaction() as connection:
            connection.execute(
                "DELETE FROM skeletons WHERE id NOT IN (SELECT skeleton_id FROM files WHERE skeleton_id IS NOT NULL)"
            )
            rows = connection.execute(
                "SELECT s.id, s.names, s.parents, s.skeleton_group, s.group_match, "
                "(SELECT min(path) FROM files f WHERE f.skeleton_id = s.id) FROM skeletons s ORDER BY s.id"
            ).fetchall()
            skeletons = [Skeleton(tuple(json.loads(r[1])), tuple(json.loads(r[2]))) for r in rows]
            groups, scores = skeleton_groups(skeletons, [r[5] for r in rows])
            for row, group, score in zip(rows, groups, scores):
                if row[3] != group or row[4] != round(score, 6):
                    connection.execute(
                        "UPDATE skeletons SET skeleton_group = ?, group_match = ? WHERE id = ?",
                        (group, round(score, 6), row[0]),
                    )
                    connection.execute("UPDATE files SET skeleton_group = ? WHERE skeleton_id = ?", (group, row[0]))

    def _transaction(self):
        return _Transaction(self.connection)

    # ------------------------------------------------------------------- indexing
    def plan(self, folders: list[str | Path], options: IndexOptions | None = None, *, force: bool = False) -> Plan:
        return plan_index(self.connection, folders, options or IndexOptions(), force=force)

    def index(
        self,
        folders: list[str | Path],
        options: IndexOptions | None = None,
        *,
        jobs: int | None = None,
        scheduler: str | None = None,
        force: bool = False,
        chunk: int = CHUNK_FILES,
        on_planned: Callable[[Plan], None] | None = None,
        on_file: Callable[[FileRecord], None] | None = None,
        on_batch: Callable[[int], None] | None = None,
        stop: Callable[[], bool] | None = None,
    ) -> IndexSummary:
        """Index ``folders`` (module docstring) and return what was done.

        jobs : local worker processes (default: every core; 1 reads in this process).
        scheduler : a Dask scheduler's address (or ``local:N``) instead of local processes.
        force : read every file again, changed or not.
        chunk : at most this many files a task (fewer when there are few files a worker);
            ``stop`` is asked after each task.
        on_planned : called with the plan before any file is read.
        on_file : called with each record as it comes back (any order).
        on_batch : called with the number of rows written after each batch is committed.
        stop : asked after each task; True ends the run early (what is written stays).
        """
        options = options or IndexOptions()
        start = time.perf_counter()
        plan = self.plan(folders, options, force=force)
        summary = IndexSummary(
            plan.folders, found=plan.found, new=plan.new, changed=plan.changed, unchanged=plan.unchanged
        )
        if on_planned is not None:
            on_planned(plan)
        self.add_folders(plan.folders)
        self.remove(plan.removed)
        summary.removed = len(plan.removed)
        folder_of = {path: folder for path, _known, folder in plan.tasks}
        n_jobs = workers.default_jobs(jobs, len(plan.tasks))
        summary.workers = workers.describe(n_jobs, scheduler)
        size = max(1, min(chunk, len(plan.tasks) // (n_jobs * 8)))
        chunks = [
            ([(path, known) for path, known, _ in plan.tasks[i : i + size]], options)
            for i in range(0, len(plan.tasks), size)
        ]
        n_tasks = len(chunks)
        if not scheduler:
            n_jobs = min(n_jobs, n_tasks) if n_tasks else 1
        pending: list[tuple[FileRecord, str]] = []
        written = [time.perf_counter()]

        def flush() -> None:
            if pending:
                begin = clock()
                self.write(pending)
                summary.database += time.perf_counter() - begin[0]
                summary.database_cpu += time.thread_time() - begin[1]
                if on_batch is not None:
                    on_batch(len(pending))
                pending.clear()
            written[0] = time.perf_counter()

        results = workers.results(describe_files, chunks, jobs=n_jobs, scheduler=scheduler) if chunks else _nothing()
        try:
            for records in results:
                for record in records:
                    _count(summary, record)
                    pending.append((record, folder_of[record.path]))
                    if on_file is not None:
                        on_file(record)
                if len(pending) >= BATCH_FILES or time.perf_counter() - written[0] >= BATCH_SECONDS:
                    flush()
                if stop is not None and stop():
                    summary.stopped = True
                    break
        finally:
            results.close()  # a pool stopped early cancels the tasks not started
            flush()
        if summary.read or summary.removed:  # skeletons may have come or gone
            self.regroup()
        self.connection.execute("PRAGMA optimize")  # the query planner's statistics, when they are due
        if not summary.stopped:
            now = time.time()
            with self._transaction() as connection:
                connection.executemany(
                    "UPDATE folders SET indexed_at = ? WHERE path = ?", [(now, f) for f in plan.folders]
                )
        summary.seconds = time.perf_counter() - start
        return summary


def _nothing():
    yield from ()


def _count(summary: IndexSummary, record: FileRecord) -> None:
    if record.unchanged:
        summary.touched += 1
        return
    summary.read += 1
    summary.failed += record.status != "ok"
    for stage, seconds in record.seconds.items():
        summary.stage_seconds[stage] = summary.stage_seconds.get(stage, 0.0) + seconds
    for stage, seconds in record.cpu.items():
        summary.stage_cpu[stage] = summary.stage_cpu.get(stage, 0.0) + seconds


class _Transaction:
    """``BEGIN IMMEDIATE`` ... ``COMMIT`` (``ROLLBACK`` on an exception): one writer at a
    time, the others waiting up to :data:`core.library.schema.BUSY_SECONDS`."""

    def __init__(self, connection: sqlite3.Connection) -> None:
        self.connection = connection

    def __enter__(self) -> sqlite3.Connection:
        self.connection.execute("BEGIN IMMEDIATE")
        return self.connection

    def __exit__(self, kind, _value, _traceback) -> None:
        self.connection.execute("COMMIT" if kind is None else "ROLLBACK")
