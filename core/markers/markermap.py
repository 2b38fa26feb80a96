"""Marker maps: how each virtual marker (a joint centre of a skeleton) comes from real markers.

A map is a small TOML file (``resources/markermaps/*.toml``; the format is documented in
``docs/markers.md``), loaded by :func:`load_marker_map` into a :class:`MarkerMap`:

- ``units``: the length unit the map works in (markers are converted to it first);
- ``[alignment]``: ``skeleton = scale * rotation @ marker + offset``, from the marker
  file's axes and units to the skeleton's (CMU: Z-up millimetres to Y-up ASF units), read
  as a :class:`~core.space.similarity.Similarity` (the file's ``offset`` its translation);
- ``[pelvis]``: ``markers = [X1, X2, X3]``, the three virtual markers of the technical
  note (pelvis root, left femur, lower back: any three points rigid with the pelvis, X1 the
  skeleton's root), with optional ``home`` positions (their rest-pose positions in
  skeleton units);
- ``[bones]`` (optional): ``JOINT = "START"``, the virtual marker where each joint's bone
  starts on the skeleton the map was made for (its parent joint). On a skeleton named
  otherwise, a bone is aimed from its start even where that skeleton has no joint there
  (CMU's BVH dropped the ASF's thorax bone: its clavicles start at the thorax's end);
- ``[virtual.NAME]``, one per virtual marker, in the order they are computed, NAME being a
  skeleton joint. One of ``marker = "LABEL"`` (the marker itself), ``mean = [labels]`` (the
  mean of markers) or ``cluster = [labels]`` (three or more markers moving as one rigid
  body) with ``offset`` (the virtual marker in the cluster's frame) and ``template`` (the
  cluster's markers in that frame), both found by calibration. A label written ``@NAME``
  is an earlier virtual marker (the hip centre helps to define the thigh).

The built-in map ``"joints"`` takes markers labelled with the joint names as the joint
centres themselves (the exact case): :func:`joints_map`.
"""

from __future__ import annotations

import dataclasses
import re
import tomllib
from collections.abc import Sequence
from pathlib import Path
from typing import Literal

import numpy as np

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.space.units import UNITS, parse_unit
from gmr_studio.resources import resource_path

MAPS_DIR = resource_path("markermaps")
FORMAT = "gmr-markermap 1"
Kind = Literal["marker", "mean", "cluster"]

#: names of the pelvis triple tried, in order, when a map does not say (CMU ASF, CMU BVH, common)
PELVIS_GUESSES = (
    ("root", "lhipjoint", "rhipjoint"),
    ("Hips", "LeftUpLeg", "RightUpLeg"),
    ("Hips", "LeftHip", "RightHip"),
    ("pelvis", "l_hip", "r_hip"),
)


@dataclasses.dataclass(frozen=True, eq=False)
class VirtualMarker:
    """One virtual marker: ``name`` (a skeleton joint), ``kind``, the ``markers`` it uses
    (``@NAME`` for an earlier virtual marker), and for a cluster the calibrated ``offset``
    (3,) and ``template`` (K, 3) in the cluster's frame (map units) and the calibration
    ``rms`` (map units); None before calibration."""

    name: str
    kind: Kind
    markers: tuple[str, ...]
    offset: np.ndarray | None = None
    template: np.ndarray | None = None
    rms: float | None = None

    @property
    def calibrated(self) -> bool:
        return self.kind != "cluster" or (self.offset is not None and self.template is not None)


@dataclasses.dataclass(frozen=True, eq=False)
class MarkerMap:
    """A loaded marker map; see the module docstring. ``joints`` marks the built-in map,
    whose virtual markers are all the markers (or joints) there are."""

    name: str
    virtual: tuple[VirtualMarker, ...]
    pelvis: tuple[str, str, str] | None = None
    pelvis_home: np.ndarray | None = None
    units: str | None = None
    alignment: Similarity = dataclasses.field(default_factory=Similarity)
    description: str = ""
    calibration: dict = dataclasses.field(default_factory=dict)
    source: str = ""
    joints: bool = False
    pelvis_note: str = ""  # how the pelvis triple was chosen, when the map did not name it
    renamed: str = ""  # how its joint names were renamed for another skeleton (core.markers.joint_names)
    bone_starts: dict[str, str] = dataclasses.field(default_factory=dict)  # [bones]: joint -> its bone's start

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.virtual)

    def replace(self, **changes) -> MarkerMap:
        return dataclasses.replace(self, **changes)

    def labels(self) -> list[str]:
        """Every real marker label the map reads, in first-use order."""
        out: list[str] = []
        for v in self.virtual:
            out += [m for m in v.markers if not m.startswith("@") and m not in out]
        return out


def joints_map(names: Sequence[str], pelvis: tuple[str, str, str] | None = None) -> MarkerMap:
    """The built-in ``joints`` map: each name is both a marker label and a virtual marker."""
    return MarkerMap(
        name="joints",
        virtual=tuple(VirtualMarker(n, "marker", (n,)) for n in names),
        pelvis=pelvis or guess_pelvis(names),
        description="markers labelled with the skeleton's joint names are the joint centres",
        joints=True,
    )


def guess_pelvis(names: Sequence[str]) -> tuple[str, str, str] | None:
    """The first of :data:`PELVIS_GUESSES` whose three names all occur (case-insensitive)."""
    lower = {n.lower(): n for n in names}
    for guess in PELVIS_GUESSES:
        if all(g.lower() in lower for g in guess):
            return tuple(lower[g.lower()] for g in guess)  # type: ignore[return-value]
    return None


def load_marker_map(name_or_path: str | Path | MarkerMap) -> MarkerMap:
    """A marker map by name (``"joints"``, or a file in ``resources/markermaps/``) or path.

    Raises MotionFileError (with line and column where TOML says) for a bad file.
    """
    if isinstance(name_or_path, MarkerMap):
        return name_or_path
    text = str(name_or_path)
    if text == "joints":
        return joints_map(())
    path = Path(text)
    if not path.suffix and not path.exists():
        path = MAPS_DIR / f"{text}.toml"
        if not path.exists():
            known = ", ".join(["joints", *sorted(p.stem for p in MAPS_DIR.glob("*.toml"))])
            raise MotionFileError(text, f"no marker map of that name: known maps are {known}")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise MotionFileError(path, f"cannot read the marker map: {exc.strerror or exc}") from None
    try:
        table = tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise MotionFileError(path, "bytes that are not UTF-8 text", None) from exc
    except tomllib.TOMLDecodeError as exc:
        found = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        message = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(exc))
        line, column = (int(found[1]), int(found[2])) if found else (None, None)
        raise MotionFileError(path, f"not valid TOML: {message}", line, column) from None
    return _map_from_table(table, path)


def _map_from_table(table: dict, path: Path) -> MarkerMap:
    def fail(message: str) -> MotionFileError:
        return MotionFileError(path, message)

    if table.get("format", FORMAT) != FORMAT:
        raise fail(f"format is {table['format']!r}: expected {FORMAT!r}")
    units = table.get("units")
    if units is not None and (not isinstance(units, str) or parse_unit(units) is None):
        raise fail(f"units {units!r}: expected one of {', '.join(UNITS)}")
    try:
        section = table.get("alignment", {})
        alignment = Similarity(  # the file's "offset" is the transform's translation
            np.array(section.get("rotation", np.eye(3)), dtype=float),
            float(section.get("scale", 1.0)),
            np.array(section.get("offset", (0.0, 0.0, 0.0)), dtype=float),
        )
    except (ValueError, TypeError) as exc:
        raise fail(f"[alignment]: {exc}") from None
    virtual: list[VirtualMarker] = []
    for name, entry in table.get("virtual", {}).items():
        virtual.append(_virtual_marker(name, entry, [v.name for v in virtual], fail))
    if not virtual:
        raise fail("the map defines no [virtual.NAME] section")
    pelvis, home = None, None
    if "pelvis" in table:
        section = table["pelvis"]
        names = section.get("markers")
        if not isinstance(names, list) or len(names) != 3 or not all(isinstance(n, str) for n in names):
            raise fail("[pelvis] needs markers = [X1, X2, X3]: pelvis root, left femur, lower back")
        pelvis = (names[0], names[1], names[2])
        missing = [p for p in pelvis if p not in {v.name for v in virtual}]
        if missing:
            raise fail(f"[pelvis] names {', '.join(missing)}, which the map does not define")
        if "home" in section:
            home = np.array(section["home"], dtype=float)
            if home.shape != (3, 3):
                raise fail("[pelvis] home must be three points of three numbers")
    bones = table.get("bones", {})
    defined = {v.name for v in virtual}
    if not isinstance(bones, dict) or not all(isinstance(s, str) for s in bones.values()):
        raise fail('[bones] needs JOINT = "START" lines')
    strangers = [f"{k} = {s}" for k, s in bones.items() if k not in defined or s not in defined]
    if strangers:
        raise fail(f"[bones] names virtual markers the map does not define: {', '.join(strangers)}")
    return MarkerMap(
        name=str(table.get("name", path.stem)),
        virtual=tuple(virtual),
        bone_starts=dict(bones),
        pelvis=pelvis,
        pelvis_home=home,
        units=units,
        alignment=alignment,
        description=str(table.get("description", "")),
        calibration=dict(table.get("calibration", {})),
        source=str(path),
    )


def _virtual_marker(name: str, entry: dict, earlier: list[str], fail) -> VirtualMarker:
    kinds = [k for k in ("marker", "mean", "cluster") if k in entry]
    if len(kinds) != 1:
        raise fail(f"[virtual.{name}] needs exactly one of marker, mean, cluster")
    kind = kinds[0]
    value = entry[kind]
    markers = (value,) if kind == "marker" else tuple(value)
    if not markers or not all(isinstance(m, str) and m for m in markers):
        raise fail(f"[virtual.{name}] {kind} must name markers")
    for m in markers:
        if m.startswith("@") and m[1:] not in earlier:
            raise fail(f"[virtual.{name}] uses {m}, which is not an earlier virtual marker")
    if kind == "cluster" and len(markers) < 3:
        raise fail(f"[virtual.{name}] a cluster needs at least three markers")
    offset = template = None
    if kind == "cluster" and ("offset" in entry or "template" in entry):
        offset = np.array(entry.get("offset"), dtype=float)
        template = np.array(entry.get("template"), dtype=float)
        if offset.shape != (3,) or template.shape != (len(markers), 3):
            raise fail(f"[virtual.{name}] offset must be 3 numbers and template {len(markers)} points")
    rms = entry.get("rms")
    return VirtualMarker(name, kind, markers, offset, template, None if rms is None else float(rms))


# ------------------------------------------------------------------------------ writing
def marker_map_text(marker_map: MarkerMap) -> str:
    """The map as TOML text (what :func:`load_marker_map` reads back)."""
    a = marker_map.alignment
    lines = [
        f"format = {_string(FORMAT)}",
        f"name = {_string(marker_map.name)}",
        f"description = {_string(marker_map.description)}",
    ]
    if marker_map.units:
        lines.append(f"units = {_string(marker_map.units)}")
    lines += [
        "",
        "# skeleton = scale * rotation @ marker + offset",
        "[alignment]",
        f"rotation = {_matrix(a.rotation)}",
        f"scale = {_number(a.scale)}",
        f"offset = {_vector(a.translation)}",
    ]
    if marker_map.pelvis:
        lines += ["", "# X1 pelvis root, X2 left femur, X3 lower back (technical note, section 1)", "[pelvis]"]
        lines.append(f"markers = [{', '.join(_string(n) for n in marker_map.pelvis)}]")
        if marker_map.pelvis_home is not None:
            lines.append(f"home = {_matrix(marker_map.pelvis_home)}")
    if marker_map.bone_starts:
        lines += ["", "# each joint's bone starts at this virtual marker (the skeleton's parent joint)", "[bones]"]
        lines += [f"{_key(k)} = {_string(s)}" for k, s in marker_map.bone_starts.items()]
    if marker_map.calibration:
        lines += ["", "[calibration]"]
        for key, value in marker_map.calibration.items():
            lines.append(f"{_key(key)} = {_string(value) if isinstance(value, str) else _number(value)}")
    for v in marker_map.virtual:
        lines += ["", f"[virtual.{_key(v.name)}]"]
        if v.kind == "marker":
            lines.append(f"marker = {_string(v.markers[0])}")
        else:
            lines.append(f"{v.kind} = [{', '.join(_string(m) for m in v.markers)}]")
        if v.offset is not None and v.template is not None:
            lines.append(f"offset = {_vector(v.offset)}")
            lines.append(f"template = {_matrix(v.template)}")
        if v.rms is not None:
            lines.append(f"rms = {_number(v.rms)}")
    return "\n".join(lines) + "\n"


def save_marker_map(marker_map: MarkerMap, path: str | Path) -> None:
    """Write the map as TOML, atomically."""
    atomic_write_text(path, marker_map_text(marker_map))


#: TOML basic-string escapes: backslash, quote, and every control character (a raw newline in
#: a description or a label would end the string and make the file unreadable)
_ESCAPES = {c: f"\\u{c:04x}" for c in (*range(0x20), 0x7F)} | {
    ord("\\"): "\\\\",
    ord('"'): '\\"',
    ord("\n"): "\\n",
    ord("\t"): "\\t",
    ord("\r"): "\\r",
}


def _string(text: str) -> str:
    return f'"{text.translate(_ESCAPES)}"'


def _key(text: str) -> str:
    return text if re.fullmatch(r"[A-Za-z0-9_-]+", text) else _string(text)


def _number(value: float) -> str:
    return repr(float(value)) if np.isfinite(value) else _string(str(value))


def _vector(values: np.ndarray) -> str:
    return "[" + ", ".join(_number(v) for v in values) + "]"


def _matrix(rows: np.ndarray) -> str:
    return "[" + ", ".join(_vector(r) for r in np.asarray(rows)) + "]"
