"""Checks of raw markers (core.checks.markers): the demo's markers (0.5 mm noise, gaps) are
clean; a planted pop, a repeated frame and noise on one marker are found; gaps are not."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings
from gmr_studio.core.checks.markers import MARKER_KINDS, marker_size, run_marker_checks
from gmr_studio.core.cli import main
from gmr_studio.core.demo import demo_markers
from gmr_studio.core.markers.trc import write_trc
from tests.conftest import shared_path


@pytest.fixture(scope="module")
def markers():
    return demo_markers()


def with_positions(markers, positions):
    return dataclasses.replace(markers, positions=positions)


def test_demo_markers_are_clean_and_gaps_are_no_finding(markers):
    assert np.isnan(markers.positions).any()  # the demo has gaps
    motion, findings = run_marker_checks(markers)
    assert findings == []
    assert motion.names == tuple(markers.labels)
    assert marker_size(markers.positions) == pytest.approx(1650, rel=0.1)  # millimetres, a person


def test_pop_on_one_marker(markers):
    positions = markers.positions.copy()
    j = markers.labels.index("LKNE")
    positions[300, j] += (30.0, 0.0, 40.0)  # 50 mm
    _, findings = run_marker_checks(with_positions(markers, positions))
    (finding,) = findings
    assert (finding.kind, finding.start, finding.end, finding.names) == ("pop", 300, 300, ("LKNE",))
    assert finding.value == pytest.approx(50.0, rel=0.1)
    assert finding.units == "mm"


def test_repeated_frame_and_noise(markers):
    positions = markers.positions.copy()
    rng = np.random.default_rng(3)
    j = markers.labels.index("RELB")
    positions[100:400, j] += rng.normal(scale=5.0, size=(300, 3))
    positions[405] = positions[404]  # the head marker is missing there: the others repeat
    _, findings = run_marker_checks(with_positions(markers, positions))
    kinds = {(f.kind, f.names) for f in findings}
    assert ("duplicate", ()) in kinds and ("jitter", ("RELB",)) in kinds
    (noise,) = [f for f in findings if f.kind == "jitter"]
    assert noise.value == pytest.approx(5.0 * np.sqrt(3), rel=0.15)
    assert {f.kind for f in findings} <= set(MARKER_KINDS)
    _, only = run_marker_checks(with_positions(markers, positions), CheckSettings(kinds=("duplicate", "foot-skate")))
    assert [f.kind for f in only] == ["duplicate"]


def test_cli_reads_marker_files(markers, tmp_path, capsys):
    path = tmp_path / "walk.trc"
    write_trc(markers, path)
    assert main(["check", str(path), "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert (document["frames"], document["frame_rate"], document["units"], document["findings"]) == (
        480,
        120.0,
        "mm",
        [],
    )


def test_cmu_markers_pop_where_the_skeleton_does(capsys):
    """docs/checks.md: 01_01.c3d's marker pops at the frames of the AMC's pops."""
    path = shared_path("cmu/subject01/01_01.c3d")
    assert main(["check", str(path), "--json", "-"]) == 0
    pops = {(f["start"], f["joints"][0]) for f in json.loads(capsys.readouterr().out)["findings"] if f["kind"] == "pop"}
    assert {(647, "LHEE"), (843, "LMT5"), (974, "LBWT"), (979, "LBWT"), (2574, "RFIN")} <= pops
