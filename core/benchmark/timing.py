"""Timing and memory helpers: best of N (the least disturbed run), with the median kept
to show how noisy the machine was."""

from __future__ import annotations

import dataclasses
import statistics
import time
import tracemalloc
from collections.abc import Callable


@dataclasses.dataclass(frozen=True)
class Timing:
    """Seconds of each run of one timed call."""

    runs: tuple[float, ...]

    @property
    def best(self) -> float:
        return min(self.runs)

    @property
    def median(self) -> float:
        return statistics.median(self.runs)

    @property
    def noise(self) -> float:
        """(median - best) / best: 0 on a quiet machine."""
        return self.median / self.best - 1.0 if self.best > 0 else 0.0

    def us_per_frame(self, frames: int) -> float:
        return self.best / max(frames, 1) * 1e6


def time_call(function: Callable[[], object], repeat: int) -> Timing:
    """Run ``function`` ``repeat`` times (at least once) and keep every duration."""
    return time_returning(function, repeat, keep=False)[0]


def time_returning(function: Callable[[], object], repeat: int, *, keep: bool = True) -> tuple[Timing, object]:
    """Like :func:`time_call`, also returning the last run's result (None unless ``keep``:
    a result held across runs is one more output in memory while the next run allocates)."""
    runs, result = [], None
    for _ in range(max(1, repeat)):
        start = time.perf_counter()
        value = function()
        runs.append(time.perf_counter() - start)
        result = value if keep else None
        del value
    return Timing(tuple(runs)), result


def peak_memory(function: Callable[[], object]) -> int:
    """Bytes allocated at the peak while ``function`` ran, above what was held before
    (tracemalloc: numpy reports its array buffers to it)."""
    was_tracing = tracemalloc.is_tracing()
    if not was_tracing:
        tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        tracemalloc.reset_peak()
        function()
        return tracemalloc.get_traced_memory()[1] - before
    finally:
        if not was_tracing:
            tracemalloc.stop()


def time_interleaved(functions: dict[str, Callable[[], object]], repeat: int) -> dict[str, Timing]:
    """Time several calls in alternation, ``repeat`` rounds: a burst of load from other
    jobs then hits all of them alike instead of one of them."""
    runs: dict[str, list[float]] = {name: [] for name in functions}
    for _ in range(max(1, repeat)):
        for name, function in functions.items():
            start = time.perf_counter()
            function()
            runs[name].append(time.perf_counter() - start)
    return {name: Timing(tuple(values)) for name, values in runs.items()}


def merged(first: Timing, second: Timing) -> Timing:
    """Both sets of runs as one timing."""
    return Timing(first.runs + second.runs)
