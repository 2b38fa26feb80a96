"""core.table.records_csv_text: the one CSV writer's mixed-row form quotes as csv_text does."""

from __future__ import annotations

import csv
import io

from gmr_studio.core.table import csv_cell, records_csv_text


def test_names_with_commas_and_quotes_are_quoted_and_read_back():
    rows = [{"file": 'walk, "fast".bvh', "frames": 120, "error": 1.5}, {"file": "plain.bvh", "frames": 3, "error": 0}]
    text = records_csv_text(["file", "frames", "error"], rows)
    assert text.splitlines()[1].startswith(csv_cell('walk, "fast".bvh') + ",120,")
    back = list(csv.DictReader(io.StringIO(text)))
    assert [r["file"] for r in back] == ['walk, "fast".bvh', "plain.bvh"] and back[0]["error"] == "1.5"
