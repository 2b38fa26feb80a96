"""TRC marker files (OpenSim / Motion Analysis "Track Row Column"), tab- or comma-separated.

Layout: a ``PathFileType`` line, a line of keys (DataRate, CameraRate, NumFrames, NumMarkers,
Units, ...) and one of their values, a line ``Frame# Time label ...`` (each label followed
by two empty fields), a line ``X1 Y1 Z1 X2 ...``, then one row per frame. Empty fields are
gaps in data rows; header rows are read by key names, tolerant of repeated separators (see
:func:`_header`). Rows beyond ``NumFrames``, or fewer of them, are read as they are and noted (real
files disagree with their header); everything else that is wrong raises
:class:`~core.errors.MotionFileError` with the line and column.
"""

from __future__ import annotations

import io
import re
import warnings
from pathlib import Path

import numpy as np

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.errors import MotionFileError, quoted, read_input
from gmr_studio.core.formats.frames import out_of_range, within_range
from gmr_studio.core.formats.hierarchy import normalise_newlines
from gmr_studio.core.markers.markerset import MarkerSet, split_subject
from gmr_studio.core.space.units import UNITS, parse_unit

_NUMBER = re.compile(rb"\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\s*\Z")


def read_trc(path: str | Path, data: bytes | None = None, *, rate: float | None = None) -> MarkerSet:
    """Read a TRC file into a :class:`MarkerSet` (``data``: the bytes, if in hand; ``rate``:
    frames per second for a file whose DataRate is missing, not positive or wrong)."""
    where = str(path)
    lines = normalise_newlines(read_input(path, data)).split(b"\n")

    def fail(message: str, line: int, column: int | None = 1) -> MotionFileError:
        return MotionFileError(where, message, line, column)

    if len(lines) < 5:
        raise fail("unexpected end of file: a TRC header has five lines", len(lines))
    first = _text(lines[0], where, 1)
    if not first.startswith("PathFileType"):
        raise fail("expected 'PathFileType' on the first line of a TRC file", 1)
    delimiter = "\t" if "\t" in first else ","
    header = _header(_text(lines[1], where, 2), _text(lines[2], where, 3), delimiter)
    for key in ("NumMarkers", "Units"):
        if key not in header:
            raise fail(f"the header has no {key}", 2)
    notes = []
    rate_key = "DataRate" if "DataRate" in header else "CameraRate"
    rate_text, rate_column = header.get(rate_key, ("", 1))
    try:
        stated = float(rate_text)
    except ValueError:
        stated = -1.0
    if rate is not None:
        if np.isfinite(stated) and stated > 0 and stated != rate:
            notes.append(f"{rate_key} is {stated:g} Hz: read at {rate:g} Hz as asked")
    elif rate_key not in header:
        raise fail("the header has no DataRate: use --rate HZ", 2)
    elif not np.isfinite(stated) or stated <= 0:
        raise fail(f"expected a positive DataRate, found {quoted(rate_text)}: use --rate HZ", 3, rate_column)
    rate = float(rate if rate is not None else stated)
    units_text, units_column = header["Units"]
    unit = parse_unit(units_text)
    if unit is None:
        raise fail(f"unknown Units {quoted(units_text)}: expected one of {', '.join(UNITS)}", 3, units_column)
    units = unit.name
    markers_text, markers_column = header["NumMarkers"]
    if not markers_text.isdigit():
        raise fail(f"expected a whole NumMarkers, found {quoted(markers_text)}", 3, markers_column)
    n_markers = int(markers_text)
    names = [name for name, _ in _fields(_text(lines[3], where, 4), delimiter)]
    if names[:2] != ["Frame#", "Time"]:
        raise fail("expected 'Frame#' and 'Time' to start the fourth line", 4)
    full_labels = names[2:]
    if len(full_labels) != n_markers:
        raise fail(f"NumMarkers says {n_markers}, but the fourth line names {len(full_labels)} markers", 4)
    split = [split_subject(label) for label in full_labels]
    positions, first_frame, rows = _read_rows(lines, 5, 2 + 3 * n_markers, delimiter, where)
    claimed = header["NumFrames"][0] if "NumFrames" in header else ""
    if claimed.isdigit() and int(claimed) != rows:
        notes.append(f"the header says NumFrames {claimed}; the file holds {rows} frames")
    return MarkerSet(
        labels=[name for _, name in split],
        subjects=[subject for subject, _ in split],
        positions=positions.reshape(rows, n_markers, 3),
        rate=rate,
        units=units,
        first_frame=first_frame,
        source=where,
        notes=notes,
    )


def _text(line: bytes, path: str, number: int) -> str:
    try:
        return line.decode("utf-8").rstrip()
    except UnicodeDecodeError as exc:
        raise MotionFileError(path, "bytes that are not UTF-8 text", number, exc.start + 1) from None


def _fields(line: str, delimiter: str, keep_empty: bool = False) -> list[tuple[str, int]]:
    """The fields of a line with their 1-based columns, stripped; empty ones dropped unless
    ``keep_empty`` (so repeated separators count as one, as OpenSim's tokenizer reads them)."""
    out, column = [], 1
    for field in line.split(delimiter):
        if field.strip() or keep_empty:
            out.append((field.strip(), column + len(field) - len(field.lstrip())))
        column += len(field) + len(delimiter)
    return out


def _header(keys_line: str, values_line: str, delimiter: str) -> dict[str, tuple[str, int]]:
    """The header's values by key name, each with its column on the values line.

    Keys and values are paired by name: OpenSim pairs the n-th non-empty key with the n-th
    non-empty value, so writers that separate the values by several tabs
    (``100.0<TAB><TAB>100.0<TAB><TAB>238``) are read as intended. When the two rows do not
    hold as many non-empty fields (a value left empty on purpose), fields pair by position.
    """
    keys, values = _fields(keys_line, delimiter), _fields(values_line, delimiter)
    if len(keys) != len(values):
        keys = _fields(keys_line, delimiter, keep_empty=True)
        values = _fields(values_line, delimiter, keep_empty=True)
    return {key: value for (key, _), value in zip(keys, values) if key}


def _read_rows(
    lines: list[bytes], start: int, n_columns: int, delimiter: str, path: str
) -> tuple[np.ndarray, int, int]:
    """(F, n_columns - 2) values of the data rows (gaps NaN), the first frame number, F."""
    sep = delimiter.encode()
    rows: list[bytes] = []
    numbers: list[int] = []  # 1-based line number of each row
    for index in range(start, len(lines)):
        line = lines[index]
        if not line.strip(b" \t,"):
            continue
        fields = line.split(sep)
        if len(fields) > n_columns:
            if any(f.strip() for f in fields[n_columns:]):
                column = len(sep.join(fields[:n_columns])) + len(sep) + 1
                raise MotionFileError(
                    path,
                    f"a row has {len(fields)} fields, expected {n_columns} (Frame#, Time, X Y Z per marker)",
                    index + 1,
                    column,
                )
            fields = fields[:n_columns]
        elif len(fields) < n_columns:
            fields += [b""] * (n_columns - len(fields))
        rows.append(sep.join(f if f.strip() else b"nan" for f in fields))
        numbers.append(index + 1)
    if not rows:
        return np.zeros((0, n_columns - 2)), 1, 0
    block = b"\n".join(rows)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            table = np.loadtxt(io.BytesIO(block), delimiter=delimiter, dtype=np.float64, comments=None, ndmin=2)
    except ValueError:
        table = None
    if table is None or table.shape != (len(rows), n_columns) or not within_range(table, allow_nan=True):
        _raise_bad_value(rows, numbers, sep, path)
    frame_numbers = table[:, 0]
    if np.isnan(frame_numbers).any():
        bad = int(np.flatnonzero(np.isnan(frame_numbers))[0])
        raise MotionFileError(path, "a row has no frame number", numbers[bad], 1)
    return table[:, 2:], int(frame_numbers[0]), len(rows)


def _raise_bad_value(rows: list[bytes], numbers: list[int], sep: bytes, path: str) -> None:
    for row, number in zip(rows, numbers):
        column = 1
        for field in row.split(sep):
            if field != b"nan" and not _NUMBER.match(field):
                found = field.decode("utf-8", "replace").strip()
                raise MotionFileError(path, f"expected a number, found {quoted(found)}", number, column)
            if field != b"nan" and not within_range(float(field)):
                raise MotionFileError(path, out_of_range(field.decode().strip()), number, column)
            column += len(field.decode("utf-8", "replace")) + len(sep)
    raise MotionFileError(path, "the marker rows could not be read", numbers[0], 1)  # pragma: no cover


def trc_text(markers: MarkerSet, digits: int = 10) -> str:
    """The marker set as tab-separated TRC text (gaps as empty fields)."""
    n_frames, n_markers = markers.n_frames, markers.n_markers
    labels = [f"{s}:{label}" if s else label for s, label in zip(markers.subjects, markers.labels)]
    rate = f"{markers.rate:g}"
    lines = [
        f"PathFileType\t4\t(X/Y/Z)\t{Path(markers.source).name or 'markers.trc'}",
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames",
        f"{rate}\t{rate}\t{n_frames}\t{n_markers}\t{markers.units}\t{rate}\t{markers.first_frame}\t{n_frames}",
        "Frame#\tTime\t" + "\t".join(f"{label}\t\t" for label in labels).rstrip("\t"),
        "\t\t" + "\t".join(f"X{m}\tY{m}\tZ{m}" for m in range(1, n_markers + 1)),
        "",
    ]
    body = []
    for f in range(n_frames):
        cells = [str(markers.first_frame + f), f"{f / markers.rate:.{digits}g}"]
        for value in markers.positions[f].reshape(-1):
            cells.append("" if np.isnan(value) else f"{value:.{digits}g}")
        body.append("\t".join(cells))
    return "\n".join(lines + body) + "\n"


def write_trc(markers: MarkerSet, path: str | Path, digits: int = 10) -> None:
    """Write a marker set as a tab-separated TRC file, atomically."""
    atomic_write_text(path, trc_text(markers, digits))
