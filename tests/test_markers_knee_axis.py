"""Functional joints (core/markers/functional_joints.py): the knee on its functional flexion
axis (SARA, CGM 2.x's functional knee) and the markers placed again after the first
refinement (OpenSim's marker placer). Synthetic hinges with a known axis (frames a cluster
misses, clusters never complete, the flexion range and its limit, the trajectory seen most, a
centre filled from its cluster), then the shared files' figures."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from gmr_studio.core.markers import functional_joints as fj
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.functional_joints import (
    SARA_MIN_FLEXION,
    flexion_axis,
    flexion_range,
    knee_on_axis,
    knee_on_flexion_axis,
)
from gmr_studio.core.markers.limbs import about_axis
from gmr_studio.core.rotations.euler import nearest_rotation
from tests.conftest import shared_path

THIGH_LOCAL = np.array([[40.0, 60.0, 250.0], [-30.0, 70.0, 180.0], [50.0, 55.0, 120.0]])  # about the knee
SHANK_LOCAL = np.array([[45.0, 40.0, -120.0], [-20.0, 50.0, -200.0], [30.0, 35.0, -300.0]])
HIP_LOCAL = np.array([0.0, 0.0, 420.0])  # the hip centre in the thigh frame, from the true knee


def _hinge_take(flexion_degrees: float, n_frames: int = 40, seed: int = 0):
    """Thigh and shank clusters (F, 3, 3) turning about a hinge through the true knee centre
    (along the thigh frame's y axis), the hip centre (F, 3), the true centre (F, 3) and the
    thigh rotations (F, 3, 3)."""
    rng = np.random.default_rng(seed)
    thigh = nearest_rotation(np.eye(3) + rng.normal(scale=0.4, size=(n_frames, 3, 3)))
    centre = rng.normal(scale=300.0, size=(n_frames, 3))
    flex = np.radians(np.linspace(0.0, flexion_degrees, n_frames))
    shank = thigh @ about_axis(np.array([0.0, 1.0, 0.0]), flex)
    thigh_markers = centre[:, None] + np.einsum("fab,kb->fka", thigh, THIGH_LOCAL)
    shank_markers = centre[:, None] + np.einsum("fab,kb->fka", shank, SHANK_LOCAL)
    hip = centre + thigh @ HIP_LOCAL
    return thigh_markers, shank_markers, hip, centre, thigh, shank


def test_sara_finds_the_hinge_axis_exactly():
    thigh_markers, shank_markers, _, centre, thigh, _ = _hinge_take(70.0)
    axis = flexion_axis(thigh_markers, shank_markers)
    assert axis.ok.all()
    # the axis is fixed in both clusters: placed by either, its direction is the thigh's y
    world_direction = np.einsum("fab,b->fa", axis.r1, axis.direction[:3])
    assert np.abs(np.abs(np.einsum("fa,fa->f", world_direction, thigh[:, :, 1])) - 1.0).max() < 1e-9
    assert np.abs(world_direction - np.einsum("fab,b->fa", axis.r2, axis.direction[3:])).max() < 1e-9
    # its point, placed in every frame, lies on the true axis through the knee
    offset = axis.place(axis.point) - centre
    off_axis = offset - np.einsum("fa,fa->f", offset, thigh[:, :, 1])[:, None] * thigh[:, :, 1]
    assert np.abs(off_axis).max() < 1e-8


def test_the_knee_moves_where_the_femur_axis_meets_the_flexion_axis():
    # the anatomical knee (the epicondyle mid-point) 20 mm anterior, 15 mm medial, 10 mm
    # distal of the true centre, as skin markers put it: the SARA knee is the point of the
    # flexion axis nearest the line from the hip to that anatomical knee
    thigh_markers, shank_markers, hip, centre, thigh, _ = _hinge_take(70.0, seed=1)
    anatomical_local = np.array([20.0, 15.0, -10.0])
    anatomical = centre + thigh @ anatomical_local
    moved, distance = knee_on_flexion_axis(flexion_axis(thigh_markers, shank_markers), hip, anatomical)
    # by hand, in the thigh frame (true knee at 0, axis y): minimise |s y - (h + u (k - h))|
    femur = anatomical_local - HIP_LOCAL
    s, _ = np.linalg.lstsq(np.stack([[0.0, 1.0, 0.0], -femur], axis=1), HIP_LOCAL, rcond=None)[0]
    expected_local = np.array([0.0, s, 0.0])
    assert np.abs(moved - (centre + thigh @ expected_local)).max() < 1e-8
    assert distance == pytest.approx(np.linalg.norm(expected_local - anatomical_local), abs=1e-8)


def test_a_knee_that_barely_flexes_keeps_its_anatomical_centre():
    # SARA's axis needs a range of motion: below SARA_MIN_FLEXION degrees the centre is kept
    for degrees, moves in ((SARA_MIN_FLEXION / 3, False), (2 * SARA_MIN_FLEXION, True)):
        thigh_markers, shank_markers, hip, centre, thigh, shank = _hinge_take(degrees, seed=2)
        anatomical = centre + thigh @ np.array([20.0, 0.0, 0.0])
        ankle = centre + shank @ np.array([0.0, 0.0, -400.0])
        assert flexion_range(hip, centre, ankle) == pytest.approx(0.9 * degrees, rel=0.01)  # 5% to 95%
        found = knee_on_axis(list(np.swapaxes(thigh_markers, 0, 1)), list(np.swapaxes(shank_markers, 0, 1)),
                             hip, anatomical, ankle)  # fmt: skip
        assert (found is not None) == moves
        if moves:
            assert np.abs(found[0] - centre).max() < 1e-8  # the femur line meets the axis at the knee
            assert found[1] == pytest.approx(20.0, abs=1e-8)


# ------------------------------------------------------------------ the shared files' figures


def _refined(relative: str):
    built = markers_to_built_motion(read_markers(shared_path(relative)), refine=True)
    valid = built.result.frame_valid
    return built, np.nanmedian(built.refinement.residuals[valid], axis=0)


def test_walking5_knees_on_their_flexion_axes_and_every_marker_within_10_mm():
    # before: the right medial condyle 10.3 mm (a ball joint at the epicondyle mid-point,
    # 25 mm off the axis the knee turns about, could not follow thigh and shank as it flexed)
    built, residual = _refined("c3d/opensim-core_walking5.c3d")
    methods = built.built.methods
    assert "SARA" in methods["LKJC"] and "SARA" in methods["RKJC"]
    moved = {note.split()[0]: float(note.split(", ")[1].split()[0]) for note in built.built.notes if "SARA" in note}
    assert 20.0 < moved["R"] < 30.0 and 8.0 < moved["L"] < 16.0  # measured 25.4 and 11.9 mm
    assert residual.max() <= 10.0, dict(zip(built.labels, residual.round(1)))  # measured 6.6 (RTH2)
    for label in ("RMFC", "RLFC", "LMFC", "LLFC"):
        assert residual[built.labels.index(label)] < 8.0  # measured 6.6, 4.8, 4.8, 3.8
    assert np.nanmax(built.built.spread) < 9.0  # the shank's length spread: 11.7 mm before, 7.4 after


def test_walking5_trc_excerpt_every_marker_within_10_mm():
    # the excerpt flexes the knee by less than 30 degrees where both clusters are seen, so its
    # knees stay anatomical; its knee markers are seen in one frame with a pelvis, placed again
    # after the first fit (before: LMFC 11.0 mm, its offset taken from the closed form)
    built, residual = _refined("trc/opensim-core_dataWithBlanksForMissingMarkers.trc")
    assert not any("SARA" in built.built.methods[k] for k in ("LKJC", "RKJC"))
    assert residual.max() <= 10.0, dict(zip(built.labels, residual.round(1)))  # measured 6.1 (LMFC)


@pytest.mark.parametrize(
    ("relative", "most"),
    [("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d", 1.0), ("c3d/c3dorg_s03_gait-pig.c3d", 6.0)],
)
def test_plug_in_gait_files_stay_within_10_mm(relative, most):
    # no thigh or shank clusters: the knees are Plug-in Gait's chord, the placement changes
    # their figures by hundredths of a millimetre (0.38 -> 0.44 and 4.71 -> 4.78 mm)
    built, residual = _refined(relative)
    assert not any("SARA" in m for m in built.built.methods.values())
    assert residual.max() <= most  # measured 0.4 and 4.8


def test_walking5_anatomical_knees_agree_with_the_lab_model_and_functional_ones_move():
    # --knee anatomical keeps the condyle mid-point, where Plug-in Gait puts its knee: the lab's
    # LKJC / RKJC stored in the file are 4.7 / 7.9 mm away (median); on the flexion axis (the
    # default) ours move 12 and 25 mm from there, and so from the lab's
    from gmr_studio.core.kinematics.fk import world_positions
    from gmr_studio.core.markers.file_model import compare_with_file_model

    markers = read_markers(shared_path("c3d/opensim-core_walking5.c3d")).in_units("mm")
    median = {}
    for knee in ("anatomical", "functional"):
        built = markers_to_built_motion(markers, knee=knee)
        motion = built.result.motion
        report = compare_with_file_model(markers, motion, world_positions(motion))
        median[knee] = {row["name"]: row["median_mm"] for row in report["joints"]}
        assert ("SARA" in built.built.methods["RKJC"]) == (knee == "functional")
    assert median["anatomical"]["LKJC"] < 6.0 and median["anatomical"]["RKJC"] < 9.0  # 4.7, 7.9
    assert median["functional"]["RKJC"] > median["anatomical"]["RKJC"] + 15.0  # 28.6
    assert median["functional"]["LAJC"] == pytest.approx(median["anatomical"]["LAJC"], abs=3.0)


def test_an_unknown_knee_or_hip_method_is_refused():
    markers = read_markers(shared_path("c3d/opensim-core_walking5.c3d"))
    with pytest.raises(ValueError, match="knee 'chord'"):
        markers_to_built_motion(markers, knee="chord")


def test_a_frame_a_cluster_misses_has_no_centre_and_the_others_are_exact():
    thigh, shank, _, centre, rotations, _ = _hinge_take(70.0, seed=2)
    thigh[3, :2] = np.nan  # one marker left: no fit in frame 3
    shank[7] = np.nan
    found = fj.functional_centre(thigh, shank)
    missing = [3, 7]
    assert np.isnan(found[missing]).all() and np.isfinite(np.delete(found, missing, axis=0)).all()
    axis = fj.flexion_axis(thigh, shank)
    assert list(np.flatnonzero(~axis.ok)) == missing
    assert np.isnan(axis.place(axis.point)[missing]).all()
    # the hinge's centre: on the axis through the true centre (the thigh's y), in the frames seen
    offset, y = np.delete(found - centre, missing, axis=0), np.delete(rotations[:, :, 1], missing, axis=0)
    assert np.abs(offset - np.einsum("fa,fa->f", offset, y)[:, None] * y).max() < 1e-8


def test_clusters_never_complete_or_never_fitted_together_give_nothing():
    thigh, shank, _, _, _, _ = _hinge_take(70.0)
    never = thigh.copy()
    never[:, 0] = np.nan
    assert np.isnan(fj.functional_centre(never, shank)).all() and fj.functional_centre(never, shank).shape == (40, 3)
    assert fj.flexion_axis(never, shank) is None and fj.flexion_axis(thigh, never) is None
    # both fitted together in one frame only: no axis (two frames at least)
    apart = shank.copy()
    apart[1:, :2] = np.nan
    assert fj.flexion_axis(thigh, apart) is None
    apart[1, :] = shank[1]
    assert fj.flexion_axis(thigh, apart) is not None


def test_in_proximal_takes_the_median_of_the_frames_seen():
    thigh, shank, hip, _, _, _ = _hinge_take(70.0)
    axis = fj.flexion_axis(thigh, shank)
    local = fj.FlexionAxis.in_proximal(axis, hip)
    points = hip.copy()
    points[5] = np.nan
    points[9] += 1000.0  # one frame far off: the median ignores it
    np.testing.assert_allclose(axis.in_proximal(points), local, atol=1e-9)
    with pytest.raises(dataclasses.FrozenInstanceError):
        axis.point = axis.point  # type: ignore[misc]


def test_flexion_range_is_the_5th_to_95th_percentile_of_the_knee_angle():
    # thigh along -z, the shank turned by 0 to 120 degrees over 121 frames (one a degree)
    angles = np.radians(np.arange(121.0))
    hjc = np.tile([0.0, 0, 400], (121, 1))
    kjc = np.zeros((121, 3))
    ajc = np.stack([np.sin(angles), np.zeros(121), -np.cos(angles)], axis=1) * 400
    assert fj.flexion_range(hjc, kjc, ajc) == pytest.approx(0.9 * 120, abs=1e-9)
    kjc[10] = np.nan  # unseen frames are left out
    seen = np.delete(np.arange(121.0), 10)
    expected = np.percentile(seen, 95) - np.percentile(seen, 5)
    assert fj.flexion_range(hjc, kjc, ajc) == pytest.approx(expected, abs=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # NaN everywhere: no angle at all
        assert fj.flexion_range(hjc, np.full((121, 3), np.nan), ajc) == 0.0


def test_a_straight_or_folded_knee_has_an_angle_though_its_cosine_rounds_beyond_one():
    # a direction whose unit vector's square sums to 1 + 2**-52: thigh and shank along it
    # (straight) or against it (folded), the cosine rounds to +-(1 + 2**-52)
    d = np.array([0.9034701816518086, 0.09401229776087457, -0.7434992493538084])
    unit = d / np.linalg.norm(d)
    assert np.sum(unit * unit) > 1.0
    hjc, kjc = np.zeros((20, 3)), np.broadcast_to(d, (20, 3))
    ajc = np.concatenate([np.broadcast_to(2 * d, (10, 3)), np.zeros((10, 3))])  # straight, then folded
    assert fj.flexion_range(hjc, kjc, ajc) == 180.0


def test_the_knee_moves_onto_the_axis_only_from_30_degrees_of_flexion():
    # the hinge flexes evenly from 0 to the angle given: its range is 0.9 of it
    for flexion, moved in ((29.5 / 0.9, False), (30.5 / 0.9, True)):
        thigh, shank, hip, centre, _, turns = _hinge_take(flexion)
        ankle = centre + turns @ [0.0, 0.0, -400.0]
        assert fj.flexion_range(hip, centre, ankle) == pytest.approx(0.9 * flexion, abs=1e-6)
        clusters = list(thigh.transpose(1, 0, 2)), list(shank.transpose(1, 0, 2))
        assert (fj.knee_on_axis(*clusters, hip, centre, ankle) is not None) == moved
    thigh, shank, hip, centre, _, _ = _hinge_take(70.0)
    assert (
        fj.knee_on_axis(list(thigh.transpose(1, 0, 2))[:2], list(shank.transpose(1, 0, 2)), hip, centre, centre) is None
    )


def test_most_seen_is_the_first_of_the_most_seen():
    a, b, c = np.zeros((4, 3)), np.zeros((4, 3)), np.zeros((4, 3))
    a[0] = np.nan
    b[1, 2] = np.nan
    c[:2] = np.nan
    assert fj.most_seen([c, a, b]) is a
    assert fj.most_seen([c, np.zeros((4, 3)) + 1, a]).sum() == 12.0


def test_a_centre_is_filled_from_its_cluster_where_it_is_missing():
    thigh, _, _, centre, _, _ = _hinge_take(70.0)
    cluster = list(thigh.transpose(1, 0, 2))
    gappy = centre.copy()
    gappy[[0, 4, 5]] = np.nan
    cluster[0][5] = np.nan  # two markers left there: not filled
    cluster[2][1] = np.nan  # frame 1 incomplete too (its centre is seen): the template is frame 0's
    filled = fj.fill_from_cluster(gappy, cluster)
    np.testing.assert_allclose(filled[[0, 4]], centre[[0, 4]], atol=1e-9)
    assert np.isnan(filled[5]).all()
    np.testing.assert_array_equal(np.delete(filled, [0, 4, 5], 0), np.delete(gappy, [0, 4, 5], 0))
    assert np.isnan(gappy[0]).all()  # the centre given is left alone
    # nothing missing, too few markers, a cluster never complete, never seen with the centre
    assert fj.fill_from_cluster(centre, cluster) is centre
    assert fj.fill_from_cluster(gappy, cluster[:2]) is gappy
    never = [m.copy() for m in cluster]
    never[1][:] = np.nan
    assert fj.fill_from_cluster(gappy, never) is gappy
    assert fj.fill_from_cluster(np.full_like(centre, np.nan), cluster).shape == (40, 3)
    assert np.isnan(fj.fill_from_cluster(np.full_like(centre, np.nan), cluster)).all()


def test_the_cluster_frames_are_their_centred_first_complete_poses():
    thigh, shank, _, _, _, _ = _hinge_take(70.0)
    thigh[0, 1] = np.nan  # the thigh's first complete frame is frame 1
    axis = fj.flexion_axis(thigh, shank)
    np.testing.assert_allclose(axis.r1[1], np.eye(3), atol=1e-12)
    np.testing.assert_allclose(axis.t1[1], thigh[1].mean(axis=0), atol=1e-9)
    np.testing.assert_allclose(axis.r2[0], np.eye(3), atol=1e-12)
    np.testing.assert_allclose(axis.t2[0], shank[0].mean(axis=0), atol=1e-9)


def test_the_axis_point_is_a_point_of_the_hinge_axis():
    thigh, shank, _, centre, rotations, _ = _hinge_take(70.0, seed=6)
    axis = fj.flexion_axis(thigh, shank)
    offset = axis.place(axis.point) - centre
    y = rotations[:, :, 1]
    assert np.abs(offset - np.einsum("fa,fa->f", offset, y)[:, None] * y).max() < 1e-8


def test_the_centre_of_a_hinge_is_its_least_norm_point():
    """Along the hinge's axis (the thigh's y) the centre is the point nearest both clusters'
    centroids in their first frames, where both frames are the world's turned to identity."""
    thigh, shank, _, centre, rotations, _ = _hinge_take(70.0, seed=4)
    y = rotations[0][:, 1]
    s = -y @ ((centre[0] - thigh[0].mean(axis=0)) + (centre[0] - shank[0].mean(axis=0))) / 2
    np.testing.assert_allclose(fj.functional_centre(thigh, shank)[0], centre[0] + s * y, atol=1e-6)


def test_a_femur_along_the_flexion_axis_leaves_the_knee_at_the_axis_point():
    still = np.broadcast_to(np.eye(3), (3, 3, 3))
    axis = fj.FlexionAxis(
        point=np.zeros(6), direction=np.array([0.0, 1, 0, 0, 1, 0]), r1=still, t1=np.zeros((3, 3)),
        r2=still, t2=np.zeros((3, 3)), ok=np.ones(3, bool),
    )  # fmt: skip
    hip, knee = np.broadcast_to([0.0, 400, 0], (3, 3)), np.broadcast_to([0.0, 20, 0], (3, 3))
    placed, distance = fj.knee_on_flexion_axis(axis, hip, knee)
    np.testing.assert_array_equal(placed, np.zeros((3, 3)))
    assert distance == 20.0


def test_a_flexion_range_of_exactly_30_degrees_is_enough():
    """21 frames (the 5th and 95th percentiles are frames 1 and 19 of the sorted angles): a
    straight knee, 18 frames at 1e-8 rad, one at a shank angle found so that the range, as
    computed, is 30 degrees to the bit, and one at 60 degrees."""
    thigh, shank, _, _, _, _ = _hinge_take(70.0, n_frames=21)
    turns = np.array([0.0, *[1e-8] * 18, 0.5235987904994597, np.radians(60.0)])
    hjc, kjc = np.tile([0.0, 0, 400], (21, 1)), np.zeros((21, 3))
    ajc = np.stack([np.sin(turns), np.zeros(21), -np.cos(turns)], axis=1) * 400
    assert fj.flexion_range(hjc, kjc, ajc) == fj.SARA_MIN_FLEXION
    clusters = list(thigh.transpose(1, 0, 2)), list(shank.transpose(1, 0, 2))
    assert fj.knee_on_axis(*clusters, hjc, kjc, ajc) is not None
