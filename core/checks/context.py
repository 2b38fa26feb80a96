"""What every check reads (:class:`CheckData`) and the run helpers that turn per-frame masks
into findings."""

from __future__ import annotations

import dataclasses
import threading
from functools import cached_property

import numpy as np

from gmr_studio.core.analysis.contacts import contact_runs
from gmr_studio.core.checks.model import Finding
from gmr_studio.core.checks.passes import second_differences
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.up_axis import axis_index, up_axis_of

#: ``Finding.units`` of lengths when the file does not state its unit
FILE_UNITS = "file units"


def units_name(motion: Motion) -> str:
    """The name of the length unit a motion's file states, else ``"file units"``."""
    return FILE_UNITS if motion.facts.unit is None else motion.facts.unit.name


@dataclasses.dataclass(frozen=True, eq=False)
class CheckData:
    """A motion and its world positions, with the scales the thresholds are relative to.

    Attributes
    ----------
    motion : the motion in its own convention (``frame_slice`` of the file's, see ``first``).
    positions : (F, J, 3) world positions of ``motion``.
    size : :attr:`Motion.size` of the whole motion (file units).
    first : the frame number, in the file, of ``motion``'s frame 0.
    """

    motion: Motion
    positions: np.ndarray
    size: float
    first: int = 0
    #: results shared by several checks (contacts, same-pose runs), keyed by what they used
    shared: dict = dataclasses.field(default_factory=dict, repr=False)
    #: a lock per key of ``shared``: checks run side by side compute each result once
    locks: dict = dataclasses.field(default_factory=dict, repr=False)

    def cached(self, key, compute):
        """``compute()``, once per ``key`` for this data (whichever check asks first; the
        others wait for it)."""
        with self.locks.setdefault(key, threading.Lock()):
            if key not in self.shared:
                self.shared[key] = compute()
        return self.shared[key]

    @property
    def frame_time(self) -> float:
        return self.motion.frame_time

    @property
    def n_frames(self) -> int:
        return self.positions.shape[0]

    @cached_property
    def up(self) -> int:
        """1 (Y) or 2 (Z): the column of the motion's up axis (:func:`core.space.up_axis.up_axis_of`)."""
        return axis_index(up_axis_of(self.motion))

    @cached_property
    def _second_differences(self) -> tuple[np.ndarray, np.ndarray]:
        return second_differences(self.positions)

    @property
    def deviations(self) -> np.ndarray:
        """(F-2, J): the lengths of the middles ``P_f - (P_{f-1} + P_{f+1}) / 2`` of frames
        1..F-2 (half the second difference, :mod:`.spikes`;
        :func:`core.checks.passes.second_differences`)."""
        return self._second_differences[0]

    @property
    def middle_products(self) -> np.ndarray:
        """(F-3, J): the dot products of the middles of consecutive frames (row i: frames
        i..i+3)."""
        return self._second_differences[1]

    @cached_property
    def units(self) -> str:
        return units_name(self.motion)

    def finding(self, kind: str, joints, start: int, end: int, level: int, value: float, units: str) -> Finding:
        """A finding at this data's frames ``start..end`` (shifted to the file's frames);
        ``level`` 1 (info) to 3 (error)."""
        if not 1 <= int(level) <= 3:
            raise ValueError(f"a {kind} finding needs a severity level of 1 to 3, not {level}")
        joints = tuple(int(j) for j in joints)
        return Finding(
            kind=kind,
            joints=joints,
            names=tuple(self.motion.names[j] for j in joints),
            start=int(start) + self.first,
            end=int(end) + self.first,
            severity=("info", "warning", "error")[int(level) - 1],
            value=float(value),
            units=units,
        )


def runs(mask: np.ndarray) -> np.ndarray:
    """Runs of True in a (N,) bool mask: (R, 2) int64 half-open ``[start, stop)``."""
    return contact_runs(mask)


def joint_runs(mask: np.ndarray) -> np.ndarray:
    """Runs of True in each column of an (N, J) bool mask: (R, 3) int64 rows
    ``[joint, start, stop)``, ordered by joint then start."""
    n, n_joints = mask.shape
    padded = np.zeros((n_joints, n + 2), np.int8)
    padded[:, 1:-1] = mask.T
    edges = np.diff(padded, axis=1)
    joints, starts = np.nonzero(edges == 1)
    stops = np.nonzero(edges == -1)[1]
    return np.stack([joints, starts, stops], axis=1).astype(np.int64)


def merge_runs(found: np.ndarray, gap: int) -> np.ndarray:
    """(R, 2) half-open runs, sorted, with runs at most ``gap`` apart joined: (R', 2)."""
    if len(found) < 2:
        return found
    breaks = np.flatnonzero(found[1:, 0] - found[:-1, 1] > gap)
    first = np.concatenate([[0], breaks + 1])
    last = np.concatenate([breaks, [len(found) - 1]])
    return np.stack([found[first, 0], found[last, 1]], axis=1)
