"""Thumbnails as a user sees them: poses side by side standing on a ground line, each tree in
its colour as the view draws it, an anchor left out, a Z-up take standing up; anti-aliased
lines; PNG files any reader takes."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.operations import split
from gmr_studio.core.edits.world import change_up_axis
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.library.drawing import BACKGROUND, GROUND_COLOR, PALETTE
from gmr_studio.core.library.thumbnails import draw_lines, motion_thumbnail, png_bytes, pose_frames
from gmr_studio.core.model.motion import Motion
from tests.conftest import shared_path
from tests.library_fixtures import read_png

MOCAP = "bvh/bvh-python_test_mocapbank.bvh"


def near(picture: np.ndarray, colour, tolerance: int = 40) -> np.ndarray:
    """(H, W) bool: pixels within ``tolerance`` of ``colour`` (RGB in [0, 1])."""
    return np.abs(picture.astype(int) - np.rint(np.asarray(colour) * 255)).max(axis=-1) < tolerance


def poses(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) columns of each run of columns holding ``mask`` pixels (gaps > 3 columns)."""
    columns = np.flatnonzero(mask.any(axis=0))
    cuts = np.flatnonzero(np.diff(columns) > 3)
    starts, ends = np.r_[columns[0], columns[cuts + 1]], np.r_[columns[cuts], columns[-1]]
    return list(zip(starts.tolist(), ends.tolist()))


def thumbnail(motion) -> np.ndarray:
    return motion_thumbnail(motion, world_positions(motion))


def test_four_poses_stand_side_by_side_on_the_ground_line():
    picture = thumbnail(read_motion(shared_path(MOCAP)))
    assert picture.shape == (64, 160, 3) and picture.dtype == np.uint8
    figure = near(picture, PALETTE[0])
    assert len(poses(figure)) == 4
    assert near(picture, BACKGROUND, 3).mean() > 0.6  # the view's background around them
    ground = near(picture, GROUND_COLOR, 12)
    ground_row = int(np.argmax(ground.sum(axis=1)))
    assert ground[ground_row].mean() > 0.5  # a line across the picture
    rows = np.flatnonzero(figure.any(axis=1))
    assert abs(rows.max() - ground_row) <= 2  # the feet on it
    assert rows.max() - rows.min() > 0.6 * 64  # the figures fill the height


def test_the_poses_are_the_middles_of_four_equal_parts():
    assert pose_frames(100).tolist() == [12, 37, 62, 87]
    assert pose_frames(2).tolist() == [0, 1] and pose_frames(1).tolist() == [0]


def test_each_tree_is_drawn_in_its_colour_as_the_view_draws_it():
    motion = read_motion(shared_path(MOCAP))
    picture = thumbnail(split(pre_from_post(motion), "Chest"))  # the upper body a tree of its own
    assert near(picture, PALETTE[0]).sum() > 40 and near(picture, PALETTE[1]).sum() > 40
    assert near(thumbnail(motion), PALETTE[1]).sum() == 0


def test_a_z_up_take_stands_up_as_in_the_view():
    motion = read_motion(shared_path(MOCAP))
    upright = near(thumbnail(motion), PALETTE[0])
    turned = near(thumbnail(change_up_axis(motion, "z")), PALETTE[0])
    for mask in (upright, turned):
        rows, columns = np.flatnonzero(mask.any(axis=1)), poses(mask)
        assert len(columns) == 4 and rows.max() - rows.min() > 2 * (columns[0][1] - columns[0][0])
    assert abs(int(upright.sum()) - int(turned.sum())) < 0.1 * upright.sum()


def test_an_anchor_at_the_origin_is_no_part_of_the_picture():
    motion = read_motion(shared_path(MOCAP))  # its root walks far from the origin
    anchored = anchored_at_origin(motion)
    assert anchored.anchors.tolist() == [True] + [False] * motion.n_joints
    # were the anchor framed, the figures would shrink into a corner, a line to it drawn
    picture = thumbnail(anchored)
    figure = near(picture, PALETTE[0])
    assert np.array_equal(figure, near(thumbnail(motion), PALETTE[0]))


def anchored_at_origin(motion: Motion) -> Motion:
    """The motion under a new root ``Anchor`` that stays at the origin (a BVH-style motion:
    the old root's translation is then its position relative to the anchor, unchanged)."""
    frames = motion.n_frames
    return Motion(
        names=("Anchor", *motion.names),
        parents=np.r_[-1, np.where(motion.parents >= 0, motion.parents + 1, 0)],
        offsets=np.concatenate([np.zeros((1, 3)), motion.offsets]),
        rotation_orders=("ZYX", *motion.rotation_orders),
        has_translation=np.r_[False, motion.has_translation],
        rotations=np.concatenate([np.broadcast_to(np.eye(3), (frames, 1, 3, 3)), motion.rotations], axis=1),
        translations=np.concatenate([np.zeros((frames, 1, 3)), motion.translations], axis=1),
        frame_time=motion.frame_time,
        convention=motion.convention,
    )


def test_lines_are_anti_aliased_and_cover_their_width():
    image = np.zeros((20, 40, 3))
    draw_lines(image, np.array([[5.0, 10.0]]), np.array([[35.0, 10.0]]), np.array([[1.0, 1.0, 1.0]]), 2.0)
    column = image[:, 20, 0]
    assert column.sum() == pytest.approx(2.0, abs=0.05)  # two pixels' worth of coverage across the line
    assert column.max() == 1.0 and ((column > 0) & (column < 1)).sum() <= 2
    image = np.zeros((20, 40, 3))
    draw_lines(image, np.array([[5.0, 5.3]]), np.array([[35.0, 14.7]]), np.array([[0.0, 1.0, 0.0]]), 1.5)
    partial = (image[..., 1] > 0.05) & (image[..., 1] < 0.95)
    assert partial.sum() > 20 and image[..., 0].max() == 0.0  # soft edges, in the line's colour only


def test_png_files_hold_the_picture_exactly():
    rng = np.random.default_rng(7)
    picture = rng.integers(0, 256, (9, 13, 3), dtype=np.uint8)
    assert np.array_equal(read_png(png_bytes(picture)), picture)


def test_thumbnails_and_the_view_share_one_home_for_colours_and_framing():
    """The view, its filmstrips and the thumbnails draw with the same colours and the same
    travel fit: one definition in core, which the app imports."""
    from gmr_studio.app.media import filmstrip
    from gmr_studio.app.model import tree_colors
    from gmr_studio.app.scene import overlays, scene
    from gmr_studio.core.library import drawing

    assert tree_colors.PALETTE is drawing.PALETTE and tree_colors.tree_identities is drawing.tree_identities
    assert scene.BACKGROUND is drawing.BACKGROUND and overlays.GROUND_COLOR is drawing.GROUND_COLOR
    assert filmstrip.travel_axis is drawing.travel_axis and filmstrip.side_by_side is drawing.side_by_side
    motion = read_motion(shared_path(MOCAP))
    split_motion = split(pre_from_post(motion), "Chest")
    np.testing.assert_array_equal(
        drawing.first_tree_colors(split_motion), tree_colors.TreeColors().colors(split_motion)
    )
