"""BVH write -> read round trips, BVH -> GMR (paper 5.2) and GMR -> BVH with dummy joints."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.operations import shift_root, split
from gmr_studio.core.formats.bvh import bvh_text, read_bvh, write_bvh
from gmr_studio.core.kinematics.convention import post_from_pre, pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from tests.conftest import random_motion, shared_files
from tests.test_bvh_reader import SMALL


def reread(motion):
    return read_bvh("round-trip.bvh", bvh_text(motion).encode())


def positions_by_name(motion, names):
    index = [motion.names.index(n) for n in names]
    return world_positions(motion)[:, index]


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_read_write_read_keeps_every_position(path, tmp_path):
    motion = read_bvh(path)
    out = tmp_path / "out.bvh"
    write_bvh(motion, out)
    again = read_bvh(out)
    assert again.names == motion.names and again.rotation_orders == motion.rotation_orders
    assert list(again.parents) == list(motion.parents)
    error = np.abs(world_positions(again) - world_positions(motion)).max()
    assert error <= 1e-6 * motion.size, error


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_bvh_to_gmr_positions_equal_post_rotation_fk(path):
    post = read_bvh(path)
    pre = pre_from_post(post)
    assert pre.convention == "pre" and pre.names == post.names
    post_positions, post_world = forward_kinematics(post)
    pre_positions, pre_world = forward_kinematics(pre)
    assert np.abs(pre_positions - post_positions).max() <= 1e-12 * post.size
    # a GMR joint's frame is its parent's post-rotation frame
    children = np.flatnonzero(post.parents >= 0)
    np.testing.assert_allclose(pre_world[:, children], post_world[:, post.parents[children]], atol=1e-12)


def test_bvh_to_gmr_by_the_paper():
    post = read_bvh("small.bvh", SMALL.encode())
    pre = pre_from_post(post)
    np.testing.assert_array_equal(pre.rotations[:, 0], np.broadcast_to(np.eye(3), (2, 3, 3)))  # R'_root = I
    np.testing.assert_array_equal(pre.rotations[:, 1], post.rotations[:, 0])  # R'_j = R_p(j)
    np.testing.assert_array_equal(pre.rotations[:, 2], post.rotations[:, 1])
    np.testing.assert_array_equal(pre.translations, post.translations)  # t'_j = t_j, G kept
    assert pre.rotation_orders == ("ZXY", "ZXY", "ZXY")


def test_writer_keeps_partial_orders_end_sites_and_named_leaves():
    text = SMALL.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 1 Yrotation").replace(
        "0 0 0 0 0 0\n", "0 0 0 0\n"
    )
    text = text.split("Frame Time: 0.5")[0] + "Frame Time: 0.5\n1 2 3 0 0 0 10\n4 5 6 90 0 0 20\n"
    motion = read_bvh("partial.bvh", text.encode())
    written = bvh_text(motion)
    assert "CHANNELS 1 Yrotation" in written and "End Site" in written
    np.testing.assert_allclose(world_positions(reread(motion)), world_positions(motion), atol=1e-12)


@pytest.mark.parametrize("target", ["Hips", "LeftFoot", "Head_End", "Spine1", "RThumb"])
def test_gmr_to_bvh_with_dummies_keeps_positions(target):
    from tests.conftest import shared_path

    post = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    gmr = shift_root(pre_from_post(post), target)
    back, dummies = post_from_pre(gmr)
    assert all(name.endswith("_dummy") for name in dummies)
    again = reread(back)
    assert len(again.roots) == 1 and again.names[0] == target
    error = np.abs(positions_by_name(again, post.names) - world_positions(post)).max()
    assert error <= 1e-9 * post.size


def test_gmr_to_bvh_without_change_needs_no_dummies(rng):
    post = random_motion(rng, [-1, 0, 1, 1, 0, 4], n_frames=4, convention="post")
    back, dummies = post_from_pre(pre_from_post(post))
    assert dummies == []
    np.testing.assert_allclose(world_positions(back), world_positions(post), atol=1e-12)


def test_independent_siblings_get_one_dummy_each(rng):
    gmr = random_motion(rng, [-1, 0, 0, 1, 2], n_frames=3)
    back, dummies = post_from_pre(gmr)
    assert dummies == ["j1_dummy", "j2_dummy"]  # j0's two children differ; single children need none
    assert back.n_joints == 7 and back.parents[1] == back.names.index("j1_dummy")
    np.testing.assert_allclose(positions_by_name(reread(back), gmr.names), world_positions(gmr), atol=1e-12)


def test_split_forest_writes_several_roots(rng):
    gmr = split(random_motion(rng, [-1, 0, 1, 2], n_frames=3), 2)
    back, _ = post_from_pre(gmr)
    again = reread(back)
    assert len(again.roots) == 2
    np.testing.assert_allclose(positions_by_name(again, gmr.names), world_positions(gmr), atol=1e-12)


def test_writer_refuses_the_wrong_convention(rng):
    with pytest.raises(ValueError, match="post-rotation"):
        bvh_text(random_motion(rng, [-1, 0]))
