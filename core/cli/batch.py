"""``gmr convert --batch IN_DIR OUT_DIR``: every motion file of a folder tree, in parallel.

- Inputs: every ``.bvh``, ``.amc`` and ``.gmr`` under IN_DIR (``.asf`` files are the AMCs'
  skeletons, found beside each AMC), except inside OUT_DIR. Outputs mirror the folders:
  ``IN_DIR/a/walk.bvh`` -> ``OUT_DIR/a/walk.gmr``. Where two inputs of a folder would give
  the same output (``01_01.bvh`` and ``01_01.amc``), each output keeps its source format
  in its name: ``01_01_bvh.gmr``, ``01_01_amc.gmr``.
- Work runs in ``--jobs`` processes (``concurrent.futures.ProcessPoolExecutor``; default:
  every core), each file independently; every output is written to a temporary name and
  renamed (``core.atomic``), so an interrupted or failed conversion leaves no partial file.
- stderr: a progress bar (redrawn in place on a terminal, one line per tenth otherwise), one
  line per failed file with its error, and a summary. Exit code 1 if any file failed.
"""

from __future__ import annotations

import os
import sys
import time
from collections import Counter
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from pathlib import Path
from typing import TextIO

from gmr_studio.core.cli.convert import INPUT_SUFFIXES, ConversionReport, ConvertOptions, convert_file
from gmr_studio.core.errors import MotionFileError, OperationError

BAR_WIDTH = 30


def find_motion_files(in_dir: Path, out_dir: Path) -> list[Path]:
    """Every input file under ``in_dir`` (sorted), none from inside ``out_dir``."""
    out = out_dir.resolve()
    files = []
    for path in sorted(in_dir.rglob("*")):
        if path.suffix.lower() not in INPUT_SUFFIXES or not path.is_file():
            continue
        resolved = path.resolve()
        if resolved == out or out in resolved.parents:
            continue
        files.append(path)
    return files


def plan_outputs(files: list[Path], in_dir: Path, out_dir: Path, to: str) -> list[tuple[Path, Path]]:
    """(input, output) pairs; inputs that would share an output name keep their format in it."""
    relative = [f.relative_to(in_dir) for f in files]
    plain = [r.with_suffix(f".{to}") for r in relative]
    clashes = Counter(str(p).lower() for p in plain)
    pairs = []
    for source, rel, target in zip(files, relative, plain):
        if clashes[str(target).lower()] > 1:
            target = rel.with_name(f"{rel.stem}_{rel.suffix[1:].lower()}.{to}")
        pairs.append((source, out_dir / target))
    return pairs


def _convert_task(source: str, output: str, options: ConvertOptions) -> tuple[bool, str, ConversionReport | None]:
    """One file, in a worker: (ok, the error line if not, the report if so). Never raises."""
    try:
        Path(output).parent.mkdir(parents=True, exist_ok=True)
        return True, "", convert_file(source, output, options)
    except MotionFileError as exc:
        return False, str(exc), None
    except (OperationError, OSError, ValueError) as exc:
        return False, f"{source}: {exc}", None
    except Exception as exc:  # one bad file must not stop the batch
        return False, f"{source}: {type(exc).__name__}: {exc}", None


class Progress:
    """A progress bar on a stream: in place on a terminal, else a line per tenth."""

    def __init__(self, total: int, stream: TextIO) -> None:
        self.total = total
        self.stream = stream
        self.terminal = stream.isatty()
        self.start = time.perf_counter()
        self.done = self.failed = 0
        self.shown_tenth = -1

    def line(self) -> str:
        filled = BAR_WIDTH * self.done // max(self.total, 1)
        failed = f", {self.failed} failed" if self.failed else ""
        seconds = time.perf_counter() - self.start
        return f"[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {self.done}/{self.total} files{failed}, {seconds:.1f} s"

    def draw(self) -> None:
        if self.terminal:
            self.stream.write("\r\033[K" + self.line())
        else:
            tenth = 10 * self.done // max(self.total, 1)
            if tenth == self.shown_tenth:
                return
            self.shown_tenth = tenth
            self.stream.write(self.line() + "\n")
        self.stream.flush()

    def message(self, text: str) -> None:
        """A line above the bar (the bar is redrawn after it)."""
        if self.terminal:
            self.stream.write("\r\033[K")
        self.stream.write(" ".join(text.splitlines()) + "\n")
        self.draw()

    def advance(self, ok: bool) -> None:
        self.done += 1
        self.failed += not ok
        self.draw()

    def close(self) -> None:
        if self.terminal:
            self.stream.write("\n")
            self.stream.flush()


def run_batch(
    in_dir: Path, out_dir: Path, to: str, options: ConvertOptions, jobs: int | None, stream: TextIO | None = None
) -> int:
    """Convert every motion file under ``in_dir`` into ``out_dir``; 1 if any failed, else 0."""
    stream = stream or sys.stderr
    if not in_dir.is_dir():
        raise OperationError(f"{in_dir} is not a folder")
    if out_dir.resolve() == in_dir.resolve():
        raise OperationError("OUT_DIR must differ from IN_DIR (outputs could overwrite their inputs)")
    files = find_motion_files(in_dir, out_dir)
    if not files:
        raise OperationError(f"no motion files ({', '.join(INPUT_SUFFIXES)}) under {in_dir}")
    pairs = plan_outputs(files, in_dir, out_dir, to)
    jobs = max(1, min(jobs or os.cpu_count() or 1, len(pairs)))
    progress = Progress(len(pairs), stream)
    progress.draw()
    frames = 0

    def finish(ok: bool, error: str, report: ConversionReport | None) -> None:
        nonlocal frames
        if not ok:
            progress.message(error)
        elif report is not None:
            frames += report.frames
        progress.advance(ok)

    if jobs == 1:
        for source, output in pairs:
            finish(*_convert_task(str(source), str(output), options))
    else:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            pending: set[Future] = {pool.submit(_convert_task, str(s), str(o), options) for s, o in pairs}
            try:
                while pending:
                    finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                    for future in finished:
                        finish(*future.result())
            except BaseException:
                pool.shutdown(wait=True, cancel_futures=True)
                raise
    progress.close()
    seconds = time.perf_counter() - progress.start
    converted = progress.done - progress.failed
    summary = (
        f"converted {converted} of {len(pairs)} files to .{to} in {seconds:.1f} s "
        f"({jobs} process{'es' if jobs > 1 else ''}, {frames} frames) into {out_dir}"
    )
    if progress.failed:
        summary += f"; {progress.failed} failed"
    stream.write(summary + "\n")
    return 1 if progress.failed else 0
