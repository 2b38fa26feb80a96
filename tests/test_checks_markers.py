"""Checks of raw markers (core.checks.markers): the demo's markers (0.5 mm noise, gaps) are
clean; a planted pop, a repeated frame and noise on one marker are found; gaps are not. On small
synthetic sets: the size on exact extents, the labels as joint names, the markers as a motion
field by field, which checks run and the findings' order."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings
from gmr_studio.core.checks.markers import MARKER_KINDS, marker_motion, marker_size, run_marker_checks
from gmr_studio.core.cli import main
from gmr_studio.core.demo import demo_markers
from gmr_studio.core.markers.markerset import MarkerSet
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


NAN = np.nan


def test_the_size_is_the_median_of_each_frames_largest_extent():
    """Extents per frame (x, y, z): (5, 4, 0), (0, 0, 2) with a marker missing, (0, 3, 1):
    largest 5, 2, 3, median 3 (the median of each axis's largest would be 4)."""
    positions = np.array(
        [
            [[0, 0, 0], [5, 0, 0], [0, 4, 0]],
            [[0, 0, 0], [0, 0, 2], [NAN, NAN, NAN]],
            [[0, 0, 0], [0, 3, 0], [0, 0, 1]],
        ],
        dtype=np.float64,
    )
    assert marker_size(positions) == 3.0
    assert marker_size(positions * 0.25) == 0.75  # below 1: measured, not replaced


def test_a_size_that_cannot_be_measured_is_one():
    one_marker = np.arange(12.0).reshape(4, 1, 3)  # extent 0 at every frame
    assert marker_size(one_marker) == 1.0
    assert marker_size(np.full((3, 2, 3), NAN)) == 1.0  # never seen
    assert marker_size(np.zeros((0, 2, 3))) == 1.0  # no frames


def _markers(labels, positions, rate=30.0, units="mm") -> MarkerSet:
    return MarkerSet(labels=tuple(labels), positions=positions, rate=rate, units=units)


def test_the_markers_as_a_motion():
    positions = np.arange(2 * 3 * 3, dtype=np.float64).reshape(2, 3, 3)
    positions[1, 2] = NAN
    labels = ("LKNE", "LKNE", "bad  label")  # repeated; two spaces: no joint name
    motion = marker_motion(_markers(labels, positions, rate=120.0, units="cm"))
    assert motion.names == ("LKNE", "marker2", "marker3")
    np.testing.assert_array_equal(motion.parents, [-1, -1, -1])
    np.testing.assert_array_equal(motion.offsets, np.zeros((3, 3)))
    assert motion.rotation_orders == ("XYZ",) * 3
    np.testing.assert_array_equal(motion.has_translation, [True, True, True])
    np.testing.assert_array_equal(motion.rotations, np.broadcast_to(np.eye(3), (2, 3, 3, 3)))
    np.testing.assert_array_equal(motion.translations, positions)
    assert motion.frame_time == 1.0 / 120.0
    assert motion.facts.unit.name == "cm"


def test_labels_are_names_unless_repeated_or_impossible():
    positions = np.zeros((1, 5, 3))
    motion = marker_motion(_markers(("A", " B", "C", "A", "marker2"), positions))
    assert motion.names == ("A", "marker2", "C", "marker4", "marker5")


def _walk_with_faults() -> MarkerSet:
    """Four markers on smooth paths (30 Hz, mm) with a 50 mm pop of C at frame 20, frame 40
    a copy of 39, and frames 49 to 57 held (0.3 s)."""
    rng = np.random.default_rng(0)
    t = np.arange(60)[:, None, None] / 30.0
    base = np.array([[0, 0, 0], [100, 0, 0], [0, 200, 0], [0, 0, 300.0]])
    positions = base[None] + 50 * np.sin(t * np.array([1.0, 2.0, 3.0])) + 10 * t
    positions = positions + rng.normal(scale=1e-3, size=positions.shape)
    positions[20, 2] += (30, 0, 40)
    positions[40] = positions[39]
    positions[50:58] = positions[49]
    return _markers(("A", "B", "C", "D"), positions)


def test_the_findings_sorted_by_frame_whatever_order_the_checks_ran():
    motion, found = run_marker_checks(_walk_with_faults())
    assert motion.names == ("A", "B", "C", "D")
    assert [(f.kind, f.start, f.end, f.names) for f in found] == [
        ("pop", 20, 20, ("C",)),
        ("duplicate", 40, 40, ()),
        ("frozen", 49, 57, ()),
    ]
    (pop, duplicate, frozen) = found
    assert pop.value == pytest.approx(50.0, abs=0.5) and pop.units == "mm"
    assert (duplicate.value, duplicate.units) == (1.0, "frames")
    assert frozen.value == pytest.approx(9 / 30.0, rel=1e-12) and frozen.units == "s"


def test_only_the_marker_kinds_asked_for_run():
    markers = _walk_with_faults()
    _, found = run_marker_checks(markers, CheckSettings(kinds=("frozen", "rest-pose", "foot-skate", "flip")))
    assert [f.kind for f in found] == ["frozen"]
    _, found = run_marker_checks(markers, CheckSettings(kinds=("pop",)))
    assert [f.kind for f in found] == ["pop"]
    assert set(MARKER_KINDS) == {"pop", "jitter", "frozen", "duplicate"}
