"""File facts on disk: the header lines of a GMR file that state a motion's space.

A GMR file (and the comments the project writes) holds :class:`~core.model.facts.FileFacts`
as ``#`` header lines, read and written here and nowhere else:

- ``units: cm`` (a registry unit, :mod:`core.space.units`) or ``units: 0.0564444 m (in / 0.45)``
  (any other length, with its name);
- ``up axis: z``;
- ``source units: 0.0564444 m (in / 0.45)`` (the unit the lengths came from).

Reading takes the last line of each kind (a file edited by hand may state a fact twice; the
later line is the newer), any case, and keeps every other line as a free comment. Older
files' lines read the same (``up axis: z (converted from y up ...)``, ``units: metres``,
``source units: 0.05644 m (written by GMR Studio ...)``).
"""

from __future__ import annotations

import re

from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import UNITS, Unit, parse_unit, unit_of_length

_UNITS = re.compile(r"^(?:length\s+)?units?\s*:\s*(.+)$", re.IGNORECASE)
_SOURCE = re.compile(r"^source units?\s*:\s*(.+)$", re.IGNORECASE)
_UP = re.compile(r"^up axis\s*:\s*([yz])\b", re.IGNORECASE)
_LENGTH = re.compile(r"^([0-9.]+(?:[eE][+-]?[0-9]+)?)\s*m\b(?:\s*\(([^)]*)\))?")


def parse_unit_text(text: str) -> Unit | None:
    """A unit as a fact line gives it (``cm``, ``metres``, ``0.0564 m (in / 0.45)``), else None."""
    text = text.strip()
    unit = parse_unit(text)
    if unit is not None:
        return unit
    length = _LENGTH.match(text)
    if length is None:
        return None
    try:
        metres = float(length.group(1))
    except ValueError:
        return None
    if not metres > 0 or metres == float("inf"):
        return None
    name = length.group(2)
    return unit_of_length(metres, name if name and not name.startswith("written by") else None)


def facts_from_comments(comments: tuple[str, ...] | list[str]) -> tuple[FileFacts, tuple[str, ...]]:
    """(the facts the lines state, the other lines): see the module docstring."""
    unit = source = up = None
    free = []
    for comment in comments:
        line = comment.strip()
        if (found := _SOURCE.match(line)) and (parsed := parse_unit_text(found.group(1))) is not None:
            source = parsed
        elif (found := _UNITS.match(line)) and (parsed := parse_unit_text(found.group(1))) is not None:
            unit = parsed
        elif found := _UP.match(line):
            up = found.group(1).lower()
        else:
            free.append(comment)
    return FileFacts(unit=unit, up_axis=up, source_unit=source), tuple(free)


def unit_text(unit: Unit) -> str:
    """A unit as a fact line writes it: the registry name, else its length and name."""
    if unit.name in UNITS:
        return unit.name
    return f"{unit.metres:.15g} m ({unit.name})"


def fact_comments(facts: FileFacts) -> tuple[str, ...]:
    """The header lines that state ``facts`` (none for facts not known)."""
    lines = []
    if facts.unit is not None:
        lines.append(f"units: {unit_text(facts.unit)}")
    if facts.up_axis is not None:
        lines.append(f"up axis: {facts.up_axis}")
    if facts.source_unit is not None:
        lines.append(f"source units: {unit_text(facts.source_unit)}")
    return tuple(lines)
