"""Joint-name maps: which joint of one skeleton is which joint of another.

Two files of the same capture name their joints differently (CMU's BVH says ``LeftUpLeg``
where its ASF says ``lhipjoint``). A joint-name map is a small TOML file
(``resources/jointmaps/*.toml``; format in ``docs/formats.md``) listing pairs ``A = "B"``;
:func:`load_joint_map` reads one into a :class:`JointMap`, and :func:`match_joints` pairs the
joints of two name lists, through a map or by name. Pairs are one to one, so a map reads in
both directions (:meth:`JointMap.reversed`); :func:`match_joints` picks the direction that
fits the names it is given. End sites are joints like any other (BVH readers name them
``<parent>_End``).
"""

from __future__ import annotations

import dataclasses
import re
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path

from gmr_studio.core.errors import MotionFileError
from gmr_studio.resources import resource_path

MAPS_DIR = resource_path("jointmaps")
FORMAT = "gmr-jointmap 1"


@dataclasses.dataclass(frozen=True)
class JointMap:
    """Pairs of joint names, ``a`` side -> ``b`` side, one to one, in file order.

    ``side_a``/``side_b`` say what each side names (free text), ``source`` where it came from.
    """

    name: str
    pairs: tuple[tuple[str, str], ...]
    description: str = ""
    side_a: str = ""
    side_b: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        for side, names in (("a", [p[0] for p in self.pairs]), ("b", [p[1] for p in self.pairs])):
            seen: set[str] = set()
            for joint in names:
                if not isinstance(joint, str) or not joint:
                    raise ValueError(f"joint names must be non-empty strings, not {joint!r}")
                if joint in seen:
                    raise ValueError(f"joint {joint!r} is paired twice on side {side}: pairs are one to one")
                seen.add(joint)

    @classmethod
    def from_pairs(cls, pairs: Mapping[str, str] | Sequence[tuple[str, str]], name: str = "explicit") -> JointMap:
        """A map given in code: ``{"Hips": "root", ...}`` or ``[("Hips", "root"), ...]``."""
        items = pairs.items() if isinstance(pairs, Mapping) else pairs
        return cls(name=name, pairs=tuple((str(a), str(b)) for a, b in items))

    @property
    def a_to_b(self) -> dict[str, str]:
        return dict(self.pairs)

    @property
    def b_to_a(self) -> dict[str, str]:
        return {b: a for a, b in self.pairs}

    def reversed(self) -> JointMap:
        """The same map read from ``b`` to ``a``."""
        return dataclasses.replace(
            self, pairs=tuple((b, a) for a, b in self.pairs), side_a=self.side_b, side_b=self.side_a
        )


@dataclasses.dataclass(frozen=True)
class JointMatch:
    """Joints of A paired with joints of B.

    pairs: (index in A, index in B), sorted by A's index; unmatched_a / unmatched_b: the
    names left over on each side, in their list's order; reversed_map: the map was read from
    its ``b`` side to its ``a`` side (because A's names are the map's ``b`` names).
    """

    pairs: list[tuple[int, int]]
    unmatched_a: list[str]
    unmatched_b: list[str]
    reversed_map: bool = False

    @property
    def index_a(self) -> list[int]:
        return [a for a, _ in self.pairs]

    @property
    def index_b(self) -> list[int]:
        return [b for _, b in self.pairs]


def available_joint_maps() -> list[str]:
    """Names of the shipped maps (``resources/jointmaps/*.toml``)."""
    return sorted(p.stem for p in MAPS_DIR.glob("*.toml"))


def read_toml(path: str | Path) -> dict:
    """A TOML file as a dict; MotionFileError (with line and column where TOML says) otherwise."""
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise MotionFileError(path, f"cannot read the file: {exc.strerror or exc}") from None
    try:
        return tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise MotionFileError(path, "bytes that are not UTF-8 text") from exc
    except tomllib.TOMLDecodeError as exc:
        found = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        message = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(exc))
        line, column = (int(found[1]), int(found[2])) if found else (None, None)
        raise MotionFileError(path, f"not valid TOML: {message}", line, column) from None


def load_joint_map(name_or_path: str | Path | JointMap | Mapping[str, str]) -> JointMap:
    """A joint map by name (a file in ``resources/jointmaps/``), by path, or given as pairs.

    Raises MotionFileError for a missing or bad file (unknown names list the shipped maps).
    """
    if isinstance(name_or_path, JointMap):
        return name_or_path
    if isinstance(name_or_path, Mapping):
        return JointMap.from_pairs(name_or_path)
    text = str(name_or_path)
    path = Path(text)
    if not path.suffix and not path.exists():
        path = MAPS_DIR / f"{text}.toml"
        if not path.exists():
            known = ", ".join(available_joint_maps())
            raise MotionFileError(text, f"no joint map of that name: known maps are {known}")
    table = read_toml(path)
    if table.get("format", FORMAT) != FORMAT:
        raise MotionFileError(path, f"format is {table['format']!r}: expected {FORMAT!r}")
    pairs = table.get("pairs")
    if not isinstance(pairs, dict) or not pairs:
        raise MotionFileError(path, 'a joint map needs a [pairs] table of A = "B" lines')
    bad = [key for key, value in pairs.items() if not isinstance(value, str)]
    if bad:
        raise MotionFileError(path, f"pair {bad[0]!r} must be a joint name in quotes")
    texts = {key: table.get(key, "") for key in ("name", "description", "a", "b")}
    if not all(isinstance(value, str) for value in texts.values()):
        raise MotionFileError(path, "name, description, a and b must be strings")
    try:
        return JointMap(
            name=texts["name"] or path.stem,
            pairs=tuple(pairs.items()),
            description=texts["description"],
            side_a=texts["a"],
            side_b=texts["b"],
            source=str(path),
        )
    except ValueError as exc:
        raise MotionFileError(path, str(exc)) from None


def match_joints(
    names_a: Sequence[str],
    names_b: Sequence[str],
    joint_map: str | Path | JointMap | Mapping[str, str] | None = None,
) -> JointMatch:
    """Pair the joints of A with those of B.

    Without a map, equal names pair. With one, its pairs come first, read in the direction
    that pairs more joints (A may hold the map's ``b`` names); joints the map does not pair
    then pair by equal name (a BVH compared with its own export through the CMU map still
    matches everything). Each joint is paired at most once.
    """
    names_a, names_b = list(names_a), list(names_b)
    index_b = {n: i for i, n in enumerate(names_b)}
    pairs: dict[int, int] = {}
    reversed_map = False
    if joint_map is not None:
        loaded = load_joint_map(joint_map)
        forward, backward = _map_pairs(names_a, index_b, loaded.a_to_b), _map_pairs(names_a, index_b, loaded.b_to_a)
        reversed_map = len(backward) > len(forward)
        pairs = backward if reversed_map else forward
    used_b = set(pairs.values())
    for i, name in enumerate(names_a):
        j = index_b.get(name)
        if i not in pairs and j is not None and j not in used_b:
            pairs[i] = j
            used_b.add(j)
    return JointMatch(
        pairs=sorted(pairs.items()),
        unmatched_a=[n for i, n in enumerate(names_a) if i not in pairs],
        unmatched_b=[n for j, n in enumerate(names_b) if j not in used_b],
        reversed_map=reversed_map,
    )


def _map_pairs(names_a: list[str], index_b: dict[str, int], mapping: dict[str, str]) -> dict[int, int]:
    return {i: index_b[mapping[n]] for i, n in enumerate(names_a) if n in mapping and mapping[n] in index_b}
