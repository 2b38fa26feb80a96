"""The result of a comparison (:class:`Comparison`) and its summaries, JSON and CSV forms."""

from __future__ import annotations

import dataclasses
from functools import cached_property

import numpy as np

from gmr_studio.core.compare.align import Alignment
from gmr_studio.core.table import csv_text


@dataclasses.dataclass(frozen=True, eq=False)
class ErrorSummary:
    """Statistics of one (F, J) error array (NaN = not compared), in its unit.

    mean (the MPJPE for positions), median, p95 over every compared (frame, joint); max with
    its frame (A's 0-based index) and joint (A's name); count of compared samples.
    per_joint_mean, per_joint_max (J,), per_joint_max_frame (J,) int (-1: never compared);
    per_frame (F,) mean over the joints of each frame.
    """

    mean: float
    median: float
    p95: float
    max: float
    max_frame: int
    max_joint: str
    count: int
    per_joint_mean: np.ndarray
    per_joint_max: np.ndarray
    per_joint_max_frame: np.ndarray
    per_frame: np.ndarray


def summarize(errors: np.ndarray, frames: np.ndarray, names: tuple[str, ...]) -> ErrorSummary:
    """Summary of errors (F, J); frames (F,) A's indices; names (J,) A's joint names."""
    finite = np.isfinite(errors)
    everywhere = bool(finite.all())
    values = errors.ravel() if everywhere else errors[finite]
    count = int(values.size)
    with np.errstate(invalid="ignore", divide="ignore"):
        if everywhere:
            per_joint_mean = errors.mean(axis=0) if len(errors) else np.full(errors.shape[1], np.nan)
            per_frame = errors.mean(axis=1) if errors.shape[1] else np.full(len(errors), np.nan)
            masked = errors
        else:
            zeroed = np.where(finite, errors, 0.0)
            per_joint_mean = zeroed.sum(axis=0) / finite.sum(axis=0)
            per_frame = zeroed.sum(axis=1) / finite.sum(axis=1)
            masked = np.where(finite, errors, -np.inf)
    if errors.size:
        # along rows of the transposed copy: numpy's argmax along axis 0 is twice as slow
        rows = np.ascontiguousarray(masked.T).argmax(axis=1)
        per_joint_max = masked[rows, np.arange(errors.shape[1])]
    else:
        rows, per_joint_max = np.zeros(errors.shape[1], dtype=np.int64), np.full(errors.shape[1], -np.inf)
    seen = np.isfinite(per_joint_max)
    per_joint_max = np.where(seen, per_joint_max, np.nan)
    per_joint_max_frame = np.where(seen, frames[rows] if len(frames) else -1, -1).astype(np.int64)
    if not count:
        nan = float("nan")
        per_joint = (per_joint_mean, per_joint_max, per_joint_max_frame)
        return ErrorSummary(nan, nan, nan, nan, -1, "", 0, *per_joint, per_frame)
    median, p95 = quantiles(values, (0.5, 0.95), overwrite=not everywhere)
    worst = int(np.nanargmax(per_joint_max))
    return ErrorSummary(
        mean=float(values.mean()),
        median=float(median),
        p95=float(p95),
        max=float(per_joint_max[worst]),
        max_frame=int(per_joint_max_frame[worst]),
        max_joint=names[worst],
        count=count,
        per_joint_mean=per_joint_mean,
        per_joint_max=per_joint_max,
        per_joint_max_frame=per_joint_max_frame,
        per_frame=per_frame,
    )


def quantiles(values: np.ndarray, q: tuple[float, ...], *, overwrite: bool = False) -> tuple[float, ...]:
    """``np.quantile(values, q)`` (its default, linear method: the same numbers) of finite
    values (N,), N >= 1, with fewer passes.

    ``np.quantile`` partitions a copy at every index it needs (both neighbours of each
    quantile, the first and the last) at once, which costs three times a partition at one
    index. Here each lower neighbour is found by a partition at that index alone, of the part
    left of the previous one, and the upper neighbour as the minimum of what lies between.
    ``overwrite``: values may be reordered (no copy is made).
    """
    n = values.size
    virtual = (n - 1) * np.asarray(q, dtype=np.float64)
    previous = np.floor(virtual)
    gamma = virtual - previous
    above = virtual >= n - 1  # np.quantile takes the largest value there
    low = np.where(above, n - 1, previous).astype(np.int64)
    high = np.where(above, n - 1, low + 1)
    work = values.reshape(-1) if overwrite else values.ravel().copy()
    order: dict[int, float] = {}
    end = n  # work[:end] holds the values up to order[end]
    for k in sorted(set(low.tolist()), reverse=True):
        part = work[:end]
        part.partition(k)
        order[k] = float(part[k])
        if k + 1 < end:
            order[k + 1] = float(part[k + 1 :].min())
        end = k
    result = []
    for a_index, b_index, t in zip(low.tolist(), high.tolist(), gamma.tolist()):
        a, b = order[a_index], order[b_index]
        # numpy's _lerp, operation by operation
        result.append(b - (b - a) * (1 - t) if t >= 0.5 else a + (b - a) * t)
    return tuple(result)


@dataclasses.dataclass(frozen=True, eq=False)
class Comparison:
    """B compared with A, on A's frames and in A's space. ``F`` compared frames, ``J`` pairs.

    names_a, names_b : the J matched joints, A's name and B's. index_a, index_b : (J,) their
    indices in each side. unmatched_a, unmatched_b : names left over.
    frames : (F,) int64, A's 0-based frame indices compared; times : (F,) seconds on A's clock.
    positions_a : (F, J, 3) A's joints; positions_b : (F, J, 3) B's matches after the
    alignment (units, up axis, fit, clock), in A's units.
    position_error : (F, J) float64 distance, A's units; NaN where a side has a gap or B
    has no sample (outside its time range).
    rotation_error : (F, J) float64 degrees, the geodesic angle between the world rotations
    (GMR convention), NaN where a side has none (roots, markers); None when a side has no
    rotations at all.
    alignment : how B was put on A's clock and in A's space (always filled in).
    units : A's length unit as stated, or None. size_a : A's size, in its units.
    """

    names_a: tuple[str, ...]
    names_b: tuple[str, ...]
    index_a: np.ndarray
    index_b: np.ndarray
    unmatched_a: list[str]
    unmatched_b: list[str]
    frames: np.ndarray
    times: np.ndarray
    positions_a: np.ndarray
    positions_b: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray | None
    alignment: Alignment
    units: str | None
    size_a: float
    label_a: str = ""
    label_b: str = ""

    @property
    def n_frames(self) -> int:
        return len(self.frames)

    @property
    def n_pairs(self) -> int:
        return len(self.names_a)

    @property
    def units_text(self) -> str:
        return self.units or "file units"

    @cached_property
    def position(self) -> ErrorSummary:
        return summarize(self.position_error, self.frames, self.names_a)

    @cached_property
    def rotation(self) -> ErrorSummary | None:
        if self.rotation_error is None:
            return None
        return summarize(self.rotation_error, self.frames, self.names_a)

    def row_of_frame(self, frame_a: int) -> int | None:
        """The row of A's frame ``frame_a`` in the (F, J) arrays, or None if not compared."""
        row = int(np.searchsorted(self.frames, frame_a))
        return row if row < len(self.frames) and self.frames[row] == frame_a else None

    def to_json(self) -> dict:
        """The JSON document of ``gmr compare --json`` (docs/compare.md); NaN -> null."""
        p, r = self.position, self.rotation
        joints = []
        for j, (name, match) in enumerate(zip(self.names_a, self.names_b)):
            row = {
                "name": name,
                "match": match,
                "mean": _num(p.per_joint_mean[j]),
                "max": _num(p.per_joint_max[j]),
                "max_frame": int(p.per_joint_max_frame[j]) if p.per_joint_max_frame[j] >= 0 else None,
            }
            if r is not None:
                row["rotation_mean_deg"] = _num(r.per_joint_mean[j])
                row["rotation_max_deg"] = _num(r.per_joint_max[j])
            joints.append(row)
        document = {
            "a": self.label_a,
            "b": self.label_b,
            "units": self.units_text,
            "size_a": self.size_a,
            "frames": self.n_frames,
            "first_frame": int(self.frames[0]) if self.n_frames else None,
            "last_frame": int(self.frames[-1]) if self.n_frames else None,
            "compared": p.count,
            "mpjpe": _num(p.mean),
            "median": _num(p.median),
            "p95": _num(p.p95),
            "max": {"value": _num(p.max), "frame": p.max_frame if p.count else None, "joint": p.max_joint or None},
            "joints": joints,
            "unmatched_a": list(self.unmatched_a),
            "unmatched_b": list(self.unmatched_b),
            "alignment": self.alignment.to_json(),
        }
        if r is not None:
            document["rotation"] = {
                "mean_deg": _num(r.mean),
                "median_deg": _num(r.median),
                "p95_deg": _num(r.p95),
                "max": {"value": _num(r.max), "frame": r.max_frame if r.count else None, "joint": r.max_joint or None},
            }
        return document

    def to_csv(self) -> str:
        """One row per compared frame: ``frame,time,mpjpe``, then each joint's position error
        (column named by A's joint) and, with rotations, each joint's angle (``NAME deg``)."""
        columns = ["frame", "time", "mpjpe", *self.names_a]
        blocks = [self.frames[:, None], self.times[:, None], self.position.per_frame[:, None], self.position_error]
        if self.rotation_error is not None:
            columns += [f"{n} deg" for n in self.names_a]
            blocks.append(self.rotation_error)
        table = np.concatenate([np.asarray(b, dtype=np.float64) for b in blocks], axis=1)
        return csv_text(columns, table, ["%d", "%.6f", "%.9g"])


def _num(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None
