"""``gmr convert --batch IN_DIR OUT_DIR``: every motion file of a folder tree, in parallel.

- Inputs: every ``.bvh``, ``.amc``, ``.gmr``, ``.glb``, ``.gltf`` and ``.fbx`` under IN_DIR
  (``.asf`` files are the AMCs' skeletons, found beside each AMC), and AMASS ``.npz`` when ``--body-model`` is given,
  except inside OUT_DIR. Outputs mirror the folders: ``IN_DIR/a/walk.bvh`` ->
  ``OUT_DIR/a/walk.gmr``. Where two inputs of a folder would give the same output
  (``01_01.bvh`` and ``01_01.amc``), each output keeps its source format in its name:
  ``01_01_bvh.gmr``, ``01_01_amc.gmr``.
- Work runs in ``--jobs`` processes (default: every core) or on a Dask cluster
  (``--scheduler tcp://HOST:8786`` or ``local:N``; :mod:`core.batch.workers`), each file
  independently; every output is written to a temporary name and renamed (``core.atomic``),
  so an interrupted or failed conversion leaves no partial file. A file whose Dask worker
  died is converted again elsewhere; temporary files such a death leaves are removed at the
  end.
- stderr: a progress bar (tqdm, on a terminal only), one line per failed file with its
  error, and a summary. Exit code 1 if any file failed.
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path
from typing import TextIO

from gmr_studio.core.batch import workers
from gmr_studio.core.batch.files import find_motion_files
from gmr_studio.core.cli.convert import INPUT_SUFFIXES, ConversionReport, ConvertOptions, convert_file
from gmr_studio.core.cli.progress import Progress
from gmr_studio.core.errors import MotionFileError, OperationError

__all__ = ["Progress", "find_motion_files", "input_suffixes", "plan_outputs", "run_batch"]


def input_suffixes(options: ConvertOptions) -> tuple[str, ...]:
    """The suffixes a batch reads: AMASS ``.npz`` only with a body model (else any ``.npz``,
    such as saved positions, would count as a failed motion)."""
    return INPUT_SUFFIXES if options.body_model else tuple(s for s in INPUT_SUFFIXES if s != ".npz")


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


def remove_stray_temporaries(pairs: list[tuple[Path, Path]]) -> int:
    """Remove the temporary files (``.NAME.*.tmp``, :mod:`core.atomic`) that a killed worker
    left beside the planned outputs; return how many."""
    removed = 0
    for folder, names in _outputs_by_folder(pairs).items():
        for name in names:
            for stray in folder.glob(f".{name}.*.tmp"):
                stray.unlink(missing_ok=True)
                removed += 1
    return removed


def _outputs_by_folder(pairs: list[tuple[Path, Path]]) -> dict[Path, set[str]]:
    folders: dict[Path, set[str]] = {}
    for _, output in pairs:
        folders.setdefault(output.parent, set()).add(output.name)
    return folders


def run_batch(
    in_dir: Path,
    out_dir: Path,
    to: str,
    options: ConvertOptions,
    jobs: int | None,
    stream: TextIO | None = None,
    *,
    scheduler: str | None = None,
) -> int:
    """Convert every motion file under ``in_dir`` into ``out_dir``; 1 if any failed, else 0."""
    stream = stream or sys.stderr
    if not in_dir.is_dir():
        raise OperationError(f"{in_dir} is not a folder")
    if out_dir.resolve() == in_dir.resolve():
        raise OperationError("OUT_DIR must differ from IN_DIR (outputs could overwrite their inputs)")
    suffixes = input_suffixes(options)
    files = find_motion_files(in_dir, out_dir, suffixes)
    if not files:
        raise OperationError(f"no motion files ({', '.join(suffixes)}) under {in_dir}")
    pairs = plan_outputs(files, in_dir, out_dir, to)
    jobs = workers.default_jobs(jobs, len(pairs))
    progress = Progress(len(pairs), stream)
    frames = 0
    tasks = [(str(source), str(output), options) for source, output in pairs]
    try:
        for ok, error, report in workers.results(_convert_task, tasks, jobs=jobs, scheduler=scheduler):
            if not ok:
                progress.message(error)
            elif report is not None:
                frames += report.frames
            progress.advance(ok)
    finally:
        progress.close()
        remove_stray_temporaries(pairs)
    converted = progress.done - progress.failed
    summary = (
        f"converted {converted} of {len(pairs)} files to .{to} in {progress.seconds:.1f} s "
        f"({workers.describe(jobs, scheduler)}, {frames} frames) into {out_dir}"
    )
    if progress.failed:
        summary += f"; {progress.failed} failed"
    stream.write(summary + "\n")
    return 1 if progress.failed else 0
