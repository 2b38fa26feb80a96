"""``python -m gmr_studio.app.tools.open_bench`` on a short take: every format's rows are
printed, each beside its reader's floor, with the opening's ratio and goal (the figures
themselves are never asserted). The FBX take needs Blender's Python; without it the FBX
rows are replaced by a line saying why."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from gmr_studio.app.tools.open_bench import amc_number_lines
from gmr_studio.core.benchmark.data import tile_amc
from gmr_studio.core.formats.acclaim import parse_amc_frames, read_asf
from tests.conftest import shared_path

pytestmark = pytest.mark.gui

SECONDS = r"\d+\.\d+ s  cpu +\d+\.\d+ s \(sys +\d+\.\d+\)"


def test_every_format_is_opened_beside_its_floor():
    shared_path("cmu/subject01/01_01.bvh")  # skips with a reason when the shared data is absent
    command = [sys.executable, "-m", "gmr_studio.app.tools.open_bench", "--frames", "300", "--rounds", "1"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=900, env=dict(os.environ), check=False)
    assert result.returncode == 0, result.stderr
    out = result.stdout
    floors = {
        "BVH": "numpy.loadtxt of the frame lines",
        "AMC": "numpy.loadtxt of its numbers, a frame a line",
        "glTF": "its animation accessors by numpy.frombuffer",
        "FBX": "ufbx's load alone, a new process",
    }
    reasons = r"(no Python with Blender's bpy at .+ \(--bpy\)|Blender's export failed \(.+\)): no FBX take to open"
    left_out = re.search(r"^FBX: left out: " + reasons, out, re.MULTILINE)
    for name, floor in floors.items():
        if name == "FBX" and left_out:
            continue
        section = re.search(
            rf"^{name}, \d+ MB, 300 frames x \d+ joints \(best of 1 rounds; x floor\):\n((?:  .*\n)+)", out, re.M
        )
        assert section, f"no rows for {name}:\n{out}"
        rows = section.group(1)
        assert re.search(re.escape(f"{floor} (floor)") + " +" + SECONDS, rows), rows
        for part in (f"read the file (core.formats, {name} as written)", "convert to GMR", "FK cache (Snapshot.of)"):
            assert re.search(re.escape(part) + r".*" + SECONDS + r" +\d+\.\d+ x floor", rows), (name, part)
        opened = (
            r"open in the window to its first drawn frame +"
            + SECONDS
            + r" +\d+\.\d+ x floor +\(goal 2.0: (met|NOT met)\)"
        )
        assert re.search(opened, rows), rows
    assert "load average" in out.splitlines()[-1]


def test_the_amc_floor_parses_the_same_numbers_as_the_reader():
    amc = shared_path("cmu/subject01/01_01.amc")
    text = tile_amc(amc, 30)
    values, first, _flags = parse_amc_frames(text, str(amc), read_asf(shared_path("cmu/subject01/01.asf")))
    lines = amc_number_lines(text).splitlines()
    assert (first, len(lines)) == (1, 30)
    # each line holds one frame's numbers, in the file's order of the bones (not the ASF's)
    assert [sorted(float(word) for word in line.split()) for line in lines] == [sorted(row) for row in values.tolist()]
