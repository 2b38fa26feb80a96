"""The curves as a table: what ``gmr curves -o OUT.csv`` and the curves dock's CSV export write.

One row per frame: ``frame`` (0-based, in the file), ``time`` (seconds,
:func:`core.timebase.clock.frame_seconds`), then one column per curve (``JOINT.QUANTITY.AXIS``,
:mod:`core.analysis.curves`); values to 10 significant digits, NaN (a marker's gaps) as an
empty cell, names quoted where they hold a comma or a quote (:func:`core.table.csv_text`).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.analysis.curves import Curves
from gmr_studio.core.table import csv_text
from gmr_studio.core.timebase.clock import frame_seconds

#: the columns before the curves
LEADING_COLUMNS = ("frame", "time")


def curves_csv_text(curves: Curves, frames: np.ndarray, frame_time: float) -> str:
    """The CSV text of ``curves`` (values (F, C)) at ``frames`` (F,) 0-based frame numbers,
    ``frame_time`` seconds apart: header ``frame,time,COLUMNS...``, then one row per frame."""
    frames = np.asarray(frames)
    table = np.column_stack([frames, frame_seconds(frames, frame_time), curves.values])
    return csv_text((*LEADING_COLUMNS, *curves.columns), table, ["%d", "%.10g"])
