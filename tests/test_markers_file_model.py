"""Our joints against the lab model's points stored in a C3D (core.markers.file_model) on
exact values: which file point stands for a joint, each joint's error statistics over the
frames both have, the pelvis frame against the file's after a constant axis offset, the
refusal, and the text."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_rotations
from gmr_studio.core.markers.file_model import compare_with_file_model, file_model_points, file_model_text
from gmr_studio.core.markers.markerset import MarkerSet
from tests.conftest import random_motion

NAMES = ["pelvis", "LHJC", "RHJC", "LKJC"]


def motion_of(n_frames: int = 3):
    motion = random_motion(np.random.default_rng(24), [-1, 0, 0, 2], n_frames=n_frames)
    return motion.replace(names=NAMES)


def markers_in_metres(points: dict[str, np.ndarray], source: str = "lab.c3d") -> MarkerSet:
    """The file's points (F, 3 each, in mm) as a marker set in metres."""
    return MarkerSet(
        labels=list(points), positions=np.stack(list(points.values()), 1) / 1000.0, rate=100, units="m", source=source
    )


def test_each_joints_error_over_the_frames_both_have():
    motion = motion_of()
    ours = np.zeros((3, 4, 3))
    ours[:, 1] = [[1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [5.0, 5.0, 5.0]]
    ours[:, 2] = [[10.0, 0.0, 0.0]] * 3
    lhjc = ours[:, 1] + [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 6.0]]  # errors 1, 2, 6 mm
    lfep = ours[:, 1] + 50.0  # LHJC comes first: LFEP is not used
    rfep = ours[:, 2] + [[3.0, 4.0, 0.0], [np.nan] * 3, [0.0, 0.0, 0.0]]  # 5, gap, 0
    pelo = np.full((3, 3), 4.0)  # the pelvis joint at the origin: 4 sqrt 3 at every frame
    gone = np.full((3, 3), np.nan)  # LKJC never seen: left out
    markers = markers_in_metres({"LFEP": lfep, "LHJC": lhjc, "RFEP": rfep, "PELO": pelo, "LKJC": gone, "RKJC": pelo})
    report = compare_with_file_model(markers, motion, ours)
    assert report["pelvis"] is None
    rows = {row["name"]: row for row in report["joints"]}
    assert [row["name"] for row in report["joints"]] == ["pelvis", "LHJC", "RHJC"]
    assert rows["pelvis"]["file_point"] == "PELO" and rows["pelvis"]["frames"] == 3
    np.testing.assert_allclose(rows["pelvis"]["max_mm"], 4 * np.sqrt(3), rtol=1e-12)
    lhjc_row = rows["LHJC"]
    assert (lhjc_row["file_point"], lhjc_row["frames"]) == ("LHJC", 3)
    np.testing.assert_allclose([lhjc_row["mean_mm"], lhjc_row["median_mm"], lhjc_row["max_mm"]], [3, 2, 6], rtol=1e-9)
    rhjc = rows["RHJC"]
    assert (rhjc["file_point"], rhjc["frames"]) == ("RFEP", 2)
    np.testing.assert_allclose([rhjc["mean_mm"], rhjc["median_mm"], rhjc["max_mm"]], [2.5, 2.5, 5], rtol=1e-9)
    assert all(isinstance(row[key], float) for row in rows.values() for key in ("mean_mm", "median_mm", "max_mm"))
    assert all(type(row["frames"]) is int for row in rows.values())
    assert file_model_points(markers) == ["LFEP", "LHJC", "RFEP", "PELO", "LKJC", "RKJC"]


def turn_z(degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    return np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])


def pelvis_points(rotations: np.ndarray, origin: np.ndarray) -> dict[str, np.ndarray]:
    """PELO and the ends of the file's pelvis axes (columns of ``rotations``), 100 mm long."""
    return {"PELO": origin, **{f"PEL{k}": origin + 100.0 * rotations[:, :, c] for c, k in enumerate("ALP")}}


def test_the_pelvis_frame_after_a_constant_offset():
    motion = motion_of(4)
    ours = world_rotations(motion)[:, 0]
    offset = turn_z(90.0)  # the lab's axes: ours turned by a quarter turn
    theirs = ours @ offset.T
    theirs[2] = theirs[2] @ turn_z(3.0).T  # one frame 3 degrees off
    origin = np.arange(12.0).reshape(4, 3)
    points = pelvis_points(theirs, origin)
    points["PELA"][3] = np.nan  # a gap: that frame is left out
    report = compare_with_file_model(markers_in_metres(points), motion, np.zeros((4, 4, 3)))
    pelvis = report["pelvis"]
    assert pelvis["file_segment"] == "PEL (PELO, PELA, PELL, PELP)" and pelvis["frames"] == 3
    # the mean offset is nearer the two exact frames than the third: the third is off most
    assert pelvis["max_deg"] == pytest.approx(2.0, abs=0.01)
    assert pelvis["median_deg"] == pytest.approx(1.0, abs=0.01)
    assert report["joints"][0]["name"] == "pelvis"  # PELO is also the pelvis joint's point
    exact = pelvis_points(ours @ offset.T, origin)
    report = compare_with_file_model(markers_in_metres(exact), motion, np.zeros((4, 4, 3)))
    assert report["pelvis"]["max_deg"] < 1e-5 and report["pelvis"]["frames"] == 4


def test_a_pelvis_never_seen_and_a_file_without_model_points():
    motion = motion_of(2)
    points = pelvis_points(world_rotations(motion)[:, 0], np.zeros((2, 3)))
    points["PELL"][:] = np.nan
    points["PELO"] = np.full((2, 3), np.nan)
    with pytest.raises(OperationError) as info:
        compare_with_file_model(markers_in_metres(points, source=""), motion, np.zeros((2, 4, 3)))
    names = "LAJC, LCLO, LEJC, LFEO, LFEP, LHJC, LHUO, LKJC, LRAO, LSJC, LTIO, LWJC, PELO, RAJC, RCLO, REJC"
    assert str(info.value).startswith(f"the file stores no model joint centres or segment frames (looked for {names},")
    assert str(info.value).endswith("RTIO, RWJC, PELO...)")
    with pytest.raises(OperationError, match=r"^walk.c3d stores no model"):
        compare_with_file_model(markers_in_metres({"LASI": np.zeros((2, 3))}, "walk.c3d"), motion, np.zeros((2, 4, 3)))


def test_the_text():
    report = {
        "joints": [
            {"name": "LHJC", "file_point": "LFEP", "frames": 120, "mean_mm": 3.04, "median_mm": 2.96, "max_mm": 12.25}
        ],
        "pelvis": {"file_segment": "PEL (PELO)", "frames": 118, "median_deg": 1.234, "max_deg": 5.678},
    }
    assert file_model_text(report).split("\n") == [
        "joint    file point frames  mean mm   median      max",
        "LHJC     LFEP          120      3.0      3.0     12.2",
        "pelvis frame vs PEL (PELO): median 1.23 deg, max 5.68 deg over 118 frames (after the constant axis offset)",
    ]
    assert file_model_text({"joints": [], "pelvis": None}) == file_model_text({"joints": []}).split("\n")[0]


def test_a_joint_never_seen_leaves_the_next_ones_compared():
    motion = motion_of(2)
    ours = np.zeros((2, 4, 3))
    markers = markers_in_metres({"LHJC": np.full((2, 3), np.nan), "RHJC": np.ones((2, 3))})
    report = compare_with_file_model(markers, motion, ours)
    assert [(row["name"], row["frames"]) for row in report["joints"]] == [("RHJC", 2)]


def test_the_pelvis_is_the_first_root():
    """A motion of two trees (the pelvis's, and a prop's): the file's pelvis frame is compared
    with the first root, the pelvis."""
    motion = random_motion(np.random.default_rng(7), [-1, 0, -1, 2], n_frames=3).replace(names=NAMES)
    rotations = world_rotations(motion)
    assert np.abs(rotations[:, 0] - rotations[:, 2]).max() > 0.1
    points = pelvis_points(rotations[:, 0] @ turn_z(30.0).T, np.zeros((3, 3)))
    report = compare_with_file_model(markers_in_metres(points), motion, np.zeros((3, 4, 3)))
    assert report["pelvis"]["max_deg"] < 1e-5
