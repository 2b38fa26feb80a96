"""The library's speed, printed side by side (asserts nothing): indexing a folder of BVH
files with one and two worker processes, what each stage costs a file, indexing again after
one file changed, queries over 100,000 rows, and the app's panel scrolling 10,000 rows.

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

from gmr_studio.core.benchmark.timing import time_call
from gmr_studio.core.library import schema
from gmr_studio.core.library.index import IndexSummary, Library
from gmr_studio.core.library.query import Query, count, parse_has, select_ids, select_rows
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


def cpu_seconds() -> float:
    """CPU seconds (user and system) of this process and of its children that have ended."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def index_run(folder: Path, db: Path, jobs: int) -> tuple[IndexSummary, float]:
    """The run's summary and the CPU seconds it took (this process and its workers)."""
    start = cpu_seconds()
    with Library(db) as library:
        summary = library.index([folder], jobs=jobs)
    return summary, cpu_seconds() - start


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


def query_figures(db: Path, repeat: int = 5) -> list[tuple[str, float, int]]:
    """(what, best milliseconds, rows) of the queries a user runs, over the library at ``db``."""
    with Library(db, create=False) as library:
        connection = library.connection
        row = connection.execute("SELECT names, parents FROM skeletons LIMIT 1").fetchone()
        skeleton = Skeleton(tuple(json.loads(row[0])), tuple(json.loads(row[1])))
        queries = {
            "all ids, sorted by name": Query(sort="name"),
            "name glob *00042*": Query(name="*00042*"),
            "format bvh, 2 to 10 s, by duration": Query(
                formats=("bvh",), min_duration=2, max_duration=10, sort="duration"
            ),
            "joints = 38": Query(joints=38),
            "has pop:warning": Query(has=(parse_has("pop:warning"),)),
            "same skeleton as a file": Query(skeleton=skeleton),
            "failed": Query(failed=True),
            "problems, worst first": Query(sort="problems", descending=True),
        }
        figures = []
        for what, query in queries.items():
            found = select_ids(connection, query)
            timing = time_call(lambda q=query: select_ids(connection, q), repeat)
            figures.append((f"ids: {what}", timing.best * 1e3, len(found)))
        page = Query(formats=("bvh",), min_duration=2, sort="duration", descending=True)
        timing = time_call(lambda: select_rows(connection, page, limit=100), repeat)
        figures.append(("first 100 rows as JSON: bvh >= 2 s, longest first", timing.best * 1e3, 100))
        timing = time_call(lambda: count(connection, Query(formats=("bvh",))), repeat)
        figures.append(("count: bvh", timing.best * 1e3, count(connection, Query(formats=("bvh",)))))
    return figures


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
    parser.add_argument("--keep", metavar="DIR", help="make the folder and libraries here and keep them")
    args = parser.parse_args()
    scratch = None if args.keep else tempfile.TemporaryDirectory()
    root = Path(args.keep or scratch.name)
    folder = root / "takes"
    start = time.perf_counter()
    corrupted = make_folder(folder, args.files)
    print(f"{args.files} BVH files ({corrupted} corrupted) made in {time.perf_counter() - start:.1f} s under {folder}")
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}; sqlite {sqlite3.sqlite_version}")

    (one, one_cpu), (two, two_cpu) = (
        index_run(folder, root / "one.sqlite", 1),
        index_run(folder, root / "two.sqlite", 2),
    )
    print()
    print(f"{'indexing':<28}{'1 worker':>12}{'2 workers':>12}")
    print(f"{'wall seconds':<28}{one.seconds:>12.1f}{two.seconds:>12.1f}")
    print(f"{'CPU seconds (all processes)':<28}{one_cpu:>12.1f}{two_cpu:>12.1f}")
    print(f"{'cores used (CPU / wall)':<28}{one_cpu / one.seconds:>12.2f}{two_cpu / two.seconds:>12.2f}")
    print(f"{'files per second':<28}{one.read / one.seconds:>12.1f}{two.read / two.seconds:>12.1f}")
    print(f"{'failed files':<28}{one.failed:>12}{two.failed:>12}")
    print(f"speed-up with 2 workers: {one.seconds / two.seconds:.2f}x (goal: at least 1.7x)")
    print()
    print(f"{'ms per file, by stage':<28}{'1 worker':>12}{'2 workers':>12}")
    for stage in STAGES:
        per_file = [1e3 * run.stage_seconds[stage] / run.read for run in (one, two)]
        print(f"{stage:<28}{per_file[0]:>12.2f}{per_file[1]:>12.2f}")
    print(f"{'database (writing)':<28}{1e3 * one.database / one.read:>12.2f}{1e3 * two.database / two.read:>12.2f}")

    changed = next(folder.rglob("take00003.bvh"))
    text = changed.read_text(encoding="utf-8")
    changed.write_text(text.replace("Frame Time:", "Frame Time: ", 1), encoding="utf-8")
    again, _cpu = index_run(folder, root / "two.sqlite", 2)
    share = again.seconds / two.seconds
    print()
    print(
        f"indexing again with one file changed: {again.seconds:.2f} s ({again.read} read, {again.unchanged} "
        f"unchanged) = {100 * share:.2f}% of the first run (goal: under 2%)"
    )

    rows = copy_rows(
        root / "two.sqlite", root / "rows.sqlite", max(1, args.rows // max(args.files, 1)), thumbnails=False
    )
    print()
    print(f"queries over {rows} rows (best of 5; goal: under 50 ms)")
    print(f"{'query':<56}{'ms':>8}{'rows':>10}")
    for what, ms, found in query_figures(root / "rows.sqlite"):
        print(f"{what:<56}{ms:>8.1f}{found:>10}")

    panel_rows = copy_rows(
        root / "two.sqlite", root / "panel.sqlite", max(1, args.panel_rows // max(args.files, 1)), thumbnails=True
    )
    print()
    print(f"panel over {panel_rows} rows (goal: at least 30 frames per second)")
    print(panel_figure(root / "panel.sqlite"))
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    if scratch is not None:
        scratch.cleanup()


if __name__ == "__main__":
    main()
