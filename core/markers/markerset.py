"""A set of labelled 3D markers over time, frames first, gaps as NaN.

================  =================  ==================================================
field             shape / type       meaning
================  =================  ==================================================
labels            tuple of M str     marker names, subject prefix removed
positions         (F, M, 3) float64  positions in ``units``; NaN where the marker is
                                     missing (a gap), all three coordinates together
computed          (F, M) bool        samples present but not measured: computed by the
                                     capture software (a C3D residual of 0: its gap
                                     filling, interpolation or filter) or by
                                     :meth:`MarkerSet.filled`; False at gaps
rate              float              frames per second
units             str                length unit of ``positions``: "mm", "cm", "m", "in"
subjects          tuple of M str     the subject prefix split off each label
                                     (``Daphnee:ASISr`` -> "Daphnee"), "" if none
first_frame       int                the file's number for frame 0
source            str                the file read, for messages
notes             tuple of str       what the reader noticed but tolerated
outputs           PointOutputs       model outputs the file stores as points (C3D
                  or None            POINT:ANGLES, FORCES...): not markers, kept apart
parameters        dict str->float    the subject's measurements a C3D stores in its
                                     PROCESSING group (KneeWidth, LAnkleWidth,
                                     MarkerDiameter, LegLength... in mm), {} if none
================  =================  ==================================================

Axes are the file's. Conversions return new marker sets: :meth:`MarkerSet.in_units`,
:meth:`MarkerSet.transformed` (any rotation/permutation, scale and offset, e.g. Z-up to
Y-up), :meth:`MarkerSet.resampled` (another frame rate). Gaps stay gaps unless the user asks
for :meth:`MarkerSet.filled` (linear interpolation of short gaps); :meth:`MarkerSet.gap_table`
describes them. Computed samples are data (the lab's own gap filling, continuous with the
measured samples around it) and kept; :meth:`MarkerSet.without_computed` makes them gaps.
"""

from __future__ import annotations

import dataclasses
from functools import cached_property

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.space.units import unit_factor, unit_named
from gmr_studio.core.space.up_axis import Y_TO_Z
from gmr_studio.core.timebase.clock import duration_of, times_of
from gmr_studio.core.timebase.sampling import interpolate, neighbours, resample_grid

#: metres per unit

#: rotations taking one up axis to another (column vectors): Z-up (x, y, z) -> Y-up (x, z, -y)
Y_UP_TO_Z_UP = Y_TO_Z
Z_UP_TO_Y_UP = Y_TO_Z.T.copy()


def frame_ranges(frames: np.ndarray, limit: int = 8) -> str:
    """Frame numbers as short text: a bool mask (F,) or sorted indices -> ``"3-9, 15, 20-22"``.

    At most ``limit`` ranges are listed, then ``"... (N ranges)"``.
    """
    frames = np.asarray(frames)
    index = np.flatnonzero(frames) if frames.dtype == bool else np.unique(frames.astype(np.int64))
    if index.size == 0:
        return "none"
    breaks = np.flatnonzero(np.diff(index) != 1)
    starts = np.concatenate([[index[0]], index[breaks + 1]])
    ends = np.concatenate([index[breaks], [index[-1]]])
    parts = [f"{a}" if a == b else f"{a}-{b}" for a, b in zip(starts[:limit], ends[:limit])]
    if starts.size > limit:
        parts.append(f"... ({starts.size} ranges)")
    return ", ".join(parts)


def gap_runs(present: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For a presence mask (F, ...), the last present frame at or before each frame and the
    first at or after it (-1 and F where there is none): arrays of the same shape."""
    n_frames = present.shape[0]
    frame = np.arange(n_frames).reshape((-1,) + (1,) * (present.ndim - 1))
    before = np.maximum.accumulate(np.where(present, frame, -1), axis=0)
    after = np.minimum.accumulate(np.where(present, frame, n_frames)[::-1], axis=0)[::-1]
    return before, after


def split_subject(label: str) -> tuple[str, str]:
    """``"Daphnee:ASISr"`` -> ``("Daphnee", "ASISr")``; ``"LASI"`` -> ``("", "LASI")``."""
    subject, sep, name = label.rpartition(":")
    return (subject, name) if sep and name else ("", label)


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class PointOutputs:
    """Analysis outputs a C3D stores among its POINT entries (joint angles, forces, moments,
    powers, scalars of a biomechanical model: ``LHipAngles``, ``RHipMoment_CGM_2.4``...),
    which the standard names in ``POINT:ANGLES``, ``POINT:FORCES``... and ``POINT:TYPE_GROUPS``.
    They are not markers: no marker set, alignment or drawing uses them.

    labels : tuple of N str (subject prefix removed); subjects : tuple of N str.
    kinds : tuple of N str, the group naming each ("angles", "forces", "moments", ...).
    values : (F, N, 3) float64, NaN where invalid, same frames as the markers.
    units : dict kind -> the unit the file gives (POINT:ANGLE_UNITS...), "" if none.
    """

    labels: tuple[str, ...]
    subjects: tuple[str, ...]
    kinds: tuple[str, ...]
    values: np.ndarray
    units: dict = dataclasses.field(default_factory=dict)

    @property
    def n_outputs(self) -> int:
        return len(self.labels)

    def by_kind(self) -> dict[str, list[str]]:
        """kind -> its labels (``subject:label`` where there is a subject), in file order."""
        out: dict[str, list[str]] = {}
        for subject, label, kind in zip(self.subjects, self.labels, self.kinds):
            out.setdefault(kind, []).append(f"{subject}:{label}" if subject else label)
        return out

    def frame_slice(self, frames: slice) -> PointOutputs:
        return dataclasses.replace(self, values=self.values[frames])


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class MarkerSet:
    """Marker trajectories; see the module docstring for the fields."""

    labels: tuple[str, ...]
    positions: np.ndarray
    rate: float
    units: str
    subjects: tuple[str, ...] = ()
    first_frame: int = 1
    source: str = ""
    notes: tuple[str, ...] = ()
    outputs: PointOutputs | None = None
    parameters: dict[str, float] = dataclasses.field(default_factory=dict)
    computed: np.ndarray | None = None

    def __post_init__(self) -> None:
        labels = tuple(str(label) for label in self.labels)
        positions = np.asarray(self.positions, dtype=np.float64)
        if positions.ndim != 3 or positions.shape[1:] != (len(labels), 3):
            raise ValueError(f"positions must have shape (F, {len(labels)}, 3), not {positions.shape}")
        subjects = tuple(self.subjects) or ("",) * len(labels)
        if len(subjects) != len(labels):
            raise ValueError("subjects must give one prefix per label")
        rate = float(self.rate)
        if not np.isfinite(rate) or rate <= 0:
            raise ValueError(f"the frame rate must be a positive number, not {rate}")
        units = unit_named(self.units).name  # ValueError naming the known units
        if self.outputs is not None and self.outputs.values.shape[0] != positions.shape[0]:
            raise ValueError("the analysis outputs must have the markers' frames")
        # a marker is missing as a whole: a NaN in any coordinate makes the sample a gap
        gaps = ~np.isfinite(positions).all(axis=2)
        if gaps.any() and np.isfinite(positions[gaps]).any():
            positions = positions.copy()
            positions[gaps] = np.nan
        view = positions.view()
        view.flags.writeable = False
        if self.computed is None:
            computed = np.zeros(positions.shape[:2], bool)
        else:
            computed = np.asarray(self.computed, dtype=bool)
            if computed.shape != positions.shape[:2]:
                raise ValueError(f"computed must have shape {positions.shape[:2]}, not {computed.shape}")
            computed = computed & ~gaps
        computed.flags.writeable = False
        set_field = object.__setattr__
        set_field(self, "labels", labels)
        set_field(self, "positions", view)
        set_field(self, "computed", computed)
        set_field(self, "subjects", subjects)
        set_field(self, "rate", rate)
        set_field(self, "units", units)
        set_field(self, "notes", tuple(self.notes))

    @property
    def n_frames(self) -> int:
        return self.positions.shape[0]

    @property
    def n_markers(self) -> int:
        return self.positions.shape[1]

    @property
    def frame_time(self) -> float:
        return 1.0 / self.rate

    @property
    def times(self) -> np.ndarray:
        """(F,) seconds from the first frame (:mod:`core.timebase.clock`)."""
        return times_of(self)

    @property
    def duration(self) -> float:
        """Seconds the frames last: frames x frame time (:mod:`core.timebase.clock`)."""
        return duration_of(self)

    @cached_property
    def present(self) -> np.ndarray:
        """(F, M) bool: the marker was seen in that frame."""
        return np.isfinite(self.positions[..., 0])

    def index(self, label: str) -> int:
        """Index of a marker, by bare label or ``subject:label``; OperationError if absent."""
        subject, bare = split_subject(label)
        for m, (s, name) in enumerate(zip(self.subjects, self.labels)):
            if name == bare and (not subject or subject == s):
                return m
        raise OperationError(f"no marker {label!r} in {self.source or 'the marker set'}")

    @property
    def measured(self) -> np.ndarray:
        """(F, M) bool: present and not computed (seen by the cameras)."""
        return self.present & ~self.computed

    def replace(self, **changes) -> MarkerSet:
        """A copy with ``changes``. New ``positions`` of another shape need their own
        ``computed`` mask unless no sample was computed (the mask then starts empty)."""
        positions = changes.get("positions")
        if "computed" not in changes and positions is not None and np.shape(positions)[:2] != self.computed.shape:
            if self.computed.any():
                raise ValueError("positions of another shape need their computed mask (F, M)")
            changes["computed"] = None
        return dataclasses.replace(self, **changes)

    def select(self, labels: list[str]) -> MarkerSet:
        """Only the named markers, in the order given."""
        index = [self.index(label) for label in labels]
        return self.replace(
            labels=[self.labels[m] for m in index],
            subjects=[self.subjects[m] for m in index],
            positions=self.positions[:, index],
            computed=self.computed[:, index],
        )

    def frame_slice(self, frames: slice) -> MarkerSet:
        start = range(self.n_frames)[frames].start if self.n_frames else 0
        outputs = self.outputs.frame_slice(frames) if self.outputs is not None else None
        return self.replace(
            positions=self.positions[frames],
            computed=self.computed[frames],
            first_frame=self.first_frame + start,
            outputs=outputs,
        )

    def without_computed(self) -> MarkerSet:
        """The computed samples made gaps (only what the cameras measured is left), with a
        note counting them."""
        count = int(self.computed.sum())
        if not count:
            return self
        positions = np.where(self.computed[..., None], np.nan, self.positions)
        note = f"{count} computed samples (not measured: the capture software's gap filling) read as gaps"
        return self.replace(positions=positions, computed=None, notes=(*self.notes, note))

    def in_units(self, units: str) -> MarkerSet:
        """The same markers measured in other units (a name of :mod:`core.space.units`)."""
        target = unit_named(units)
        factor = unit_factor(unit_named(self.units), target)
        return self.replace(positions=self.positions * factor, units=target.name)

    def transformed(
        self, rotation: np.ndarray | None = None, scale: float = 1.0, offset=(0.0, 0.0, 0.0), units: str | None = None
    ) -> MarkerSet:
        """``p' = scale * rotation @ p + offset`` for every sample (gaps stay gaps).

        ``rotation`` (3, 3) may be any rotation or axis permutation (e.g.
        :data:`Z_UP_TO_Y_UP`); ``units`` names the unit of the result (default: unchanged).
        """
        matrix = np.eye(3) if rotation is None else np.asarray(rotation, dtype=np.float64)
        positions = scale * np.einsum("ab,fmb->fma", matrix, self.positions) + np.asarray(offset, dtype=np.float64)
        return self.replace(positions=positions, units=units or self.units)

    def filled(self, max_gap: int) -> MarkerSet:
        """Gaps of at most ``max_gap`` frames with a seen sample on both sides, filled by linear
        interpolation between those samples and marked computed; longer gaps and gaps at
        either end stay gaps. A note says how many samples were filled."""
        if max_gap < 1:
            return self
        present = self.present
        before, after = gap_runs(present)
        n_frames = self.n_frames
        fill = ~present & (before >= 0) & (after < n_frames) & (after - before - 1 <= max_gap)
        if not fill.any():
            return self
        frame = np.arange(n_frames)[:, None]
        lo = np.where(fill, before, 0)
        hi = np.where(fill, after, 0)
        weight = np.where(fill, (frame - lo) / np.maximum(hi - lo, 1), 0.0)[..., None]
        marker = np.arange(self.n_markers)[None, :]
        values = (1 - weight) * self.positions[lo, marker] + weight * self.positions[hi, marker]
        positions = np.where(fill[..., None], values, self.positions)
        note = f"{int(fill.sum())} samples in gaps of at most {max_gap} frames filled by linear interpolation"
        return self.replace(positions=positions, computed=self.computed | fill, notes=(*self.notes, note))

    def gap_table(self) -> list[dict]:
        """Per marker: ``label``, ``missing`` (frames), ``gaps`` (runs), ``longest`` (frames)
        and ``computed`` (frames present but computed, not measured)."""
        missing = ~self.present
        starts = missing & np.vstack([np.ones((1, self.n_markers), bool), ~missing[:-1]])
        before, after = gap_runs(self.present)
        length = np.where(missing, after - before - 1, 0)
        return [
            {
                "label": f"{s}:{label}" if s else label,
                "missing": int(missing[:, m].sum()),
                "gaps": int(starts[:, m].sum()),
                "longest": int(length[:, m].max(initial=0)),
                "computed": int(self.computed[:, m].sum()),
            }
            for m, (s, label) in enumerate(zip(self.subjects, self.labels))
        ]

    def resampled(self, rate: float) -> MarkerSet:
        """Linear interpolation in time to another rate (:mod:`core.timebase.sampling`); a
        sample between a gap and a good sample is a gap, one between a computed sample and
        another is computed. Analysis outputs are left behind (``outputs`` None)."""
        if rate <= 0:
            raise ValueError("the frame rate must be positive")
        if self.n_frames < 2 or rate == self.rate:
            return self.replace(rate=rate, outputs=None) if self.n_frames < 2 else self
        at = resample_grid(self.n_frames, self.frame_time, rate)  # the one grid and interpolator
        low, high, weight = neighbours(at, self.n_frames)
        computed = self.computed[low] | (self.computed[high] & (weight > 0)[:, None])
        return self.replace(positions=interpolate(self.positions, at), computed=computed, rate=rate, outputs=None)
