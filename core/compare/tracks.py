"""What a comparison reads of each side: a :class:`Track` of world positions (and rotations).

A track is the world trajectory of named points: the joints of a motion (after forward
kinematics, in GMR's convention, so a joint's rotation is that of the bone ending at it) or
the markers of a marker set. Gaps are NaN. Units and up axis are what the source states;
:func:`to_common_space` brings B into A's units and up axis, recording what it did.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.space.units import Unit, unit_factor, unit_named
from gmr_studio.core.space.up_axis import check_up_axis, up_axis_of, up_turn

#: sizes of A and B (in their own units) further apart than this factor, with no unit stated
#: for both, get a warning: the two are probably in different units
SIZE_MISMATCH = 3.0


@dataclasses.dataclass(frozen=True, eq=False)
class Track:
    """World trajectories of named points, frames first.

    names : tuple of J str.
    positions : (F, J, 3) float64, NaN where the point is missing.
    rotations : (F, J, 3, 3) float64 world rotations (GMR convention: the frame of the bone
        ending at the joint), NaN where missing; None when the source has none (markers).
    has_rotation : (J,) bool, the point has an orientation (not a root, not a marker).
    frame_rate : float, frames per second.
    unit : the length unit the source states (:class:`~core.space.units.Unit`), or None.
    up : "y" or "z", the source's up axis (:func:`core.space.up_axis.up_axis_of`).
    size : float, the source's size (extent of its rest pose or of its points), in its units.
    label : where it came from (file name), for messages.
    source_unit : for a file written in metres from a motion in other units (our glTF
        export), the unit of that source (its file facts), else None.
    """

    names: tuple[str, ...]
    positions: np.ndarray
    rotations: np.ndarray | None
    has_rotation: np.ndarray
    frame_rate: float
    unit: Unit | None = None
    up: str = "y"
    size: float = 1.0
    label: str = ""
    source_unit: Unit | None = None

    @property
    def units(self) -> str | None:
        """The stated unit's name, or None."""
        return None if self.unit is None else self.unit.name

    @property
    def n_frames(self) -> int:
        return self.positions.shape[0]

    @property
    def n_points(self) -> int:
        return self.positions.shape[1]


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
        unit=motion.facts.unit,
        up=up_axis_of(motion),
        size=motion.size,
        label=label,
        source_unit=motion.facts.source_unit,
    )


def track_of_points(
    names: tuple[str, ...] | list[str],
    positions: np.ndarray,
    frame_rate: float,
    *,
    units: str | Unit | None = None,
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
        unit=unit_named(units) if isinstance(units, str) else units,
        up=check_up_axis(up),
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

    @property
    def transform(self) -> Similarity:
        """B's space to A's as one similarity: turned up, then scaled."""
        return Similarity(self.up_rotation, self.scale)


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
    elif a.unit and b.unit:
        scale = unit_factor(b.unit, a.unit)
        notes.append(f"B in {b.unit}, A in {a.unit}: B scaled by {scale:g}")
    elif b.unit and not a.unit and b.source_unit:
        scale = unit_factor(b.unit, b.source_unit)
        notes.append(
            f"B in {b.unit}, exported from {b.source_unit} (its file facts); A states no unit and is taken "
            f"in {b.source_unit}: B scaled by {scale:g}"
        )
    elif a.unit and not b.unit and a.source_unit:
        scale = unit_factor(a.source_unit, a.unit)
        notes.append(
            f"A in {a.unit}, exported from {a.source_unit} (its file facts); B states no unit and is taken "
            f"in {a.source_unit}: B scaled by {scale:g}"
        )
    else:
        scale = 1.0
        stated = a.unit or b.unit
        notes.append(
            f"units: only one side states them ({stated}); the other is taken as the same"
            if stated
            else "units: neither file states them; taken as the same"
        )
        ratio = (b.size / a.size) if a.size > 0 and b.size > 0 else 1.0
        if max(ratio, 1.0 / ratio) > SIZE_MISMATCH:
            notes.append(
                f"WARNING: B is {ratio:.3g} times A's size, and the files do not both state their units: "
                "they are probably in different units; give --scale (A units per B unit)"
            )
    up_source = check_up_axis(up_b or b.up)
    rotation = up_turn(up_source, a.up)
    if up_source == a.up:
        notes.append(f"up axis: {a.up} on both sides")
    else:
        notes.append(f"up axis: B turned from {up_source} up to A's {a.up} up")
    return SpaceChange(float(scale), rotation, a.units, b.units, a.up, up_source, tuple(notes))
