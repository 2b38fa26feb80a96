"""core.rigs: the convention rigs, and Motion.size measuring the actor on every one of them
(a Root pinned at the origin left out), invariant under the operations."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.rigs import RIGS, make_rig, walk
from gmr_studio.core.space.up_axis import detect_up_axis

SMALL_RIGS = [name for name in RIGS if name != "long_take"]


@pytest.fixture(scope="module")
def rigs() -> dict:
    return {name: make_rig(name) for name in SMALL_RIGS}


def _figure_height(motion, up: int = 1) -> float:
    """Largest extent along the up axis over all frames, joints other than anchors, computed
    without Motion.size."""
    points = world_positions(motion)[:, ~motion.anchors]
    return float((points[..., up].max(axis=1) - points[..., up].min(axis=1)).max())


def test_every_rig_is_a_valid_motion_of_the_promised_shape(rigs):
    for motion in rigs.values():
        motion.check_invariants()
    assert rigs["fingers_and_face"].n_joints == 250
    assert rigs["one_joint"].n_joints == 1
    assert rigs["t_pose"].n_frames == 1
    assert rigs["six_channels"].has_translation.all()
    origin = rigs["origin_root"]
    path = world_positions(origin)
    assert np.array_equal(path[:, 0], np.zeros_like(path[:, 0])), "the Root stays at the origin"
    assert np.ptp(path[:, 1, 2]) > 4.0, "the hips walk several metres"


def test_the_long_take_has_100000_frames_of_the_walk():
    motion = make_rig("long_take")
    assert motion.n_frames == 100_000
    np.testing.assert_array_equal(motion.rotations[:300], walk().rotations)
    assert motion.size == pytest.approx(walk().size, rel=1e-3)


def test_size_is_the_actors_height_whatever_the_units_and_the_root(rigs):
    metres = rigs["metres"]
    # the walk stands upright: its height is its largest extent, measured independently
    # (within what sampling 64 frames of the 300 misses of the bob of the hips)
    assert metres.size == pytest.approx(_figure_height(metres), rel=1e-5)
    assert 1.7 < metres.size < 1.9
    assert rigs["origin_root"].size == pytest.approx(metres.size, rel=1e-12)
    assert rigs["six_channels"].size == pytest.approx(metres.size, rel=1e-12)
    mm = rigs["z_up_millimetres"]
    assert mm.size == pytest.approx(1000 * metres.size, rel=1e-12)
    assert mm.size == pytest.approx(_figure_height(mm, up=2), rel=1e-5)


def test_only_the_pinned_root_is_an_anchor(rigs):
    for name, motion in rigs.items():
        expected = [0] if name in ("origin_root", "game_root") else []
        assert np.flatnonzero(motion.anchors).tolist() == expected, name


def test_the_up_axis_is_guessed_from_the_actor(rigs):
    for name, motion in rigs.items():
        if name in ("one_joint",):
            continue
        positions = world_positions(motion)[:, ~motion.anchors]
        assert detect_up_axis(positions) == ("z" if name == "z_up_millimetres" else "y"), name


@pytest.mark.parametrize("name", SMALL_RIGS)
def test_size_and_anchors_are_invariant_under_the_operations(rigs, name):
    motion = pre_from_post(rigs[name].frame_slice(slice(0, 12)))  # a few frames: the operations cost
    hips = 1 if name == "origin_root" else 0
    leaf = motion.n_joints - 1
    edits = (
        [split_all, join_all]
        if motion.n_joints == 1
        else [
            split_all,
            lambda m: join_all(split_all(m)),
            lambda m: shift_root(m, leaf),
            lambda m: split(m, leaf),
            lambda m: join(split(m, leaf), leaf),
        ]
    )
    if motion.n_joints > 1 and hips:
        edits += [lambda m: split(m, hips), lambda m: shift_root(m, hips)]
    for edit in edits:
        edited = edit(motion)
        assert abs(edited.size - motion.size) <= 1e-12 * motion.size
        assert np.array_equal(edited.anchors, motion.anchors)
