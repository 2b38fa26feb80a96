"""Issue 21, item 9: a filmstrip fills its picture and labels every pose, and draws the link
from a root pinned at the origin as the view does (dashed, no part of the figure)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.media.filmstrip import render_filmstrip
from gmr_studio.app.media.video import image_pixels
from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene.onion import pose_lines, pose_points
from gmr_studio.app.scene.scene import BACKGROUND, GROUND_COLOR
from gmr_studio.core.kinematics.fk import world_positions, world_rotations
from gmr_studio.core.rigs import origin_root

pytestmark = pytest.mark.gui


def _snapshot(motion) -> Snapshot:
    return Snapshot(motion, world_positions(motion), world_rotations(motion))


def test_pose_lines_dash_the_link_from_an_anchor():
    motion = origin_root()
    assert motion.anchors.any()
    pairs, links, n_points = pose_lines(motion)
    anchor = int(np.flatnonzero(motion.anchors)[0])
    assert any(anchor in link for link in links.tolist())  # the anchor's bone is a dashed link
    solid = pairs[pairs.max(axis=1) < motion.n_joints]
    assert not np.isin(solid, anchor).any()  # ... and no solid bone
    points = pose_points(world_positions(motion)[0], links)
    assert points.shape == (n_points, 3)


def test_a_filmstrip_of_a_pinned_root_walk_fills_the_picture_and_labels_every_pose(tmp_path):
    from PyQt6.QtGui import QImage

    motion = origin_root()
    frames = np.linspace(0, motion.n_frames - 1, 7).astype(int)
    drawn: dict = {}
    out = tmp_path / "strip.png"
    width, height = render_filmstrip(_snapshot(motion), frames, out, (800, 400), "side", drawn)
    image = image_pixels(QImage(str(out)))[..., :3].astype(int)
    background = np.round(np.array(BACKGROUND) * 255)
    ground = np.round(np.array(GROUND_COLOR) * 255)
    figure = (np.abs(image - background).max(-1) > 40) & (np.abs(image - ground).max(-1) > 40)
    columns = np.flatnonzero(figure.any(axis=0))
    rows = np.flatnonzero(figure.any(axis=1))
    assert np.ptp(columns) > 0.75 * width, "the poses do not fill the picture's width"
    assert np.ptp(rows) > 0.4 * height, "the figures are too small"
    boxes = drawn["labels"]
    assert len(boxes) == len(frames)  # every pose labelled ...
    left, bottom, w, h = boxes.T
    assert (left >= 0).all() and (left + w <= width).all() and (bottom >= 0).all() and (bottom + h <= height).all()
    order = np.argsort(left)
    assert (left[order][1:] > (left + w)[order][:-1]).all()  # ... and no label hides another


def _cases():
    from gmr_studio.app.tools.gallery import all_cases

    return all_cases()


@pytest.mark.parametrize("case", _cases(), ids=lambda case: case.name)
def test_every_file_and_rig_gives_a_filled_labelled_filmstrip(case, tmp_path, qapp):
    """Issue 21's agreement suite: on every shared file and rig, the filmstrip's figures fill
    the picture and every pose has its label, none hidden by another."""
    from PyQt6.QtGui import QImage

    snapshot = case.load()
    n = snapshot.motion.n_frames
    frames = np.unique(np.linspace(0, n - 1, min(n, 5)).astype(int))
    drawn: dict = {}
    out = tmp_path / "strip.png"
    width, height = render_filmstrip(snapshot, frames, out, (480, 240), "side", drawn)
    image = image_pixels(QImage(str(out)))[..., :3].astype(int)
    background = np.round(np.array(BACKGROUND) * 255)
    ground = np.round(np.array(GROUND_COLOR) * 255)
    figure = (np.abs(image - background).max(-1) > 40) & (np.abs(image - ground).max(-1) > 40)
    columns, rows = np.flatnonzero(figure.any(axis=0)), np.flatnonzero(figure.any(axis=1))
    if snapshot.motion.n_joints > 1:  # a lone node (an FBX cube's node animation) has no bone to draw
        assert max(np.ptp(columns) / width, np.ptp(rows) / height) > 0.5, "the figures do not fill the picture"
    left, bottom, w, h = drawn["labels"].T
    assert len(left) == len(frames)
    assert (left >= 0).all() and (left + w <= width + 1).all() and (bottom >= 0).all() and (bottom + h <= height).all()
    if len(frames) > 1:
        order = np.argsort(left)
        assert (left[order][1:] >= (left + w)[order][:-1]).all(), "a label hides another"


def test_poses_in_one_place_get_their_labels_side_by_side_in_frame_order(tmp_path):
    motion = origin_root()
    still = motion.frame_slice(np.zeros(4, dtype=np.int64))  # a figure standing still
    drawn: dict = {}
    render_filmstrip(_snapshot(still), np.arange(4), tmp_path / "strip.png", (640, 320), "path", drawn)
    left, _bottom, w, _h = drawn["labels"].T
    assert (left[1:] >= (left + w)[:-1]).all()  # left to right in frame order, none on another
