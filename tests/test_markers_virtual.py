"""Virtual markers and calibration (core/markers/virtual.py) beyond the exact case of
tests/test_markers_map.py: what resolve_map does with each kind of map, the reasons given for
gaps, the refusals of calibration, the frames it uses and what it keeps."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.jointmap import JointMap
from gmr_studio.core.markers.markermap import MarkerMap, VirtualMarker, joints_map
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.virtual import calibrate_marker_map, compute_virtual_markers, resolve_map
from gmr_studio.core.space.similarity import Similarity
from tests.conftest import random_motion

PERMUTATION = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])


def labelled(labels, positions, units="mm", source="") -> MarkerSet:
    return MarkerSet(labels=labels, positions=positions, rate=50.0, units=units, source=source)


#: a rigid triangle in its own frame (x, y in its plane), centred
TRIANGLE = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 60.0, 0.0]]) - [100.0 / 3, 20.0, 0.0]


def triangle_cluster(n_frames: int, rng) -> np.ndarray:
    """(F, 3, 3) the triangle's three markers moving and turning."""
    from scipy.spatial.transform import Rotation

    turns = Rotation.random(n_frames, random_state=3).as_matrix()
    return np.einsum("fab,kb->fka", turns, TRIANGLE) + rng.normal(size=(n_frames, 1, 3)) * 300


# ------------------------------------------------------------------ resolve_map
def test_a_named_map_is_returned_as_is_or_renamed_for_another_skeleton(rng):
    named = MarkerMap(
        "lab", (VirtualMarker("root", "cluster", ("A", "B", "C")), VirtualMarker("lhip", "marker", ("D",)),
                VirtualMarker("rhip", "marker", ("E",))), pelvis=("root", "lhip", "rhip"),
    )  # fmt: skip
    markers = labelled(list("ABCDE"), rng.normal(size=(2, 5, 3)))
    assert resolve_map(named, markers) is named
    assert resolve_map(named, markers, ["Hips", "L", "R"]) is named  # names alone: no renaming
    pairs = JointMap.from_pairs({"Hips": "root", "L": "lhip", "R": "rhip"})
    renamed = resolve_map(named, markers, ["Hips", "L", "R"], joint_map=pairs)
    assert renamed.names == ("Hips", "L", "R")
    skeleton = random_motion(rng, [-1, 0, 0], n_frames=2).replace(names=("Hips", "L", "R"))
    assert resolve_map(named, markers, skeleton=skeleton, joint_map=pairs).pelvis == ("Hips", "L", "R")


def test_the_joints_map_keeps_the_names_labelled_in_the_skeletons_order(rng):
    markers = labelled(["c", "x", "a", "b"], rng.normal(size=(3, 4, 3)), source="take.trc")
    aligned = joints_map(()).replace(alignment=Similarity(PERMUTATION, 2.0))
    resolved = resolve_map(aligned, markers, ["a", "b", "z", "c"], skeleton=None)
    assert resolved.names == ("a", "b", "c") and resolved.joints
    assert resolved.alignment.scale == 2.0
    every_label = resolve_map(joints_map(()), markers)
    assert every_label.names == ("c", "x", "a", "b")
    with pytest.raises(
        OperationError, match=r"^the 'joints' map needs markers labelled with joint names; take.trc has none$"
    ):
        resolve_map(joints_map(()), markers, ["p", "q"])
    with pytest.raises(OperationError, match=r"the marker set has none$"):
        resolve_map(joints_map(()), markers.replace(source=""), ["p", "q"])


def test_the_joints_maps_pelvis_named_when_labelled_else_chosen_and_said(rng):
    labels = ["root", "lhipjoint", "rhipjoint", "lowerback"]
    positions = np.array([[0.0, 0, 0], [-1.0, 0, -0.3], [1.0, 0, -0.3], [0.0, 1.0, 0.2]])
    markers = labelled(labels, np.broadcast_to(positions, (4, 4, 3)) + rng.normal(size=(4, 1, 3)))
    named = resolve_map(joints_map(labels, pelvis=("root", "lowerback", "lhipjoint")), markers)
    assert named.pelvis == ("root", "lowerback", "lhipjoint") and named.pelvis_note == ""
    chosen = resolve_map(joints_map(()), markers)
    assert chosen.pelvis == ("root", "lhipjoint", "rhipjoint")
    assert chosen.pelvis_note.startswith("pelvis triple root, lhipjoint, rhipjoint (root and both hips, by their names")
    level = markers.positions.copy()
    level[:, 1:3, 2] = level[:, :1, 2]  # hips level with the root: collinear, no choice; the names' guess
    guessed = resolve_map(joints_map(()), markers.replace(positions=level))
    assert guessed.pelvis == ("root", "lhipjoint", "rhipjoint") and guessed.pelvis_note == ""
    with_skeleton = resolve_map(
        joints_map(()), markers, skeleton=random_motion(rng, [-1, 0, 0, 0], angle=0.0).replace(names=labels)
    )
    assert with_skeleton.pelvis_note.startswith("pelvis triple root, lhipjoint, lowerback (the technical note's")


def test_with_a_skeleton_the_joints_are_its_own_and_its_motion_measures_the_shape(rng):
    """The skeleton's names, not every label; its lower back moving on the pelvis in its own
    motion (two frames or more: measured exactly) is refused though the markers keep their
    shape, and the hips are taken."""
    labels = ["root", "lhipjoint", "rhipjoint", "lowerback"]
    positions = np.array([[0.0, 0, 0], [-1.0, 0, -0.3], [1.0, 0, -0.3], [0.0, 1.0, 0.2], [5.0, 5.0, 5.0]])
    markers = labelled([*labels, "wand"], np.broadcast_to(positions, (4, 5, 3)) + rng.normal(size=(4, 1, 3)))
    for n_frames in (2, 3):
        skeleton = random_motion(rng, [-1, 0, 0, 0], n_frames, translation_joints=(3,), angle=0.0)
        resolved = resolve_map(joints_map(()), markers, skeleton=skeleton.replace(names=labels))
        assert resolved.names == tuple(labels)
        assert resolved.pelvis_note.startswith("pelvis triple root, lhipjoint, rhipjoint (root and both hips")
    still = random_motion(rng, [-1, 0, 0, 0], 1, translation_joints=(3,), angle=0.0).replace(names=labels)
    on_markers = resolve_map(joints_map(()), markers, skeleton=still)  # one frame: the markers measure
    assert on_markers.pelvis_note.startswith("pelvis triple root, lhipjoint, lowerback (the technical note's")
    named = resolve_map(joints_map(()), markers, ["root", "lhipjoint", "rhipjoint"], skeleton=still)
    assert named.names == ("root", "lhipjoint", "rhipjoint")  # names given win over the skeleton's


def test_options_after_the_markers_are_keywords(rng):
    markers = labelled(["a"], rng.normal(size=(2, 1, 3)))
    with pytest.raises(TypeError):
        resolve_map(joints_map(()), markers, ["a"], None)  # type: ignore[misc]
    with pytest.raises(TypeError):
        calibrate_marker_map(joints_map(()), markers, np.zeros((2, 1, 3)), ["a"], None, None)  # type: ignore[misc]


def test_virtual_markers_are_frozen_and_compared_by_identity(rng):
    markers = labelled(["a"], rng.normal(size=(2, 1, 3)))
    virtual = compute_virtual_markers(markers, joints_map(["a"]))
    with pytest.raises(dataclasses.FrozenInstanceError):
        virtual.units = "m"  # type: ignore[misc]
    assert virtual != dataclasses.replace(virtual) and len({virtual, virtual}) == 1


# ------------------------------------------------------------------ compute
def test_virtual_markers_of_each_kind_in_the_maps_units(rng):
    cluster = triangle_cluster(5, rng)
    markers = labelled(["A", "B", "C"], cluster / 1000.0, units="m", source="t.c3d")
    template = TRIANGLE
    marker_map = MarkerMap(
        "m", (
            VirtualMarker("mid", "mean", ("A", "B")),
            VirtualMarker("c", "marker", ("C",)),
            VirtualMarker("body", "cluster", ("A", "B", "C"), np.array([0.0, 0.0, 50.0]), template),
            VirtualMarker("tip", "mean", ("@mid", "@c")),
        ), units="mm", alignment=Similarity(PERMUTATION, 0.5),
    )  # fmt: skip
    virtual = compute_virtual_markers(markers, marker_map)
    assert virtual.units == "mm" and virtual.rate == 50.0 and virtual.n_frames == 5 and virtual.reasons == ()
    np.testing.assert_allclose(virtual.positions[:, 0], cluster[:, :2].mean(axis=1), rtol=1e-12)
    np.testing.assert_allclose(virtual.positions[:, 1], cluster[:, 2], rtol=1e-12)
    np.testing.assert_allclose(virtual.positions[:, 3], (virtual.positions[:, 0] + cluster[:, 2]) / 2, rtol=1e-12)
    normal = np.cross(cluster[:, 1] - cluster[:, 0], cluster[:, 2] - cluster[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    np.testing.assert_allclose(virtual.positions[:, 2], cluster.mean(axis=1) + 50.0 * normal, atol=1e-9)
    assert np.isnan(virtual.fit_rms[:, [0, 1, 3]]).all() and virtual.fit_rms[:, 2].max() < 1e-9
    assert virtual.valid.all() and virtual.index("body") == 2
    with pytest.raises(OperationError, match=r"^no virtual marker 'nose'$"):
        virtual.index("nose")
    np.testing.assert_allclose(virtual.skeleton_positions(), 0.5 * virtual.positions @ PERMUTATION.T)
    same_units = compute_virtual_markers(markers.in_units("mm"), marker_map.replace(units=None))
    assert same_units.units == "mm"
    np.testing.assert_allclose(same_units.positions, virtual.positions, rtol=1e-12)


def test_the_reasons_name_the_frames_and_the_markers_lacking(rng):
    cluster = triangle_cluster(6, rng)
    positions = np.concatenate([cluster, cluster[:, :1] + 10.0], axis=1)
    positions[[1, 2], 3] = np.nan  # D missing in frames 1-2
    positions[4, 0] = np.nan  # A missing in frame 4: two markers left of the three, no fit
    template = TRIANGLE
    marker_map = MarkerMap("m", (
        VirtualMarker("ad", "mean", ("A", "D")),
        VirtualMarker("body", "cluster", ("A", "B", "C"), np.zeros(3), template),
        VirtualMarker("far", "mean", ("A", "Z", "Y")),
    ))  # fmt: skip
    virtual = compute_virtual_markers(labelled(list("ABCD"), positions, source="s.c3d"), marker_map)
    assert virtual.reasons == (
        "the markers Z, Y are not in s.c3d",
        "ad: missing in frames 1-2, 4 (3 frames), its markers A, D lack there",
        "body: missing in frames 4 (1 frames), its markers A lack there",
        "far: missing in frames 0-5 (6 frames), its markers A, Z, Y lack there",
    )
    assert virtual.valid[:, 0].tolist() == [True, False, False, True, False, True]
    assert np.isnan(virtual.positions[~virtual.valid]).all()


def test_a_cluster_with_a_degenerate_template_says_so(rng):
    """Every marker seen, but the template (an edited map's) is a line: the roll is free."""
    markers = labelled(list("ABC"), triangle_cluster(3, rng))
    line = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]])
    marker_map = MarkerMap("m", (VirtualMarker("body", "cluster", ("A", "B", "C"), np.zeros(3), line),))
    virtual = compute_virtual_markers(markers, marker_map)
    assert virtual.reasons == ("body: missing in frames 0-2 (3 frames), its markers are degenerate",)
    uncalibrated = MarkerMap("m", (VirtualMarker("body", "cluster", ("A", "B", "C")),))
    with pytest.raises(OperationError, match=r"^virtual marker 'body' of map 'm' is not calibrated: calibrate"):
        compute_virtual_markers(markers, uncalibrated)


# ------------------------------------------------------------------ calibration
def calibration_case(rng, n_frames=8):
    cluster = triangle_cluster(n_frames, rng)
    centre = cluster.mean(axis=1)
    normal = np.cross(cluster[:, 1] - cluster[:, 0], cluster[:, 2] - cluster[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    joint = centre + 40.0 * normal  # the joint, rigid with the cluster
    markers = labelled(list("ABC"), cluster)
    marker_map = MarkerMap("m", (
        VirtualMarker("body", "cluster", ("A", "B", "C")), VirtualMarker("mid", "mean", ("A", "B")),
    ), calibration={"by": "hand"})  # fmt: skip
    return markers, marker_map, joint


def test_calibration_finds_the_offset_and_keeps_the_rest(rng):
    markers, marker_map, joint = calibration_case(rng)
    home = np.arange(9.0).reshape(3, 3)
    calibrated = calibrate_marker_map(
        marker_map, markers, joint[:, None], ["body"], note={"frames": "all"}, pelvis_home=home
    )
    body = calibrated.virtual[0]
    np.testing.assert_allclose(np.linalg.norm(body.offset), 40.0, rtol=1e-9)
    assert body.rms < 1e-9 and calibrated.virtual[1] is marker_map.virtual[1]
    assert calibrated.calibration == {"by": "hand", "frames": "all"} and marker_map.calibration == {"by": "hand"}
    np.testing.assert_array_equal(calibrated.pelvis_home, home)
    kept = calibrate_marker_map(marker_map.replace(pelvis_home=home + 1), markers, joint[:, None], ["body"])
    np.testing.assert_array_equal(kept.pelvis_home, home + 1)
    assert kept.calibration == {"by": "hand"}
    np.testing.assert_allclose(compute_virtual_markers(markers, kept).positions[:, 0], joint, atol=1e-9)


def test_calibration_rms_is_the_root_mean_square_distance_and_the_template_the_first_frames(rng):
    """The joint off its rigid place by d along the cluster's normal, out and in in turn: the
    offset is the rigid one, the RMS d. The template is the first complete frame's shape,
    centred, in the markers' axes (a recalibration on the same frames writes the same map)."""
    markers, marker_map, joint = calibration_case(rng, n_frames=9)
    cluster = markers.positions
    normal = joint - cluster.mean(axis=1)  # 40 along the normal
    wobble = joint + normal / 40.0 * 2.5 * np.array([0.0] + [1.0, -1.0] * 4)[:, None]
    gappy = cluster.copy()
    gappy[0, 1] = np.nan  # frame 0 incomplete: the first complete frame is frame 1
    body = calibrate_marker_map(marker_map, markers.replace(positions=gappy), wobble[:, None], ["body"]).virtual[0]
    assert body.rms == pytest.approx(2.5, rel=1e-9)
    np.testing.assert_allclose(np.linalg.norm(body.offset), 40.0, rtol=1e-9)
    np.testing.assert_allclose(body.template, cluster[1] - cluster[1].mean(axis=0), atol=1e-9)


def test_calibration_uses_only_the_frames_chosen(rng):
    markers, marker_map, joint = calibration_case(rng)
    wrong = joint.copy()
    wrong[5:] += 30.0  # frames 5-7 disagree with the others
    for frames in (slice(0, 5), np.arange(5), np.arange(8) < 5):
        body = calibrate_marker_map(marker_map, markers, wrong[:, None], ["body"], frames).virtual[0]
        assert body.rms < 1e-9, frames
    assert calibrate_marker_map(marker_map, markers, wrong[:, None], ["body"]).virtual[0].rms > 1.0


def test_a_static_pose_of_one_frame_calibrates_frames_held_still(rng):
    markers, marker_map, joint = calibration_case(rng)
    still = markers.replace(positions=np.broadcast_to(markers.positions[:1], markers.positions.shape))
    body = calibrate_marker_map(marker_map, still, joint[:1, None], ["body"]).virtual[0]
    assert body.rms < 1e-9
    with pytest.raises(OperationError, match=r"the reference has 2 frames and the markers 8: calibration needs"):
        calibrate_marker_map(marker_map, markers, joint[:2, None], ["body"])


def test_calibration_refusals(rng):
    markers, marker_map, joint = calibration_case(rng)
    with pytest.raises(OperationError, match=r"^virtual marker 'body' is not a joint of the reference$"):
        calibrate_marker_map(marker_map, markers, joint[:, None], ["torso"])
    gappy = markers.positions.copy()
    gappy[:, 1] = np.nan
    with pytest.raises(
        OperationError, match=r"^cluster 'body' \(A, B, C\) is never complete in the calibration frames$"
    ):
        calibrate_marker_map(marker_map, markers.replace(positions=gappy), joint[:, None], ["body"])
    line = markers.positions.copy()
    line[:, 2] = 2 * line[:, 1] - line[:, 0]
    with pytest.raises(OperationError, match=r"^cluster 'body': its markers are collinear in every calibration frame$"):
        calibrate_marker_map(marker_map, markers.replace(positions=line), joint[:, None], ["body"])
