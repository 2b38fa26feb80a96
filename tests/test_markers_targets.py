"""What the refinement fits (core/markers/targets.py): a map refused when the file lacks most
of its markers, targets moved past a bone the skeleton lacks, each joint's weight from its
virtual marker's calibration. Synthetic markers, maps and skeletons only."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.markermap import MarkerMap, VirtualMarker, joints_map
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.targets import below_missing_bones, check_map_fits, inverse_variance, transported
from tests.conftest import random_motion
from tests.test_markers_build import generated_markers


def markers_labelled(labels, n_frames=2) -> MarkerSet:
    positions = np.arange(n_frames * len(labels) * 3, dtype=float).reshape(n_frames, len(labels), 3)
    return MarkerSet(labels=labels, positions=positions, rate=100.0, units="mm")


def map_reading(labels, name="lab") -> MarkerMap:
    """A map with one virtual marker per label (and one built on the first, which reads no
    label of its own)."""
    virtual = [VirtualMarker(f"v{k}", "marker", (label,)) for k, label in enumerate(labels)]
    virtual.append(VirtualMarker("later", "mean", ("@v0", labels[0])))
    return MarkerMap(name=name, virtual=tuple(virtual))


# ------------------------------------------------------------------ check_map_fits
def test_a_map_whose_markers_are_half_present_or_more_fits():
    labels = ["A", "B", "C", "D"]
    check_map_fits(markers_labelled(labels), map_reading(labels))
    check_map_fits(markers_labelled(["A", "B", "X"]), map_reading(labels))  # two of four absent: half
    check_map_fits(markers_labelled(["A", "B", "X"]), map_reading(["A", "B", "C"]))  # one of three


def test_a_map_missing_most_of_its_markers_is_refused_naming_them_in_order():
    with pytest.raises(OperationError) as error:
        check_map_fits(markers_labelled(["A", "X", "Y"]), map_reading(["D", "A", "C", "B"]))
    message = str(error.value)
    assert message.startswith("this file's markers are of no known set, not map lab (missing: D, C, B)")
    assert "gmr markers builds" not in message  # no set to build a skeleton from
    with pytest.raises(OperationError, match=r"not map lab \(missing: B, C\)$"):
        check_map_fits(markers_labelled(["A", "X"]), map_reading(["A", "B", "C"]))  # two of three absent


def test_a_map_on_the_markers_of_a_known_set_names_the_set_and_the_builder():
    markers, _ = generated_markers("helen-hayes", n_frames=2)
    cmu_like = map_reading(["LFWT", "RFWT", "LBWT", "RBWT"], name="cmu")
    with pytest.raises(OperationError) as error:
        check_map_fits(markers, cmu_like)
    assert str(error.value) == (
        "this file's markers are set helen-hayes, not map cmu (missing: LFWT, RFWT, LBWT, RBWT)"
        "; without --skeleton and --map, gmr markers builds a skeleton from them"
    )


def test_the_joints_map_and_a_map_reading_no_label_always_fit():
    check_map_fits(markers_labelled(["X"]), joints_map(["root", "hip", "knee"]))
    check_map_fits(markers_labelled(["X"]), MarkerMap(name="empty", virtual=()))


# ------------------------------------------------------------------ transported
#: j0 root; j1 a bone the skeleton has but no marker measures (CMU BVH's missing thorax: its
#: joint is never measured); j2 starts, by the map, at a virtual marker; j3 below j2; j4 and j5
#: a measured branch, j5's start given too
PARENTS = [-1, 0, 1, 2, 0, 4]


def measured_and_starts(motion, rng):
    n_frames = motion.n_frames
    measured = rng.normal(size=(n_frames, 6, 3))
    measured[:, 1] = np.nan
    starts = np.full_like(measured, np.nan)
    starts[:, 2] = rng.normal(size=(n_frames, 3))
    starts[:, 5] = rng.normal(size=(n_frames, 3))
    return measured, starts


def test_joints_past_an_unmeasured_bone_move_by_its_start_and_the_rest_stay(rng):
    motion = random_motion(rng, PARENTS, n_frames=4)
    measured, starts = measured_and_starts(motion, rng)
    starts[2, 2] = np.nan  # a frame where the start is not seen: no move there
    seed = world_positions(motion)
    targets = transported(motion, measured, starts, motion)
    shift = seed[:, 1] - starts[:, 2]
    shift[2] = 0.0
    np.testing.assert_array_equal(targets[:, 2], measured[:, 2] + shift)
    np.testing.assert_array_equal(targets[:, 3], measured[:, 3] + shift)  # carried below
    np.testing.assert_array_equal(targets[:, [0, 4, 5]], measured[:, [0, 4, 5]])  # parents measured
    assert np.isnan(targets[:, 1]).all()


def test_a_start_seen_in_no_frame_or_a_parent_measured_once_moves_nothing(rng):
    motion = random_motion(rng, PARENTS, n_frames=3)
    measured, starts = measured_and_starts(motion, rng)
    no_start = starts.copy()
    no_start[:, 2] = np.nan
    assert transported(motion, measured, no_start, motion) is None
    partial = starts.copy()
    partial[:, 2, 0] = np.nan  # a coordinate missing in every frame: no start seen whole
    assert transported(motion, measured, partial, motion) is None
    once = measured.copy()
    once[1, 1] = 0.5  # the parent measured in one frame: the skeleton reaches it
    assert transported(motion, once, starts, motion) is None


def test_a_second_unmeasured_bone_below_the_first_replaces_the_shift(rng):
    """j2 unmeasured too, j3 starting at its own marker: j3's shift is its own start's gap,
    not j2's carried down."""
    motion = random_motion(rng, PARENTS, n_frames=3)
    measured, starts = measured_and_starts(motion, rng)
    measured[:, 2] = np.nan
    starts[:, 3] = rng.normal(size=(3, 3))
    seed = world_positions(motion)
    targets = transported(motion, measured, starts, motion)
    np.testing.assert_array_equal(targets[:, 3], measured[:, 3] + (seed[:, 2] - starts[:, 3]))


def test_the_skeletons_tree_is_walked_parents_first(rng):
    """Joints listed children first: the order of the tree, not of the list, carries a shift."""
    parents = [-1, 2, 3, 0]  # 0 -> 3 -> 2 -> 1: 3 unmeasured, 2 starts at a marker, 1 below it
    motion = random_motion(rng, parents, n_frames=3)
    measured = rng.normal(size=(3, 4, 3))
    measured[:, 3] = np.nan
    starts = np.full_like(measured, np.nan)
    starts[:, 2] = rng.normal(size=(3, 3))
    seed = world_positions(motion)
    targets = transported(motion, measured, starts, motion)
    shift = seed[:, 3] - starts[:, 2]
    np.testing.assert_array_equal(targets[:, 1], measured[:, 1] + shift)
    np.testing.assert_array_equal(targets[:, 2], measured[:, 2] + shift)


def test_an_unmeasured_root_moves_its_children_and_a_root_has_no_bone_to_move(rng):
    """The root never measured, its child j4 starting at a marker: j4 and j5 move by the
    root's seed position minus that start. A start given for the root itself (a root has no
    bone) moves nothing, even with the last joint unmeasured."""
    motion = random_motion(rng, PARENTS, n_frames=3)
    measured, starts = measured_and_starts(motion, rng)
    measured[:, 1] = rng.normal(size=(3, 3))
    measured[:, 0] = np.nan
    starts[:, 2] = np.nan
    starts[:, 5] = np.nan
    starts[:, 4] = rng.normal(size=(3, 3))
    seed = world_positions(motion)
    targets = transported(motion, measured, starts, motion)
    shift = seed[:, 0] - starts[:, 4]
    np.testing.assert_array_equal(targets[:, 4], measured[:, 4] + shift)
    np.testing.assert_array_equal(targets[:, 5], measured[:, 5] + shift)
    np.testing.assert_array_equal(targets[:, 1:4], measured[:, 1:4])
    root_start = np.full_like(measured, np.nan)
    root_start[:, 0] = rng.normal(size=(3, 3))
    last_unmeasured = measured.copy()
    last_unmeasured[:, 0] = rng.normal(size=(3, 3))
    last_unmeasured[:, 5] = np.nan
    assert transported(motion, last_unmeasured, root_start, motion) is None


# ------------------------------------------------------------------ inverse_variance
def test_weights_are_inverse_variances_scaled_to_mean_one():
    marker_map = MarkerMap(
        name="calibrated",
        virtual=(
            VirtualMarker("a", "cluster", ("A", "B", "C"), rms=1.0),
            VirtualMarker("b", "cluster", ("A", "B", "D"), rms=2.0),
            VirtualMarker("c", "mean", ("A", "B")),  # no rms: weight 1
            VirtualMarker("d", "cluster", ("B", "C", "D"), rms=0.0),  # no spread measured: weight 1
            VirtualMarker("f", "cluster", ("A", "C", "D"), rms=0.5),  # not a joint of the skeleton
        ),
    )
    weights = inverse_variance(marker_map, ["a", "b", "c", "d", "e"])
    np.testing.assert_allclose(weights, [1.6, 0.4, 1.0, 1.0, 1.0], rtol=1e-15)
    assert inverse_variance(marker_map.replace(virtual=marker_map.virtual[2:4]), ["c", "d"]) is None


# ------------------------------------------------------------------ below_missing_bones
#: 0 root; 1 at the root (a bone of length 0); 2 on 1; 3 on 2; 4 on 3; 5 on the root
BELOW_PARENTS = [-1, 0, 1, 2, 3, 0]


def below_case(rng):
    motion = random_motion(rng, BELOW_PARENTS, n_frames=3)
    offsets = np.array(motion.offsets)
    offsets[1] = 0.0
    skeleton = motion.replace(offsets=offsets)
    measured = rng.normal(size=(3, 6, 3))
    starts = np.full_like(measured, np.nan)
    return skeleton, measured, starts


def test_a_bone_starting_at_its_parent_or_an_ancestor_at_the_same_place_is_the_skeletons(rng):
    skeleton, measured, starts = below_case(rng)
    assert not below_missing_bones(measured, starts, skeleton).any()  # no start given: all own
    starts[:, 2] = measured[:, 0]  # 2's parent 1 sits on the root: the root's place is 1's
    starts[:, 3] = measured[:, 2]
    starts[:, 5] = measured[:, 0]
    starts[:, 0] = rng.normal(size=(3, 3))  # a root has no bone
    assert not below_missing_bones(measured, starts, skeleton).any()
    gappy = measured.copy()
    gappy[1, 2] = np.nan
    starts[:, 3] = gappy[:, 2]  # NaN where the parent is missing too: the same place
    assert not below_missing_bones(gappy, starts, skeleton).any()


def test_a_bone_starting_elsewhere_is_missing_and_everything_below_it_is_below(rng):
    skeleton, measured, starts = below_case(rng)
    starts[:, 3] = rng.normal(size=(3, 3))  # a virtual marker the skeleton has no joint for
    assert below_missing_bones(measured, starts, skeleton).tolist() == [False, False, False, True, True, False]
    starts[:, 3] = measured[:, 1]  # the grandparent, but 2 is no bone of length 0
    assert below_missing_bones(measured, starts, skeleton).tolist() == [False, False, False, True, True, False]
    starts[:, 3] = np.nan
    starts[:, 2] = measured[:, 1] + 1.0
    assert below_missing_bones(measured, starts, skeleton).tolist() == [False, False, True, True, True, False]
    starts[:, 2] = np.nan
    starts[0, 5] = measured[0, 0]  # seen in one frame only, and there the root's: still not the root's track
    assert below_missing_bones(measured, starts, skeleton).tolist() == [False, False, False, False, False, True]


def test_zero_length_bones_are_climbed_to_the_root_and_no_further(rng):
    skeleton, measured, starts = below_case(rng)
    offsets = np.array(skeleton.offsets)
    offsets[[0, 2]] = 0.0  # the root, 1 and 2 all at one place
    flat = skeleton.replace(offsets=offsets)
    starts[:, 3] = measured[:, 0]  # 3 starts at the root, through 2 and 1
    assert not below_missing_bones(measured, starts, flat).any()
    starts[:, 3] = np.nan
    starts[:, 5] = measured[:, 5]  # the root's own place is no other joint's (not the last joint's)
    assert below_missing_bones(measured, starts, flat).tolist() == [False, False, False, False, False, True]
    starts[:, 5] = np.nan
    starts[:, 3] = measured[:, 5]  # climbing from 2 stops at the root: the last joint is no place of 2's
    assert below_missing_bones(measured, starts, flat).tolist() == [False, False, False, True, True, False]


def test_the_climb_stops_at_a_bone_of_some_length(rng):
    skeleton, measured, starts = below_case(rng)
    offsets = np.array(skeleton.offsets)
    offsets[3] = 0.0  # 3 sits on 2, which has a length; 1 sits on the root
    chain = skeleton.replace(offsets=offsets)
    starts[:, 4] = measured[:, 2]  # 4's parent 3 is at 2: its own start
    assert not below_missing_bones(measured, starts, chain).any()
    starts[:, 4] = measured[:, 1]  # beyond 2's bone: not 4's place
    assert below_missing_bones(measured, starts, chain).tolist() == [False, False, False, False, True, False]
