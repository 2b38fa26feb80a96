"""What a comparison reads of each side: a :class:`Track` of world positions (and rotations).

A track is the world trajectory of named points: the joints of a motion (after forward
kinematics, in GMR's convention, so a joint's rotation is that of the bone ending at it) or
the markers of a marker set. Gaps are NaN. Units and up axis are what the source states;
:func:`to_common_space` brings B into A's units and up axis, recording what it did.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.conversions import UP_AXES, Y_TO_Z, up_axis_of

#: metres per unit of the length units a file may state
UNIT_SCALE = {"mm": 1e-3, "cm": 1e-2, "m": 1.0, "in": 0.0254, "ft": 0.3048}
_UNITS_COMMENT = re.compile(r"^(?:length\s+)?units?\s*:\s*(mm|cm|m|in|ft)\b", re.IGNORECASE)
#: what a glTF file written by this project says of its source's unit (core.formats.gltf_in)
_SOURCE_UNITS_COMMENT = re.compile(r"^source units:\s*([0-9.eE+-]+)\s*m\b")


@dataclasses.dataclass(frozen=True, eq=False)
class Track:
    """World trajectories of named points, frames first.

    names : tuple of J str.
    positions : (F, J, 3) float64, NaN where the point is missing.
    rotations : (F, J, 3, 3) float64 world rotations (GMR convention: the frame of the bone
        ending at the joint), NaN where missing; None when the source has none (markers).
    has_rotation : (J,) bool, the point has an orientation (not a root, not a marker).
    frame_rate : float, frames per second.
    units : the length unit the source states ("mm", "cm", "m", "in", "ft"), or None.
    up : "y" or "z", the source's up axis.
    size : float, the source's size (extent of its rest pose or of its points), in its units.
    label : where it came from (file name), for messages.
    source_metres : for a file written in metres from a motion in other units (our glTF
        export), the metres per unit of that source, else None.
    """

    names: tuple[str, ...]
    positions: np.ndarray
    rotations: np.ndarray | None
    has_rotation: np.ndarray
    frame_rate: float
    units: str | None = None
    up: str = "y"
    size: float = 1.0
    label: str = ""
    source_metres: float | None = None

    @property
    def n_frames(self) -> int:
        return self.positions.shape[0]

    @property
    def n_points(self) -> int:
        return self.positions.shape[1]


def units_of(motion: Motion) -> str | None:
    """The length unit a motion's comments state (the last ``units: mm`` line), else None."""
    for comment in reversed(motion.comments):
        found = _UNITS_COMMENT.match(comment.strip())
        if found:
            return found.group(1).lower()
    return None


def source_metres_of(motion: Motion) -> float | None:
    """The metres per unit of the motion a file was exported from, when its comments say
    (``source units: 0.0564444 m``), else None."""
    for comment in reversed(motion.comments):
        found = _SOURCE_UNITS_COMMENT.match(comment.strip())
        if found:
            try:
                value = float(found.group(1))
            except ValueError:
                return None
            return value if np.isfinite(value) and value > 0 else None
    return None


def track_of_motion(
    motion: Motion,
    *,
    with_rotations: bool = True,
    positions: np.ndarray | None = None,
    label: str = "",
) -> Track:
    """The joints of a motion as a track (forward kinematics once, all frames).

    ``positions``: the motion's world positions (F, J, 3) when the caller has them already
    (the app's cache); rotations are then computed only if asked for.
    """
    gmr = pre_from_post(motion)
    rotations = None
    if with_rotations or positions is None:
        positions, rotations = forward_kinematics(gmr, with_rotations=with_rotations, threads=None)
    return Track(
        names=motion.names,
        positions=positions,
        rotations=rotations,
        has_rotation=np.asarray(motion.parents) >= 0,
        frame_rate=motion.frame_rate,
        units=units_of(motion),
        up=up_axis_of(motion),
        size=motion.size,
        label=label,
        source_metres=source_metres_of(motion),
    )


def track_of_points(
    names: tuple[str, ...] | list[str],
    positions: np.ndarray,
    frame_rate: float,
    *,
    units: str | None = None,
    up: str = "y",
    label: str = "",
) -> Track:
    """Points without orientation (markers, virtual markers): positions (F, J, 3), NaN = gap."""
    positions = np.asarray(positions, dtype=np.float64)
    finite = positions[np.isfinite(positions).all(axis=-1)]
    size = float(np.ptp(finite, axis=0).max()) if len(finite) else 1.0
    return Track(
        names=tuple(names),
        positions=positions,
        rotations=None,
        has_rotation=np.zeros(len(names), dtype=bool),
        frame_rate=float(frame_rate),
        units=units,
        up=up,
        size=size or 1.0,
        label=label,
    )


@dataclasses.dataclass(frozen=True)
class SpaceChange:
    """How B was brought into A's space before any fitted alignment.

    scale : A units per B unit; up_rotation : (3, 3) turning B's up axis into A's;
    notes : sentences saying where each came from (the files, or the caller).
    """

    scale: float
    up_rotation: np.ndarray
    units_a: str | None
    units_b: str | None
    up_a: str
    up_b: str
    notes: tuple[str, ...]


def space_change(a: Track, b: Track, *, scale: float | None = None, up_b: str | None = None) -> SpaceChange:
    """B's units and up axis -> A's: from what the tracks state, or ``scale``/``up_b`` given.

    ``scale``: A units per B unit (overrides the stated units); ``up_b``: B's up axis
    (overrides what B states). Raises ValueError for a bad scale or axis.
    """
    notes = []
    if scale is not None:
        if not (np.isfinite(scale) and scale > 0):
            raise ValueError(f"the scale must be a positive number, not {scale}")
        notes.append(f"B scaled by {scale:g} (given)")
    elif a.units and b.units:
        scale = UNIT_SCALE[b.units] / UNIT_SCALE[a.units]
        notes.append(f"B in {b.units}, A in {a.units}: B scaled by {scale:g}")
    elif b.units == "m" and not a.units and b.source_metres:
        scale = 1.0 / b.source_metres
        notes.append(
            f"B in m, exported from units of {b.source_metres:.6g} m (its note); A states none and is taken "
            f"in those: B scaled by {scale:g}"
        )
    elif a.units == "m" and not b.units and a.source_metres:
        scale = a.source_metres
        notes.append(
            f"A in m, exported from units of {a.source_metres:.6g} m (its note); B states none and is taken "
            f"in those: B scaled by {scale:g}"
        )
    else:
        scale = 1.0
        stated = a.units or b.units
        notes.append(
            f"units: only one side states them ({stated}); the other is taken as the same"
            if stated
            else "units: neither file states them; taken as the same"
        )
    up_source = (up_b or b.up).lower()
    if up_source not in UP_AXES:
        raise ValueError(f"the up axis must be one of {', '.join(UP_AXES)}, not {up_source!r}")
    if up_source == a.up:
        rotation = np.eye(3)
        notes.append(f"up axis: {a.up} on both sides")
    else:
        rotation = Y_TO_Z if a.up == "z" else Y_TO_Z.T
        notes.append(f"up axis: B turned from {up_source} up to A's {a.up} up")
    return SpaceChange(float(scale), rotation, a.units, b.units, a.up, up_source, tuple(notes))
