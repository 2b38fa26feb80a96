"""Onion skins in the window, and filmstrips from the command line."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.app.filmstrip import parse_frame_steps, side_by_side, travel_axis
from gmr_studio.app.onion import ghost_opacity, onion_frames
from gmr_studio.app.scene import BACKGROUND
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics import world_positions
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
STUDIO = [sys.executable, "-m", "gmr_studio.app.main"]


def figure_mask(image: np.ndarray) -> np.ndarray:
    """(H, W) pixels that are neither the background nor near it."""
    background = np.round(np.array(BACKGROUND) * 255)
    return np.abs(image[..., :3].astype(int) - background).max(axis=-1) > 12


def test_onion_frames_around_the_current_one():
    frames, distance = onion_frames(100, 1000, 10, 3)
    assert frames.tolist() == [90, 110, 80, 120, 70, 130]
    assert distance.tolist() == [-1, 1, -2, 2, -3, 3]
    frames, distance = onion_frames(5, 30, 10, 3)  # clipped at both ends
    assert frames.tolist() == [15, 25]
    opacity = ghost_opacity(np.array([1, 2, 3]), 3)
    assert opacity[0] > opacity[1] > opacity[2] > 0
    with pytest.raises(ValueError):
        onion_frames(0, 10, 0, 3)


@pytest.mark.gui
def test_onion_skin_draws_the_ghost_poses_and_goes_away(studio, qtbot):
    open_file(studio, demo_folder() / MOTION_FILE)
    state, onion = studio.state, studio.onion
    state.set_frame(200)
    studio.view.scene.render(now=True)
    plain = screen_image(studio)
    onion.toggle.setChecked(True)
    assert onion.skins.frames.tolist() == [190, 210, 180, 220, 170, 230]
    for part, frame in zip(onion.skins.parts, onion.skins.frames, strict=True):
        np.testing.assert_array_equal(np.asarray(part.mesh.points), state.snapshot.positions[frame])
    studio.view.scene.render(now=True)
    ghosts = screen_image(studio)
    assert figure_mask(ghosts).sum() > 1.15 * figure_mask(plain).sum()
    state.set_frame(300)  # the ghosts follow the frame
    assert onion.skins.frames.tolist()[:2] == [290, 310]
    onion._set_step(30)
    assert onion.skins.frames.tolist()[:2] == [270, 330]
    onion.toggle.setChecked(False)
    state.set_frame(200)
    studio.view.scene.render(now=True)
    assert not onion.skins.parts
    again = screen_image(studio)
    changed = np.abs(again.astype(int) - plain.astype(int)).max(axis=-1) > 0
    assert changed.mean() < 1e-4  # the same picture but for a few antialiased pixels


def test_frames_are_python_slices():
    assert parse_frame_steps("10:50:20", 100).tolist() == [10, 30]
    assert parse_frame_steps("::40", 100).tolist() == [0, 40, 80]
    assert parse_frame_steps("-2:", 100).tolist() == [98, 99]
    assert parse_frame_steps("7", 100).tolist() == [7]
    for bad in ("a:b", "1:2:0", "200:300", "1:2:3:4"):
        with pytest.raises(ValueError):
            parse_frame_steps(bad, 100)


def test_side_by_side_poses_do_not_overlap_and_keep_their_heights():
    motion = load_gmr(demo_folder() / MOTION_FILE)
    positions = world_positions(motion)[::60]
    placed = side_by_side(positions, up=1)
    axis = travel_axis(positions, 1)
    along = placed @ axis
    assert np.all(along[1:].min(axis=1) > along[:-1].max(axis=1))  # each pose right of the previous
    np.testing.assert_array_equal(placed[..., 1], positions[..., 1])
    shape = placed - placed.mean(axis=1, keepdims=True)
    np.testing.assert_allclose(shape, positions - positions.mean(axis=1, keepdims=True), atol=1e-9)


@pytest.mark.gui
@pytest.mark.parametrize("layout", ["side", "path"])
def test_filmstrip_command_renders_every_pose(tmp_path, layout):
    out = tmp_path / "strip.png"
    bvh = shared_path("cmu/subject01/01_01.bvh")
    command = [*STUDIO, str(bvh), "--filmstrip", str(out), "--frames", "400:1600:300", "--layout", layout]
    result = subprocess.run([*command, "--size", "1200x400"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "4 poses: frames 400 to 1300" in result.stdout
    from PyQt6.QtGui import QImage

    image = QImage(str(out))
    assert (image.width(), image.height()) == (1200, 400)
    if layout == "side":
        rgb8 = image.convertToFormat(QImage.Format.Format_RGB888)
        bits = rgb8.constBits()
        bits.setsize(rgb8.sizeInBytes())
        rows = np.frombuffer(bits, np.uint8).reshape(400, rgb8.bytesPerLine())
        rgb = rows[:, : 1200 * 3].reshape(400, 1200, 3).astype(int)
        mask = rgb.max(axis=-1) - rgb.min(axis=-1) > 60  # the poses are coloured, the grid grey
        columns = mask.any(axis=0).astype(int)
        runs = int((np.diff(np.concatenate([[0], columns])) == 1).sum())
        assert runs >= 4  # four poses with gaps between them


def test_filmstrip_refuses_bad_frames(tmp_path):
    result = subprocess.run(
        [*STUDIO, "--filmstrip", str(tmp_path / "x.png"), "--frames", "9999:"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and "selects no frame" in result.stderr
    assert not (tmp_path / "x.png").exists()
