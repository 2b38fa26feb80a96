"""What the checks report and how they are tuned: :class:`Finding`, :class:`CheckSettings`.

A finding names its kind (:data:`KINDS`), the joints (indices and names; none means the
whole pose), an inclusive frame range, a severity (:data:`SEVERITIES`), and a measured value
with its units. Each kind measures one quantity ``q`` (a length as a fraction of
:attr:`core.model.motion.Motion.size`, an angle in degrees, a percentage, seconds or frames) and
has three limits ``(info, warning, error)``: nothing is reported while ``q`` is below the
first; past it the severity is the highest limit ``q`` reaches. The settings are plain
numbers and strings: :meth:`CheckSettings.to_dict` / :meth:`CheckSettings.from_dict` give
JSON (an infinite limit is ``null``), so the app can remember them.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

#: the kinds of finding, in the order the checks run and the reports list them
KINDS = (
    "foot-skate",
    "penetration",
    "pop",
    "jitter",
    "flip",
    "bone-length",
    "frozen",
    "duplicate",
    "teleport",
    "rest-pose",
)
#: severities, mildest first; their position + 1 is their level in :func:`joint_flags`
SEVERITIES = ("info", "warning", "error")


@dataclasses.dataclass(frozen=True)
class Finding:
    """One problem: a kind, joints, frames ``start..end`` (inclusive), severity, value.

    ``joints`` are indices into the motion's joints and ``names`` their names (both empty:
    the whole pose). ``value`` is in ``units`` (the file's length unit, ``deg``, ``%``,
    ``s`` or ``frames``).
    """

    kind: str
    joints: tuple[int, ...]
    names: tuple[str, ...]
    start: int
    end: int
    severity: str
    value: float
    units: str

    @property
    def level(self) -> int:
        """1 (info), 2 (warning) or 3 (error)."""
        return SEVERITIES.index(self.severity) + 1

    def to_dict(self) -> dict:
        """The finding as the JSON of ``gmr check`` (docs/checks.md)."""
        return {
            "kind": self.kind,
            "joints": list(self.names),
            "start": self.start,
            "end": self.end,
            "severity": self.severity,
            "value": round(float(self.value), 6),
            "units": self.units,
        }


@dataclasses.dataclass(frozen=True)
class Skipped:
    """Frames ``start..end`` (inclusive, 0-based) that the checks ``kinds`` left out, and
    why (``reason``, one line a user reads: ``"the rest pose at the start"``)."""

    start: int
    end: int
    kinds: tuple[str, ...]
    reason: str

    def to_dict(self) -> dict:
        """The JSON of ``gmr check``'s ``skipped`` list (docs/checks.md)."""
        return {"start": self.start, "end": self.end, "kinds": list(self.kinds), "reason": self.reason}


Limits = tuple[float, float, float]


@dataclasses.dataclass(frozen=True)
class CheckSettings:
    """Which checks run and their thresholds (module docstring; formulas in docs/checks.md).

    Lengths are fractions of the motion's size, speeds fractions of the size per second.
    """

    kinds: tuple[str, ...] = KINDS
    # foot contacts (core.analysis.contacts): height and speed thresholds as fractions of the size
    contact_height: float = 0.03
    contact_speed: float = 0.4
    #: a planted foot faster than this (size per second) slides; limits: distance slid / size
    skate_speed: float = 0.02
    #: ... and is within this height (fraction of the size) of its lowest point; joints
    #: typically higher than this above the lowest of their foot never touch the ground
    skate_height: float = 0.015
    skate_limits: Limits = (0.01, 0.03, 0.08)
    #: limits: depth below the foot's contact level / size
    penetration_limits: Limits = (0.02, 0.04, 0.08)
    #: robust outlier factor (times the MAD) for pops; limits: displacement / size
    pop_mad: float = 8.0
    pop_limits: Limits = (0.005, 0.01, 0.03)
    #: jitter: block length (s); limits: RMS noise / size
    jitter_window: float = 0.2
    jitter_limits: Limits = (0.002, 0.004, 0.01)
    #: flip: a step faster than this (deg/s) and above the first limit (deg) flips
    flip_speed: float = 1800.0
    flip_limits: Limits = (45.0, 90.0, 150.0)
    #: limits: change of a bone's length, percent of its median length
    bone_limits: Limits = (1.0, 2.5, 10.0)
    #: frames closer than this (fraction of the size, every joint) are the same pose
    same_pose: float = 1e-7
    #: limits: seconds a pose is held (frozen), frames repeated (duplicate)
    frozen_limits: Limits = (0.2, 0.5, 2.0)
    duplicate_limits: Limits = (1.0, 1.0, 3.0)
    #: limits: the jump of a root beyond its own velocity / size
    teleport_limits: Limits = (0.05, 0.1, 0.2)
    #: rest pose: this fraction of the moving non-root joints within this many degrees
    #: of their rest rotation; limits: frames at the start or end
    rest_angle: float = 0.5
    rest_fraction: float = 0.6
    rest_limits: Limits = (1.0, 1.0, math.inf)

    def __post_init__(self) -> None:
        unknown = [k for k in self.kinds if k not in KINDS]
        if unknown:
            raise ValueError(f"unknown check {unknown[0]!r}: expected some of {', '.join(KINDS)}")
        object.__setattr__(self, "kinds", tuple(k for k in KINDS if k in self.kinds))
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if field.name.endswith("_limits"):
                limits = tuple(float(v) for v in value)
                if len(limits) != 3 or not (0 <= limits[0] <= limits[1] <= limits[2]):
                    raise ValueError(f"{field.name} must be three increasing numbers (info, warning, error)")
                object.__setattr__(self, field.name, limits)
            elif field.name != "kinds":
                number = float(value)
                if not (number > 0 and math.isfinite(number)):
                    raise ValueError(f"{field.name} must be a positive number, not {value!r}")
                object.__setattr__(self, field.name, number)

    def with_kinds(self, kinds: tuple[str, ...] | list[str]) -> CheckSettings:
        return dataclasses.replace(self, kinds=tuple(kinds))

    def to_dict(self) -> dict:
        """Plain JSON values (lists for the limits, ``None`` for an infinite limit)."""
        out: dict = {}
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if field.name.endswith("_limits"):
                value = [None if math.isinf(v) else v for v in value]
            elif field.name == "kinds":
                value = list(value)
            out[field.name] = value
        return out

    @classmethod
    def from_dict(cls, data: dict) -> CheckSettings:
        """The settings :meth:`to_dict` wrote (missing keys keep their defaults); ValueError
        for unknown keys or bad values."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(data) - names)
        if unknown:
            raise ValueError(f"unknown check setting {unknown[0]!r}")
        given = {}
        for key, value in data.items():
            if key.endswith("_limits"):
                value = tuple(math.inf if v is None else float(v) for v in value)
            elif key == "kinds":
                value = tuple(value)
            given[key] = value
        return cls(**given)


def severity_levels(quantity: np.ndarray, limits: Limits) -> np.ndarray:
    """0 (not reported), 1, 2 or 3 for each measured quantity: (...) -> (...) int8."""
    if isinstance(quantity, float | int):  # one number (a finding's): no array
        q = float(quantity)
        return np.int8((q >= limits[0]) + (q >= limits[1]) + (q >= limits[2]))
    q = np.asarray(quantity, dtype=np.float64)
    return ((q >= limits[0]).astype(np.int8) + (q >= limits[1]) + (q >= limits[2])).astype(np.int8)


def joint_flags(findings: list[Finding], n_frames: int, n_joints: int) -> np.ndarray:
    """(F, J) int8: per frame and joint, the highest level (1 info, 2 warning, 3 error) of
    the findings covering it, 0 where none does. A finding without joints (the whole
    pose) covers every joint. For the app's warning colours and timeline flags."""
    flags = np.zeros((n_frames, n_joints), np.int8)
    for finding in findings:
        rows = slice(max(finding.start, 0), min(finding.end, n_frames - 1) + 1)
        columns = list(finding.joints) if finding.joints else slice(None)
        flags[rows, columns] = np.maximum(flags[rows, columns], finding.level)
    return flags
