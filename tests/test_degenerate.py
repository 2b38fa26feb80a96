"""Degenerate motion through every conversion: zero-length bones, coincident joints,
gimbal-lock poses. No NaN from finite input, round trips still exact."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.formats.bvh import bvh_text, read_bvh
from gmr_studio.core.formats.bvh_export import bvh_export, bvh_export_trees
from gmr_studio.core.formats.gmr import gmr_text, read_gmr
from gmr_studio.core.kinematics.convention import post_from_pre, pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.euler import EULER_ORDERS, euler_from_matrix, matrix_from_euler

PARENTS = [-1, 0, 1, 2, 1, 4, 0, 6]


def gimbal_motion(order: str, convention: str, offsets: np.ndarray) -> Motion:
    """Every joint at pitch +-90 degrees about its order's middle axis, turning about the rest."""
    n, frames = len(PARENTS), 24
    angles = np.zeros((frames, n, 3))
    angles[..., 0] = np.linspace(-170, 170, frames)[:, None]
    angles[..., 1] = np.where(np.arange(frames) % 2, 90.0, -90.0)[:, None]
    angles[..., 2] = np.linspace(30, -30, frames)[:, None]
    channels = {0: np.linspace(0, 10, frames)[:, None] * np.ones(3)}
    return Motion(
        names=[f"j{j}" for j in range(n)],
        parents=PARENTS,
        offsets=offsets,
        rotation_orders=[order] * n,
        has_translation=np.eye(1, n, dtype=bool)[0],
        rotations=matrix_from_euler(np.radians(angles), order),
        translations=build_translations(frames, offsets, channels),
        frame_time=1 / 60,
        convention=convention,
    )


OFFSETS = {
    "zero-length bones": np.array(
        [[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 1, 0], [0, 0, 0], [0, 0, 0], [0, 0, 2]], float
    ),
    "all joints coincident": np.zeros((len(PARENTS), 3)),
    "ordinary": np.random.default_rng(5).normal(size=(len(PARENTS), 3)),
}


def assert_finite_and_equal(a, b, names_b=None, scale=1.0):
    pa, pb = world_positions(a), world_positions(b)
    if names_b is not None:
        pb = pb[:, [b.names.index(n) for n in names_b]]
    assert np.isfinite(pa).all() and np.isfinite(pb).all()
    assert np.abs(pa - pb).max() <= 1e-9 * scale


@pytest.mark.parametrize("order", EULER_ORDERS)
@pytest.mark.parametrize("case", list(OFFSETS))
def test_gimbal_lock_and_degenerate_bones_through_every_conversion(order, case):
    post = gimbal_motion(order, "post", OFFSETS[case])
    size = post.size
    # BVH text round trip (Euler angles at gimbal lock)
    again = read_bvh("g.bvh", bvh_text(post).encode())
    assert np.isfinite(again.rotations).all()
    assert_finite_and_equal(post, again, scale=size)
    # BVH -> GMR -> operations -> GMR text -> BVH with dummies
    gmr = pre_from_post(post)
    assert_finite_and_equal(post, gmr, scale=size)
    edited = split(shift_root(gmr, 3), 5)
    assert_finite_and_equal(gmr, edited, scale=size)
    assert_finite_and_equal(edited, read_gmr("g.gmr", gmr_text(edited).encode()), edited.names, size)
    everything = split_all(edited)
    restored = join_all(everything)
    for motion in (everything, restored, join(edited, 5)):
        motion.check_invariants()
        assert_finite_and_equal(gmr, motion, scale=size)
    back, _ = post_from_pre(restored)
    assert_finite_and_equal(gmr, read_bvh("b.bvh", bvh_text(back).encode()), gmr.names, size)
    # the forest as one BVH (dummies, a world root) and as one BVH per tree
    export = bvh_export(everything)
    read = read_bvh("f.bvh", export.text().encode())
    assert_finite_and_equal(everything, read, export.names, size)
    for _, tree in bvh_export_trees(edited):
        joints = [j for j, name in enumerate(tree.names) if name is not None]
        read = read_bvh("t.bvh", tree.text().encode())
        theirs = world_positions(read)[:, [read.names.index(tree.names[j]) for j in joints]]
        assert np.isfinite(theirs).all()
        assert np.abs(world_positions(edited)[:, joints] - theirs).max() <= 1e-9 * size


def test_gimbal_lock_rotations_rebuild_exactly():
    for order in EULER_ORDERS:
        rotations = gimbal_motion(order, "post", OFFSETS["ordinary"]).rotations
        rebuilt = matrix_from_euler(euler_from_matrix(rotations, order), order)
        np.testing.assert_allclose(rebuilt, rotations, atol=1e-12)


def test_a_motion_with_every_joint_at_one_point_has_a_usable_size():
    motion = gimbal_motion("ZYX", "pre", OFFSETS["all joints coincident"])
    assert motion.size > 0 and np.isfinite(motion.size)
    positions, world = forward_kinematics(motion)
    assert np.isfinite(positions).all() and np.isfinite(world).all()
