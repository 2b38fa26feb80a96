"""Marker sets recognised from their labels: Plug-in Gait, CGM 2.x, Helen Hayes, CMU, OpenSim, Qualisys.

A *marker set* is the list of markers a lab places (a protocol); it is described by a TOML file
in ``resources/markermaps/sets/`` (format ``gmr-markerset 1``, documented in
``docs/markers.md``):

- ``sides = ["L", "R"]``: the prefixes of left and right labels (``L_``/``R_`` for Qualisys,
  ``L.``/``R.`` for OpenSim's gait2392);
- ``[roles.sided]`` and ``[roles.centre]``: the project's role names (Plug-in Gait's, e.g.
  ``ASI``, ``KNE``, ``C7``) -> this set's label; a sided role gives the *left* label and the
  right one swaps the prefix; a list gives alternatives tried in order; ``"A+B"`` is the mean
  of two markers;
- ``required`` (roles; ``"PSI|SACR"``: either) and ``optional`` roles.

:func:`identify_marker_set` scores every known set against a file's labels (subject prefixes
already stripped by the readers: ``A22:RKNE`` is ``RKNE``) and returns the best
:class:`SetMatch`: the set, the labels it lacks, and the optional groups present.
:func:`role_positions` gives each role's trajectory, ``(F, 3)`` (NaN in gaps), for the
skeleton builder (:mod:`core.markers.build`).
"""

from __future__ import annotations

import dataclasses
import tomllib
from collections.abc import Sequence
from functools import lru_cache
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.resources import resource_path

SETS_DIR = resource_path("markermaps", "sets")
FORMAT = "gmr-markerset 1"
SIDES = ("L", "R")
#: share of a set's required markers a file needs for "this is set X, missing ..."
NEAR_MATCH = 0.6


@dataclasses.dataclass(frozen=True)
class MarkerSetDefinition:
    """One known marker set (a protocol). ``roles`` maps a role (``"LKNE"`` for sided roles,
    ``"C7"`` for centre ones) to its alternative labels in this set; ``required`` holds
    alternatives groups: each a tuple of roles of which one must be present."""

    name: str
    title: str
    description: str
    roles: dict[str, tuple[str, ...]]
    required: tuple[tuple[str, ...], ...]
    optional: tuple[str, ...]
    source: str = ""

    def labels_of(self, role: str) -> tuple[str, ...]:
        return self.roles.get(role, ())

    def sided_roles(self) -> set[str]:
        """The roles that come in a left and a right version, without the side letter."""
        return {r[1:] for r in self.roles if r[:1] == "L" and "R" + r[1:] in self.roles}


@dataclasses.dataclass(frozen=True)
class SetMatch:
    """How well a file's labels fit a set: ``found`` role -> the label (or ``A+B``) used,
    ``missing`` the labels of required roles the file lacks, ``score`` the share of required
    roles present, ``optional`` the optional roles present."""

    definition: MarkerSetDefinition
    found: dict[str, str]
    missing: tuple[str, ...]
    score: float
    optional: tuple[str, ...]

    @property
    def complete(self) -> bool:
        return not self.missing

    def summary(self) -> str:
        """One line: ``plug-in-gait-full (Plug-in Gait full body (Vicon)), with KNM, MED; missing RFIN``."""
        text = f"{self.definition.name} ({self.definition.title})"
        if self.optional:
            sided = self.definition.sided_roles()
            roles = dict.fromkeys(r[1:] if r[:1] in SIDES and r[1:] in sided else r for r in self.optional)
            text += f", with {', '.join(roles)}"
        if self.missing:
            text += f"; missing {', '.join(self.missing)}"
        return text


def _sided(label: str, sides: tuple[str, str], path: Path) -> tuple[str, str]:
    left, right = sides
    if not label.startswith(left):
        raise MotionFileError(path, f"sided role label {label!r} does not start with the left prefix {left!r}")
    return label, right + label[len(left) :]


def _swap_all(text: str, sides: tuple[str, str]) -> str:
    return "+".join(sides[1] + part[len(sides[0]) :] for part in text.split("+"))


def load_set_definition(path: str | Path) -> MarkerSetDefinition:
    """One set file; MotionFileError (with line and column from TOML) for a bad one."""
    path = Path(path)
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise MotionFileError(path, f"not a readable marker-set TOML file: {exc}") from None
    if table.get("format") != FORMAT:
        raise MotionFileError(path, f"format is {table.get('format')!r}: expected {FORMAT!r}")
    sides = tuple(table.get("sides", SIDES))
    if len(sides) != 2:
        raise MotionFileError(path, "sides must give the left and the right prefix")
    roles: dict[str, tuple[str, ...]] = {}
    section = table.get("roles", {})
    for role, value in section.get("sided", {}).items():
        labels = (value,) if isinstance(value, str) else tuple(value)
        for label in labels:
            _sided(label.split("+")[0], sides, path)
        roles["L" + role] = labels
        roles["R" + role] = tuple(_swap_all(label, sides) for label in labels)
    for role, value in section.get("centre", {}).items():
        roles[role] = (value,) if isinstance(value, str) else tuple(value)
    sided = set(section.get("sided", {}))
    required: list[tuple[str, ...]] = []
    for entry in table.get("required", []):
        choices = entry.split("|")
        unknown = [c for c in choices if c not in sided and c not in roles]
        if unknown:
            raise MotionFileError(path, f"required role {', '.join(unknown)} has no label in [roles]")
        if all(c in sided for c in choices):
            required += [tuple("L" + c for c in choices), tuple("R" + c for c in choices)]
        else:
            required.append(tuple(c if c in roles else "L" + c for c in choices))
    optional: list[str] = []
    for role in table.get("optional", []):
        optional += ["L" + role, "R" + role] if role in sided else [role]
    return MarkerSetDefinition(
        name=str(table.get("name", path.stem)),
        title=str(table.get("title", path.stem)),
        description=str(table.get("description", "")),
        roles=roles,
        required=tuple(required),
        optional=tuple(optional),
        source=str(path),
    )


@lru_cache(maxsize=1)
def known_sets() -> tuple[MarkerSetDefinition, ...]:
    """Every set file shipped in ``resources/markermaps/sets/``, by file name."""
    return tuple(load_set_definition(p) for p in sorted(Path(SETS_DIR).glob("*.toml")))


def set_by_name(name: str) -> MarkerSetDefinition:
    for definition in known_sets():
        if definition.name == name:
            return definition
    if Path(name).suffix == ".toml":
        return load_set_definition(name)
    raise MotionFileError(name, f"no marker set of that name: known sets are {', '.join(s.name for s in known_sets())}")


def _resolve(labels: set[str], alternatives: Sequence[str]) -> str | None:
    for label in alternatives:
        if all(part in labels for part in label.split("+")):
            return label
    return None


def match_set(labels: Sequence[str], definition: MarkerSetDefinition) -> SetMatch:
    """How ``labels`` (bare, without subject prefixes) fit ``definition``."""
    present = set(labels)
    found = {r: hit for r, alts in definition.roles.items() if (hit := _resolve(present, alts)) is not None}
    missing: list[str] = []
    for choices in definition.required:
        if not any(c in found for c in choices):
            first = definition.labels_of(choices[0])
            missing += [part for part in first[0].split("+") if part not in present and part not in missing]
    have = sum(any(c in found for c in choices) for choices in definition.required)
    score = have / max(len(definition.required), 1)
    optional = tuple(r for r in definition.optional if r in found)
    return SetMatch(definition, found, tuple(missing), score, optional)


def identify_marker_set(
    markers: MarkerSet | Sequence[str], candidates: Sequence[MarkerSetDefinition] | None = None
) -> SetMatch | None:
    """The known set the labels fit best, or None when none reaches :data:`NEAR_MATCH`.

    Markers that are gaps in every frame do not count. Ranking: complete sets first, then the
    number of required roles present (Plug-in Gait full body before lower body; a full-body
    file lacking a marker is still full body), then fewer missing, then the number of optional
    roles present, then file order.
    """
    if isinstance(markers, MarkerSet):
        seen = markers.present.any(axis=0) if markers.n_frames else np.zeros(markers.n_markers, bool)
        labels = [label for label, s in zip(markers.labels, seen) if s]
    else:
        labels = list(markers)
    matches = [match_set(labels, d) for d in (candidates or known_sets())]
    matches = [m for m in matches if m.score >= NEAR_MATCH]
    if not matches:
        return None
    return max(
        matches,
        key=lambda m: (m.complete, round(m.score * len(m.definition.required)), -len(m.missing), len(m.optional)),
    )


def _some(labels: Sequence[str], most: int = 8) -> str:
    """``"A, B, C"``, at most ``most`` of them, then ``" (+N more)"``; ``"none"`` if empty."""
    shown = ", ".join(labels[:most]) or "none"
    return shown + (f" (+{len(labels) - most} more)" if len(labels) > most else "")


def no_match_text(labels: Sequence[str], never_seen: Sequence[str] = ()) -> str:
    """What to say when no known set fits ``labels`` (the markers seen at least once): the
    three nearest sets with the share of their required markers present, the file's labels
    each matched and the labels it misses; the labels in the file but never seen; and how
    to map the markers oneself (``--skeleton`` with a marker map, ``--map FILE.toml``)."""
    scored = sorted((match_set(labels, d) for d in known_sets()), key=lambda m: -m.score)[:3]
    near = []
    for m in scored:
        matched = list(dict.fromkeys(part for label in m.found.values() for part in label.split("+")))
        near.append(
            f"{m.definition.name} {100 * m.score:.0f}% (matched {_some(matched)}; missing {_some(list(m.missing))})"
        )
    unseen = f"; in the file but never seen: {_some(list(never_seen))}" if never_seen else ""
    return (
        "no known marker set fits these labels (nearest: " + "; ".join(near) + unseen + "). To convert them, "
        "give a skeleton and a marker map of your own: gmr markers FILE --skeleton S.asf|S.bvh --map MAP.toml, "
        "the map placing each joint from the markers that locate it (the pelvis from left and right ASIS and "
        "PSIS or a sacral marker; knees and ankles from lateral (and medial) markers with a thigh and a shank "
        "marker; heel and toe; C7, CLAV, shoulder, elbow, wrist and hand markers); see docs/markers.md, "
        "'Marker maps'"
    )


def role_positions(markers: MarkerSet, match: SetMatch) -> dict[str, np.ndarray]:
    """Each found role's positions (F, 3) in the markers' units and axes (mean for ``A+B``)."""
    out: dict[str, np.ndarray] = {}
    for role, label in match.found.items():
        parts = [markers.positions[:, markers.index(p)] for p in label.split("+")]
        out[role] = parts[0] if len(parts) == 1 else np.mean(parts, axis=0)
    return out
