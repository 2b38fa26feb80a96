"""Finding takes in the library: filters, sorting, and rows as JSON and CSV.

A :class:`Query` is what ``gmr library list|query`` and the app's filter box ask for; every
filter it holds must hold (AND). :func:`select_rows` answers it as JSON-ready dicts
(:func:`row_json`, docs/library.md), :func:`select_ids` as row ids in order, a page of them at
a time if asked (the app's table reads the ids of the rows in view, then those rows),
:func:`count` (:func:`first_ids`: both for the first block), and :func:`positions` where
given rows come in that order.

The filter box's text (:func:`parse_filter`) holds the same filters as words:
``walk format:bvh min:2 max:10 joints:31 has:pop:warning group:3 failed``; words that are
no filter match the name (all of them, anywhere in it, any case; ``*`` and ``?`` make a
word a pattern of the whole name).
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import sqlite3
from collections.abc import Mapping, Sequence

import numpy as np

from gmr_studio.core.checks import KINDS, SEVERITIES
from gmr_studio.core.library.skeletons import GROUP_MATCH, Skeleton, match_score

#: ``--sort`` fields and the columns they sort by, one or several, then by path (ties in the
#: path's order); a file without the value (a failed file's frames) comes first going up, last
#: going down. The fields the panel sorts by have an index that gives that order
#: (:data:`core.library.schema.FILE_INDEXES`); the others are sorted when asked.
SORT_FIELDS: dict[str, str | tuple[str, ...]] = {
    "path": "files.path",
    "name": "files.name COLLATE NOCASE",
    "format": "files.format",
    "status": "files.status",
    "frames": "files.frames",
    "rate": "files.frame_rate",
    "duration": "files.duration",
    "joints": "files.joints",
    "roots": "files.roots",
    "markers": "files.markers",
    "size": "files.size",
    "modified": "files.mtime_ns",
    "group": "files.skeleton_group",
    "findings": "files.findings",
    "errors": "files.errors",
    "warnings": "files.warnings",
    "infos": "files.infos",
    "worst": "files.worst_level",
    "problems": ("files.worst_level", "files.errors", "files.warnings", "files.infos"),
    "indexed": "files.indexed_at",
}


@dataclasses.dataclass(frozen=True)
class Query:
    """Filters and order (every filter left at its default lets every row through).

    name : a pattern (``*``, ``?``, ``[...]``) of the file name, any case; of the whole path
        when it holds a ``/``.
    words : words each found somewhere in the name, any case.
    formats : file formats (``bvh``, ``c3d``...), any of them.
    min_duration, max_duration : seconds, both included.
    joints : the exact joint count.
    groups : skeleton groups, any of them.
    skeleton : rows whose skeleton matches this one at ``min_match`` or better
        (:func:`core.library.skeletons.match_score`).
    has : (kind, level): a finding of that kind (``any``: of any kind) at that level
        (1 info, 2 warning, 3 error) or worse; every pair must hold.
    failed : only the files that could not be read.
    sort : a key of :data:`SORT_FIELDS`; ``descending`` reverses it.
    """

    name: str | None = None
    words: tuple[str, ...] = ()
    formats: tuple[str, ...] = ()
    min_duration: float | None = None
    max_duration: float | None = None
    joints: int | None = None
    groups: tuple[int, ...] = ()
    skeleton: Skeleton | None = None
    min_match: float = GROUP_MATCH
    has: tuple[tuple[str, int], ...] = ()
    failed: bool = False
    sort: str = "path"
    descending: bool = False

    def __post_init__(self) -> None:
        if self.sort not in SORT_FIELDS:
            raise ValueError(f"cannot sort by {self.sort!r}: expected one of {', '.join(SORT_FIELDS)}")
        for kind, level in self.has:
            if kind != "any" and kind not in KINDS:
                raise ValueError(f"unknown kind of problem {kind!r}: expected any or one of {', '.join(KINDS)}")
            if level not in (1, 2, 3):
                raise ValueError(f"a severity level is 1, 2 or 3, not {level}")


def parse_has(text: str) -> tuple[str, int]:
    """``KIND[:SEVERITY]`` -> (kind, level); ValueError naming what was expected."""
    kind, _, severity = text.strip().partition(":")
    severity = severity.strip() or "info"
    if severity not in SEVERITIES:
        raise ValueError(f"{text!r}: the severity is one of {', '.join(SEVERITIES)}, not {severity!r}")
    if kind != "any" and kind not in KINDS:
        raise ValueError(f"{text!r}: the kind is any or one of {', '.join(KINDS)}")
    return kind, SEVERITIES.index(severity) + 1


def parse_sort(text: str) -> tuple[str, bool]:
    """``FIELD`` or ``-FIELD`` (descending) -> (field, descending)."""
    descending = text.startswith("-")
    field = text.lstrip("-")
    if field not in SORT_FIELDS:
        raise ValueError(f"cannot sort by {field!r}: expected one of {', '.join(SORT_FIELDS)}")
    return field, descending


def parse_filter(text: str, base: Query | None = None) -> Query:
    """The filter box's text as a query (module docstring), on top of ``base``'s order;
    ValueError for a filter word with a bad value."""
    changes: dict = {"words": [], "formats": [], "has": [], "groups": []}
    for word in text.split():
        key, sep, value = word.partition(":")
        key = key.lower()
        try:
            if sep and key == "format":
                changes["formats"] += [v.lower().lstrip(".") for v in value.split(",") if v]
            elif sep and key in ("min", "max"):
                changes[f"{key}_duration"] = float(value.lower().rstrip("s"))
            elif sep and key == "joints":
                changes["joints"] = int(value)
            elif sep and key == "group":
                changes["groups"] += [int(v) for v in value.split(",") if v]
            elif sep and key == "has":
                changes["has"].append(parse_has(value))
            elif not sep and key == "failed":
                changes["failed"] = True
            elif any(c in word for c in "*?["):
                changes["name"] = word
            else:
                changes["words"].append(word)
        except ValueError as exc:
            raise ValueError(f"cannot read the filter {word!r}: {exc}") from None
    base = base or Query()
    return dataclasses.replace(
        base,
        name=changes.get("name"),
        words=tuple(changes["words"]),
        formats=tuple(changes["formats"]),
        min_duration=changes.get("min_duration"),
        max_duration=changes.get("max_duration"),
        joints=changes.get("joints"),
        groups=tuple(changes["groups"]),
        has=tuple(changes["has"]),
        failed=changes.get("failed", False),
    )


def matching_skeletons(connection: sqlite3.Connection, skeleton: Skeleton, min_match: float) -> dict[int, float]:
    """skeleton id -> match score, of the library's skeletons that match ``skeleton`` at
    ``min_match`` or better."""
    found = {}
    for row in connection.execute("SELECT id, signature, names, parents FROM skeletons"):
        if row["signature"] == skeleton.signature:
            found[row["id"]] = 1.0
            continue
        other = Skeleton(tuple(json.loads(row["names"])), tuple(json.loads(row["parents"])))
        score = match_score(skeleton, other)
        if score >= min_match:
            found[row["id"]] = score
    return found


def _where(connection: sqlite3.Connection, query: Query) -> tuple[str, list]:
    clauses, values = [], []
    if query.name:
        column = "files.path" if "/" in query.name else "files.name"
        if "[" in query.name:  # a character class: only GLOB has them
            clauses.append(f"lower({column}) GLOB ?")
            values.append(query.name.lower())
        else:  # LIKE ignores case by itself, and is quicker
            clauses.append(f"{column} LIKE ? ESCAPE '\\'")
            values.append(_escaped(query.name).replace("*", "%").replace("?", "_"))
    for word in query.words:
        clauses.append("files.name LIKE ? ESCAPE '\\'")
        values.append("%" + _escaped(word) + "%")
    if query.formats:
        clauses.append(f"files.format IN ({', '.join('?' * len(query.formats))})")
        values += [f.lower().lstrip(".") for f in query.formats]
    if query.min_duration is not None:
        clauses.append("files.duration >= ?")
        values.append(query.min_duration)
    if query.max_duration is not None:
        clauses.append("files.duration <= ?")
        values.append(query.max_duration)
    if query.joints is not None:
        clauses.append("files.joints = ?")
        values.append(query.joints)
    if query.groups:
        clauses.append(f"files.skeleton_group IN ({', '.join('?' * len(query.groups))})")
        values += list(query.groups)
    if query.skeleton is not None:
        ids = matching_skeletons(connection, query.skeleton, query.min_match)
        clauses.append(f"files.skeleton_id IN ({', '.join(str(int(i)) for i in ids) or 'NULL'})")
    for kind, level in query.has:  # the files found through the problems' index
        if kind == "any":
            clauses.append("files.worst_level >= ?")
            values.append(level)
        else:
            clauses.append("files.id IN (SELECT file_id FROM problems WHERE kind = ? AND level >= ?)")
            values += [kind, level]
    if query.failed:
        clauses.append("files.status = 'failed'")
    return (" WHERE " + " AND ".join(clauses)) if clauses else "", values


def _escaped(text: str) -> str:
    """``text`` with LIKE's wildcards and its escape character escaped."""
    return text.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")


#: the filters that an index answers with its rows already in a sort's order: the sort's own
#: field's index, or a ``(field, path)`` index under the path's order (one value a filter)
_IN_ORDER = {
    "path": ("formats", "joints", "groups", "failed"),
    "duration": ("min_duration", "max_duration", "formats"),
    "joints": ("joints",),
    "group": ("groups",),
}
#: the sort fields whose own filter may hold several values and still come in order
_OWN_MANY = {"group": "groups"}
_FILTERS = ("name", "words", "formats", "min_duration", "max_duration", "joints", "groups", "skeleton", "has", "failed")


def _in_order(query: Query) -> bool:
    """Whether one index finds the rows the query's filters let through in its order."""
    active = [a for a in _FILTERS if getattr(query, a) not in (None, (), False)]
    if not set(active) <= set(_IN_ORDER.get(query.sort, ())):
        return False
    many = [a for a in ("formats", "groups") if a in active and a != _OWN_MANY.get(query.sort)]
    equal = [a for a in active if a in ("formats", "joints", "groups", "failed")]
    return all(len(getattr(query, a)) == 1 for a in many) and (query.sort != "path" or len(equal) <= 1)


def _order(query: Query, filtered: bool) -> str:
    """The ORDER BY clause: the sort's columns, then the path. ``filtered`` and the filters'
    rows not found in order (:func:`_in_order`): the columns are written ``+column`` so that
    the filters' indexes find the rows (then sorted), not the sort's index (which would visit
    every row to test the filters)."""
    direction = " DESC" if query.descending else ""
    keys = SORT_FIELDS[query.sort]
    keys = (keys,) if isinstance(keys, str) else keys
    plus = "+" if filtered and not _in_order(query) else ""
    tie = [] if query.sort == "path" else [f"{plus}files.path{direction}"]
    return " ORDER BY " + ", ".join([*(f"{plus}{key}{direction}" for key in keys), *tie])


#: ids a reader of a large result asks for at a time: the app's table reads the count and
#: the first block to show a query's answer, then the blocks it is scrolled to
ID_BLOCK = 2048


def select_ids(
    connection: sqlite3.Connection, query: Query, *, limit: int | None = None, offset: int = 0
) -> np.ndarray:
    """(N,) int64 ids of the rows ``query`` lets through, in its order (the query's indexes
    read; no row is); ``limit`` of them from ``offset``."""
    where, values = _where(connection, query)
    page = f" LIMIT {int(limit)} OFFSET {int(offset)}" if limit is not None else ""
    cursor = connection.execute(f"SELECT id FROM files{where}{_order(query, bool(where))}{page}", values)
    cursor.row_factory = None
    return np.fromiter(itertools.chain.from_iterable(cursor), np.int64)


def first_ids(connection: sqlite3.Connection, query: Query, block: int = ID_BLOCK) -> tuple[int, np.ndarray]:
    """(how many rows ``query`` lets through, the ids of the first ``block`` of them in its
    order): what a reader of a large result shows first. The rows are counted only when
    there are more than a block of them."""
    ids = select_ids(connection, query, limit=block)
    return (len(ids) if len(ids) < block else count(connection, query)), ids


def positions(connection: sqlite3.Connection, query: Query, ids: Sequence[int]) -> dict[int, int]:
    """id -> its place (from 0) among the ids :func:`select_ids` gives, of each of ``ids``
    that ``query`` lets through."""
    if not len(ids):
        return {}
    where, values = _where(connection, query)
    order = _order(query, bool(where))
    marks = ", ".join(str(int(i)) for i in ids)
    cursor = connection.execute(
        f"SELECT id, place FROM (SELECT id, row_number() OVER ({order.strip()}) - 1 AS place FROM files{where}) "
        f"WHERE id IN ({marks})",
        values,
    )
    cursor.row_factory = None
    return dict(cursor.fetchall())


def count(connection: sqlite3.Connection, query: Query | None = None) -> int:
    where, values = _where(connection, query or Query())
    return connection.execute(f"SELECT count(*) FROM files{where}", values).fetchone()[0]


#: the columns a row is read with: the files' that a row shows, its time as text, its
#: skeleton's, and whether it has a thumbnail
_FILE_FIELDS = (
    "id path name folder size mtime_ns hash format kind status message frames frame_rate duration joints roots "
    "markers units up_axis skeleton_id skeleton_group findings infos warnings errors worst worst_frame"
).split()
_ROW_SQL = (
    f"SELECT {', '.join(f'files.{field}' for field in _FILE_FIELDS)}, "
    "strftime('%Y-%m-%dT%H:%M:%SZ', files.mtime_ns / 1000000000, 'unixepoch') AS modified, "
    "skeletons.signature AS skeleton_signature, skeletons.topology AS skeleton_topology, "
    "skeletons.group_match AS skeleton_match, "
    "EXISTS (SELECT 1 FROM thumbnails t WHERE t.file_id = files.id) AS has_thumbnail "
    "FROM files LEFT JOIN skeletons ON skeletons.id = files.skeleton_id"
)
#: more rows than this, all the query lets through: their problems are found through the
#: query's filters, not a list of their ids
_FEW_ROWS = 500


def select_rows(
    connection: sqlite3.Connection, query: Query | None = None, *, limit: int | None = None, offset: int = 0
) -> list[dict]:
    """The rows ``query`` lets through, in its order, as :func:`row_json` dicts; ``limit``
    rows from ``offset`` (a page: the sort's index may find it without reading the rest)."""
    query = query or Query()
    where, values = _where(connection, query)
    page = f" LIMIT {int(limit)} OFFSET {int(offset)}" if limit is not None else ""
    rows = _read_rows(connection, f"{_ROW_SQL}{where}{_order(query, bool(where) and not page)}{page}", values)
    if page or len(rows) <= _FEW_ROWS:
        return _with_problems(connection, rows)
    return _with_problems(connection, rows, f"SELECT files.id FROM files{where}", values)


def rows_by_id(connection: sqlite3.Connection, ids: Sequence[int]) -> dict[int, dict]:
    """id -> :func:`row_json` dict of the rows ``ids`` (ids without a row left out)."""
    if not len(ids):
        return {}
    marks = ", ".join(str(int(i)) for i in ids)
    rows = _read_rows(connection, f"{_ROW_SQL} WHERE files.id IN ({marks})", ())
    return {row["id"]: row for row in _with_problems(connection, rows)}


def row_of_path(connection: sqlite3.Connection, path: str) -> dict | None:
    """The row of the file at ``path`` (absolute), with its skeleton's joint names and
    parents; None when the library has no row for it."""
    rows = _read_rows(connection, f"{_ROW_SQL} WHERE files.path = ?", (path,))
    if not rows:
        return None
    result = _with_problems(connection, rows)[0]
    if rows[0]["skeleton_id"] is not None:
        names, parents = connection.execute(
            "SELECT names, parents FROM skeletons WHERE id = ?", (rows[0]["skeleton_id"],)
        ).fetchone()
        result["skeleton"].update(names=json.loads(names), parents=json.loads(parents))
    return result


def _read_rows(connection: sqlite3.Connection, sql: str, values: Sequence) -> list[dict]:
    """The rows of ``sql`` (a :data:`_ROW_SQL`), each a dict of its columns."""
    cursor = connection.execute(sql, values)
    cursor.row_factory = None
    names = [column[0] for column in cursor.description]
    return [dict(zip(names, row)) for row in cursor]


def _with_problems(
    connection: sqlite3.Connection, rows: list[dict], ids_sql: str | None = None, values: Sequence = ()
) -> list[dict]:
    """:func:`row_json` of each row, with its problems per kind; read for the rows' ids,
    or for the ids ``ids_sql`` (with ``values``) selects."""
    kinds: dict[int, dict] = {}
    if rows:
        if ids_sql is None:
            ids_sql, values = ", ".join(str(int(r["id"])) for r in rows), ()
        cursor = connection.execute(
            f"SELECT file_id, kind, level, count FROM problems WHERE file_id IN ({ids_sql}) "
            "ORDER BY file_id, kind, level",
            values,
        )
        cursor.row_factory = None
        for file_id, kind, level, number in cursor:
            kinds.setdefault(file_id, {}).setdefault(kind, {})[SEVERITIES[level - 1]] = number
    return [row_json(row, kinds.get(row["id"], {})) for row in rows]


def row_json(row: Mapping, kinds: dict) -> dict:
    """One row as JSON (docs/library.md): the file, what it holds, its skeleton, its quality
    (``row``: the columns of :data:`_ROW_SQL`)."""
    ok = row["status"] == "ok"
    skeleton = None
    if row["skeleton_id"] is not None:
        skeleton = {
            "group": row["skeleton_group"],
            "signature": row["skeleton_signature"],
            "topology": row["skeleton_topology"],
            "group_match": row["skeleton_match"],
        }
    quality = None
    if ok:
        quality = {
            "findings": row["findings"],
            "info": row["infos"],
            "warning": row["warnings"],
            "error": row["errors"],
            "worst": row["worst"],
            "worst_frame": row["worst_frame"],
            "kinds": {kind: kinds[kind] for kind in KINDS if kind in kinds},
        }
    return {
        "id": row["id"],
        "path": row["path"],
        "name": row["name"],
        "folder": row["folder"],
        "size": row["size"],
        "modified": row["modified"],
        "mtime_ns": row["mtime_ns"],
        "hash": row["hash"],
        "format": row["format"],
        "kind": row["kind"],
        "status": row["status"],
        "message": row["message"],
        "frames": row["frames"],
        "frame_rate": row["frame_rate"],
        "duration": row["duration"],
        "joints": row["joints"],
        "roots": row["roots"],
        "markers": row["markers"],
        "units": row["units"],
        "up_axis": row["up_axis"],
        "skeleton": skeleton,
        "quality": quality,
        "thumbnail": bool(row["has_thumbnail"]),
    }


def rows_json_text(rows: Sequence[dict]) -> str:
    """The JSON text of a list of :func:`row_json` rows, one row a line (each encoded by the
    json module's C encoder, which an indented dump does not use)."""
    if not rows:
        return "[]\n"
    return "[\n" + ",\n".join(json.dumps(row) for row in rows) + "\n]\n"


#: columns of the CSV table (one row per file), then one count column per kind of problem
CSV_COLUMNS = (
    "path",
    "name",
    "format",
    "status",
    "frames",
    "frame_rate",
    "duration",
    "joints",
    "roots",
    "markers",
    "units",
    "up_axis",
    "size",
    "modified",
    "hash",
    "skeleton_group",
    "skeleton_signature",
    "findings",
    "info",
    "warning",
    "error",
    "worst",
    "worst_frame",
    *KINDS,
    "message",
)


def csv_record(row: dict) -> dict:
    """A :func:`row_json` dict flattened to :data:`CSV_COLUMNS` (a kind's count sums its
    severities; empty cells where a failed file has no value)."""
    flat = {column: row.get(column) for column in CSV_COLUMNS}
    skeleton, quality = row["skeleton"] or {}, row["quality"] or {}
    flat["skeleton_group"], flat["skeleton_signature"] = skeleton.get("group"), skeleton.get("signature")
    for key in ("findings", "info", "warning", "error", "worst", "worst_frame"):
        flat[key] = quality.get(key)
    for kind in KINDS:
        flat[kind] = sum(quality.get("kinds", {}).get(kind, {}).values()) if quality else None
    return flat
