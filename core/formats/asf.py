"""ASF files (Acclaim Skeleton File): the skeleton that AMC motion files animate.

Read into an :class:`~core.formats.acclaim_skeleton.AcclaimSkeleton`, a small record of
what the file says (units, root, bones with their direction, length, axis, degrees of
freedom and limits, hierarchy). The conversion to GMR is in :mod:`core.formats.amc`; the
formulas are in ``docs/formats.md``.

What the reader accepts: ``#`` comments, CRLF/CR/LF endings, tabs, commas and parentheses
as white space (as the Acclaim definition says), keywords in any case, sections in any
order, ``inf`` limits. Every problem raises :class:`~core.errors.MotionFileError` with the
line and column and what was expected there: unknown keywords, wrong counts of numbers,
a dof or limit list that does not match, unknown or repeated bones in ``:hierarchy``,
cycles, bones not connected to the root, missing sections.

Angles are radians inside (``:units angle deg`` files are converted); lengths stay in the
file's units (``:units length`` is kept as data, never applied).
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError, quoted, read_input
from gmr_studio.core.formats.acclaim_skeleton import (
    BONE_DOFS,
    ROOT_NAME,
    ROTATION_DOFS,
    TRANSLATION_DOFS,
    AcclaimBone,
    AcclaimSkeleton,
    AcclaimUnits,
)
from gmr_studio.core.formats.frames import MAX_ABS_VALUE, out_of_range, within_range
from gmr_studio.core.formats.hierarchy import normalise_newlines
from gmr_studio.core.model.motion import check_joint_name

_NUMBER = re.compile(r"[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf|infinity)\Z", re.IGNORECASE)
_SEPARATORS = str.maketrans({",": " ", "(": " ", ")": " "})
_SECTIONS = (":version", ":name", ":units", ":documentation", ":root", ":bonedata", ":hierarchy", ":skin")


# ------------------------------------------------------------------------------ tokens
@dataclasses.dataclass
class _Token:
    text: str
    line: int
    column: int


class _Lines:
    """The file's lines as tokens, comments and separators removed, blank lines skipped."""

    def __init__(self, path: str, data: bytes) -> None:
        self.path = path
        try:
            text = normalise_newlines(data).decode("utf-8")
        except UnicodeDecodeError:
            text = normalise_newlines(data).decode("latin-1")
        self.raw = text.split("\n")
        self.lines: list[tuple[int, list[_Token]]] = []
        for number, line in enumerate(self.raw, start=1):
            content = line.split("#", 1)[0].translate(_SEPARATORS)
            tokens = [_Token(m.group(), number, m.start() + 1) for m in re.finditer(r"\S+", content)]
            if tokens:
                self.lines.append((number, tokens))
        self.index = 0

    def error(self, message: str, token: _Token | None = None, line: int | None = None) -> MotionFileError:
        if token is not None:
            return MotionFileError(self.path, message, token.line, token.column)
        return MotionFileError(self.path, message, line if line is not None else len(self.raw), 1)

    def peek(self) -> list[_Token] | None:
        return self.lines[self.index][1] if self.index < len(self.lines) else None

    def next(self) -> list[_Token]:
        tokens = self.lines[self.index][1]
        self.index += 1
        return tokens

    def at_section(self) -> bool:
        tokens = self.peek()
        return tokens is None or tokens[0].text.startswith(":")


def _number(lines: _Lines, token: _Token, what: str) -> float:
    if not _NUMBER.match(token.text):
        raise lines.error(f"expected {what}, found {quoted(token.text)}", token)
    return float(token.text)


def _numbers(lines: _Lines, key: _Token, values: list[_Token], count: int, what: str) -> np.ndarray:
    if len(values) < count:
        where = values[-1] if values else key
        raise lines.error(f"'{key.text}' needs {count} numbers ({what}), found {len(values)}", where)
    if len(values) > count:
        raise lines.error(
            f"'{key.text}' takes {count} numbers ({what}); unexpected {quoted(values[count].text)}", values[count]
        )
    out = np.array([_number(lines, v, f"a number for '{key.text}'") for v in values])
    if not np.isfinite(out).all():
        bad = values[int(np.flatnonzero(~np.isfinite(out))[0])]
        raise lines.error(f"'{key.text}' needs finite numbers, found {quoted(bad.text)}", bad)
    if not within_range(out):
        bad = values[int(np.flatnonzero(np.abs(out) > MAX_ABS_VALUE)[0])]
        raise lines.error(out_of_range(bad.text), bad)
    return out


def _axis_order(lines: _Lines, token: _Token) -> str:
    order = token.text.upper()
    if sorted(order) != ["X", "Y", "Z"]:
        raise lines.error(
            f"expected a rotation order such as XYZ (the three axes, once each), found {quoted(token.text)}", token
        )
    return order


# ------------------------------------------------------------------------------ reader
def read_asf(path: str | Path, data: bytes | None = None) -> AcclaimSkeleton:
    """Read an ASF file (``data``: its bytes, if already in hand).

    Raises
    ------
    MotionFileError for an unreadable or malformed file (line, column, what was expected).
    """
    path_text = str(path)
    data = read_input(path, data)
    lines = _Lines(path_text, data)
    found: dict[str, _Token] = {}
    fields: dict = {"name": "", "version": "", "documentation": "", "units": AcclaimUnits()}
    bones: list[AcclaimBone] = []
    hierarchy: list[list[_Token]] | None = None
    while lines.peek() is not None:
        tokens = lines.next()
        keyword = tokens[0]
        section = keyword.text.lower()
        if section not in _SECTIONS:
            raise lines.error(
                f"expected a section keyword ({', '.join(_SECTIONS)}), found {quoted(keyword.text)}", keyword
            )
        if section in found:
            raise lines.error(f"second {section} section (the first is at line {found[section].line})", keyword)
        found[section] = keyword
        if section in (":name", ":version"):  # the rest of the line as written
            raw = lines.raw[keyword.line - 1].split("#", 1)[0]
            fields[section[1:]] = raw[keyword.column - 1 + len(keyword.text) :].strip()
        elif section == ":documentation":
            fields["documentation"] = _documentation(lines, keyword)
        elif section == ":units":
            fields["units"] = _units(lines)
        elif section == ":root":
            fields.update(_root(lines, fields["units"]))
        elif section == ":bonedata":
            bones = _bonedata(lines, fields["units"])
        elif section == ":hierarchy":
            hierarchy = _hierarchy_lines(lines, keyword)
        else:  # :skin names skin files: nothing for a skeleton reader
            while not lines.at_section():
                lines.next()
    for section in (":root", ":bonedata", ":hierarchy"):
        if section not in found:
            raise lines.error(f"the file has no {section} section (an ASF needs :root, :bonedata and :hierarchy)")
    parents = _parents(lines, bones, hierarchy or [], found[":hierarchy"])
    bones = [dataclasses.replace(b, parent=p) for b, p in zip(bones, parents)]
    return AcclaimSkeleton(
        path=path_text,
        name=fields["name"],
        version=fields["version"],
        units=fields["units"],
        documentation=fields["documentation"],
        root_order=fields["root_order"],
        root_axis=fields["root_axis"],
        root_position=fields["root_position"],
        root_orientation=fields["root_orientation"],
        bones=tuple(bones),
    )


def _documentation(lines: _Lines, keyword: _Token) -> str:
    """Free text up to the next line that starts with a keyword (comments included)."""
    start = keyword.line  # 1-based line of :documentation; its text follows on later lines
    while not lines.at_section():
        lines.next()
    end = lines.lines[lines.index][0] - 1 if lines.peek() is not None else len(lines.raw)
    text = [line.strip() for line in lines.raw[start:end]]
    return "\n".join(text).strip()


def _units(lines: _Lines) -> AcclaimUnits:
    values: dict = {}
    while not lines.at_section():
        tokens = lines.next()
        key = tokens[0]
        name = key.text.lower()
        if name not in ("mass", "length", "angle"):
            raise lines.error(f"expected 'mass', 'length' or 'angle' in :units, found {quoted(key.text)}", key)
        if len(tokens) != 2:
            where = tokens[2] if len(tokens) > 2 else key
            raise lines.error(f"expected one value after '{key.text}'", where)
        if name == "angle":
            unit = tokens[1].text.lower()
            if unit not in ("deg", "rad"):
                raise lines.error(f"expected 'deg' or 'rad' after 'angle', found {quoted(tokens[1].text)}", tokens[1])
            values["angle"] = unit
        else:
            value = _number(lines, tokens[1], f"a number after '{key.text}'")
            if not np.isfinite(value) or value <= 0:
                raise lines.error(f"'{key.text}' must be a positive number, found {quoted(tokens[1].text)}", tokens[1])
            values[name] = value
    return AcclaimUnits(**values)


def _angle_factor(units: AcclaimUnits) -> float:
    return np.pi / 180.0 if units.angle == "deg" else 1.0


def _root(lines: _Lines, units: AcclaimUnits) -> dict:
    out = {
        "root_axis": "XYZ",
        "root_position": np.zeros(3),
        "root_orientation": np.zeros(3),
    }
    order = None
    while not lines.at_section():
        tokens = lines.next()
        key = tokens[0]
        name = key.text.lower()
        if name == "order":
            order = []
            for token in tokens[1:]:
                dof = token.text.lower()
                if dof not in (*TRANSLATION_DOFS, *ROTATION_DOFS):
                    raise lines.error(
                        f"expected one of TX TY TZ RX RY RZ in the root order, found {quoted(token.text)}", token
                    )
                if dof in order:
                    raise lines.error(f"'{token.text}' appears twice in the root order", token)
                order.append(dof)
            if not order:
                raise lines.error("expected the root's channels after 'order' (e.g. TX TY TZ RX RY RZ)", key)
        elif name == "axis":
            if len(tokens) != 2:
                raise lines.error("expected one rotation order (e.g. XYZ) after 'axis'", tokens[-1])
            out["root_axis"] = _axis_order(lines, tokens[1])
        elif name == "position":
            out["root_position"] = _numbers(lines, key, tokens[1:], 3, "x y z")
        elif name == "orientation":
            out["root_orientation"] = _numbers(lines, key, tokens[1:], 3, "angles about x y z") * _angle_factor(units)
        else:
            raise lines.error(
                f"expected 'order', 'axis', 'position' or 'orientation' in :root, found {quoted(key.text)}", key
            )
    if order is None:
        raise lines.error(
            "the :root section has no 'order' line (e.g. order TX TY TZ RX RY RZ)", line=lines.lines[lines.index - 1][0]
        )
    out["root_order"] = tuple(order)
    return out


def _bonedata(lines: _Lines, units: AcclaimUnits) -> list[AcclaimBone]:
    bones: list[AcclaimBone] = []
    seen: dict[str, int] = {}
    while not lines.at_section():
        tokens = lines.next()
        if tokens[0].text.lower() != "begin" or len(tokens) > 1:
            where = tokens[0] if tokens[0].text.lower() != "begin" else tokens[1]
            raise lines.error(f"expected 'begin' opening a bone in :bonedata, found {quoted(where.text)}", where)
        bones.append(_bone(lines, tokens[0], units, seen))
    return bones


def _bone(lines: _Lines, begin: _Token, units: AcclaimUnits, seen: dict[str, int]) -> AcclaimBone:
    """One bone block; ``seen`` maps the names read so far to their lines (updated)."""
    fields: dict = {"line": begin.line, "parent": -1}
    keys: dict[str, _Token] = {}
    limits_tokens: list[_Token] | None = None
    limits_key = None
    angle = _angle_factor(units)
    while True:
        tokens = lines.peek()
        if tokens is None or tokens[0].text.startswith(":"):
            raise lines.error(
                f"expected 'end' closing the bone opened at line {begin.line}", tokens[0] if tokens else None
            )
        lines.next()
        key, values = tokens[0], tokens[1:]
        name = key.text.lower()
        if name == "end":
            if values:
                raise lines.error(f"unexpected {quoted(values[0].text)} after 'end'", values[0])
            break
        if name in keys:
            raise lines.error(f"second '{key.text}' in the bone opened at line {begin.line}", key)
        keys[name] = key
        if name == "id":
            if len(values) != 1 or not re.fullmatch(r"[+-]?[0-9]+", values[0].text):
                raise lines.error("expected a whole number after 'id'", values[0] if values else key)
            fields["id"] = int(values[0].text)
        elif name == "name":
            if len(values) != 1:
                raise lines.error("expected one bone name after 'name'", values[1] if values else key)
            try:
                bone_name = check_joint_name(values[0].text)
            except ValueError as exc:
                raise lines.error(str(exc), values[0]) from None
            if bone_name == ROOT_NAME:
                raise lines.error(f"a bone cannot be named '{ROOT_NAME}' (the name of the skeleton's root)", values[0])
            if bone_name in seen:
                raise lines.error(f"bone name '{bone_name}' is used twice (first at line {seen[bone_name]})", values[0])
            seen[bone_name] = values[0].line
            fields["name"] = bone_name
        elif name == "direction":
            direction = _numbers(lines, key, values, 3, "x y z")
            norm = float(np.linalg.norm(direction))
            fields["direction"] = direction / norm if norm > 0 else direction
        elif name == "length":
            fields["length"] = float(_numbers(lines, key, values, 1, "the bone length")[0])
        elif name == "axis":
            if len(values) != 4:
                raise lines.error(
                    "expected three angles and a rotation order after 'axis' (e.g. axis 0 0 20 XYZ)",
                    values[-1] if values else key,
                )
            fields["axis"] = _numbers(lines, key, values[:3], 3, "angles about x y z") * angle
            fields["axis_order"] = _axis_order(lines, values[3])
        elif name == "dof":
            dof = []
            for token in values:
                d = token.text.lower()
                if d not in BONE_DOFS:
                    raise lines.error(f"expected a dof from {' '.join(BONE_DOFS)}, found {quoted(token.text)}", token)
                if d in dof:
                    raise lines.error(f"dof '{token.text}' appears twice", token)
                dof.append(d)
            if not dof:
                raise lines.error("expected at least one dof after 'dof'", key)
            fields["dof"] = tuple(dof)
        elif name == "limits":
            limits_key, limits_tokens = key, list(values)
            while (more := lines.peek()) is not None and _NUMBER.match(more[0].text):
                limits_tokens += lines.next()
        elif name in ("bodymass", "cofmass"):
            fields[name] = float(_numbers(lines, key, values, 1, name)[0])
        else:
            raise lines.error(
                "expected id, name, direction, length, axis, dof, limits, bodymass, cofmass or end "
                f"in a bone, found {quoted(key.text)}",
                key,
            )
    for required in ("name", "direction", "length"):
        if required not in fields:
            raise lines.error(f"the bone opened at line {begin.line} has no '{required}'", line=begin.line)
    fields.setdefault("axis", np.zeros(3))
    fields.setdefault("axis_order", "XYZ")
    dof = fields.setdefault("dof", ())
    limits = np.full((len(dof), 2), np.nan)
    if limits_tokens is not None:
        if len(limits_tokens) != 2 * len(dof):
            where = limits_tokens[2 * len(dof)] if len(limits_tokens) > 2 * len(dof) else limits_key
            raise lines.error(
                f"'limits' needs one (min max) pair per dof ({len(dof)} pairs), found {len(limits_tokens)} numbers",
                where,
            )
        values = np.array([_number(lines, t, "a limit") for t in limits_tokens]).reshape(-1, 2)
        scale = np.array([angle if d in ROTATION_DOFS else 1.0 for d in dof])
        limits = values * scale[:, None]
    fields["limits"] = limits
    return AcclaimBone(**fields)


def _hierarchy_lines(lines: _Lines, keyword: _Token) -> list[list[_Token]]:
    tokens = lines.peek()
    if tokens is None or tokens[0].text.lower() != "begin":
        raise lines.error("expected 'begin' after :hierarchy", tokens[0] if tokens else keyword)
    lines.next()
    out = []
    while True:
        tokens = lines.peek()
        if tokens is None or tokens[0].text.startswith(":"):
            raise lines.error("expected 'end' closing :hierarchy", tokens[0] if tokens else None)
        lines.next()
        if tokens[0].text.lower() == "end" and len(tokens) == 1:
            return out
        if len(tokens) < 2:
            raise lines.error(f"expected a parent and its children, found only {quoted(tokens[0].text)}", tokens[0])
        out.append(tokens)


def _parents(lines: _Lines, bones: list[AcclaimBone], hierarchy: list[list[_Token]], keyword: _Token) -> list[int]:
    """Parent index per bone (-1: the root) from the ``:hierarchy`` lines; every bone must
    hang from the root exactly once, without cycles."""
    index = {b.name: i for i, b in enumerate(bones)}
    parent_of: dict[int, tuple[int, _Token]] = {}
    for tokens in hierarchy:
        parent_token, children = tokens[0], tokens[1:]
        if parent_token.text == ROOT_NAME:
            parent = -1
        elif parent_token.text in index:
            parent = index[parent_token.text]
        else:
            raise lines.error(
                f"unknown bone {quoted(parent_token.text)} in :hierarchy (not in :bonedata)", parent_token
            )
        for child_token in children:
            if child_token.text == ROOT_NAME:
                raise lines.error(f"'{ROOT_NAME}' cannot be a child (it is the top of the hierarchy)", child_token)
            child = index.get(child_token.text)
            if child is None:
                raise lines.error(
                    f"unknown bone {quoted(child_token.text)} in :hierarchy (not in :bonedata)", child_token
                )
            if child in parent_of:
                first = parent_of[child][1]
                raise lines.error(
                    f"bone '{child_token.text}' has a second parent (first given at line {first.line})", child_token
                )
            if child == parent:
                raise lines.error(f"bone '{child_token.text}' is its own parent", child_token)
            parent_of[child] = (parent, child_token)
    parents = [parent_of.get(i, (None, None))[0] for i in range(len(bones))]
    orphans = [bones[i].name for i, p in enumerate(parents) if p is None]
    if orphans:
        raise lines.error(
            f"bones not in :hierarchy (no parent): {', '.join(orphans)}; every bone must hang from the root",
            keyword,
        )
    # cycles: walk up from every bone; a walk longer than the bone count never reaches the root
    for start in range(len(bones)):
        j, steps = start, 0
        while j >= 0:
            j = parents[j]
            steps += 1
            if steps > len(bones):
                cycle_token = parent_of[start][1]
                raise lines.error(
                    f"bone '{bones[start].name}' is in a cycle in :hierarchy: it never reaches '{ROOT_NAME}'",
                    cycle_token,
                )
    return [int(p) for p in parents]
