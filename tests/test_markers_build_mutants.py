"""The built skeleton's edges (core/markers/build.py) that its mutation run showed untested:
the rest pose's bone directions, the root alone translating, the rate, the bone lengths'
spread and span, the subject's widths, and the pelvis or a leg the markers cannot place."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.build import DEFAULT_WIDTHS, _width, build_skeleton, joint_centre_trajectories
from gmr_studio.core.markers.sets import match_set, set_by_name
from tests.test_markers_build import generated_markers

DOWN = ("LKJC", "LAJC", "RKJC", "RAJC", "LEJC", "LWJC", "LHAND", "REJC", "RWJC", "RHAND")


@pytest.fixture(scope="module")
def full_body():
    markers, _ = generated_markers("plug-in-gait-full", n_frames=6, seed=2)
    return markers, build_skeleton(markers)


def test_the_rest_pose_hangs_legs_and_arms_below_the_trunk(full_body):
    _, built = full_body
    skeleton = built.skeleton
    offsets = np.asarray(skeleton.offsets)
    up = offsets[skeleton.joint_index("thorax")] / np.linalg.norm(offsets[skeleton.joint_index("thorax")])
    assert np.count_nonzero(np.abs(up) > 1e-12) == 1  # one of the file's axes
    for name in DOWN:
        j = skeleton.joint_index(name)
        np.testing.assert_allclose(offsets[j], -built.lengths[j] * up, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(np.linalg.norm(offsets[1:], axis=1), built.lengths[1:], rtol=1e-12)


def test_the_root_alone_translates_at_the_markers_rate_and_the_source_is_named(full_body):
    markers, built = full_body
    skeleton = built.skeleton
    assert skeleton.has_translation.tolist() == [True] + [False] * (skeleton.n_joints - 1)
    assert skeleton.frame_time == pytest.approx(1 / markers.rate, rel=1e-15)
    assert skeleton.comments == ("skeleton built from the markers of (memory), set plug-in-gait-full",)
    named = build_skeleton(markers.replace(source="walk.c3d", rate=250.0))
    assert named.skeleton.comments[0] == "skeleton built from the markers of walk.c3d, set plug-in-gait-full"
    assert named.skeleton.frame_time == pytest.approx(1 / 250.0, rel=1e-15)


def test_a_bones_length_is_the_median_its_spread_the_rms_about_it_and_its_span_5_to_95(rng):
    """The toe marker slid along the foot by +d and -d in turn: the toe bone's length is the
    rigid one, its spread d, its span the 5th and 95th percentiles."""
    markers, joints = generated_markers("helen-hayes", n_frames=8, seed=4)
    built = build_skeleton(markers)
    j = built.skeleton.joint_index("LTOE")
    rigid = built.lengths[j]
    assert built.spread[j] < 1e-9
    foot = joints["LTOE"] - joints["LAJC"]
    foot /= np.linalg.norm(foot, axis=1, keepdims=True)
    slide = 3.0 * np.array([1.0, -1.0] * 4)[:, None] * foot
    positions = markers.positions.copy()
    positions[:, markers.index("LTOE")] += slide
    moved = build_skeleton(markers.replace(positions=positions))
    assert moved.lengths[j] == pytest.approx(rigid, rel=1e-12)
    assert moved.spread[j] == pytest.approx(3.0, rel=1e-9)
    np.testing.assert_allclose(moved.span[j], np.percentile(rigid + 3.0 * np.array([1.0, -1.0] * 4), [5, 95]))
    assert np.isnan(moved.lengths[0]) and np.isnan(moved.spread[0]) and np.isnan(moved.span[0]).all()


def test_the_rest_pose_stands_up_the_files_axis_nearest_the_pelvis_vertical(full_body):
    """z (up) of the rest pose is the file's axis nearest the pelvis frame's mean vertical, with
    its sign: for the markers as generated and turned a quarter about x (z to -y)."""
    from gmr_studio.core.markers import joint_centres as jc

    markers, _ = full_body
    quarter = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
    seen = set()
    for turned in (markers, markers.transformed(quarter)):
        lasi, rasi = (turned.positions[:, turned.index(n)] for n in ("LASI", "RASI"))
        psi = 0.5 * (turned.positions[:, turned.index("LPSI")] + turned.positions[:, turned.index("RPSI")])
        vertical = np.nanmean(jc.pelvis_frame(lasi, rasi, psi)[1][:, :, 2], axis=0)
        k = int(np.argmax(np.abs(vertical)))
        expected = np.zeros(3)
        expected[k] = np.sign(vertical[k])
        built = build_skeleton(turned)
        thorax = built.skeleton.joint_index("thorax")
        np.testing.assert_allclose(built.skeleton.offsets[thorax] / built.lengths[thorax], expected, atol=1e-12)
        seen.add(tuple(expected))
    assert len(seen) == 2


def test_span_is_the_5th_and_95th_percentiles_of_the_lengths():
    markers, joints = generated_markers("helen-hayes", n_frames=21, seed=4)
    j = build_skeleton(markers).skeleton.joint_index("LTOE")
    foot = joints["LTOE"] - joints["LAJC"]
    foot /= np.linalg.norm(foot, axis=1, keepdims=True)
    steps = 0.3 * np.arange(-10, 11)
    positions = markers.positions.copy()
    positions[:, markers.index("LTOE")] += steps[:, None] * foot
    moved = build_skeleton(markers.replace(positions=positions))
    rigid = moved.lengths[j]
    np.testing.assert_allclose(moved.span[j], rigid + np.percentile(steps, [5, 95]), rtol=1e-12)
    assert moved.spread[j] == pytest.approx(np.sqrt(np.mean(steps**2)), rel=1e-9)


def test_widths_by_side_then_in_general_else_assumed_and_said_once():
    notes: list[str] = []
    assert _width({"KneeWidth": 0.5}, "KneeWidth", "L", notes) == 0.5  # any positive width
    params = {"LKneeWidth": 90.0, "RightKneeWidth": 110.0, "KneeWidth": 120.0, "AnkleWidth": 0.0}
    assert _width(params, "KneeWidth", "L", notes) == 90.0
    assert _width(params, "KneeWidth", "R", notes) == 110.0
    assert _width({"LeftKneeWidth": 95.0, "RKneeWidth": 0.0, "KneeWidth": 120.0}, "KneeWidth", "L", notes) == 95.0
    assert _width({"LKneeWidth": 95.0, "KneeWidth": 120.0}, "KneeWidth", "R", notes) == 120.0
    assert notes == []
    assert _width(params, "AnkleWidth", "L", notes) == DEFAULT_WIDTHS["AnkleWidth"] == 70.0  # 0: not a width
    assert _width({}, "AnkleWidth", "R", notes) == 70.0
    assert _width({}, "KneeWidth", "R", notes) == DEFAULT_WIDTHS["KneeWidth"] == 100.0
    assert _width({}, "ElbowWidth", "R", notes) == DEFAULT_WIDTHS["ElbowWidth"] == 70.0
    assert notes == [
        "no AnkleWidth in the file's PROCESSING parameters: 70 mm assumed",
        "no KneeWidth in the file's PROCESSING parameters: 100 mm assumed",
        "no ElbowWidth in the file's PROCESSING parameters: 70 mm assumed",
    ]


def test_unknown_methods_are_refused():
    markers, _ = generated_markers("helen-hayes", n_frames=2)
    with pytest.raises(ValueError, match=r"hip 'bell' or knee 'functional': expected one of"):
        build_skeleton(markers, hip="bell")
    with pytest.raises(ValueError, match=r"hip 'harrington' or knee 'hinge'"):
        build_skeleton(markers, knee="hinge")


def lower_body(drop=(), add=None):
    markers, _ = generated_markers("plug-in-gait-lower", n_frames=4, seed=6)
    keep = [label for label in markers.labels if label not in drop]
    markers = markers.select(keep)
    if add:
        for label, values in add.items():
            markers = markers.replace(
                labels=(*markers.labels, label), subjects=(*markers.subjects, ""),
                positions=np.concatenate([markers.positions, values[:, None]], axis=1),
            )  # fmt: skip
    return markers, match_set(markers.labels, set_by_name("plug-in-gait-lower"))


@pytest.mark.parametrize("hidden", ["LPSI", "RPSI"])
def test_a_sacral_marker_stands_in_for_a_psis_hidden_throughout(hidden):
    full, match = lower_body()
    sacrum = 0.5 * (full.positions[:, full.index("LPSI")] + full.positions[:, full.index("RPSI")])
    markers, match = lower_body(drop=(hidden,), add={"SACR": sacrum})
    centres = joint_centre_trajectories(markers, match)[0]
    expected = joint_centre_trajectories(full, match_set(full.labels, set_by_name("plug-in-gait-lower")))[0]
    for name in ("LHJC", "RHJC", "pelvis"):
        np.testing.assert_allclose(centres[name], expected[name], atol=1e-9)


@pytest.mark.parametrize("drop", [("LASI",), ("RASI",), ("LPSI",), ("RPSI",), ("LASI", "LPSI"), ("RASI", "LPSI")])
def test_a_pelvis_the_markers_cannot_place_is_refused(drop):
    """An ASIS missing throughout, or a PSIS without a sacral marker; with the sacral marker
    standing in for the PSIS, an ASIS missing still."""
    full, _ = lower_body()
    sacrum = 0.5 * (full.positions[:, full.index("LPSI")] + full.positions[:, full.index("RPSI")])
    markers, match = lower_body(drop=drop, add={"SACR": sacrum} if len(drop) == 2 else None)
    with pytest.raises(
        OperationError, match=r"^set plug-in-gait-lower: the pelvis needs both ASIS and the PSIS or a sacral"
    ):
        joint_centre_trajectories(markers, match)


@pytest.mark.parametrize("drop", ["LANK", "LKNE"])
def test_a_leg_without_its_lateral_knee_or_ankle_marker_is_refused(drop):
    markers, match = lower_body(drop=(drop,))
    with pytest.raises(OperationError, match=r"^set plug-in-gait-lower has no lateral knee and ankle markers"):
        joint_centre_trajectories(markers, match)
