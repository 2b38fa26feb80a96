"""``gmr check FILE``: what is wrong with a motion, at which frames and joints.

- ``gmr check FILE [--json OUT] [--only KINDS] [--settings S.json] [--strict [--fail-on S]]``:
  runs :func:`core.checks.run_checks` and prints a table of findings, after a line per
  stretch of frames some checks left out and why (:func:`core.checks.skipped_frames`: the
  rest pose at the ends); ``--json OUT`` writes the document of :mod:`core.checks.report`
  (``-`` for stdout). A marker file (``.c3d``,
  ``.trc``) gets the checks of points (:mod:`core.checks.markers`), its markers as joints,
  read as ``--drop-computed`` and ``--rate HZ`` ask (:func:`core.cli.markers.add_marker_options`).
- ``gmr check --batch DIR [--table OUT.csv|OUT.parquet] [--json OUT] [--jobs N | --scheduler S]``:
  every motion file of a folder tree (``.bvh``, ``.amc`` with its ``.asf``, ``.gmr``, AMASS
  ``.npz`` with ``--body-model``; :func:`core.cli.batch.find_motion_files`) and marker file
  (``.c3d``, ``.trc``), checked in
  ``--jobs`` processes or on a Dask cluster (:mod:`core.batch.workers`), one summary line per
  file on stdout (in path order) and, with ``--table``, one row per file
  (:data:`core.checks.report.SUMMARY_COLUMNS` then one count per kind); ``--json`` then
  writes ``{"files": [document, ...]}``. A file that cannot be read is a row with its error
  as status; the exit code is then 1.
- ``--strict``: exit code 1 when any finding is at ``--fail-on`` (default ``warning``) or
  worse, to gate a data pipeline. Exit 2 for a bad file or option (one line, as every
  ``gmr`` command).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from gmr_studio.core.atomic import atomic_write_bytes, atomic_write_text
from gmr_studio.core.batch import workers
from gmr_studio.core.batch.files import find_motion_files
from gmr_studio.core.checks import KINDS, SEVERITIES, CheckSettings, run_checks, skipped_frames
from gmr_studio.core.checks.markers import run_marker_checks
from gmr_studio.core.checks.report import SUMMARY_COLUMNS, check_document, failing, findings_text, summary_row
from gmr_studio.core.cli.convert import INPUT_SUFFIXES
from gmr_studio.core.cli.markers import add_marker_options, marker_options
from gmr_studio.core.cli.output import write_json
from gmr_studio.core.cli.progress import Progress
from gmr_studio.core.cli.reading import add_reading_options, reader_options, transformed_by_args
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.markers import MARKER_READERS, read_markers
from gmr_studio.core.table import records_csv_text

#: marker files, checked as points (pops, jitter, frozen and duplicated frames)
MARKER_SUFFIXES = tuple(MARKER_READERS)


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = __doc__.split("\n\n")[0] if __doc__ else None
    parser.usage = (
        "gmr check FILE [--json OUT] [--only KINDS] [--strict [--fail-on S]]\n"
        "       gmr check --batch DIR [--table OUT.csv|OUT.parquet] [--json OUT] [--jobs N | --scheduler S]"
    )
    parser.add_argument("input", help="a motion or marker file (with --batch: a folder, searched recursively)")
    parser.add_argument("--json", metavar="OUT", help="write the findings as JSON (- for stdout)")
    parser.add_argument("--only", metavar="KINDS", help=f"comma-separated kinds to run (of {', '.join(KINDS)})")
    parser.add_argument("--settings", metavar="S.json", help="thresholds as CheckSettings.to_dict() writes them")
    parser.add_argument("--strict", action="store_true", help="exit 1 if any finding is at --fail-on or worse")
    parser.add_argument("--fail-on", choices=SEVERITIES, default="warning", help="with --strict (warning)")
    parser.add_argument("--batch", action="store_true", help="check every motion file of the folder tree")
    parser.add_argument("--table", metavar="OUT", help="with --batch: one row per file, .csv or .parquet")
    parser.add_argument("--jobs", type=int, default=None, help="with --batch: parallel processes (all cores)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:8786|local:N", help="with --batch: a Dask cluster")
    add_marker_options(parser)
    add_reading_options(parser)
    parser.set_defaults(run=run)


def settings_from_args(args: argparse.Namespace) -> CheckSettings:
    """The settings of ``--settings`` and ``--only``; OperationError when they are wrong."""
    try:
        data = {}
        if args.settings:
            try:
                data = json.loads(Path(args.settings).read_text(encoding="utf-8"))
            except (OSError, json.JSONDecodeError) as exc:
                raise OperationError(f"cannot read --settings {args.settings}: {exc}") from None
            if not isinstance(data, dict):
                raise OperationError(f"--settings {args.settings}: expected a JSON object")
        settings = CheckSettings.from_dict(data)
        if args.only:
            settings = settings.with_kinds([k.strip() for k in args.only.split(",") if k.strip()])
    except (ValueError, TypeError) as exc:
        raise OperationError(str(exc)) from None
    return settings


def check_file(
    path: str | Path,
    settings: CheckSettings,
    reading: dict | None = None,
    transforms: dict | None = None,
    marker_reading: dict | None = None,
) -> dict:
    """Read one motion or marker file and return its JSON document (MotionFileError if
    unreadable). ``reading``: :func:`core.cli.reading.reader_options`; ``transforms``:
    ``scale``, ``up``, ``from_up`` as the reading options give them (``--up y --from-up z``
    checks a Z-up file whose header does not say so); ``marker_reading``: the keywords of
    :func:`core.markers.read_markers` (:func:`core.cli.markers.marker_options`). Markers get
    the checks of points only (:mod:`core.checks.markers`)."""
    if Path(path).suffix.lower() in MARKER_SUFFIXES:
        motion, findings = run_marker_checks(read_markers(path, **(marker_reading or {})), settings)
        return check_document(str(path), motion, findings)
    motion = transformed_by_args(read_motion(path, **(reading or {})), argparse.Namespace(**(transforms or {})))
    return check_document(str(path), motion, run_checks(motion, settings), skipped_frames(motion, settings))


def _transforms(args: argparse.Namespace) -> dict:
    return {key: getattr(args, key, None) for key in ("scale", "up", "from_up")}


def _check_task(
    source: str, settings: dict, reading: dict, transforms: dict, marker_reading: dict | None = None
) -> tuple[str, str, dict | None]:
    """One file, in a worker: (file, error or "", document or None). Never raises."""
    error, document = workers.file_task(
        check_file, source, CheckSettings.from_dict(settings), reading, transforms, marker_reading
    )
    return source, error, document


def run(args: argparse.Namespace) -> int:
    settings = settings_from_args(args)
    if args.batch:
        return run_batch(args, settings)
    if args.table:
        raise OperationError("--table goes with --batch")
    reading = reader_options(args.input, args.asf, args.frame_rate, args.body_model)
    document = check_file(args.input, settings, reading, _transforms(args), marker_options(args))
    if args.json:
        write_json(document, args.json)
    if args.json != "-":
        print(findings_text(document))
    return 1 if args.strict and failing(document["findings"], args.fail_on) else 0


def batch_line(row: dict) -> str:
    """The stdout line of one file of a batch."""
    if row["status"] != "ok":
        return f"{row['file']}: {row['status']}"
    kinds = ", ".join(f"{row[k]} {k}" for k in KINDS if row[k])
    counts = ", ".join(f"{row[s]} {s}" for s in reversed(SEVERITIES) if row[s])
    return f"{row['file']}: {row['frames']} frames, {row['findings']} findings" + (
        f" ({counts}): {kinds}" if kinds else ""
    )


def run_batch(args: argparse.Namespace, settings: CheckSettings) -> int:
    folder = Path(args.input)
    if not folder.is_dir():
        raise OperationError(f"{folder} is not a folder")
    motions = INPUT_SUFFIXES if args.body_model else tuple(s for s in INPUT_SUFFIXES if s != ".npz")
    suffixes = (*motions, *MARKER_SUFFIXES)
    files = find_motion_files(folder, None, suffixes)
    if not files:
        raise OperationError(f"no motion files ({', '.join(suffixes)}) under {folder}")
    if args.table and Path(args.table).suffix.lower() not in (".csv", ".parquet"):
        raise OperationError(f"the --table is written as .csv or .parquet, not {Path(args.table).name!r}")
    tasks = [
        (
            str(f),
            settings.to_dict(),
            reader_options(f, args.asf, args.frame_rate, args.body_model),
            _transforms(args),
            marker_options(args),
        )
        for f in files
    ]
    jobs = workers.default_jobs(args.jobs, len(tasks))
    progress = Progress(len(tasks), sys.stderr, label="check")
    results: dict[str, tuple[str, dict | None]] = {}
    try:
        for source, error, document in workers.results(_check_task, tasks, jobs=jobs, scheduler=args.scheduler):
            results[source] = (error, document)
            progress.advance(not error)
    finally:
        progress.close()
    rows, documents = [], []
    for source in (str(f) for f in files):
        error, document = results[source]
        rows.append(summary_row(document, source, error or "ok"))
        if document is not None:
            documents.append(document)
        if args.json != "-":  # the JSON alone on stdout
            print(batch_line(rows[-1]))
    if args.table:
        write_table(rows, Path(args.table))
    if args.json:
        write_json({"files": documents}, args.json)
    flagged = sum(1 for d in documents if failing(d["findings"], args.fail_on))
    summary = (
        f"checked {len(documents)} of {len(files)} files in {progress.seconds:.1f} s "
        f"({workers.describe(jobs, args.scheduler)}); {flagged} with findings at {args.fail_on} or worse"
    )
    if progress.failed:
        summary += f"; {progress.failed} could not be read"
    print(summary, file=sys.stderr)
    return 1 if progress.failed or (args.strict and flagged) else 0


def write_table(rows: list[dict], target: Path) -> None:
    """The batch rows as CSV (header, one line per file) or Parquet, written atomically."""
    columns = [*SUMMARY_COLUMNS, *KINDS]
    if target.suffix.lower() == ".csv":
        atomic_write_text(target, records_csv_text(columns, rows))  # the project's one CSV writer
        return
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise OperationError("parquet output needs pyarrow: pip install 'gmr-studio[cluster]'") from None
    table = pa.table({c: [row[c] for row in rows] for c in columns})
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    atomic_write_bytes(target, sink.getvalue().to_pybytes())
