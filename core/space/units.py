"""Length units: one registry for every file format, comparison and marker alignment.

A :class:`Unit` is a name and its length in metres. The registry (:data:`UNITS`) names the
units motion and marker files use; :func:`parse_unit` reads a file's unit string (``"mm"``,
``"millimeters"``, ``"Centimeter"``...), :func:`acclaim_unit` is an ASF's ``:units length L``
(one unit is ``1 / L`` inch: CMU's ``0.45`` makes 56.444 mm), :func:`unit_of_length` names
any length (a registry unit when it is one, to rounding). Lengths are converted with
:func:`unit_factor`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

INCH = 0.0254
#: relative difference below which two unit lengths are one unit (rounding of a printed factor)
SAME_UNIT_TOLERANCE = 1e-9


@dataclasses.dataclass(frozen=True)
class Unit:
    """A length unit: ``name`` (``"mm"``, ``"in / 0.45"``) and ``metres``, its length."""

    name: str
    metres: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.metres) and self.metres > 0):
            raise ValueError(f"unit {self.name!r}: its length must be a positive number of metres, not {self.metres}")
        object.__setattr__(self, "metres", float(self.metres))

    def scaled(self, factor: float) -> Unit:
        """The unit of lengths multiplied by ``factor``: ``factor`` new units make one old
        (a length in cm times 0.01 is in m)."""
        return unit_of_length(self.metres / factor)

    def __str__(self) -> str:
        return self.name


UNITS: dict[str, Unit] = {
    unit.name: unit
    for unit in (
        Unit("m", 1.0),
        Unit("cm", 0.01),
        Unit("mm", 0.001),
        Unit("in", INCH),
        Unit("ft", 0.3048),
    )
}
#: other spellings of the registry's units in files (lower case)
ALIASES = {
    "meter": "m",
    "meters": "m",
    "metre": "m",
    "metres": "m",
    "centimeter": "cm",
    "centimeters": "cm",
    "centimetre": "cm",
    "centimetres": "cm",
    "millimeter": "mm",
    "millimeters": "mm",
    "millimetre": "mm",
    "millimetres": "mm",
    "inch": "in",
    "inches": "in",
    "foot": "ft",
    "feet": "ft",
}


def parse_unit(text: str) -> Unit | None:
    """The registry unit a file's unit string names (any case, spaces trimmed), else None."""
    key = str(text).strip().lower()
    key = ALIASES.get(key, key)
    return UNITS.get(key)


def unit_named(name: str) -> Unit:
    """The registry unit of that name or spelling; ValueError naming the known ones."""
    unit = parse_unit(name)
    if unit is None:
        raise ValueError(f"unknown length unit {name!r}: expected one of {', '.join(UNITS)}")
    return unit


def unit_of_length(metres: float, name: str | None = None) -> Unit:
    """The unit ``metres`` long: the registry's when one is that long (to rounding), else a
    unit called ``name`` (default: its length, ``"0.0564444 m"``)."""
    for unit in LIKELY_UNITS:
        if abs(metres / unit.metres - 1.0) <= SAME_UNIT_TOLERANCE:
            return unit
    return Unit(name or f"{metres:.6g} m", metres)


def acclaim_unit(length: float) -> Unit:
    """An ASF's length unit, ``:units length L``: one unit is ``1 / L`` inch."""
    metres = INCH / float(length)
    return unit_of_length(metres, f"ASF unit (in / {float(length):g})")


#: CMU's ASF unit, ``:units length 0.45`` (1 / 0.45 inch, 56.444 mm)
CMU_UNIT = Unit("ASF unit (in / 0.45)", INCH / 0.45)
#: the units a file of unstated unit is likely in, for guesses from a figure's size
LIKELY_UNITS = (*UNITS.values(), CMU_UNIT)


def unit_factor(source: Unit, target: Unit) -> float:
    """Target units per source unit: a length in ``source`` times this is in ``target``."""
    return source.metres / target.metres


def nearest_unit(metres: float, candidates: tuple[Unit, ...] | None = None, tolerance: float = 0.25) -> Unit | None:
    """The candidate unit (default: the registry's) within ``tolerance`` (relative) of a
    length in metres, the nearest in ratio; None when none is."""
    best, ratio = None, np.inf
    for unit in candidates if candidates is not None else tuple(UNITS.values()):
        off = abs(np.log(metres / unit.metres))
        if off < ratio:
            best, ratio = unit, off
    return best if best is not None and abs(np.exp(ratio) - 1.0) <= tolerance else None
