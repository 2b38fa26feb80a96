"""``python -m gmr_studio.app.tools.curves_bench`` on a short motion: it prints the wall and CPU
figures of every repeat and their medians (the figures themselves are never asserted)."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import numpy as np
import pytest

from tests.conftest import shared_path

pytestmark = pytest.mark.gui


def test_the_bench_reports_wall_and_cpu_time_for_each_repeat():
    shared_path("cmu/subject01/01_01.bvh")  # skips with a reason when the shared data is absent
    command = [
        sys.executable,
        "-m",
        "gmr_studio.app.tools.curves_bench",
        "--frames",
        "3000",
        "--updates",
        "6",
        "--warmup",
        "1",
    ]
    done = subprocess.run(
        [*command, "--repeats", "2"], capture_output=True, text=True, timeout=600, env=dict(os.environ)
    )
    assert done.returncode == 0, done.stderr
    for clock in ("wall", "cpu"):
        repeats = re.findall(rf"repeat \d, +{clock}: .* added +([-+]\d+\.\d+) ms", done.stdout)
        assert len(repeats) == 2, done.stdout
        summary = re.search(
            rf"adds to a frame update, {clock} time: median ([-+]\d+\.\d+) ms over 2 repeats", done.stdout
        )
        assert summary is not None, done.stdout
        added = [float(v) for v in repeats]
        assert float(summary.group(1)) == pytest.approx(np.median(added), abs=0.011)
    assert "9 curves of 3000 points" in done.stdout
