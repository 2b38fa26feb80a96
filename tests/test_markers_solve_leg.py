"""The solver (core/markers/solve.py) on a small leg where every figure is known.

A small hand-built skeleton (a pelvis triple, a leg with a zero-length dummy bone) moved by
known rotations: its joints are the markers (the exact case), so every figure is known.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import MarkerSet, markers_to_motion
from gmr_studio.core.markers.markermap import MarkerMap, VirtualMarker
from gmr_studio.core.markers.report import conversion_table
from gmr_studio.core.markers.solve import FROM_REFERENCE, HELD, MEASURED, SOURCE_NAMES, TWIST_MARKER, solve_positions
from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.euler import matrix_from_euler, rotation_angle

PELVIS = ("pelvis", "lhip", "back")


def leg(n_frames: int = 6, straight_foot: bool = False, scale: float = 1.0) -> Motion:
    """pelvis (0) -> lhip (1) -> knee (3) -> dummy (4, zero offset) -> foot (5); back (2).
    ``straight_foot``: the foot unrotated, its offset along the knee's (a twist of the knee
    about its bone moves no joint); ``scale`` multiplies every length."""
    offsets = scale * np.array(
        [[0.0, 90.0, 0.0], [10.0, -5.0, 0.0], [0.0, 20.0, -3.0], [0.0, -40.0, 2.0], [0.0, 0.0, 0.0], [0.0, -38.0, 4.0]]
    )
    rng = np.random.default_rng(7)
    rotations = matrix_from_euler(rng.uniform(-1.0, 1.0, (n_frames, 6, 3)), "ZYX")
    rotations[:, 4] = np.eye(3)  # the dummy: no bone direction, no rotation to find
    if straight_foot:
        offsets[5] = 0.95 * offsets[3]
        rotations[:, 5] = np.eye(3)
    return Motion(
        names=["pelvis", "lhip", "back", "knee", "dummy", "foot"],
        parents=np.array([-1, 0, 0, 1, 3, 4]),
        offsets=offsets,
        rotation_orders=["ZYX", "XYZ", "ZXY", "YZX", "ZYX", "XZY"],
        has_translation=np.array([True, False, False, False, False, False]),
        rotations=rotations,
        translations=build_translations(n_frames, offsets, {0: rng.normal(size=(n_frames, 3)) * 5 * scale}),
        frame_time=1 / 30,
    )


def test_the_options_are_keywords_only_and_the_positions_may_be_named():
    truth = leg()
    positions = world_positions(truth)
    named = solve_positions(measured=positions, skeleton=truth, pelvis=PELVIS)
    np.testing.assert_allclose(world_positions(named.motion), positions, atol=1e-9)
    with pytest.raises(TypeError):
        solve_positions(positions, truth, PELVIS, truth)  # the reference only by its name
    markers = MarkerSet(labels=truth.names, positions=positions, rate=30.0, units="mm")
    by_name = markers_to_motion(markers=markers, skeleton=truth, marker_map=bones_map({}))
    np.testing.assert_allclose(world_positions(by_name.motion), positions, atol=1e-9)
    with pytest.raises(TypeError):
        markers_to_motion(markers, truth, bones_map({}), truth)


def test_a_zero_length_bone_is_solved_without_a_warning():
    truth = leg()
    positions = world_positions(truth)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for reference in (None, truth):
            result = solve_positions(positions, truth, PELVIS, reference=reference)
            np.testing.assert_allclose(world_positions(result.motion), positions, atol=1e-9)


def test_matches_are_minus_one_without_reference_and_on_frames_without_pelvis():
    truth = leg()
    positions = world_positions(truth)
    free = solve_positions(positions, truth, PELVIS)
    np.testing.assert_array_equal(free.matches, np.full(6, -1))
    assert np.isnan(free.match_distances).all()
    positions[2, 0] = np.nan  # frame 2 has no pelvis root: a copy of frame 1
    matched = solve_positions(positions, truth, PELVIS, reference=truth)
    np.testing.assert_array_equal(matched.matches, [0, 1, -1, 3, 4, 5])
    assert np.isnan(matched.match_distances[2]) and (matched.match_distances[[0, 1, 3, 4, 5]] <= 1e-9).all()


def test_position_errors_are_per_frame_and_joint():
    truth = leg()
    positions = world_positions(truth)
    result = solve_positions(positions, truth, PELVIS, reference=truth, root_at="pelvis")
    moved = result.measured.copy()
    moved[3, 5] += [0.0, 3.0, 4.0]  # the foot's marker 5 units away in frame 3
    errors = type(result)(**{**result.__dict__, "measured": moved}).position_errors()
    assert errors.shape == (6, 6)
    expected = np.zeros((6, 6))
    expected[3, 5] = 5.0
    np.testing.assert_allclose(errors, expected, atol=1e-9)


def test_a_zero_length_bone_is_never_measured_even_when_its_marker_strays():
    truth = leg()
    positions = world_positions(truth)
    positions[:, 4] += [0.0, -6.0, 1.0]  # the dummy's marker off its parent: no direction to trust
    matched = solve_positions(positions, truth, PELVIS, reference=truth)
    assert (matched.sources[:, 4] == FROM_REFERENCE).all()
    names = [SOURCE_NAMES[code] for code in matched.sources[0]]
    assert names == ["root", "measured", "measured", "measured", "from reference", "measured"]
    np.testing.assert_allclose(matched.motion.rotations[:, 4], truth.rotations[:, 4], atol=1e-9)
    free = solve_positions(positions, truth, PELVIS)
    assert (free.sources[:, 4] == HELD).all()
    np.testing.assert_array_equal(free.motion.rotations[:, 4], np.broadcast_to(np.eye(3), (6, 3, 3)))


def test_only_the_unmatched_frames_are_named():
    truth = leg()
    positions = world_positions(truth)[[0, 3]]
    # frame 0 (at 10 s) matches reference frame 0; frame 1 (at 0 s) finds every reference frame too close
    result = solve_positions(
        positions, truth, PELVIS, reference=truth, query_times=np.array([10.0, 0.0]), exclude_within=0.5
    )
    np.testing.assert_array_equal(result.matches, [0, -1])
    assert "no reference frame could be matched in frames 1" in result.reasons


def bones_map(bone_starts: dict[str, str]) -> MarkerMap:
    """One virtual marker per joint (and a toe the skeleton lacks), each at its own marker."""
    names = [*leg().names, "toe"]
    return MarkerMap(
        name="leg",
        virtual=tuple(VirtualMarker(n, "marker", (n,)) for n in names),
        pelvis=PELVIS,
        bone_starts=bone_starts,
    )


def test_the_maps_bones_aim_the_joints_they_name_and_a_bone_of_no_joint_is_ignored():
    truth = leg()
    positions = world_positions(truth)
    positions[:, 4] += [0.0, -6.0, 1.0]  # the dummy's marker strays: only the knee starts the foot's bone
    toe = positions[:, 5:6] + [0.0, -2.0, 9.0]
    markers = MarkerSet(
        labels=[*truth.names, "toe"], positions=np.concatenate([positions, toe], axis=1), rate=30.0, units="mm"
    )
    foot = {}
    for starts in ({}, {"foot": "knee", "toe": "foot"}):
        result = markers_to_motion(markers, truth, bones_map(starts), reference=truth, root_at="pelvis")
        foot[len(starts)] = rotation_angle(np.swapaxes(result.motion.rotations[:, 5], -1, -2) @ truth.rotations[:, 5])
    assert foot[2].max() <= 1e-9  # aimed from the knee: the true direction
    assert foot[0].min() > 0.05  # aimed from the stray dummy marker: radians off


def test_the_marker_frames_times_start_at_zero_or_at_the_slices_start():
    truth = leg()
    markers = MarkerSet(labels=truth.names, positions=world_positions(truth), rate=30.0, units="mm")
    # the reference is the same trial: half a frame's exclusion leaves out exactly the frame itself
    for frames, first in ((None, 0), (slice(2, 6), 2)):
        result = markers_to_motion(
            markers, truth, bones_map({}), reference=truth, exclude_within=0.5 / 30, frames=frames, root_at="pelvis"
        )
        itself = first + np.arange(len(result.matches))
        assert (result.matches >= 0).all() and (result.matches != itself).all()
        assert (result.match_distances > 1.0).all()


def about(axis: np.ndarray, angle: float) -> np.ndarray:
    """(3, 3) the rotation by ``angle`` about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k


def test_a_twist_marker_decides_the_twist_whatever_the_reference():
    truth = leg(straight_foot=True)
    positions = world_positions(truth)
    knee_world = truth.rotations[:, 0] @ truth.rotations[:, 1] @ truth.rotations[:, 3]
    twist_markers = np.full_like(positions, np.nan)
    twist_markers[:, 3] = positions[:, 1] + np.einsum("fab,b->fa", knee_world, [5.0, 0.0, 0.0])
    axis = truth.offsets[3] / np.linalg.norm(truth.offsets[3])
    twisted = truth.rotations.copy()
    twisted[:, 3] = twisted[:, 3] @ about(axis, 0.7)
    other = truth.replace(rotations=twisted)
    np.testing.assert_allclose(world_positions(other), positions, atol=1e-9)  # the same joints: the same matches
    knee = []
    for reference in (truth, other):
        result = solve_positions(positions, truth, PELVIS, reference=reference, twist_markers=twist_markers)
        assert (result.sources[:, 3] == TWIST_MARKER).all()
        knee.append(result.motion.rotations[:, 3])
    np.testing.assert_allclose(knee[0], knee[1], atol=1e-12)
    # measured from the marker's mean direction: the truth but for one twist, the same in every frame
    offset = np.swapaxes(knee[0], -1, -2) @ truth.rotations[:, 3]
    np.testing.assert_allclose(offset, np.broadcast_to(offset[0], offset.shape), atol=1e-9)


def test_a_post_rotation_skeleton_and_reference_are_taken_in_their_gmr_form():
    post = leg().replace(convention="post")
    truth = pre_from_post(post)
    np.testing.assert_allclose(world_positions(post), world_positions(truth), atol=1e-9)
    markers = MarkerSet(labels=truth.names, positions=world_positions(truth), rate=30.0, units="mm")
    results = [markers_to_motion(markers, truth, bones_map({}), reference=r) for r in (truth, post)]
    np.testing.assert_array_equal(results[1].matches, np.arange(6))
    np.testing.assert_allclose(results[1].motion.rotations, results[0].motion.rotations, atol=1e-9)
    np.testing.assert_allclose(results[1].motion.rotations, truth.rotations, atol=1e-9)
    on_post = markers_to_motion(markers, post, bones_map({}), reference=post)  # the skeleton converted too
    np.testing.assert_allclose(on_post.motion.rotations, truth.rotations, atol=1e-9)


def test_a_frame_without_pelvis_copies_the_frame_before_it_even_the_first():
    truth = leg()
    positions = world_positions(truth)
    positions[1, 0] = np.nan  # after frame 0: its copy, not frame 2's
    result = solve_positions(positions, truth, PELVIS, reference=truth)
    np.testing.assert_array_equal(result.frame_valid, [True, False, True, True, True, True])
    np.testing.assert_array_equal(result.motion.rotations[1], result.motion.rotations[0])
    np.testing.assert_array_equal(result.motion.translations[1], result.motion.translations[0])


def test_gaps_stay_gaps_by_default_and_the_note_names_the_source():
    truth = leg()
    positions = world_positions(truth)
    positions[2, 3] = np.nan  # a one-frame gap in the knee
    markers = MarkerSet(labels=truth.names, positions=positions, rate=30.0, units="mm")
    kept = markers_to_motion(markers, truth, bones_map({}), reference=truth)
    assert np.isnan(kept.measured[2, 3]).all() and kept.sources[2, 3] == FROM_REFERENCE
    assert kept.motion.comments[0] == "from markers (memory) with map leg"
    filled = markers_to_motion(markers.replace(source="walk.trc"), truth, bones_map({}), reference=truth, fill_gaps=1)
    assert np.isfinite(filled.measured[2, 3]).all() and filled.sources[2, 3] == MEASURED
    assert filled.motion.comments[0] == "from markers walk.trc with map leg"


def test_no_pelvis_or_two_pelvis_markers_are_refused_with_the_reason():
    truth = leg()
    for pelvis in (None, PELVIS[:2]):
        with pytest.raises(OperationError, match="names no pelvis markers"):
            solve_positions(world_positions(truth), truth, pelvis)
    with pytest.raises(OperationError, match="pelvis root 'lhip' is not a root"):  # a child of joint 0
        solve_positions(world_positions(truth), truth, ("lhip", "pelvis", "back"))


@pytest.mark.parametrize("scale", [1.0, 1e-3])
def test_a_marker_on_its_parent_gives_no_direction_one_just_off_it_does(scale):
    # the bone is measured when the marker is more than 1e-12 of the bone's length from its start
    truth = leg(scale=scale)
    length = np.linalg.norm(truth.offsets[3])
    positions = world_positions(truth)
    unit = np.array([0.6, 0.0, 0.8])
    for distance, source in ((0.0, FROM_REFERENCE), (0.25e-12 * length, FROM_REFERENCE), (5e-12 * length, MEASURED)):
        moved = positions.copy()
        moved[2, 3] = moved[2, 1] + distance * unit
        result = solve_positions(moved, truth, PELVIS, reference=truth)
        assert result.sources[2, 3] == source, distance


def test_the_motion_keeps_the_orders_the_first_frames_root_and_the_frames_times():
    truth = leg()
    result = solve_positions(world_positions(truth), truth, PELVIS, reference=truth, exclude_within=0.5 / 30)
    assert result.motion.rotation_orders == truth.rotation_orders
    np.testing.assert_array_equal(result.motion.offsets[0], result.motion.translations[0, 0])
    np.testing.assert_array_equal(result.motion.offsets[1:], truth.offsets[1:])
    # the frames at i / 30 s: half a frame's exclusion leaves out each frame itself
    assert (result.matches >= 0).all() and (result.matches != np.arange(6)).all()


def test_the_result_is_compared_by_identity_and_its_codes_feed_the_conversion_table():
    truth = leg()
    result = solve_positions(world_positions(truth), truth, PELVIS, reference=truth)
    copy = dataclasses.replace(result)
    assert result == result and result != copy and len({result, copy}) == 2  # hashable: arrays inside
    rows = conversion_table(result, None)  # counts the codes with np.bincount: 0 measured ... 4 twist marker
    assert [row["source"] for row in rows] == ["root", "measured", "measured", "measured", "from reference", "measured"]
    assert [row["measured"] for row in rows] == [1.0, 1.0, 1.0, 1.0, 0.0, 1.0]


def test_a_gap_after_the_first_frame_holds_the_first_frames_rotation():
    truth = leg()
    positions = world_positions(truth)
    positions[1:3, 3] = np.nan
    result = solve_positions(positions, truth, PELVIS)
    assert (result.sources[1:3, 3] == HELD).all()
    np.testing.assert_array_equal(result.motion.rotations[1:3, 3], result.motion.rotations[[0, 0], 3])
    positions[0, 3] = np.nan  # now frames 0-2: they take the first measured frame's, frame 3's
    start = solve_positions(positions, truth, PELVIS)
    np.testing.assert_array_equal(start.motion.rotations[:3, 3], start.motion.rotations[[3, 3, 3], 3])


def test_a_child_of_the_first_joint_becomes_a_root_and_the_pelvis_origin_is_its_root():
    truth = leg()
    positions = world_positions(truth)
    result = solve_positions(positions, truth, PELVIS, reference=truth, roots=("lhip",))
    assert result.motion.parents[1] == -1 and result.motion.soft_parents[1] == 0
    np.testing.assert_allclose(world_positions(result.motion), positions, atol=1e-9)
    np.testing.assert_array_equal(result.pelvis.origins, positions[:, 0])


@pytest.mark.parametrize(
    "bone, cases",
    [
        (1.0, ((1e-12, HELD), (2e-12, MEASURED))),  # exactly 1e-12 of the bone: the threshold is strict
    ],
)
def test_a_bone_exactly_at_the_threshold_is_not_measured(bone, cases):
    # a second tree (a prop, unrotated without a reference) whose tip is a hair from it
    base = leg(n_frames=2)
    offsets = np.vstack([base.offsets, [[50.0, 0.0, 0.0], [bone, 0.0, 0.0]]])
    skeleton = Motion(
        names=[*base.names, "prop", "tip"],
        parents=np.array([*base.parents, -1, 6]),
        offsets=offsets,
        rotation_orders=[*base.rotation_orders, "ZYX", "ZYX"],
        has_translation=np.array([True, False, False, False, False, False, True, False]),
        rotations=np.broadcast_to(np.eye(3), (2, 8, 3, 3)).copy(),
        translations=build_translations(2, offsets, {}),
        frame_time=1 / 30,
    )
    for distance, source in cases:
        measured = np.concatenate([world_positions(base), np.zeros((2, 2, 3))], axis=1)
        measured[:, 7, 0] = distance
        result = solve_positions(measured, skeleton, PELVIS)
        assert (result.sources[:, 7] == source).all(), distance
