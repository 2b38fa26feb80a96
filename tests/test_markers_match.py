"""The pose matcher (core/markers/match.py): the nearest reference frame of each query frame.

Few reference frames and one more than the candidates re-measured, ties resolved by time,
tiny and huge figures, query frames with one joint or none, an empty side, and the reference
poses in the skeleton's order and pelvis frame.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gmr_studio.core.markers import match as match_module
from gmr_studio.core.markers.match import best_matches

#: how many frames the matcher re-measures exactly (match.CANDIDATES): references of that many
#: frames and one more take both of its paths
CANDIDATES = 4


def matches(query, present, reference, query_times, reference_times, exclude_within=None):
    return best_matches(
        query, present, reference, query_times=query_times, reference_times=reference_times,
        exclude_within=exclude_within,
    )  # fmt: skip


def test_times_are_keywords_only(rng):
    reference = rng.normal(size=(3, 2, 3))
    with pytest.raises(TypeError):
        best_matches(reference, np.ones((3, 2), bool), reference, np.arange(3.0), np.arange(3.0))  # type: ignore[misc]


@pytest.mark.parametrize("offset", [0.01, 0.5])
@pytest.mark.parametrize("n_reference", [1, 2, 3, CANDIDATES, CANDIDATES + 1])
def test_the_nearest_frame_wins_whatever_its_place_among_few(rng, n_reference, offset):
    """With no more frames than candidates every frame is re-measured; with one more the
    partition picks the candidates: the nearest (the last frame) wins either way, near or
    as far as a tenth of the pose's size (where the tie margin is below the rounding of the
    distance: the best must count as tied with itself)."""
    reference = rng.normal(size=(n_reference, 3, 3)) * 5.0
    query = reference[-1:] + offset
    index, distance = matches(query, np.ones((1, 3), bool), reference, np.zeros(1), np.zeros(n_reference))
    assert index[0] == n_reference - 1
    assert distance[0] == pytest.approx(offset * np.sqrt(3.0), rel=1e-9)


def test_copies_of_the_pose_go_to_the_copy_nearest_in_time(rng):
    """CANDIDATES copies of one pose among farther frames: each query frame (the pose, at the
    time of one copy) gets that copy, whichever order the frames are in."""
    far = rng.normal(size=(6, 3, 3)) + 10.0
    pose = rng.normal(size=(3, 3))
    reference = np.concatenate([far[:3], np.repeat(pose[None], CANDIDATES, axis=0), far[3:]])
    times = np.arange(len(reference)) * 1.0
    copies = np.arange(3, 3 + CANDIDATES)
    query = np.repeat(pose[None], CANDIDATES, axis=0)
    index, distance = matches(query, np.ones((CANDIDATES, 3), bool), reference, times[copies] + 0.1, times)
    np.testing.assert_array_equal(index, copies)
    np.testing.assert_array_equal(distance, 0.0)


def test_scaled_copies_of_the_query_the_nearest_is_the_query_itself():
    """Frames that are the query scaled by 1.3 .. 1.8 and the query itself last: the expanded
    form |q|^2 + |r|^2 - 2 q.r must rank the query itself first (a wrong weight on q.r favours
    the larger copies and leaves it out of the candidates)."""
    query = np.array([[[1.0, 0.5, -0.2], [0.3, -1.0, 0.4]]])
    scales = np.array([1.3, 1.4, 1.5, 1.6, 1.7, 1.8, 1.0])
    reference = scales[:, None, None] * query
    index, distance = matches(query, np.ones((1, 2), bool), reference, np.zeros(1), np.arange(7.0))
    assert index[0] == 6 and distance[0] == 0.0


@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e6])
def test_a_strictly_nearer_frame_beats_one_nearer_in_time_at_any_scale(rng, scale):
    """Ties are relative to the pose's size: the choice is the same in any unit. Frame 0 is
    nearer by a relative 1e-10 of the pose's size, frame 1 nearer in time."""
    query = rng.normal(size=(1, 4, 3))
    step = np.zeros((4, 3))
    step[0, 0] = 1e-5
    reference = np.stack([query[0] + step, query[0] + 2 * step, query[0] + 1.0])
    index, distance = matches(
        query * scale, np.ones((1, 4), bool), reference * scale, np.zeros(1), np.array([5.0, 0.0, 0.0])
    )
    assert index[0] == 0
    assert distance[0] == pytest.approx(scale * 1e-5 / 2, rel=1e-6)


def test_query_frames_with_one_joint_or_none(rng):
    """One measured joint: matched on it, its distance that joint's. None: no match (-1,
    NaN), without a division warning."""
    reference = rng.normal(size=(6, 3, 3))
    query = reference[[4, 2]] + 0.0
    query[0, 1] += 0.3  # a joint not measured moves freely
    query[0, 0] += np.array([0.0, 0.0, 0.02])
    present = np.array([[True, False, False], [False, False, False]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        index, distance = matches(query, present, reference, np.zeros(2), np.zeros(6))
    assert index[0] == 4 and distance[0] == pytest.approx(0.02, rel=1e-9)
    assert index[1] == -1 and np.isnan(distance[1])


def test_one_query_frame_one_reference_frame_and_empty_sides(rng):
    reference = rng.normal(size=(1, 2, 3))
    index, distance = matches(reference + 0.1, np.ones((1, 2), bool), reference, np.zeros(1), np.zeros(1))
    assert index.tolist() == [0] and distance[0] == pytest.approx(0.1 * np.sqrt(3.0))
    index, distance = matches(
        rng.normal(size=(3, 2, 3)), np.ones((3, 2), bool), reference[:0], np.zeros(3), np.zeros(0)
    )
    assert index.tolist() == [-1, -1, -1] and np.isnan(distance).all()
    index, distance = matches(reference[:0], np.ones((0, 2), bool), reference, np.zeros(0), np.zeros(1))
    assert index.shape == (0,) and distance.shape == (0,)


def test_more_reference_frames_than_a_chunk_holds_one_query_frame_at_a_time(rng, monkeypatch):
    monkeypatch.setattr(match_module, "CHUNK_ELEMENTS", 7)
    reference = rng.normal(size=(12, 3, 3))
    order = np.array([5, 0, 11, 7])
    index, distance = matches(reference[order], np.ones((4, 3), bool), reference, np.zeros(4), np.zeros(12))
    np.testing.assert_array_equal(index, order)
    np.testing.assert_array_equal(distance, 0.0)


# ------------------------------------------------------------------ reference_poses
def test_reference_poses_in_the_skeletons_order_and_pelvis_frame(rng):
    """A reference with the skeleton's joints in another order: local rotations and positions
    come back in skeleton order; features are the joints in the pelvis frame from the root;
    the correction takes the pelvis frame to the root's world rotation; times from frame 0."""
    from gmr_studio.core.kinematics.fk import joint_world_transform, world_positions
    from gmr_studio.core.markers.match import reference_poses
    from gmr_studio.core.markers.pelvis import pelvis_rotations
    from tests.conftest import random_motion

    skeleton = random_motion(rng, [-1, 0, 0, 0, 3], n_frames=1)
    shuffled = [3, 0, 4, 1, 2]  # reference joint k is skeleton joint shuffled[k]
    names = [skeleton.names[j] for j in shuffled]
    parents = [-1 if skeleton.parents[j] < 0 else shuffled.index(int(skeleton.parents[j])) for j in shuffled]
    reference = random_motion(rng, parents, n_frames=5).replace(names=names, frame_time=0.25)
    triple = [0, 1, 2]
    local, features, correction, times = reference_poses(reference, skeleton, triple, None, "note")
    order = [names.index(n) for n in skeleton.names]
    np.testing.assert_array_equal(local, reference.rotations[:, order])
    positions = world_positions(reference)[:, order]
    rotations = pelvis_rotations(positions[:, triple])[0]
    expected = np.einsum("fba,fjb->fja", rotations, positions - positions[:, :1])
    np.testing.assert_allclose(features, expected, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(features[:, 0], axis=-1), 0.0, atol=1e-12)
    root_world = joint_world_transform(reference, order[0])[0]
    np.testing.assert_allclose(rotations @ correction, root_world, atol=1e-12)
    np.testing.assert_allclose(times, [0.0, 0.25, 0.5, 0.75, 1.0])
    assert reference_poses(None, skeleton, triple, None, "note") is None


def test_reference_poses_refusals(rng):
    from gmr_studio.core.errors import OperationError
    from gmr_studio.core.markers.match import reference_poses
    from tests.conftest import random_motion

    skeleton = random_motion(rng, [-1, 0, 0, 0, 0, 0, 0, 0, 0], n_frames=1)  # j0 .. j8
    seven = random_motion(rng, [-1, 0], n_frames=2)  # j0, j1: seven missing, six listed
    with pytest.raises(OperationError, match=r"^the reference motion is not of the skeleton: it lacks the joints "
                       r"j2, j3, j4, j5, j6, j7 \.\.\.$"):  # fmt: skip
        reference_poses(seven, skeleton, [0, 1, 2], None, "note")
    six = random_motion(rng, [-1, 0, 0], n_frames=2).replace(names=("j0", "j1", "j2"))
    with pytest.raises(OperationError, match=r"it lacks the joints j3, j4, j5, j6, j7, j8$"):  # six: all listed
        reference_poses(six, skeleton, [0, 1, 2], None, "note")
    empty = skeleton.frame_slice(slice(0, 0))
    with pytest.raises(OperationError, match=r"^the reference motion has no frames$"):
        reference_poses(empty, skeleton, [0, 1, 2], None, "note")
    assert reference_poses(skeleton, skeleton, [0, 1, 2], None, "note")[3].tolist() == [0.0]  # one frame will do
    flat = skeleton.replace(  # every joint at the root
        offsets=np.zeros_like(skeleton.offsets), translations=np.zeros_like(skeleton.translations)
    )
    with pytest.raises(OperationError, match=r"^the reference motion's own pelvis is degenerate: "):
        reference_poses(flat, flat, [0, 1, 2], None, "note")
