"""Onion skins in the window, and filmstrips from the command line."""

from __future__ import annotations

import argparse
import subprocess
import sys

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.arguments import parse_onion
from gmr_studio.app.media.filmstrip import parse_frame_steps, side_by_side, travel_axis
from gmr_studio.app.media.video import image_pixels
from gmr_studio.app.model import commands
from gmr_studio.app.scene.layer_onion import layer_slot_frames, slot_of
from gmr_studio.app.scene.onion import ghost_opacity, onion_frames
from gmr_studio.app.scene.scene import BACKGROUND
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions
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
    for part, frame in zip(onion.skins.poses, onion.skins.frames, strict=True):
        np.testing.assert_array_equal(np.asarray(part.mesh.points), state.snapshot.positions[frame])
    studio.view.scene.render(now=True)
    ghosts = screen_image(studio)
    assert figure_mask(ghosts).sum() > 1.15 * figure_mask(plain).sum()
    state.set_frame(300)  # the ghosts follow the frame
    assert onion.skins.frames.tolist()[:2] == [290, 310]
    onion.set_step(30)
    assert onion.skins.frames.tolist()[:2] == [270, 330]
    onion.toggle.setChecked(False)
    state.set_frame(200)
    studio.view.scene.render(now=True)
    assert not any(part.visible for part in onion.skins.pool)
    again = screen_image(studio)
    changed = np.abs(again.astype(int) - plain.astype(int)).max(axis=-1) > 0
    assert changed.mean() < 1e-4  # the same picture but for a few antialiased pixels


BVH = "cmu/subject01/01_01.bvh"
AMC = "cmu/subject01/01_01.amc"


def layer_mask(image: np.ndarray) -> np.ndarray:
    """(H, W) pixels of the first layer's magenta (1, 0.45, 0.9), also faded over the
    background: red and blue well above green (no tree, onion or error colour of a one-tree
    document is)."""
    rgb = image[..., :3].astype(int)
    return (rgb[..., 0] - rgb[..., 1] > 40) & (rgb[..., 2] - rgb[..., 1] > 30)


def green_mask(image: np.ndarray) -> np.ndarray:
    rgb = image[..., :3].astype(int)
    return (rgb[..., 1] - rgb[..., 0] > 40) & (rgb[..., 1] - rgb[..., 2] > 40)


def _compare_amc(window) -> None:
    open_file(window, shared_path(BVH))
    window.files.compare_path(str(shared_path(AMC)), joint_map="cmu", wait=True)
    QApplication.processEvents()
    assert len(window.layers) == 1


def _drawn(layer_onions, index: int) -> dict[int, object]:
    """frame -> part of what layer ``index`` shows; every other slot hidden."""
    drawn = {}
    for part, frame in zip(layer_onions.pools[index], layer_onions.slot_frames[index], strict=True):
        assert part.visible == (frame >= 0)
        if frame >= 0:
            drawn[int(frame)] = part
    return drawn


def test_layer_onion_slots_skip_frames_without_samples():
    assert slot_of(np.array([-1, 1, -2, 2, -3, 3])).tolist() == [0, 1, 2, 3, 4, 5]
    ghost = np.arange(50 * 2 * 3, dtype=float).reshape(50, 2, 3)
    ghost[:5] = np.nan  # B starts at A's frame 5
    ghost[30, 1] = np.nan  # one joint missing is no pose either
    frames, distance = onion_frames(20, 60, 10, 3)  # 10, 30, 0, 40, (-10), 50
    assert frames.tolist() == [10, 30, 0, 40, 50]
    assert layer_slot_frames(ghost, frames, distance, 3).tolist() == [10, -1, -1, 40, -1, -1]
    # a ghost of a document that has just grown (not recomputed yet): frame 50 is past its end
    assert layer_slot_frames(ghost[:45], frames, distance, 3).tolist() == [10, -1, -1, 40, -1, -1]
    frames, distance = onion_frames(45, 50, 10, 1)  # only 35: 55 is past the end
    assert layer_slot_frames(ghost, frames, distance, 1).tolist() == [35, -1]


def test_onion_flag_parses():
    assert parse_onion(None) is None
    assert parse_onion("30,2") == (30, 2)
    for bad in ("30", "a,b", "0,3", "10,0"):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_onion(bad)


@pytest.mark.gui
def test_layer_onion_poses_are_the_layer_ghost_at_the_onion_frames(studio):
    _compare_amc(studio)
    state, onion, layers = studio.state, studio.onion, studio.layers
    layer_onions = onion.layer_onions
    assert onion.include_layers.isChecked()  # on by default
    state.set_frame(1518)
    onion.set_step(30)
    assert not layer_onions.pools  # nothing drawn while the onion skin is off
    onion.toggle.setChecked(True)
    layer = layers[0]
    expected = [1488, 1548, 1458, 1578, 1428, 1608]
    assert onion.skins.frames.tolist() == expected
    drawn = _drawn(layer_onions, 0)
    assert sorted(drawn) == sorted(expected)
    doc_opacity = dict(zip(onion.skins.frames.tolist(), onion.skins.opacities, strict=True))
    for frame, part in drawn.items():
        np.testing.assert_array_equal(np.asarray(part.mesh.points), layer.ghost[frame])
        # the document's fading (the layer at its default opacity)
        assert part.actor.GetProperty().GetOpacity() == pytest.approx(doc_opacity[frame])
        assert part.actor.GetProperty().GetColor() == pytest.approx(layer.colour)
    # a frame change writes points into the same actors
    actors = [id(part.actor) for part in layer_onions.pools[0]]
    state.set_frame(1600)
    assert [id(part.actor) for part in layer_onions.pools[0]] == actors
    drawn = _drawn(layer_onions, 0)
    assert sorted(drawn) == [1510, 1540, 1570, 1630, 1660, 1690]
    for frame, part in drawn.items():
        np.testing.assert_array_equal(np.asarray(part.mesh.points), layer.ghost[frame])
    # frames where B has no sample are skipped: A's frame 0 comes before B's first (offset -1)
    assert np.isnan(layer.ghost[0]).all()
    onion.set_step(10)
    state.set_frame(20)
    assert 0 in onion.skins.frames.tolist()  # the document's onion pose at frame 0 is drawn
    assert sorted(_drawn(layer_onions, 0)) == [10, 30, 40, 50]
    assert layer_onions.slot_frames[0][slot_of(np.array([-2]))[0]] == -1
    # colour and opacity follow the Layers dock, without new actors
    state.set_frame(1518)
    layers.set_colour(0, (0.3, 1.0, 0.3))
    layers.set_opacity(0, 0.25)
    assert [id(part.actor) for part in layer_onions.pools[0]] == actors
    doc_opacity = dict(zip(onion.skins.frames.tolist(), onion.skins.opacities, strict=True))
    for frame, part in _drawn(layer_onions, 0).items():
        assert part.actor.GetProperty().GetColor() == pytest.approx((0.3, 1.0, 0.3))
        assert part.actor.GetProperty().GetOpacity() == pytest.approx(0.5 * doc_opacity[frame])  # 0.25 of 0.5
    # an edit recomputes the layer: the onion poses are its new ghost
    before = layer.ghost
    assert commands.shift_root_to(state, state.motion.joint_index("LeftHand"))
    assert layers[0].ghost is not before
    for frame, part in _drawn(layer_onions, 0).items():
        np.testing.assert_array_equal(np.asarray(part.mesh.points), layers[0].ghost[frame])
    # removing the layer removes its actors
    renderer = studio.view.scene.plotter.renderer
    pool = layer_onions.pools[0]
    layers.remove(0)
    assert layer_onions.pools == []
    assert not any(renderer.HasViewProp(part.actor) for part in pool)


@pytest.mark.gui
def test_layer_onion_pixels_follow_the_switches(studio):
    _compare_amc(studio)
    state, onion, layers = studio.state, studio.onion, studio.layers
    state.set_frame(0)  # the layer's own ghost is not drawn here (no sample of B): only its onion
    onion.set_step(60)
    assert layer_mask(screen_image(studio)).sum() == 0
    onion.toggle.setChecked(True)
    shown = layer_mask(screen_image(studio)).sum()
    assert shown > 400
    onion.include_layers.setChecked(False)  # the option leaves them out
    assert not layer_onions_drawn(onion)
    image = screen_image(studio)
    assert layer_mask(image).sum() == 0
    assert figure_mask(image).sum() > 0  # the document's onion poses stay
    onion.include_layers.setChecked(True)
    assert layer_mask(screen_image(studio)).sum() == shown
    layers.set_visible(0, False)
    assert layer_mask(screen_image(studio)).sum() == 0
    layers.set_visible(0, True)
    assert layer_mask(screen_image(studio)).sum() == shown
    layers.set_colour(0, (0.3, 1.0, 0.3))  # drawn in the layer's new colour
    image = screen_image(studio)
    assert layer_mask(image).sum() == 0 and green_mask(image).sum() > 400
    layers.set_colour(0, (1.0, 0.45, 0.9))
    onion.toggle.setChecked(False)
    assert layer_mask(screen_image(studio)).sum() == 0
    onion.toggle.setChecked(True)
    state.set_frame(1518)  # with the live ghost: the onion poses add to its pixels
    with_onion = layer_mask(screen_image(studio)).sum()
    onion.include_layers.setChecked(False)
    assert with_onion > 1.5 * layer_mask(screen_image(studio)).sum()
    onion.include_layers.setChecked(True)
    layers.remove(0)
    assert layer_mask(screen_image(studio)).sum() == 0


@pytest.mark.gui
def test_screenshot_with_the_onion_flag_shows_the_layer_onion(tmp_path):
    """Frame 0 of 01_01.bvh has no sample of 01_01.amc: the magenta is the layer's onion."""
    out = tmp_path / "onion.png"
    command = [*STUDIO, str(shared_path(BVH)), "--compare", str(shared_path(AMC)), "--map", "cmu"]
    command += ["--screenshot", str(out), "--frame", "0", "--onion", "60,3", "--size", "640x420"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    from tests.test_app_cli import read_png

    image = read_png(out)
    assert image.shape == (420, 640, 3)
    assert layer_mask(image).sum() > 100


def layer_onions_drawn(onion) -> bool:
    return any(part.visible for pool in onion.layer_onions.pools for part in pool)


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
        rgb = image_pixels(image).astype(int)
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


@pytest.mark.gui
def test_the_onion_skin_with_a_marker_set_layer_draws_only_posed_layers(studio):
    """A marker-set layer has no poses: the onion skin leaves it out (it used to ask it for a
    skeleton it does not have); a motion layer beside it keeps its onion poses."""
    open_file(studio, shared_path(BVH))
    studio.files.compare_path(str(shared_path("cmu/subject01/01_01.c3d")), wait=True)
    studio.files.compare_path(str(shared_path(AMC)), joint_map="cmu", wait=True)
    QApplication.processEvents()
    onion, layer_onions = studio.onion, studio.onion.layer_onions
    studio.state.set_frame(1518)
    onion.toggle.setChecked(True)
    studio.state.set_frame(1520)
    assert [len(pool) for pool in layer_onions.pools] == [0, 6]
    assert sorted(_drawn(layer_onions, 1)) == [1490, 1500, 1510, 1530, 1540, 1550]  # every 10, 3 a side
