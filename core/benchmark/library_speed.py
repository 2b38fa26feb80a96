"""The library's speed, printed side by side (asserts nothing): indexing a folder of BVH
files with one and two worker processes, what each stage costs a file, indexing again after
one file changed, queries over 100,000 rows, and the app's panel scrolling 10,000 rows.

Other jobs on the machine slow a run down (the load average is printed before each part):
beside each wall-clock figure is the CPU time it took, which they do not change much. The
speed-up two workers would give on two idle cores follows from the CPU times by Amdahl's law:
the writing process's CPU seconds are the serial part, the workers' the parallel part.

A query answers when the panel can show it: the count of the rows it lets through and the
ids of the first :data:`core.library.query.ID_BLOCK` of them in its order
(:func:`core.library.query.first_ids`), read from the library file; beside it, every id in
order (what a whole listing starts from). The first page of rows, every row of a large
result as dicts and their JSON text (what ``gmr library list --json`` prints) are timed on
their own lines.

The folder (``--files`` BVH files, 2,000 by default, in a temporary folder) is made from the
shared takes: each file a stretch of one take (trimmed to 60 to 600 frames, tiled where the
take is shorter), some with their joints renamed (a ``rig:`` namespace), a few corrupted
(cut in the middle of a frame, or not BVH at all). The 100,000 rows are the folder's rows
copied under other paths; the 10,000 rows of the panel likewise, thumbnails included. The
panel's figure needs a display (``xvfb-run``): it runs ``app.tools.library_bench``.

Run: ``.venv/bin/python -m gmr_studio.core.benchmark.library_speed [--files 2000]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import resource
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gmr_studio.core.library import schema
from gmr_studio.core.library.index import IndexSummary, Library
from gmr_studio.core.library.query import (
    ID_BLOCK,
    Query,
    count,
    first_ids,
    parse_has,
    rows_json_text,
    select_ids,
    select_rows,
)
from gmr_studio.core.library.reading import STAGES
from gmr_studio.core.library.skeletons import Skeleton
from gmr_studio.core.shared_data import shared_file

#: the takes the files are cut from
SOURCES = (
    "cmu/subject01/01_01.bvh",
    "bvh/assimp_Boxing_Toes.bvh",
    "bvh/bvh-python_test_mocapbank.bvh",
    "bvh/bvh-python_test_freebvh.bvh",
    "bvh/cmu_cgspeed_npybvh_example_75f.bvh",
)
#: one file in this many is renamed, one in this many corrupted
RENAMED, CORRUPTED = 5, 100


def split_bvh(text: str) -> tuple[str, list[str], str]:
    """(hierarchy up to ``MOTION``, frame lines, frame time line) of a BVH file's text."""
    lines = text.splitlines()
    motion = next(i for i, line in enumerate(lines) if line.strip() == "MOTION")
    frame_time = next(line for line in lines[motion + 1 : motion + 4] if line.strip().startswith("Frame Time"))
    start = lines.index(frame_time) + 1
    return "\n".join(lines[:motion]), [line for line in lines[start:] if line.strip()], frame_time


def make_folder(folder: Path, n_files: int, seed: int = 1) -> int:
    """Write ``n_files`` BVH files into ``folder`` (module docstring); how many are corrupted."""
    rng = np.random.default_rng(seed)
    takes = [split_bvh(shared_file(s).read_text(encoding="utf-8", errors="replace")) for s in SOURCES]
    corrupted = 0
    for k in range(n_files):
        hierarchy, frames, frame_time = takes[k % len(takes)]
        length = int(rng.integers(60, 601))
        start = int(rng.integers(0, len(frames)))
        chosen = [frames[(start + i) % len(frames)] for i in range(length)]  # tiled where too short
        if k % RENAMED == 1:
            hierarchy = _renamed(hierarchy)
        text = f"{hierarchy}\nMOTION\nFrames: {length}\n{frame_time}\n" + "\n".join(chosen) + "\n"
        if k % CORRUPTED == CORRUPTED - 1:
            corrupted += 1
            text = text[: len(text) // 2] if k % (2 * CORRUPTED) else "not a motion file\n" + text[:100]
        subfolder = folder / f"session{k // 250:02d}"
        subfolder.mkdir(parents=True, exist_ok=True)
        (subfolder / f"take{k:05d}.bvh").write_text(text, encoding="utf-8")
    return corrupted


def _renamed(hierarchy: str) -> str:
    """Every joint name given a ``rig:`` namespace."""
    out = []
    for line in hierarchy.splitlines():
        words = line.split()
        if len(words) == 2 and words[0] in ("ROOT", "JOINT"):
            line = line.replace(words[1], f"rig:{words[1]}")
        out.append(line)
    return "\n".join(out)


def cpu_seconds() -> tuple[float, float]:
    """CPU seconds (user and system) of this process, and of its children that have ended."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime


@dataclasses.dataclass
class IndexRun:
    """An indexing run's summary, and the CPU seconds of this process (planning, writing)
    and of its worker processes, and the load average before it."""

    summary: IndexSummary
    own_cpu: float
    workers_cpu: float
    load: float

    @property
    def cpu(self) -> float:
        return self.own_cpu + self.workers_cpu


def index_run(folder: Path, db: Path, jobs: int) -> IndexRun:
    load = os.getloadavg()[0]
    own, children = cpu_seconds()
    with Library(db) as library:
        summary = library.index([folder], jobs=jobs)
    own_after, children_after = cpu_seconds()
    return IndexRun(summary, own_after - own, children_after - children, load)


def amdahl(one: IndexRun, two: IndexRun) -> tuple[float, float, float]:
    """(serial fraction, Amdahl's speed-up on two idle cores for it, the speed-up two idle
    cores give with the CPU seconds the runs took): the writing process's CPU seconds are the
    serial part, the workers' the parallel part; one worker's run is one thread, so its CPU
    seconds are its wall clock on an idle core, and two workers' wall clock on idle cores is
    the writing process's CPU seconds alone plus the workers' shared by two cores."""
    serial = two.own_cpu / two.cpu
    return serial, 1 / (serial + (1 - serial) / 2), one.cpu / (two.own_cpu + two.workers_cpu / 2)


def print_indexing(one: IndexRun, two: IndexRun) -> None:
    runs = (one, two)
    print(f"{'indexing':<36}{'1 worker':>12}{'2 workers':>12}")
    print(f"{'load average before (1 min)':<36}{one.load:>12.1f}{two.load:>12.1f}")
    print(f"{'wall seconds':<36}{one.summary.seconds:>12.1f}{two.summary.seconds:>12.1f}")
    print(f"{'CPU seconds, all processes':<36}{one.cpu:>12.1f}{two.cpu:>12.1f}")
    print(f"{'  of the writing process':<36}{one.own_cpu:>12.1f}{two.own_cpu:>12.1f}")
    print(f"{'  of the worker processes':<36}{one.workers_cpu:>12.1f}{two.workers_cpu:>12.1f}")
    print(
        f"{'cores used (CPU / wall)':<36}{one.cpu / one.summary.seconds:>12.2f}{two.cpu / two.summary.seconds:>12.2f}"
    )
    print(f"{'files read per second':<36}{one.summary.read / one.summary.seconds:>12.1f}", end="")
    print(f"{two.summary.read / two.summary.seconds:>12.1f}")
    print(f"{'failed files':<36}{one.summary.failed:>12}{two.summary.failed:>12}")
    serial, bound, idle = amdahl(one, two)
    print(f"speed-up with 2 workers: {one.summary.seconds / two.summary.seconds:.2f}x measured (goal: at least 1.7x)")
    print(
        f"  serial fraction {100 * serial:.1f}% of the CPU: Amdahl's law gives {bound:.2f}x on two idle cores; "
        f"with the {100 * (two.cpu / one.cpu - 1):+.0f}% CPU two workers took, {idle:.2f}x"
    )
    print()
    print(f"{'ms per file read, by stage':<36}{'1 worker':>12}{'2 workers':>12}{'1 w. CPU':>12}{'2 w. CPU':>12}")
    for stage in STAGES:
        wall = [1e3 * run.summary.stage_seconds[stage] / run.summary.read for run in runs]
        cpu = [1e3 * run.summary.stage_cpu[stage] / run.summary.read for run in runs]
        print(f"{stage:<36}{wall[0]:>12.2f}{wall[1]:>12.2f}{cpu[0]:>12.2f}{cpu[1]:>12.2f}")
    wall = [1e3 * run.summary.database / run.summary.read for run in runs]
    cpu = [1e3 * run.summary.database_cpu / run.summary.read for run in runs]
    print(f"{'database (writing process)':<36}{wall[0]:>12.2f}{wall[1]:>12.2f}{cpu[0]:>12.2f}{cpu[1]:>12.2f}")
    print(f"{'all of the writing process':<36}{'':>12}{'':>12}{'':>12}{1e3 * two.own_cpu / two.summary.read:>12.2f}")


def copy_rows(source: Path, target: Path, copies: int, *, thumbnails: bool) -> int:
    """A library of ``copies`` times the rows of ``source`` under other paths; its row count."""
    shutil.copyfile(source, target)
    with Library(target) as library:
        connection = library.connection
        top = connection.execute("SELECT max(id) FROM files").fetchone()[0]
        columns = [c for c in schema.FILE_COLUMNS if c != "path"]
        listed = ", ".join(columns)
        connection.execute("BEGIN IMMEDIATE")
        for k in range(1, copies):
            shift = k * top
            connection.execute(
                f"INSERT INTO files(id, path, {listed}) SELECT id + {shift}, path || '#{k}', {listed} FROM files "
                f"WHERE id <= {top}"
            )
            connection.execute(
                f"INSERT INTO problems SELECT file_id + {shift}, kind, level, count FROM problems "
                f"WHERE file_id <= {top}"
            )
            if thumbnails:
                connection.execute(
                    f"INSERT INTO thumbnails SELECT file_id + {shift}, png FROM thumbnails WHERE file_id <= {top}"
                )
        connection.execute("COMMIT")
        connection.execute("ANALYZE")
        return library.count()


def timed(function, repeat: int) -> tuple[float, float]:
    """(best wall-clock ms, best CPU ms of this process) of ``repeat`` calls."""
    wall, cpu = [], []
    for _ in range(max(1, repeat)):
        start, start_cpu = time.perf_counter(), time.process_time()
        function()
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return 1e3 * min(wall), 1e3 * min(cpu)


@dataclasses.dataclass
class QueryFigure:
    """A query's best wall-clock and CPU milliseconds: ``answer`` its count and first block of
    ids (what the panel reads to show it), ``ids`` every id; ``rows`` how many it lets through."""

    what: str
    answer: tuple[float, float]
    ids: tuple[float, float]
    rows: int


def query_figures(db: Path, repeat: int = 5) -> tuple[list[QueryFigure], list[tuple[str, float, float, int]]]:
    """The queries a user runs over the library at ``db`` (module docstring: what a query
    is), and (what, best wall ms, best CPU ms, rows) of reading rows: a first page, every row
    of a large result as dicts and as JSON text."""
    with Library(db, create=False) as library:
        connection = library.connection
        row = connection.execute("SELECT names, parents FROM skeletons LIMIT 1").fetchone()
        skeleton = Skeleton(tuple(json.loads(row[0])), tuple(json.loads(row[1])))
        queries = {
            "every row, by name": Query(sort="name"),
            "every row, problems worst first": Query(sort="problems", descending=True),
            "every row, by frames, longest first": Query(sort="frames", descending=True),
            "format bvh, 2 to 10 s, by duration": Query(
                formats=("bvh",), min_duration=2, max_duration=10, sort="duration"
            ),
            "2 to 10 s (by path)": Query(min_duration=2, max_duration=10),
            "joints = 38": Query(joints=38),
            "same skeleton as a file": Query(skeleton=skeleton),
            "name glob *00042*": Query(name="*00042*"),
            "has pop:warning": Query(has=(parse_has("pop:warning"),)),
            "failed": Query(failed=True),
        }
        figures = []
        for what, query in queries.items():
            answer = timed(lambda q=query: first_ids(connection, q), repeat)
            ids = timed(lambda q=query: select_ids(connection, q), repeat)
            figures.append(QueryFigure(what, answer, ids, count(connection, query)))
        page = Query(formats=("bvh",), min_duration=2, sort="duration", descending=True)
        first = timed(lambda: (count(connection, page), select_rows(connection, page, limit=100)), repeat)
        reading = [("first page: count, 100 rows as dicts (bvh >= 2 s, longest first)", *first, 100)]
        large = queries["format bvh, 2 to 10 s, by duration"]
        rows = select_rows(connection, large)
        reading.append(
            ("every row as dicts: bvh, 2 to 10 s", *timed(lambda: select_rows(connection, large), 1), len(rows))
        )
        reading.append(
            ("  their JSON text (gmr library list --json)", *timed(lambda: rows_json_text(rows), 1), len(rows))
        )
    return figures, reading


def print_queries(db: Path, rows: int) -> None:
    print(f"queries over {rows} rows (best of 5; goal: under 50 ms); load average {os.getloadavg()[0]:.1f}")
    print(
        f"{'':<40}{'count + first ' + str(ID_BLOCK) + ' ids':>24}{'every id':>18}\n"
        f"{'query':<40}{'wall ms':>12}{'CPU ms':>12}{'wall ms':>9}{'CPU ms':>9}{'rows':>9}  goal"
    )
    figures, reading = query_figures(db)
    for figure in figures:
        (wall, cpu), (all_wall, all_cpu) = figure.answer, figure.ids
        verdict = "met" if wall < 50 else "over" + (", CPU under" if cpu < 50 else "")
        print(f"{figure.what:<40}{wall:>12.1f}{cpu:>12.1f}{all_wall:>9.1f}{all_cpu:>9.1f}{figure.rows:>9}  {verdict}")
    print()
    print(f"{'reading rows':<66}{'wall ms':>9}{'CPU ms':>9}{'rows':>9}")
    for what, wall, cpu, found in reading:
        print(f"{what:<66}{wall:>9.1f}{cpu:>9.1f}{found:>9}")


def panel_figure(db: Path) -> str:
    """The app bench's line (``app.tools.library_bench``), or why it did not run."""
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return "panel: skipped (no display: run under xvfb-run)"
    command = [sys.executable, "-m", "gmr_studio.app.tools.library_bench", str(db)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=900)
    if done.returncode:
        return f"panel: the bench failed: {done.stderr.strip().splitlines()[-1] if done.stderr else done.returncode}"
    return done.stdout.strip()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--files", type=int, default=2000, help="BVH files in the folder (2000)")
    parser.add_argument("--rows", type=int, default=100_000, help="rows of the library the queries run on")
    parser.add_argument("--panel-rows", type=int, default=10_000, help="rows the panel scrolls")
    parser.add_argument("--rounds", type=int, default=2, help="indexing runs with each worker count, alternated (2)")
    parser.add_argument("--keep", metavar="DIR", help="make the folder and libraries here and keep them")
    args = parser.parse_args()
    scratch = None if args.keep else tempfile.TemporaryDirectory()
    root = Path(args.keep or scratch.name)
    folder = root / "takes"
    start = time.perf_counter()
    corrupted = make_folder(folder, args.files)
    print(f"{args.files} BVH files ({corrupted} corrupted) made in {time.perf_counter() - start:.1f} s under {folder}")
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}; sqlite {sqlite3.sqlite_version}")

    runs: dict[int, list[IndexRun]] = {1: [], 2: []}
    for round_ in range(max(1, args.rounds)):  # in alternation: a burst of load hits both alike
        for jobs in (1, 2):
            runs[jobs].append(index_run(folder, root / f"{jobs}-{round_}.sqlite", jobs))
    one, two = (min(runs[jobs], key=lambda run: run.summary.seconds) for jobs in (1, 2))
    two_db = root / f"2-{runs[2].index(two)}.sqlite"
    print(
        f"indexed {len(runs[1])} times with each; the fastest run of each below "
        f"(wall seconds, 1 worker: {', '.join(f'{r.summary.seconds:.1f}' for r in runs[1])}; "
        f"2 workers: {', '.join(f'{r.summary.seconds:.1f}' for r in runs[2])})"
    )
    print()
    print_indexing(one, two)

    changed = next(folder.rglob("take00003.bvh"))
    text = changed.read_text(encoding="utf-8")
    changed.write_text(text.replace("Frame Time:", "Frame Time: ", 1), encoding="utf-8")
    again = index_run(folder, two_db, 2).summary
    share = again.seconds / two.summary.seconds
    print()
    print(
        f"indexing again with one file changed: {again.seconds:.2f} s ({again.read} read, {again.unchanged} "
        f"unchanged) = {100 * share:.2f}% of the first run (goal: under 2%)"
    )

    rows = copy_rows(two_db, root / "rows.sqlite", max(1, args.rows // max(args.files, 1)), thumbnails=False)
    print()
    print_queries(root / "rows.sqlite", rows)

    panel_rows = copy_rows(
        two_db, root / "panel.sqlite", max(1, args.panel_rows // max(args.files, 1)), thumbnails=True
    )
    print()
    print(f"panel over {panel_rows} rows (goal: at least 30 frames per second); load average {os.getloadavg()[0]:.1f}")
    print(panel_figure(root / "panel.sqlite"))
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    if scratch is not None:
        scratch.cleanup()


if __name__ == "__main__":
    main()
