"""One benchmark run: parse, BVH baseline, yardstick, C_1..C_J, operations, peers, memory.

Every figure is the best of ``repeat`` runs (the least disturbed one; the median is kept
to show the noise). Two variants of every FK timing, starting from:

- **matrices**: the local rotations as cached at load, ``Motion.rotations`` (F, J, 3, 3);
- **euler**: the Euler angles as a file stores them, (F, J, 3) radians (recovered once
  from the matrices, untimed; equal to the file's values to rounding), turned into
  matrices inside the timed call, only for the joints whose rotation FK reads.

The BVH baseline runs the same engine (same kernel, same care) on the post-rotation
motion; the yardstick is ``positions.copy()`` of the (F, J, 3) output, a memory-bound
pass that any FK must at least make.
"""

from __future__ import annotations

import dataclasses
import io
import os
import platform
import resource
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from gmr_studio.core.benchmark.configs import random_root_sets, with_roots
from gmr_studio.core.benchmark.data import build_benchmark_data
from gmr_studio.core.benchmark.peers import run_peers
from gmr_studio.core.benchmark.timing import merged, peak_memory, time_call, time_interleaved, time_returning
from gmr_studio.core.edits.operations import join, shift_root, split
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.kinematics.fk import reference_forward_kinematics


@dataclasses.dataclass(frozen=True)
class BenchOptions:
    """What ``gmr bench`` was asked for."""

    folders: tuple[Path, ...]
    frames: int = 100_000
    seed: int = 6
    instances: int = 10
    repeat: int = 5
    peer_frames: int = 1000
    peers: bool = True

    @property
    def repeat_config(self) -> int:
        """Runs per configuration instance (there are J x instances of them)."""
        return max(1, min(self.repeat, 3))


def machine() -> dict:
    """CPU model, cores, Python and library versions, the FK backend."""
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        cpu = platform.processor() or "unknown"
    info = {
        "cpu": cpu,
        "cores": len(os.sched_getaffinity(0)),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "platform": platform.platform(),
        "fk_backend": "numba" if fk_engine.have_numba() else "numpy",
    }
    if fk_engine.have_numba():
        import numba

        info["numba"] = numba.__version__
    return info


def _per_frame(seconds: float, frames: int) -> float:
    return seconds / max(frames, 1) * 1e6


def run_benchmark(options: BenchOptions, log: Callable[[str], None] = print) -> dict:
    """Run everything; returns the results (the JSON document, see core.benchmark)."""
    result: dict = {"machine": machine(), "seed": options.seed, "repeat": options.repeat}
    with tempfile.TemporaryDirectory(prefix="gmr-bench-") as folder:
        data = build_benchmark_data(list(options.folders), options.frames, Path(folder))
        post, gmr = data.post, data.gmr
        frames, joints = post.n_frames, post.n_joints
        result.update(frames=frames, joints=joints, frame_rate=120.0, size=gmr.size)
        result["sources"] = [
            {"path": str(s.path), "frames": s.frames, "joints": s.joints, "included": s.included, "note": s.note}
            for s in data.sources
        ]
        log(f"motion: {frames} frames x {joints} joints, {data.file_bytes / 1e6:.1f} MB of BVH text")
        for s in data.sources:
            state = "in" if s.included else "left out"
            log(f"  {s.path} ({s.frames} frames, {s.joints} joints, {1 / s.frame_time:.0f} fps): {state} {s.note}")

        log("parsing ...")
        parsing = time_interleaved(
            {
                "parse": lambda: read_bvh(data.path),
                "numpy_parse": lambda: np.loadtxt(io.BytesIO(data.block), dtype=np.float64, comments=None, ndmin=2),
            },
            options.repeat,
        )
        parse, numpy_parse = parsing["parse"], parsing["numpy_parse"]
        result["parse_mb_per_s"] = data.file_bytes / parse.best / 1e6
        result["numpy_parse_mb_per_s"] = data.block_bytes / numpy_parse.best / 1e6
        result["parse_ms"] = parse.best * 1e3
        result["numpy_parse_ms"] = numpy_parse.best * 1e3

        log("BVH baseline and yardstick ...")
        positions = fk_engine.world_positions(post)
        post_angles = fk_engine.euler_angles(post)
        baselines = {
            "yardstick": positions.copy,
            "bvh": lambda: fk_engine.world_positions(post),
            "bvh_euler": lambda: fk_engine.positions_from_euler(post, post_angles),
            "single_root": lambda: fk_engine.world_positions(gmr),
            "single_root_threads": lambda: fk_engine.world_positions(gmr, threads=None),
        }
        timings = time_interleaved(baselines, options.repeat)
        reference_bvh, (reference, _) = time_returning(
            lambda: reference_forward_kinematics(post, with_rotations=False), 1
        )
        reference_gmr = time_call(lambda: reference_forward_kinematics(gmr, with_rotations=False), 1)
        result.update(
            reference_bvh_us_per_frame=reference_bvh.us_per_frame(frames),
            reference_gmr_us_per_frame=reference_gmr.us_per_frame(frames),
        )
        result["engine_vs_reference_error"] = float(np.abs(positions - reference).max() / gmr.size)
        del reference

        log("memory ...")
        rotations_bytes = frames * joints * 9 * 8
        result["memory"] = {
            "rotations_array_mb": rotations_bytes / 1e6,
            "positions_peak_mb": peak_memory(lambda: fk_engine.world_positions(gmr)) / 1e6,
            "positions_and_rotations_peak_mb": peak_memory(lambda: fk_engine.forward_kinematics(gmr)) / 1e6,
            "positions_from_euler_peak_mb": peak_memory(lambda: fk_engine.positions_from_euler(post, post_angles))
            / 1e6,
        }

        log(f"configurations C_1 .. C_{joints}, {options.instances} instances each ...")
        result["configs"] = _configurations(gmr, positions, options, baselines, timings, log)
        result.update(
            bvh_us_per_frame=timings["bvh"].us_per_frame(frames),
            bvh_euler_us_per_frame=timings["bvh_euler"].us_per_frame(frames),
            yardstick_us_per_frame=timings["yardstick"].us_per_frame(frames),
            single_root_us_per_frame=timings["single_root"].us_per_frame(frames),
            single_root_threads_us_per_frame=timings["single_root_threads"].us_per_frame(frames),
            threads=os.cpu_count() or 1,
            baseline_runs={name: len(t.runs) for name, t in timings.items()},
            noise={name: t.noise for name, t in timings.items()}
            | {"parse": parse.noise, "numpy_parse": numpy_parse.noise},
        )

        log("operations on the whole motion ...")
        result["operations"] = _operations(gmr, options.repeat)

        result["peers"] = []
        if options.peers:
            log("peers ...")
            short = Path(folder) / "peers-short.bvh"
            text = data.path.read_bytes()
            head = text[: len(text) - data.block_bytes]
            lines = [line for line in data.block.split(b"\n") if line][: options.peer_frames]
            short.write_bytes(
                head.replace(b"Frames: %d" % frames, b"Frames: %d" % len(lines)) + b"\n".join(lines) + b"\n"
            )
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                peers = run_peers(data.path, short, positions, post.names, gmr.size, options.repeat,
                                  options.peer_frames, log)  # fmt: skip
            result["peers"] = [dict(dataclasses.asdict(p), agrees=p.agrees()) for p in peers]
    result["max_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3
    return result


def _configurations(gmr, base_positions, options, baselines, timings, log) -> list[dict]:
    """Time C_1..C_J; the baselines are timed again (interleaved, once) at every k, and
    ``timings`` (updated in place) keeps all their runs: the ratios use the best run of
    the whole benchmark for every side."""
    rng = np.random.default_rng(options.seed)
    frames, joints = gmr.n_frames, gmr.n_joints
    raw = []
    for k in range(1, joints + 1):
        matrices, eulers, errors = [], [], []
        for roots in random_root_sets(joints, k, options.instances, rng):
            config = with_roots(gmr, roots)
            timing, out = time_returning(lambda config=config: fk_engine.world_positions(config), options.repeat_config)
            errors.append(float(np.abs(out - base_positions).max()))
            del out
            angles = fk_engine.euler_angles(config, fk_engine.FKPlan.of(config, False).needs_rotation())
            euler = time_call(lambda c=config, a=angles: fk_engine.positions_from_euler(c, a), options.repeat_config)
            matrices.append(timing.best)
            eulers.append(euler.best)
            del config, angles
        for name, again in time_interleaved(baselines, 1).items():
            timings[name] = merged(timings[name], again)
        raw.append((k, matrices, eulers, errors))
        log(
            f"  C_{k:<3d}{_per_frame(float(np.mean(matrices)), frames):8.3f} us/frame (rotations cached), "
            f"{_per_frame(float(np.mean(eulers)), frames):8.3f} us/frame (from Euler angles)"
        )
    bvh, bvh_euler, yardstick = (timings[name].best for name in ("bvh", "bvh_euler", "yardstick"))
    rows = []
    for k, matrices, eulers, errors in raw:
        mean, euler_mean = float(np.mean(matrices)), float(np.mean(eulers))
        rows.append(
            {
                "k": k,
                "us_per_frame": _per_frame(mean, frames),
                "min_us_per_frame": _per_frame(min(matrices), frames),
                "max_us_per_frame": _per_frame(max(matrices), frames),
                "ratio_to_bvh": bvh / mean,
                "ratio_to_yardstick": mean / yardstick,
                "euler_us_per_frame": _per_frame(euler_mean, frames),
                "euler_ratio_to_bvh": bvh_euler / euler_mean,
                "max_position_error": max(errors) / gmr.size,
            }
        )
    return rows


def _operations(gmr, repeat: int) -> dict:
    """Seconds for shift root (to the deepest joint), split and join (a mid-depth joint)."""
    deepest = int(np.argmax(gmr.depths))
    path = gmr.path_from_root(deepest)
    middle = path[len(path) // 2]
    shifted = time_call(lambda: shift_root(gmr, deepest), max(1, repeat // 2))
    split_timing = time_call(lambda: split(gmr, middle), max(1, repeat // 2))
    parted = split(gmr, middle)
    join_timing = time_call(lambda: join(parted, middle), max(1, repeat // 2))
    return {
        "shift_root": {"joint": gmr.names[deepest], "seconds": shifted.best},
        "split": {"joint": gmr.names[middle], "seconds": split_timing.best},
        "join": {"joint": gmr.names[middle], "seconds": join_timing.best},
    }
