"""Marker maps: the TOML format, the shipped maps, virtual markers, gaps and calibration."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.errors import MotionFileError, OperationError
from gmr_studio.core.markers import load_marker_map
from gmr_studio.core.markers.markermap import MAPS_DIR, MarkerMap, VirtualMarker, marker_map_text
from gmr_studio.core.markers.markerset import MarkerSet, frame_ranges
from gmr_studio.core.markers.virtual import calibrate_marker_map, compute_virtual_markers, resolve_map
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.space.units import unit_named

SMALL_MAP = """
format = "gmr-markermap 1"
name = "small"
units = "mm"

[alignment]
rotation = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
scale = 0.5

[pelvis]
markers = ["hips", "left", "back"]

[virtual.hips]
cluster = ["A", "B", "C", "D"]
[virtual.left]
mean = ["A", "B"]
[virtual.back]
marker = "C"
[virtual.knee]
cluster = ["@left", "E", "F"]
"""


def rigid_markers(rng, n_frames=30, units="mm"):
    """Markers A..F on two rigid bodies, and the true positions of joints hips and knee."""
    body = rng.normal(size=(4, 3)) * 100
    leg = rng.normal(size=(2, 3)) * 100
    rotations = Rotation.random(n_frames, random_state=11).as_matrix()
    legs = Rotation.random(n_frames, random_state=12).as_matrix()
    shift = rng.normal(size=(n_frames, 3)) * 500
    upper = np.einsum("fab,kb->fka", rotations, body) + shift[:, None]
    left = upper[:, :2].mean(axis=1)
    lower = np.einsum("fab,kb->fka", legs, leg - leg[0] + 50) + left[:, None]
    hips_local, knee_local = np.array([10.0, -20.0, 30.0]), np.array([5.0, 60.0, 0.0])
    hips = np.einsum("fab,b->fa", rotations, hips_local) + shift
    knee_frame = np.stack([left, lower[:, 0], lower[:, 1]], axis=1)
    knee = np.einsum("fab,b->fa", legs, knee_local) + knee_frame.mean(axis=1)
    markers = MarkerSet(labels=list("ABCDEF"), positions=np.concatenate([upper, lower], axis=1), rate=100, units=units)
    return markers, hips, knee


def test_shipped_maps_load_and_are_calibrated():
    assert (MAPS_DIR / "cmu.toml").exists()
    cmu = load_marker_map("cmu")
    assert cmu.pelvis == ("root", "lhipjoint", "rhipjoint") and cmu.units == "mm"
    assert len(cmu.virtual) == 31 and all(v.calibrated for v in cmu.virtual)
    assert len(cmu.labels()) == 41  # the CMU 41-marker set
    np.testing.assert_allclose(cmu.alignment.scale, 0.45 / 25.4)
    joints = load_marker_map("joints")
    assert joints.joints and joints.virtual == ()


def test_text_round_trip(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL_MAP)
    loaded = load_marker_map(path)
    assert loaded.names == ("hips", "left", "back", "knee") and loaded.pelvis == ("hips", "left", "back")
    assert [v.kind for v in loaded.virtual] == ["cluster", "mean", "marker", "cluster"]
    again_path = tmp_path / "again.toml"
    again_path.write_text(marker_map_text(loaded))
    again = load_marker_map(again_path)
    assert marker_map_text(again) == marker_map_text(loaded)
    np.testing.assert_array_equal(again.alignment.rotation, loaded.alignment.rotation)


@pytest.mark.parametrize(
    ("change", "message", "line"),
    [
        (("[virtual.hips]", "[virtual.hips"), "not valid TOML", 13),
        (('marker = "C"', 'marker = "C"\nmean = ["C"]'), "exactly one of marker, mean, cluster", None),
        (('["@left", "E", "F"]', '["@nope", "E", "F"]'), "@nope, which is not an earlier virtual marker", None),
        (('["A", "B", "C", "D"]', '["A", "B"]'), "a cluster needs at least three markers", None),
        (('"hips", "left", "back"', '"hips", "left", "elbow"'), "[pelvis] names elbow", None),
        (('units = "mm"', 'units = "furlong"'), "units 'furlong'", None),
        (("scale = 0.5", "scale = -1"), "[alignment]", None),
    ],
)
def test_bad_map_files(tmp_path, change, message, line):
    path = tmp_path / "bad.toml"
    path.write_text(SMALL_MAP.replace(*change))
    with pytest.raises(MotionFileError) as error:
        load_marker_map(path)
    assert message in str(error.value) and error.value.line == line


def test_unknown_map_name_lists_the_known_ones():
    with pytest.raises(
        MotionFileError, match="known maps are joints, asis-psis, cmu, opensim-gait, plug-in-gait, qualisys"
    ):
        load_marker_map("nonesuch")


def test_calibration_finds_exact_offsets_on_rigid_clusters(rng, tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL_MAP)
    markers, hips, knee = rigid_markers(rng)
    marker_map = load_marker_map(path)
    alignment = marker_map.alignment
    joints = alignment.apply(np.stack([hips, knee], axis=1))  # known poses, skeleton space
    calibrated = calibrate_marker_map(marker_map, markers, joints, ["hips", "knee"], slice(0, 20))
    assert all(v.calibrated for v in calibrated.virtual)
    assert calibrated.virtual[0].rms < 1e-9 and calibrated.virtual[3].rms < 1e-9
    virtual = compute_virtual_markers(markers, calibrated)
    assert virtual.valid.all() and virtual.reasons == ()
    # frames 20-29 were not used for calibration: still exact
    np.testing.assert_allclose(virtual.positions[:, 0], hips, atol=1e-9)
    np.testing.assert_allclose(virtual.positions[:, 3], knee, atol=1e-9)
    np.testing.assert_allclose(virtual.positions[:, 1], markers.positions[:, :2].mean(axis=1))
    np.testing.assert_allclose(virtual.skeleton_positions()[:, 0], joints[:, 0], atol=1e-9)
    assert np.nanmax(virtual.fit_rms[:, 0]) < 1e-9
    # markers in metres are converted to the map's millimetres first
    metres = markers.in_units("m")
    np.testing.assert_allclose(compute_virtual_markers(metres, calibrated).positions, virtual.positions, atol=1e-9)


def test_gaps_spoil_the_frames_they_touch_and_say_so(rng, tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL_MAP)
    markers, hips, knee = rigid_markers(rng)
    calibrated = calibrate_marker_map(
        load_marker_map(path), markers, load_marker_map(path).alignment.apply(np.stack([hips, knee], 1)),
        ["hips", "knee"],
    )  # fmt: skip
    positions = markers.positions.copy()
    positions[5, 0] = np.nan  # A: hips keeps three markers, left (a mean) is lost, so is knee (@left)
    positions[8:11, 4] = np.nan  # E: knee keeps @left and F only
    gappy = markers.replace(positions=positions)
    virtual = compute_virtual_markers(gappy, calibrated)
    np.testing.assert_array_equal(virtual.valid[:, 0], True)
    np.testing.assert_allclose(virtual.positions[5, 0], hips[5], atol=1e-9)
    assert list(np.flatnonzero(~virtual.valid[:, 1])) == [5]
    assert list(np.flatnonzero(~virtual.valid[:, 3])) == [5, 8, 9, 10]
    assert np.isnan(virtual.positions[~virtual.valid]).all()
    text = " | ".join(virtual.reasons)
    assert "left: missing in frames 5 (1 frames), its markers A lack there" in text
    assert "knee: missing in frames 5, 8-10 (4 frames)" in text
    # frames without gaps are untouched by them
    clean = compute_virtual_markers(markers, calibrated)
    untouched = np.setdiff1d(np.arange(30), [5, 8, 9, 10])
    np.testing.assert_array_equal(virtual.positions[untouched], clean.positions[untouched])
    # filled only when asked: the gap of 3 frames in E is bridged by interpolation
    filled = compute_virtual_markers(gappy.filled(3), calibrated)
    assert filled.valid[8:11, 3].all()


def test_uncalibrated_clusters_and_absent_markers(rng, tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL_MAP)
    markers, _, _ = rigid_markers(rng)
    with pytest.raises(OperationError, match="'hips' of map 'small' is not calibrated"):
        compute_virtual_markers(markers, load_marker_map(path))
    plain = MarkerMap("p", (VirtualMarker("x", "mean", ("A", "Z")),))
    virtual = compute_virtual_markers(markers, plain)
    assert not virtual.valid.any() and "the markers Z are not in" in virtual.reasons[0]


def test_joints_map_resolves_against_the_skeleton_names(rng):
    markers = MarkerSet(labels=["root", "lhipjoint", "rhipjoint", "extra"], positions=rng.normal(size=(2, 4, 3)),
                        rate=30, units="mm")  # fmt: skip
    resolved = resolve_map(load_marker_map("joints"), markers, ["root", "lhipjoint", "rhipjoint", "lfemur"])
    assert resolved.names == ("root", "lhipjoint", "rhipjoint") and resolved.pelvis == resolved.names
    virtual = compute_virtual_markers(markers, resolved)
    np.testing.assert_array_equal(virtual.positions, markers.positions[:, :3])
    with pytest.raises(OperationError, match="needs markers labelled with joint names"):
        resolve_map(load_marker_map("joints"), markers, ["a", "b"])


def test_alignment_round_trip_and_the_cmu_relation():
    alignment = Similarity(np.array([[0.0, 1, 0], [0, 0, 1], [1, 0, 0]]), 0.45 / 25.4)
    amc = np.array([1.0, 2.0, 3.0])
    c3d = alignment.inverse().apply(amc)
    np.testing.assert_allclose(c3d, 56.444444 * np.array([3.0, 1.0, 2.0]), rtol=1e-6)  # (z, x, y) * 56.444
    np.testing.assert_allclose(alignment.apply(c3d), amc)
    with pytest.raises(ValueError):
        Similarity(np.diag([1.0, 1.0, 2.0]))


def test_frame_ranges_text():
    assert frame_ranges(np.array([0, 1, 2, 5, 7, 8])) == "0-2, 5, 7-8"
    assert frame_ranges(np.zeros(4, bool)) == "none"
    assert frame_ranges(np.arange(0, 40, 2), limit=3) == "0, 2, 4, ... (20 ranges)"


@pytest.mark.parametrize(
    ("relative", "map_name"),
    [
        ("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d", "plug-in-gait"),
        ("c3d/ezc3d_Vicon.c3d", "asis-psis"),
        ("trc/pyomeca_markers_comma_delimited.trc", "asis-psis"),
        ("c3d/ezc3d_Qualisys.c3d", "qualisys"),
        ("trc/opensim_gait2392_subject01_walk1.trc", "opensim-gait"),
    ],
)
def test_pelvis_only_maps_give_pelvis_frames_on_other_marker_sets(relative, map_name):
    from gmr_studio.core.markers import read_markers, recover_pelvis
    from gmr_studio.core.rotations.euler import rotation_angle
    from tests.conftest import shared_path

    markers = read_markers(shared_path(relative))
    frames = recover_pelvis(markers, map_name)
    assert frames.valid.all() and frames.reasons == () and frames.labels == ("pelvis", "left", "back")
    np.testing.assert_allclose(np.linalg.det(frames.rotations), 1.0)
    np.testing.assert_allclose(
        frames.rotations @ np.swapaxes(frames.rotations, -1, -2),
        np.broadcast_to(np.eye(3), frames.rotations.shape),
        atol=1e-12,
    )
    # skin markers on the pelvis keep its shape to a few millimetres, and it turns smoothly
    assert np.nanmax(frames.residuals) * unit_named(frames.units).metres * 1000 < 10.0  # millimetres
    step = rotation_angle(np.swapaxes(frames.rotations[:-1], -1, -2) @ frames.rotations[1:])
    assert np.degrees(step).max() < 5.0
