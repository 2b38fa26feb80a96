"""``gmr dataset IN_DIR -o OUT.npz|OUT.parquet``: one table of every motion file's world
positions (or rotations) for machine learning, built file by file.

- Inputs: as ``gmr convert --batch`` (``.bvh``, ``.amc`` with the ``.asf`` beside it,
  ``.gmr``, ``.glb``/``.gltf`` (``--animation``, ``--skin``), and AMASS ``.npz`` with
  ``--body-model``), sorted by path. A file that cannot be
  read is reported (one line) and left out; exit code 1 if any was.
- ``--quantity positions`` (default): world positions (F, J, 3), in each file's units and
  axes. ``--quantity rotations``: world rotations of the GMR form (the frame of the bone that
  ends at each joint) as unit quaternions ``x, y, z, w`` (F, J, 4), sign-continuous.
- ``--rate HZ``: resample every file to this rate (times ``0, 1/HZ, ...`` up to its last
  frame, as :func:`core.edits.clip.resample` counts them): positions linearly, quaternions by
  normalised linear interpolation.
- Work runs file by file in ``--jobs`` processes or on a Dask cluster (``--scheduler``,
  :mod:`core.batch.workers`); results come back in file order, a few at a time, and are
  written as they arrive, so memory holds a handful of files, never the dataset.
- ``.npz``: per file ``i`` (in ``files`` order) ``values_i`` float32 (F, J, 3|4) and
  ``joints_i`` (J,) str; then ``files`` (N,) relative paths, ``frame_rate`` (N,) and
  ``quantity``. ``.parquet`` (pyarrow, extra ``cluster``): one row per file, frame and joint,
  columns ``file, frame, time, joint`` and ``x, y, z`` or ``qx, qy, qz, qw`` (float32), one row
  group per file. Either is written to a temporary name and renamed when complete.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import tempfile
import zipfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from gmr_studio.core.batch import workers
from gmr_studio.core.batch.files import find_motion_files
from gmr_studio.core.cli.batch import input_suffixes
from gmr_studio.core.cli.convert import ConvertOptions, positive_number, read_for_conversion
from gmr_studio.core.cli.progress import Progress
from gmr_studio.core.cli.reading import add_gltf_options
from gmr_studio.core.errors import MotionFileError, OperationError
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.rotations.continuity import continuous_quaternions
from gmr_studio.core.rotations.quaternions import quaternion_from_matrix
from gmr_studio.core.timebase.sampling import interpolate, interpolate_rotations, resample_grid

QUANTITIES = ("positions", "rotations")
COLUMNS = {"positions": ("x", "y", "z"), "rotations": ("qx", "qy", "qz", "qw")}


def register(parser: argparse.ArgumentParser) -> None:
    parser.description = __doc__.split("\n\n")[0] if __doc__ else None
    parser.add_argument("input", help="a folder of motion files (searched recursively)")
    parser.add_argument("-o", "--output", required=True, help="OUT.npz or OUT.parquet")
    parser.add_argument("--quantity", choices=QUANTITIES, default="positions", help="what to export (positions)")
    parser.add_argument("--rate", type=positive_number, help="resample every file to this many frames per second")
    parser.add_argument("--jobs", type=int, default=None, help="parallel processes (default: all cores)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:8786|local:N", help="run on a Dask cluster")
    parser.add_argument("--asf", help="skeleton of .amc inputs (default: the .asf beside each AMC)")
    parser.add_argument("--body-model", help="the SMPL/SMPL-H/SMPL-X model (.npz/.pkl) of AMASS .npz inputs")
    add_gltf_options(parser)
    parser.set_defaults(run=run)


def file_values(
    source: str, quantity: str, rate: float | None, options: ConvertOptions
) -> tuple[tuple[str, ...], np.ndarray, float]:
    """(joint names, values (F, J, 3|4) float32, frame rate) of one file."""
    motion = read_for_conversion(source, options)
    at = None if rate is None else resample_grid(motion.n_frames, motion.frame_time, rate)
    if quantity == "positions":
        values = forward_kinematics(motion, with_rotations=False)[0]
        if at is not None:
            values = interpolate(values, at)
    else:
        world = forward_kinematics(pre_from_post(motion))[1]
        if at is not None:
            world = interpolate_rotations(world, at)
        values = continuous_quaternions(quaternion_from_matrix(world, scalar_last=True))
    return motion.names, values.astype(np.float32), motion.frame_rate if rate is None else rate


def _dataset_task(source: str, quantity: str, rate: float | None, options: ConvertOptions):
    """One file, in a worker: (ok, error line, (names, values, frame rate) or None). Never raises."""
    try:
        return True, "", file_values(source, quantity, rate, options)
    except MotionFileError as exc:
        return False, str(exc), None
    except (OperationError, OSError, ValueError) as exc:
        return False, f"{source}: {exc}", None
    except Exception as exc:  # one bad file must not stop the dataset
        return False, f"{source}: {type(exc).__name__}: {exc}", None


@contextlib.contextmanager
def atomic_target(target: Path) -> Iterator[Path]:
    """A temporary path beside ``target``, renamed over it when the block succeeds and
    removed if it fails (the streaming counterpart of :mod:`core.atomic`)."""
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    temporary = Path(name)
    try:
        yield temporary
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


class NpzTable:
    """Writes the ``.npz`` layout entry by entry (module docstring)."""

    def __init__(self, path: Path, quantity: str) -> None:
        self.archive = zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED, allowZip64=True)
        self.quantity = quantity
        self.files: list[str] = []
        self.rates: list[float] = []

    def _array(self, key: str, array: np.ndarray) -> None:
        info = zipfile.ZipInfo(f"{key}.npy", date_time=(1980, 1, 1, 0, 0, 0))
        with self.archive.open(info, "w", force_zip64=True) as handle:
            np.lib.format.write_array(handle, np.asanyarray(array), allow_pickle=False)

    def add(self, relative: str, names: tuple[str, ...], values: np.ndarray, frame_rate: float) -> None:
        i = len(self.files)
        self._array(f"values_{i}", values)
        self._array(f"joints_{i}", np.array(names))
        self.files.append(relative)
        self.rates.append(frame_rate)

    def close(self) -> None:
        self._array("files", np.array(self.files, dtype=str))
        self._array("frame_rate", np.array(self.rates, dtype=np.float64))
        self._array("quantity", np.array(self.quantity))
        self.archive.close()


class ParquetTable:
    """Writes the long ``.parquet`` layout, one row group per file (module docstring)."""

    def __init__(self, path: Path, quantity: str) -> None:
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise OperationError("parquet output needs pyarrow: pip install 'gmr-studio[cluster]'") from None
        self.pa = pa
        self.columns = COLUMNS[quantity]
        fields = [("file", pa.string()), ("frame", pa.int32()), ("time", pa.float64()), ("joint", pa.string())]
        self.schema = pa.schema(fields + [(c, pa.float32()) for c in self.columns])
        self.writer = pq.ParquetWriter(str(path), self.schema)

    def add(self, relative: str, names: tuple[str, ...], values: np.ndarray, frame_rate: float) -> None:
        n_frames, n_joints = values.shape[:2]
        frames = np.repeat(np.arange(n_frames, dtype=np.int32), n_joints)
        columns = {
            "file": self.pa.array([relative] * (n_frames * n_joints), self.pa.string()),
            "frame": frames,
            "time": frames / frame_rate,
            "joint": self.pa.array(np.tile(np.array(names, dtype=object), n_frames), self.pa.string()),
        }
        flat = values.reshape(n_frames * n_joints, -1)
        columns.update({c: flat[:, k] for k, c in enumerate(self.columns)})
        self.writer.write_table(self.pa.table(columns, schema=self.schema))

    def close(self) -> None:
        self.writer.close()


def build_dataset(
    in_dir: Path,
    output: Path,
    *,
    quantity: str = "positions",
    rate: float | None = None,
    options: ConvertOptions | None = None,
    jobs: int | None = None,
    scheduler: str | None = None,
    stream=None,
) -> int:
    """Write the dataset of every motion file under ``in_dir``; 1 if any file failed, else 0."""
    stream = stream or sys.stderr
    options = options or ConvertOptions()
    suffix = output.suffix.lower()
    if suffix not in (".npz", ".parquet"):
        raise OperationError(f"the dataset is written as .npz or .parquet, not '{output.suffix}'")
    if not in_dir.is_dir():
        raise OperationError(f"{in_dir} is not a folder")
    suffixes = input_suffixes(options)
    files = [f for f in find_motion_files(in_dir, None, suffixes) if f.resolve() != output.resolve()]
    if not files:
        raise OperationError(f"no motion files ({', '.join(suffixes)}) under {in_dir}")
    jobs = workers.default_jobs(jobs, len(files))
    progress = Progress(len(files), stream, label="dataset")
    frames = 0
    tasks = ((str(f), quantity, rate, options) for f in files)
    try:
        with atomic_target(output) as temporary:
            table = (NpzTable if suffix == ".npz" else ParquetTable)(temporary, quantity)
            try:
                results = workers.ordered_results(_dataset_task, tasks, jobs=jobs, scheduler=scheduler)
                for source, (ok, error, result) in zip(files, results):
                    if ok:
                        names, values, frame_rate = result
                        table.add(str(source.relative_to(in_dir)), names, values, frame_rate)
                        frames += values.shape[0]
                    else:
                        progress.message(error)
                    progress.advance(ok)
            finally:
                table.close()
    finally:
        progress.close()
    written = progress.done - progress.failed
    summary = (
        f"wrote {quantity} of {written} of {len(files)} files ({frames} frames) to {output} in "
        f"{progress.seconds:.1f} s ({workers.describe(jobs, scheduler)})"
    )
    stream.write(summary + (f"; {progress.failed} failed" if progress.failed else "") + "\n")
    return 1 if progress.failed else 0


def run(args: argparse.Namespace) -> int:
    options = ConvertOptions(asf=args.asf, body_model=args.body_model, animation=args.animation, skin=args.skin)
    return build_dataset(
        Path(args.input),
        Path(args.output),
        quantity=args.quantity,
        rate=args.rate,
        options=options,
        jobs=args.jobs,
        scheduler=args.scheduler,
    )
