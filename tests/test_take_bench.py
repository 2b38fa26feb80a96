"""``python -m gmr_studio.app.tools.take_bench`` on a short take: every row is printed with its
yardstick, its ratio and its goal (the figures themselves are never asserted)."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from gmr_studio.app.tools.take_bench import edits, tiled_motion
from tests.conftest import shared_path

pytestmark = pytest.mark.gui


def test_every_row_is_printed_beside_its_yardstick_and_goal():
    shared_path("cmu/subject01/01_01.bvh")  # skips with a reason when the shared data is absent
    # opening the take is open_bench's, tested in test_open_bench.py
    command = [sys.executable, "-m", "gmr_studio.app.tools.take_bench", "--frames", "400", "--rounds", "1", "--no-open"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=600, env=dict(os.environ), check=False)
    assert result.returncode == 0, result.stderr
    out = result.stdout
    ratio = r"\d+\.\d+ s  cpu +\d+\.\d+ s \(sys +\d+\.\d+\) +\d+\.\d+ x {against} +\(goal {goal}: (met|NOT met)\)"
    for label, against, goal in (
        ("single-root FK, 1 thread", "copy P", "2.0"),
        ("FK cache of a document", "FK 1", "1.5"),
        ("gmr check", "FK 1", "3.0"),
    ):
        assert re.search(re.escape(label) + r".*" + ratio.format(against=against, goal=goal), out), label
    names = [name for name, *_ in edits(tiled_motion(40))]
    assert len(names) == 11
    for name in names:
        assert re.search(re.escape(f"{name}: core") + r".*" + ratio.format(against="copy R", goal="1.5"), out), name
        assert re.search(re.escape(f"{name}: app edit") + r".*" + ratio.format(against="copy R", goal="2.0"), out)
        peak = r" +peak +\d+ MB \( *\d+\.\d+ x R\) of +\d+ MB allowed \((within|over)\); undo/redo"
        assert re.search(re.escape(name) + peak, out), name
    assert re.search(r"undo history: keeps \d+ edit\(s\) for this take; after \d+ edits it holds \d+", out)
    assert "load average" in out.splitlines()[-1]
