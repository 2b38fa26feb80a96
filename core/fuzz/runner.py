"""Run fuzz cases in worker processes, each case bounded in time and memory.

Outcomes of a case:

- ``read``: the reader returned a motion or marker set that passes its sanity check;
- ``clean``: the reader raised :class:`~core.errors.MotionFileError` carrying the path, a
  message and (for text formats) a line;
- ``other``: any other exception, an error without its location, a read that returned
  something impossible (NaN from finite input...), or numpy's RuntimeWarning (overflow,
  invalid value) on the way to a read or an error: the reader computed with numbers it had
  not bounded. A bug, each of them;
- ``hang``: the case ran longer than the time bound (the worker is killed);
- ``memory``: the reader tried to allocate beyond the memory bound (a file claiming 10^12
  frames must be refused before allocating);
- ``crash``: the worker process died (a segfault in a compiled reader).

Only ``read`` and ``clean`` are acceptable. Cases are deterministic: (format, seed, index)
regenerates the same bytes (:func:`make_case`).
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import resource
import signal
import sys
import tempfile
import time
import warnings
import zlib
from collections import Counter, deque
from multiprocessing.connection import Connection, wait
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.fuzz.targets import Target, all_targets

ACCEPTABLE = ("read", "clean")
OUTCOMES = ("read", "clean", "other", "hang", "memory", "crash")
BINARY_FORMATS = {"c3d", "gltf", "fbx"}  # errors name a byte or a JSON object (ufbx: neither), not a line


@dataclasses.dataclass(frozen=True)
class Case:
    target: str
    index: int
    seed_file: str
    mutations: tuple[str, ...]
    data: bytes


@dataclasses.dataclass
class CaseResult:
    target: str
    index: int
    outcome: str
    seed_file: str
    mutations: tuple[str, ...]
    detail: str = ""


_CUTS: dict[str, list[tuple[int, int]]] = {}


def structural_cuts(target: Target) -> list[tuple[int, int]]:
    """(seed file, byte offset) of every structural point of every seed file: each line
    start of a text header (and of the first frames), each section of a binary file."""
    if target.name not in _CUTS:
        _CUTS[target.name] = [
            (number, offset) for number, (_, data) in enumerate(target.seeds()) for offset in target.structure(data)
        ]
    return _CUTS[target.name]


def make_case(target: Target, seed: int, index: int) -> Case:
    """The case ``index`` of a run seeded with ``seed``. The first cases truncate each seed
    file at each structural point in turn; the others apply 1 to 3 random mutations."""
    seeds = target.seeds()
    cuts = structural_cuts(target)
    if index < len(cuts):
        number, offset = cuts[index]
        label, data = seeds[number]
        return Case(target.name, index, label, (f"truncate at structural point {offset}",), data[:offset])
    rng = np.random.default_rng([seed, zlib.crc32(target.name.encode()), index])
    label, data = seeds[int(rng.integers(len(seeds)))]
    names = list(target.mutations)
    applied = []
    for _ in range(int(rng.choice([1, 1, 1, 1, 1, 1, 1, 2, 2, 3]))):
        name = names[int(rng.integers(len(names)))]
        data = target.mutations[name](data, rng)
        applied.append(name)
    return Case(target.name, index, label, tuple(applied), data)


def run_case(target: Target, case: Case, folder: Path) -> CaseResult:
    """Read one case and classify what happened."""
    path = folder / f"{target.name}-case{case.index}{target.suffix}"
    if target.needs_file:
        path.write_bytes(case.data)

    def result(outcome: str, detail: str = "") -> CaseResult:
        return CaseResult(case.target, case.index, outcome, case.seed_file, case.mutations, detail[:300])

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        outcome, detail, value = _read(target, case, path)
        if outcome == "read":
            try:
                target.check(value)
            except AssertionError as exc:
                outcome, detail = "other", str(exc)
    numeric = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    if numeric and outcome in ACCEPTABLE:
        # overflow, invalid values...: the reader computed with numbers it had not bounded
        warning = numeric[0]
        return result(
            "other",
            f"{warning.category.__name__} at {Path(warning.filename).name}:{warning.lineno}: "
            f"{warning.message} ({outcome}: {detail})",
        )
    return result(outcome, detail)


def _read(target: Target, case: Case, path: Path) -> tuple[str, str, object]:
    """(outcome, detail, value) of reading one case, before the sanity check."""
    try:
        value = target.read(path, case.data, case.seed_file)
    except MotionFileError as exc:
        if not exc.path or not exc.message:
            return "other", f"MotionFileError without path or message: {exc!r}", None
        if target.name not in BINARY_FORMATS and exc.line is None:
            return "other", f"MotionFileError without a line: {exc}", None
        return "clean", str(exc), None
    except MemoryError as exc:
        return "memory", f"MemoryError {exc}", None
    except Exception as exc:
        return "other", f"{type(exc).__name__}: {exc}", None
    finally:
        if target.needs_file:
            path.unlink(missing_ok=True)
    return "read", "", value


def _address_space_in_use() -> int:
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _worker(connection: Connection, targets: dict[str, Target], seed: int, memory_bytes: int, folder: str) -> None:
    os.setpgrp()  # its own process group: killing a stuck case kills the reader's children too
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    limit = _address_space_in_use() + memory_bytes
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    while True:
        task = connection.recv()
        if task is None:
            return
        name, index = task
        target = targets[name]
        try:
            case = make_case(target, seed, index)
        except Exception as exc:
            connection.send(CaseResult(name, index, "other", "?", (), f"case generation failed: {exc!r}"))
            continue
        connection.send(run_case(target, case, Path(folder)))


@dataclasses.dataclass
class FuzzReport:
    seed: int
    cases_per_target: int
    counts: dict[str, Counter]
    failures: list[CaseResult]
    seconds: float
    unavailable: list[str]

    def table(self) -> str:
        header = f"{'format':<8}{'cases':>8}{'read':>8}{'clean':>8}{'other':>8}{'hang':>6}{'memory':>8}{'crash':>7}"
        lines = [header]
        for name, counts in self.counts.items():
            lines.append(
                f"{name:<8}{sum(counts.values()):>8}"
                + "".join(f"{counts[o]:>{w}}" for o, w in zip(OUTCOMES, (8, 8, 8, 6, 8, 7)))
            )
        return "\n".join(lines)


class _Worker:
    def __init__(self, context, targets, seed, memory_bytes, folder):
        self.connection, child = context.Pipe()
        self.process = context.Process(target=_worker, args=(child, targets, seed, memory_bytes, folder), daemon=True)
        self.process.start()
        child.close()
        self.task: tuple[str, int] | None = None
        self.started = 0.0

    def stop(self, kill: bool = False) -> None:
        if kill:
            try:
                os.killpg(self.process.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                self.process.kill()
        else:
            try:
                self.connection.send(None)
            except (BrokenPipeError, OSError):
                pass
        self.process.join(5)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()


def run_fuzz(
    names: list[str] | None = None,
    cases: int = 10_000,
    seed: int = 0,
    timeout: float = 10.0,
    memory_mb: int = 2048,
    jobs: int | None = None,
    progress=None,
    stride: int = 1,
) -> FuzzReport:
    """Run ``cases`` cases for each target (all available ones by default): the cases
    numbered 0, stride, 2 stride, ... (a stride above 1 samples structural cuts and random
    mutations alike in a short run)."""
    available = all_targets()
    wanted = names or list(available)
    unavailable = [n for n in wanted if n not in available]
    targets = {n: available[n] for n in wanted if n in available}
    for target in targets.values():
        if not target.seeds():
            unavailable.append(f"{target.name} (no seed files: is ../shared/data there?)")
    targets = {n: t for n, t in targets.items() if t.seeds()}
    tasks = deque((name, i * stride) for i in range(cases) for name in targets)
    counts = {name: Counter() for name in targets}
    failures: list[CaseResult] = []
    context = multiprocessing.get_context("fork")
    start = time.perf_counter()
    done = 0
    with tempfile.TemporaryDirectory(prefix="gmr-fuzz-") as folder:
        spawn = lambda: _Worker(context, targets, seed, memory_mb * 2**20, folder)  # noqa: E731
        workers = [spawn() for _ in range(max(1, jobs or os.cpu_count() or 1))]
        try:
            while tasks or any(w.task for w in workers):
                for w in workers:
                    if w.task is None and tasks:
                        w.task, w.started = tasks.popleft(), time.perf_counter()
                        w.connection.send(w.task)
                busy = [w for w in workers if w.task]
                limit = {w: max(timeout, targets[w.task[0]].timeout) for w in busy}
                deadline = min(w.started + limit[w] for w in busy)
                ready = set(wait([w.connection for w in busy], max(0.0, deadline - time.perf_counter())))
                for i, w in enumerate(workers):
                    if w.task is None:
                        continue
                    name, index = w.task
                    outcome = None
                    if w.connection in ready:
                        try:
                            outcome = w.connection.recv()
                        except (EOFError, OSError):
                            outcome = CaseResult(name, index, "crash", "", (), f"worker died ({w.process.exitcode})")
                    elif time.perf_counter() - w.started > limit[w]:
                        outcome = CaseResult(name, index, "hang", "", (), f"no answer within {limit[w]} s")
                    if outcome is None:
                        continue
                    if outcome.outcome in ("crash", "hang"):
                        w.stop(kill=True)
                        workers[i] = w = spawn()
                    w.task = None
                    counts[name][outcome.outcome] += 1
                    if outcome.outcome not in ACCEPTABLE:
                        failures.append(outcome)
                    done += 1
                    if progress and done % 500 == 0:
                        progress(done, len(targets) * cases)
        finally:
            for w in workers:
                w.stop()
    return FuzzReport(seed, cases, counts, failures, time.perf_counter() - start, unavailable)


def replay(name: str, seed: int, index: int) -> tuple[Case, CaseResult]:
    """Regenerate one case and read it in this process (for debugging a failure)."""
    target = all_targets()[name]
    case = make_case(target, seed, index)
    with tempfile.TemporaryDirectory(prefix="gmr-fuzz-") as folder:
        return case, run_case(target, case, Path(folder))


def print_progress(done: int, total: int) -> None:
    print(f"\rfuzz: {done}/{total} cases", end="", file=sys.stderr, flush=True)
