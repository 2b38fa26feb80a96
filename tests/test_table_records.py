"""core.table.records_csv_text: the one CSV writer's mixed-row form quotes as csv_text does."""

from __future__ import annotations

import csv
import io

import numpy as np

from gmr_studio.core.table import csv_cell, records_csv_text


def test_names_with_commas_and_quotes_are_quoted_and_read_back():
    rows = [{"file": 'walk, "fast".bvh', "frames": 120, "error": 1.5}, {"file": "plain.bvh", "frames": 3, "error": 0}]
    text = records_csv_text(["file", "frames", "error"], rows)
    assert text.splitlines()[1].startswith(csv_cell('walk, "fast".bvh') + ",120,")
    back = list(csv.DictReader(io.StringIO(text)))
    assert [r["file"] for r in back] == ['walk, "fast".bvh', "plain.bvh"] and back[0]["error"] == "1.5"


def test_a_gap_is_an_empty_cell_and_numbers_keep_their_formats():
    from gmr_studio.core.table import csv_text

    table = np.array([[0, 1.5, np.nan], [1, np.nan, 2.25]])
    assert csv_text(["frame", "a,b", "c"], table, ["%d", "%.6g"]) == 'frame,"a,b",c\n0,1.5,\n1,,2.25\n'
    assert csv_text(["frame", "x"], np.array([[0, 0.5], [1, 2.0]]), ["%d", "%.3f"]) == "frame,x\n0,0.500\n1,2.000\n"
