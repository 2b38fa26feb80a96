"""One CSV writer for every table the project writes (curves, the curves dock, comparisons).

A header row of column names (a name holding a comma, a quote or a line break is quoted, as
RFC 4180 says), then one row per frame; numbers in the column's printf format, NaN as an
empty cell (what spreadsheets, pandas and ``numpy.genfromtxt`` read as missing).
"""

from __future__ import annotations

import io
from collections.abc import Sequence

import numpy as np


def csv_cell(text: str) -> str:
    """A header cell: quoted (inner quotes doubled) when it holds ``,``, ``"`` or a line break."""
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in ',"\r\n') else text


def csv_text(columns: Sequence[str], table: np.ndarray, formats: Sequence[str]) -> str:
    """The CSV text of ``table`` (F, C) float64 under ``columns`` (C names).

    formats : C printf formats (``"%d"``, ``"%.10g"``), or fewer: the last one repeats.
    """
    table = np.asarray(table, dtype=np.float64).reshape(-1, len(columns))
    fmt = list(formats)[: len(columns)]
    fmt += [fmt[-1]] * (len(columns) - len(fmt))
    header = ",".join(csv_cell(c) for c in columns) + "\n"
    if not table.size:
        return header
    body = io.StringIO()
    missing = np.isnan(table)
    if missing.any():  # NaN: an empty cell (the formats print numbers only, so this is exact)
        np.savetxt(body, np.where(missing, 0.0, table), delimiter=",", fmt=fmt)
        rows = body.getvalue().splitlines()
        for r in np.flatnonzero(missing.any(axis=1)):
            cells = rows[r].split(",")
            for c in np.flatnonzero(missing[r]):
                cells[c] = ""
            rows[r] = ",".join(cells)
        return header + "\n".join(rows) + "\n"
    np.savetxt(body, table, delimiter=",", fmt=fmt)
    return header + body.getvalue()


def records_csv_text(columns: Sequence[str], rows: Sequence[dict]) -> str:
    """The CSV text of ``rows`` (one dict a line, values of any kind) under ``columns``: the
    same quoting as :func:`csv_text` (a cell with ``,``, ``"`` or a line break quoted, inner
    quotes doubled), for tables that mix names and numbers (``gmr check --batch``)."""
    import csv

    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue()
