"""What ``gmr`` prints about markers (core/markers/report.py): a marker file's description and
text, the conversion table against its virtual markers and a true motion, the pelvis fit's
figures; on markers, motions and fits written by hand."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.markerset import MarkerSet, PointOutputs
from gmr_studio.core.markers.report import (
    conversion_table,
    conversion_text,
    describe_markers,
    markers_text,
    pelvis_fit_summary,
    pelvis_fit_text,
)
from gmr_studio.core.markers.solve import MarkerMotion
from tests.conftest import random_motion
from tests.test_markers_build import generated_markers


def small_markers(**fields) -> MarkerSet:
    positions = np.arange(4 * 2 * 3, dtype=float).reshape(4, 2, 3)
    positions[1:3, 0] = np.nan  # A: one gap of two frames
    return MarkerSet(
        labels=["A", "LongLabel"], subjects=["Ann", ""], positions=positions, rate=50.0, units="mm", first_frame=3,
        notes=("read twice",), **fields,
    )  # fmt: skip


# ------------------------------------------------------------------ a marker file
def test_a_marker_files_description():
    outputs = PointOutputs(
        labels=("LHipAngles", "LKneeForce"), subjects=("Ann", ""), kinds=("angles", "forces"),
        values=np.zeros((4, 2, 3)), units={"angles": "deg"},
    )  # fmt: skip
    info = describe_markers(small_markers(outputs=outputs), "take.C3D")
    assert {k: info[k] for k in ("path", "format", "frames", "frame_rate", "duration", "first_frame", "units")} == {
        "path": "take.C3D", "format": "C3D", "frames": 4, "frame_rate": 50.0, "duration": 0.08, "first_frame": 3,
        "units": "mm",
    }  # fmt: skip
    assert info["subjects"] == ["Ann"] and info["notes"] == ["read twice"]
    assert info["missing_fraction"] == 2 / 8
    assert info["markers"][0] == {"label": "Ann:A", "missing": 2, "gaps": 1, "longest": 2, "computed": 0}
    assert info["computed_fraction"] == 0.0
    assert info["outputs"] == {
        "angles": {"units": "deg", "labels": ["Ann:LHipAngles"]}, "forces": {"units": "", "labels": ["LKneeForce"]},
    }  # fmt: skip
    assert info["marker_set"]["name"] is None and info["marker_set"]["note"].startswith("no known marker set fits")
    plain = describe_markers(small_markers(), "walk.trc")
    assert plain["format"] == "TRC" and plain["outputs"] == {}
    empty = MarkerSet(labels=[], positions=np.zeros((3, 0, 3)), rate=10.0, units="m")
    assert describe_markers(empty, "x.trc")["missing_fraction"] == 0.0


def test_a_known_sets_description():
    markers, _ = generated_markers("helen-hayes", n_frames=2)
    info = describe_markers(markers, "gait.c3d")["marker_set"]
    assert info["name"] == "helen-hayes" and info["title"] == "Helen Hayes (Kadaba et al. 1990)"
    assert info["missing"] == [] and info["summary"].startswith("helen-hayes (Helen Hayes (Kadaba et al. 1990))")
    assert info["with"] == [role for role in info["with"]]  # the optional roles, a list
    lacking = describe_markers(markers.select([label for label in markers.labels if label != "LTOE"]), "g.c3d")
    assert lacking["marker_set"]["missing"] == ["LTOE"]


def test_the_text_of_a_marker_file():
    outputs = PointOutputs(
        labels=("LHipAngles", "LKneeForce", "RHipAngles"), subjects=("", "", ""), kinds=("angles", "forces", "angles"),
        values=np.zeros((4, 3, 3)), units={"angles": "deg"},
    )  # fmt: skip
    text = markers_text(describe_markers(small_markers(outputs=outputs), "take.c3d"))
    lines = text.splitlines()
    assert lines[:8] == [
        "file:       take.c3d",
        "format:     C3D markers",
        "frames:     4 at 50 Hz (0.080 s), first frame 3",
        "units:      mm (axes as in the file)",
        "markers:    2",
        "subjects:   Ann",
        "gaps:       25.00% of all samples",
        "set:        " + lines[7][len("set:        "):],
    ]  # fmt: skip
    assert lines[7].startswith("set:        no known marker set fits")
    assert lines[8:11] == [
        "note:       read twice",
        "output:     2 angles (deg): LHipAngles, RHipAngles",
        "output:     1 forces: LKneeForce",
    ]
    assert lines[11:] == [
        "",
        "marker      missing   gaps  longest  computed",
        "Ann:A             2      1        2         0",
        "LongLabel         0      0        0         0",
    ]


def test_the_text_without_subjects_set_or_long_labels():
    info = describe_markers(small_markers().replace(subjects=("", ""), labels=("A", "B")), "take.trc")
    info["marker_set"] = {}
    lines = markers_text(info).splitlines()
    assert lines[5] == "subjects:   none (no prefix on the labels)"
    assert not any(line.startswith("set:") for line in lines)
    assert lines[-3:] == [
        "marker   missing   gaps  longest  computed",
        "A              2      1        2         0",
        "B              0      0        0         0",
    ]
    computed = np.zeros((4, 2), bool)
    computed[1:3, 1] = True  # B's frames 1-2 filled in by the capture software
    lines = markers_text(describe_markers(small_markers().replace(computed=computed), "take.c3d")).splitlines()
    assert lines[7] == (
        "computed:   25.00% of all samples (2, kept): filled in by the capture software, not measured "
        "(--drop-computed reads them as gaps)"
    )
    assert lines[-1].endswith("0      0        0         2")
    known, _ = generated_markers("helen-hayes", n_frames=2)
    assert "set:        helen-hayes (Helen Hayes" in markers_text(describe_markers(known, "g.c3d"))


# ------------------------------------------------------------------ a conversion
def conversion(rng):
    """A motion of three joints, virtual markers off its joints by known distances, and the
    sources of each joint's rotation."""
    motion = random_motion(rng, [-1, 0, 1], n_frames=4)
    positions = world_positions(motion)
    measured = positions.copy()
    measured[:, 1, 0] += np.array([1.0, 2.0, 3.0, 6.0])  # joint 1: 1, 2, 3, 6 from its marker
    measured[:, 2] = np.nan  # joint 2: no marker
    measured[0, 0, 2] += 0.5  # the root: 0.5 in frame 0
    sources = np.array([[3, 0, 1], [3, 0, 1], [3, 2, 1], [3, 1, 4]], dtype=np.int8)
    result = MarkerMotion(
        motion=motion, measured=measured, sources=sources, frame_valid=np.ones(4, bool), pelvis=None,
        matches=np.full(4, -1), match_distances=np.full(4, np.nan),
    )  # fmt: skip
    return result, motion, positions


def test_the_conversion_table_per_joint(rng):
    result, _, _ = conversion(rng)
    rows = conversion_table(result, None)
    assert [r["joint"] for r in rows] == ["j0", "j1", "j2"]
    assert [r["measured"] for r in rows] == [1.0, 0.5, 0.0]  # the root counts as measured
    assert [r["source"] for r in rows] == ["root", "measured", "from reference"]
    assert rows[0]["marker_mean"] == pytest.approx(0.125) and rows[0]["marker_max"] == pytest.approx(0.5)
    assert rows[1]["marker_mean"] == pytest.approx(3.0) and rows[1]["marker_max"] == pytest.approx(6.0)
    assert rows[2]["marker_mean"] is None and rows[2]["marker_max"] is None
    assert "position_error" not in rows[0] and "angle_error_deg" not in rows[1]
    in_mm = conversion_table(result, 10.0)
    assert in_mm[1]["marker_mean"] == pytest.approx(30.0) and in_mm[1]["marker_max"] == pytest.approx(60.0)


def test_the_conversion_table_against_the_truth(rng):
    result, motion, positions = conversion(rng)
    truth = positions.copy()
    truth[:, 2, 1] += np.array([2.0, 2.0, 4.0, 4.0])
    turn = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # 90 degrees about x
    truth_rotations = motion.rotations.copy()
    truth_rotations[:2, 1] = motion.rotations[:2, 1] @ turn
    rows = conversion_table(result, 2.0, truth, truth_rotations)
    assert rows[2]["position_error"] == pytest.approx(2.0 * 3.0) and rows[0]["position_error"] == 0.0
    assert "angle_error_deg" not in rows[0]  # the root has no parent to be measured against
    assert rows[1]["angle_error_deg"] == pytest.approx(45.0) and rows[2]["angle_error_deg"] == pytest.approx(
        0.0, abs=1e-6
    )


def test_the_conversion_text(rng):
    result, motion, positions = conversion(rng)
    plain = conversion_text(conversion_table(result, None), "mm").splitlines()
    assert plain == [
        "joint    measured       to marker (mean/max mm)",
        "j0         100.0%            0.1            0.5",
        "j1          50.0%            3.0            6.0",
        "j2           0.0%              -              -",
    ]  # the names' column as wide as "overall": the header and the last row line up
    truth = positions.copy()
    truth[:, 0, 0] += 1.0
    rotations = motion.rotations.copy()
    full = conversion_text(conversion_table(result, None, truth, rotations), "mm").splitlines()
    assert full == [
        "joint    measured       to marker (mean/max mm)   vs truth mm  angle deg",
        "j0         100.0%            0.1            0.5           1.0          -",
        "j1          50.0%            3.0            6.0           0.0       0.00",
        "j2           0.0%              -              -           0.0       0.00",
        "overall                                                   0.3",
    ]
    long_name = conversion_table(result, None)
    long_name[0]["joint"] = "LeftUpLegRoll"
    assert conversion_text(long_name, "cm").splitlines()[1].startswith("LeftUpLegRoll    100.0%")
    positions_only = conversion_text(conversion_table(result, None, truth), "mm").splitlines()
    assert positions_only[0].endswith("vs truth mm") and positions_only[-1].startswith("overall")


# ------------------------------------------------------------------ the pelvis fit
def pelvis(**fields):
    base = dict(
        units="mm", labels=("root", "lhip", "back"), fit_labels=None, note="",
        residuals=np.array([1.0, 2.0, 3.0, np.nan, 5.0]), marker_fit=None, virtual_residuals=None, virtual_fit=None,
    )  # fmt: skip
    return SimpleNamespace(**{**base, **fields})


def test_the_pelvis_fit_figures():
    summary = pelvis_fit_summary(pelvis())
    assert summary["units"] == "mm" and summary["fit_labels"] == ["root", "lhip", "back"] and summary["note"] == ""
    assert summary["procrustes"] == {"min": 1.0, "median": 2.5, "p95": pytest.approx(4.7), "max": 5.0}
    assert summary["markers"] is None
    assert summary["virtual"]["lhip"] == {"residual": None, "cluster_fit": None}
    residuals = np.arange(15.0).reshape(5, 3)
    fits = np.full((5, 3), np.nan)
    fits[:, 1] = [0.5, 0.5, 0.5, 0.5, 1.5]
    detailed = pelvis_fit_summary(
        pelvis(fit_labels=("A", "B", "C", "D"), marker_fit=np.array([[0.2, 0.4]]), virtual_residuals=residuals,
               virtual_fit=fits, note="hips by their names")
    )  # fmt: skip
    assert detailed["fit_labels"] == ["A", "B", "C", "D"]
    assert detailed["markers"] == {"min": 0.2, "median": pytest.approx(0.3), "p95": pytest.approx(0.39), "max": 0.4}
    assert detailed["virtual"]["back"]["residual"] == {
        "min": 2.0,
        "median": 8.0,
        "p95": pytest.approx(13.4),
        "max": 14.0,
    }
    assert detailed["virtual"]["root"]["cluster_fit"] is None
    assert detailed["virtual"]["lhip"]["cluster_fit"]["max"] == 1.5
    assert pelvis_fit_summary(pelvis(residuals=np.full(3, np.nan)))["procrustes"] is None


def test_the_pelvis_fit_text():
    residuals = np.arange(15.0).reshape(5, 3)
    summary = pelvis_fit_summary(pelvis(marker_fit=np.array([0.25]), virtual_residuals=residuals, note="guessed"))
    assert pelvis_fit_text(summary).splitlines() == [
        "pelvis fit (mm, min / median / 95% / max over the frames):",
        "  Procrustes on root, lhip, back: 1.00 / 2.50 / 4.70 / 5.00",
        "  real markers to the cluster template: 0.25 / 0.25 / 0.25 / 0.25",
        "  root: from its fitted home 0.00 / 6.00 / 11.40 / 12.00; cluster fit -",
        "  lhip: from its fitted home 1.00 / 7.00 / 12.40 / 13.00; cluster fit -",
        "  back: from its fitted home 2.00 / 8.00 / 13.40 / 14.00; cluster fit -",
        "  (guessed)",
    ]
    bare = pelvis_fit_text(pelvis_fit_summary(pelvis(residuals=np.full(2, np.nan)))).splitlines()
    assert bare[1] == "  Procrustes on root, lhip, back: -" and len(bare) == 5
