"""``gmr library``: index folders of takes into one SQLite file, then find, list and look at them.

- ``gmr library index DIR... [--db FILE] [--workers N] [--scheduler ADDRESS]``: every file
  the project reads under the folders (:mod:`core.library`), read in parallel; a progress bar
  (on a terminal), one line per file that cannot be read, and a summary (files read, new,
  changed, removed, failed, time). Only new and changed files are read; removed ones are
  dropped. Exit 0 even when files failed: they are rows (``--failed`` lists them).
- ``gmr library list|query [filters] [--sort FIELD] [--json | --csv]``: the rows that pass
  every filter (``--name GLOB``, ``--format F``, ``--min-duration S``, ``--max-duration S``,
  ``--joints N``, ``--same-skeleton-as FILE``, ``--has KIND[:SEVERITY]``, ``--failed``), as a
  table, JSON (a list of rows, docs/library.md) or CSV.
- ``gmr library show FILE [--json]``: one file's row, its skeleton's joints included.
- ``gmr library thumbnails --out DIR [filters]``: the thumbnails as PNG files, mirroring the
  folders (``DIR/<folder name>/<path in it>.png``).

``--db FILE`` names the library (default: :func:`core.library.schema.default_library_path`).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from gmr_studio.core.atomic import atomic_write_bytes
from gmr_studio.core.checks import KINDS, SEVERITIES
from gmr_studio.core.cli.output import write_json
from gmr_studio.core.cli.progress import Progress
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import (
    CSV_COLUMNS,
    SORT_FIELDS,
    Query,
    csv_record,
    parse_has,
    parse_sort,
    row_of_path,
    rows_json_text,
    select_rows,
)
from gmr_studio.core.library.reading import IndexOptions
from gmr_studio.core.library.schema import default_library_path
from gmr_studio.core.library.skeletons import Skeleton
from gmr_studio.core.table import records_csv_text


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = __doc__.split("\n\n")[0] if __doc__ else None
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    index = actions.add_parser("index", help="read every file under the folders into the library")
    index.add_argument("folders", nargs="+", metavar="DIR", help="folders of motion and marker files")
    _add_db(index)
    index.add_argument("--workers", type=int, default=None, help="local worker processes (default: every core)")
    index.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler (tcp://HOST:8786, or local:N)")
    index.add_argument("--body-model", help="the SMPL/SMPL-H/SMPL-X model (.npz/.pkl) of AMASS .npz files")
    index.add_argument("--force", action="store_true", help="read every file again, changed or not")
    index.set_defaults(run=run_index)
    for name, text in (("list", "the rows that pass the filters"), ("query", "the same as list")):
        listing = actions.add_parser(name, help=text)
        _add_db(listing)
        _add_filters(listing)
        listing.add_argument(
            "--sort", default="path", help=f"--sort=-FIELD: descending; FIELD one of {', '.join(SORT_FIELDS)}"
        )
        listing.add_argument("--limit", type=int, help="at most this many rows")
        out = listing.add_mutually_exclusive_group()
        out.add_argument("--json", action="store_true", help="a JSON list of rows (docs/library.md)")
        out.add_argument("--csv", action="store_true", help="one CSV line per row")
        listing.set_defaults(run=run_list)
    show = actions.add_parser("show", help="one file's row")
    show.add_argument("file", help="a file of the library")
    _add_db(show)
    show.add_argument("--json", action="store_true", help="the row as JSON")
    show.set_defaults(run=run_show)
    pictures = actions.add_parser("thumbnails", help="write the thumbnails as PNG files")
    pictures.add_argument("--out", required=True, metavar="DIR", help="the folder to write them into")
    _add_db(pictures)
    _add_filters(pictures)
    pictures.set_defaults(run=run_thumbnails, sort="path")


def _add_db(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--db", metavar="FILE", help=f"the library file (default {default_library_path()})")


def _add_filters(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("filters (all must hold)")
    group.add_argument("--name", metavar="GLOB", help="file name pattern, any case (the path's with a /)")
    group.add_argument("--format", action="append", metavar="F", help="file format: bvh, amc, c3d... (repeatable)")
    group.add_argument("--min-duration", type=float, metavar="S", help="at least S seconds")
    group.add_argument("--max-duration", type=float, metavar="S", help="at most S seconds")
    group.add_argument("--joints", type=int, metavar="N", help="exactly N joints")
    group.add_argument("--same-skeleton-as", metavar="FILE", help="the same rig as FILE (renamed rigs too)")
    group.add_argument(
        "--has",
        action="append",
        metavar="KIND[:SEVERITY]",
        help=f"a finding of KIND (or any) at SEVERITY ({'|'.join(SEVERITIES)}) or worse; kinds: {', '.join(KINDS)}",
    )
    group.add_argument("--failed", action="store_true", help="only files that could not be read")


def _db(args: argparse.Namespace) -> Path:
    return Path(args.db).expanduser() if args.db else default_library_path()


def query_from_args(args: argparse.Namespace, library: Library) -> Query:
    """The filters and order of the command line; OperationError for a bad value."""
    try:
        sort, descending = parse_sort(getattr(args, "sort", "path"))
        formats = tuple(f.lower().lstrip(".") for text in (args.format or []) for f in text.split(",") if f)
        has = tuple(parse_has(text) for text in (args.has or []))
        skeleton = _skeleton_of(args.same_skeleton_as, library) if args.same_skeleton_as else None
        return Query(
            name=args.name,
            formats=formats,
            min_duration=args.min_duration,
            max_duration=args.max_duration,
            joints=args.joints,
            skeleton=skeleton,
            has=has,
            failed=args.failed,
            sort=sort,
            descending=descending,
        )
    except ValueError as exc:
        raise OperationError(str(exc)) from None


def _skeleton_of(path: str, library: Library) -> Skeleton:
    """The skeleton of a file: its row's if the library has it, else read from the file."""
    row = row_of_path(library.connection, str(Path(path).resolve()))
    if row is not None and row["skeleton"] is not None:
        return Skeleton(tuple(row["skeleton"]["names"]), tuple(row["skeleton"]["parents"]))
    if row is not None and row["status"] != "ok":
        raise OperationError(f"{path} could not be read when it was indexed: {row['message']}")
    return Skeleton.of(read_motion(path))


def run_index(args: argparse.Namespace) -> int:
    if args.workers is not None and args.workers < 1:
        raise OperationError("--workers must be at least 1")
    with Library(_db(args)) as library:
        progress: list[Progress] = []

        def planned(plan) -> None:
            progress.append(Progress(len(plan.tasks), sys.stderr, label="library"))

        def on_file(record) -> None:
            if record.status != "ok":
                progress[0].message(record.message or record.path)
            progress[0].advance(record.status == "ok")

        try:
            summary = library.index(
                args.folders,
                IndexOptions(body_model=args.body_model),
                jobs=args.workers,
                scheduler=args.scheduler,
                force=args.force,
                on_planned=planned,
                on_file=on_file,
            )
        finally:
            if progress:
                progress[0].close()
    print(f"{summary.text()} into {_db(args)}", file=sys.stderr)
    return 0


def run_list(args: argparse.Namespace) -> int:
    if args.limit is not None and args.limit < 0:
        raise OperationError("--limit must be 0 or more")
    with Library(_db(args), create=False) as library:
        rows = select_rows(library.connection, query_from_args(args, library), limit=args.limit)
        total = library.count()
    if args.json:
        sys.stdout.write(rows_json_text(rows))
    elif args.csv:
        sys.stdout.write(records_csv_text(CSV_COLUMNS, [csv_record(r) for r in rows]))
    else:
        for line in table_lines(rows):
            print(line)
        print(f"{len(rows)} of {total} files", file=sys.stderr)
    return 0


def table_lines(rows: list[dict]) -> list[str]:
    """The rows as a terminal table: name, format, frames, rate, duration, joints (or
    markers), skeleton group, problems; a failed file's message instead of its numbers."""
    width = max([len(r["name"]) for r in rows] + [4])
    lines = [f"{'name':<{width}}  format  frames     rate  duration      joints  group  problems"]
    for row in rows:
        head = f"{row['name']:<{width}}  {row['format']:<6}"
        if row["status"] != "ok":
            lines.append(f"{head}  failed: {row['message']}")
            continue
        joints = f"{row['joints']}" if row["joints"] is not None else f"{row['markers']} markers"
        group = row["skeleton"]["group"] if row["skeleton"] else "-"
        lines.append(
            f"{head}  {row['frames']:>6}  {row['frame_rate']:>7.4g}  {row['duration']:>7.3f}s  {joints:>10}  "
            f"{group:>5}  {problems_text(row['quality'])}"
        )
    return lines


def problems_text(quality: dict | None) -> str:
    """``2 error, 5 warning: pop, jitter`` or ``none``."""
    if not quality or not quality["findings"]:
        return "none"
    counts = ", ".join(f"{quality[s]} {s}" for s in reversed(SEVERITIES) if quality[s])
    return f"{counts}: {', '.join(quality['kinds'])}"


def run_show(args: argparse.Namespace) -> int:
    with Library(_db(args), create=False) as library:
        path = str(Path(args.file).expanduser().resolve())
        row = row_of_path(library.connection, path)
    if row is None:
        raise OperationError(f"{path} is not in the library {_db(args)}: index its folder (gmr library index DIR)")
    if args.json:
        write_json(row, "-")
        return 0
    skeleton = row.pop("skeleton") or {}
    quality = row.pop("quality") or {}
    for key, value in row.items():
        print(f"{key:<12} {value}")
    if skeleton:
        print(
            f"{'skeleton':<12} group {skeleton['group']} (match {skeleton['group_match']:.2f}), "
            f"signature {skeleton['signature'][:16]}, topology {skeleton['topology'][:16]}"
        )
        print(f"{'joints':<12} {', '.join(skeleton['names'])}")
    if quality:
        where = f" (worst at frame {quality['worst_frame']})" if quality["findings"] else ""
        print(f"{'problems':<12} {problems_text(quality)}{where}")
        for kind, severities in quality["kinds"].items():
            print(f"{'':<12} {kind}: {json.dumps(severities)}")
    return 0


def run_thumbnails(args: argparse.Namespace) -> int:
    out = Path(args.out)
    written = 0
    with Library(_db(args), create=False) as library:
        rows = select_rows(library.connection, query_from_args(args, library))
        for row in rows:
            picture = library.thumbnail(row["id"]) if row["thumbnail"] else None
            if picture is None:
                continue
            relative = Path(row["path"]).relative_to(row["folder"]) if row["path"].startswith(row["folder"]) else None
            target = out / Path(row["folder"]).name / (relative or Path(row["name"]))
            target = target.with_name(target.name + ".png")
            target.parent.mkdir(parents=True, exist_ok=True)
            atomic_write_bytes(target, picture)
            written += 1
    print(f"wrote {written} thumbnails (of {len(rows)} files) into {out}", file=sys.stderr)
    return 0
