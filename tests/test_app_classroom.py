"""The Teach dock and its overlay in the real window, on CMU 01_01; and the overlay's drawing
(app/scene/teach_overlay.py) on a small random motion in a stand-in scene with bare VTK
renderers: the chain from the root, the pre-rotation bone and the post-rotation bones turned
by the slider's amount (worked out from the motion's own rotations and translations)."""

from __future__ import annotations

import dataclasses
import itertools
from types import SimpleNamespace

import numpy as np
import pytest
from vtkmodules.vtkRenderingCore import vtkRenderer

from gmr_studio.app.model import commands
from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene.teach_overlay import POST_COLOR, PRE_COLOR, TeachOverlay, teaching_geometry
from gmr_studio.core.analysis.classroom import scaled_rotation
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import random_motion, shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

CMU = "cmu/subject01/01_01.bvh"


def color_pixels(image: np.ndarray, color, tolerance: int = 40) -> np.ndarray:
    """(N, 2) row/column of the pixels within ``tolerance`` of ``color`` (0..1 floats)."""
    target = np.round(np.array(color) * 255)
    return np.argwhere(np.abs(image[..., :3].astype(int) - target).max(axis=-1) <= tolerance)


@pytest.fixture
def classroom(studio, qtbot):
    open_file(studio, shared_path(CMU))
    studio.state.set_frame(619)
    studio.state.select(studio.state.motion.names.index("LeftForeArm"))
    studio.classroom.show()
    qtbot.waitUntil(lambda: studio.classroom.panel.chain is not None, timeout=3000)
    return studio


def test_the_chain_of_the_selected_joint_is_shown_both_ways(classroom, qtbot):
    panel, state = classroom.classroom.panel, classroom.state
    joint = state.motion.names.index("LeftForeArm")
    qtbot.waitUntil(lambda: panel.chain is not None and panel.chain.joints[-1] == joint, timeout=3000)
    assert panel.chain.joints == state.motion.path_from_root(joint)
    np.testing.assert_allclose(panel.chain.gmr_product[:3, 3], state.snapshot.positions[619, joint], atol=1e-9)
    text = panel.chain_view.toPlainText()
    for name in (
        "Hips",
        "LeftShoulder",
        "LeftArm",
        "LeftForeArm",
        "Product of the links",
        "World transform (FK)",
        "rounding",
    ):
        assert name in text
    assert "LeftForeArm" in panel.title.text() and "619" in panel.title.text()


def test_a_screenshot_shows_the_chain_without_waiting_for_the_dock(studio):
    open_file(studio, shared_path(CMU))
    studio.state.select(studio.state.motion.names.index("LeftForeArm"))
    studio.classroom.dock.show()  # its refresh is deferred to a timer
    studio.classroom.panel.settle()  # what a screenshot calls before it grabs the window
    assert "LeftForeArm" in studio.classroom.panel.title.text()


def test_a_short_dock_scrolls_instead_of_overlapping_its_parts(studio, qtbot):
    open_file(studio, shared_path(CMU))
    studio.resize(1280, 480)
    studio.state.select(studio.state.motion.names.index("LeftForeArm"))
    studio.classroom.dock.show()  # from the View menu: a tab of the narrow side column
    studio.classroom.dock.raise_()
    panel = studio.classroom.panel
    qtbot.waitUntil(lambda: panel.chain is not None, timeout=3000)
    parts = [panel.title, panel.chain_view, panel.amount_label, panel.amount]
    assert studio.classroom.dock.height() < panel.minimumSizeHint().height()  # shorter than the panel

    def apart() -> bool:
        return all(a.geometry().bottom() < b.geometry().top() for a, b in itertools.pairwise(parts))

    qtbot.waitUntil(apart, timeout=3000)
    bar = panel.chain_view.horizontalScrollBar()  # a matrix's rows wider than the view scroll sideways
    assert bar.maximum() > 0 or panel.chain_view.document().idealWidth() <= panel.chain_view.viewport().width()


def test_the_rotation_slider_turns_the_drawn_bones(classroom, qtbot):
    window, panel, overlay = classroom, classroom.classroom.panel, classroom.classroom.overlay
    snapshot, joint = window.state.snapshot, window.state.selected
    assert overlay.geometry is not None
    np.testing.assert_allclose(overlay.geometry.pre[1], snapshot.positions[619, joint], atol=1e-9)
    child = snapshot.motion.children[joint][0]
    np.testing.assert_allclose(overlay.geometry.post[1], snapshot.positions[619, child], atol=1e-9)
    window.view.scene.render(now=True)
    posed = screen_image(window)
    assert len(color_pixels(posed, PRE_COLOR)) > 20 and len(color_pixels(posed, POST_COLOR)) > 20
    panel.amount.setValue(0)
    turned = overlay.geometry
    bone = snapshot.positions[619, joint] - snapshot.positions[619, snapshot.motion.parents[joint]]
    assert np.linalg.norm(turned.pre[1] - snapshot.positions[619, joint]) > 0.05 * np.linalg.norm(bone)
    np.testing.assert_allclose(np.linalg.norm(turned.pre[1] - turned.pre[0]), np.linalg.norm(bone), rtol=1e-9)
    window.view.scene.render(now=True)
    rest = screen_image(window)
    before, after = color_pixels(posed, PRE_COLOR).mean(axis=0), color_pixels(rest, PRE_COLOR).mean(axis=0)
    assert np.abs(before - after).max() > 2  # the pink bone moved on the screen


def test_hiding_the_dock_removes_the_drawing(classroom, qtbot):
    classroom.classroom.dock.hide()
    qtbot.waitUntil(lambda: classroom.classroom.overlay.geometry is None, timeout=3000)
    classroom.view.scene.render(now=True)
    assert len(color_pixels(screen_image(classroom), PRE_COLOR, tolerance=20)) == 0


def test_shift_root_is_explained(classroom):
    state, panel = classroom.state, classroom.classroom.panel
    assert commands.shift_root_to(state, state.motion.names.index("LeftHand"))
    text = panel.shift_text.text()
    assert "LeftHand became the root" in text and "Hips" in text and "did not move" in text


def test_the_roots_slider_measures_in_the_background(classroom, qtbot):
    panel, state = classroom.classroom.panel, classroom.state
    panel.roots.setValue(6)
    qtbot.waitUntil(lambda: 6 in panel.points, timeout=20000)
    point = panel.points[6]
    assert point.roots == 6 and len(point.split_joints) == 5
    assert point.largest_change <= 1e-9 * state.motion.size
    assert point.fk_us_per_frame > 0
    assert "6 root(s): FK" in panel.roots_label.text()
    assert state.motion.n_joints == len(state.motion.names) and (state.motion.parents < 0).sum() == 1  # untouched


# ------------------------------------------------------- the overlay's drawing, no window
#: 0 root, 1 under it, 2 and 3 children of 1, 4 under 3
PARENTS = [-1, 0, 1, 1, 3]
N_FRAMES = 6


@pytest.fixture
def small() -> Snapshot:
    return Snapshot.of(random_motion(np.random.default_rng(11), PARENTS, n_frames=N_FRAMES, angle=2.0))


def _turned(snapshot: Snapshot, frame: int, joint: int, amount: float) -> np.ndarray:
    """Where ``joint`` is with its own rotation scaled by ``amount`` (its parent's frame kept)."""
    motion = snapshot.motion
    parent = motion.parents[joint]
    rotation = scaled_rotation(motion.rotations[frame, joint], amount)
    offset = motion.translations[frame, joint]
    return snapshot.positions[frame, parent] + snapshot.rotations[frame, parent] @ rotation @ offset


@pytest.mark.parametrize("amount", [1.0, 0.0, 0.35])
def test_the_bones_turn_with_the_amount_from_the_posed_skeleton(small, amount):
    positions = small.positions[4]
    geometry = teaching_geometry(small, 3, 4, amount)
    np.testing.assert_array_equal(geometry.chain, positions[[0, 1, 3]])
    np.testing.assert_allclose(geometry.pre, [positions[1], _turned(small, 4, 3, amount)], rtol=0, atol=1e-12)
    np.testing.assert_allclose(geometry.post, [positions[3], _turned(small, 4, 4, amount)], rtol=0, atol=1e-12)
    geometry = teaching_geometry(small, 1, 4, amount)  # a child of the root, with two children
    np.testing.assert_allclose(geometry.pre, [positions[0], _turned(small, 4, 1, amount)], rtol=0, atol=1e-12)
    expected = [positions[1], _turned(small, 4, 2, amount), positions[1], _turned(small, 4, 3, amount)]
    np.testing.assert_allclose(geometry.post, expected, rtol=0, atol=1e-12)
    if amount == 1.0:  # the posed skeleton itself
        np.testing.assert_allclose(geometry.pre[1], positions[1], rtol=0, atol=1e-12)
        np.testing.assert_allclose(geometry.post[[1, 3]], positions[[2, 3]], rtol=0, atol=1e-12)


def test_a_root_has_no_pre_bone_and_a_leaf_no_post_bone(small):
    positions = small.positions[2]
    root = teaching_geometry(small, 0, 2, 0.5)
    np.testing.assert_array_equal(root.chain, positions[[0]])
    np.testing.assert_array_equal(root.pre, [positions[0], positions[0]])
    leaf = teaching_geometry(small, 2, 2, 0.5)
    np.testing.assert_array_equal(leaf.post, [positions[2], positions[2]])
    assert leaf.post.shape == (2, 3) and root.pre.shape == (2, 3)
    with pytest.raises(dataclasses.FrozenInstanceError):
        leaf.pre = root.pre  # the geometry drawn is not changed behind the drawing


class StandInScene:
    """What the overlay reads of a scene: the snapshot, the frame and the renderers."""

    def __init__(self, snapshot: Snapshot | None) -> None:
        self.plotter = SimpleNamespace(renderer=vtkRenderer())
        self.front_renderer = vtkRenderer()
        self.snapshot = snapshot
        self.frame = 0


def _points(part) -> np.ndarray:
    return np.asarray(part.mesh.points)


def test_the_overlay_draws_the_joints_chain_and_bones_in_front(small):
    scene, overlay = StandInScene(small), TeachOverlay()
    overlay.joint = 1
    assert not overlay.wanted(scene)  # the Teach dock hidden
    overlay.build(scene)
    assert overlay.parts == {} and overlay.geometry is None
    overlay.shown = True
    assert overlay.wanted(scene)
    scene.frame = N_FRAMES + 3  # past the end: the last frame's geometry sizes the parts
    overlay.build(scene)
    assert scene.front_renderer.GetViewProps().GetNumberOfItems() == 3
    assert scene.plotter.renderer.GetViewProps().GetNumberOfItems() == 0
    chain, pre, post = (overlay.parts[name] for name in ("chain", "pre", "post"))
    assert (chain.n_points, pre.n_points, post.n_points) == (2, 2, 4)
    lines = {name: np.asarray(part.mesh.lines).reshape(-1, 3)[:, 1:].tolist() for name, part in overlay.parts.items()}
    assert lines == {"chain": [[0, 1]], "pre": [[0, 1]], "post": [[0, 1], [2, 3]]}
    colours = [part.actor.GetProperty().GetColor() for part in (chain, pre, post)]
    assert colours[1:] == [pytest.approx(PRE_COLOR), pytest.approx(POST_COLOR)]
    assert len({tuple(np.round(c, 2)) for c in colours}) == 3  # the chain, the two bones: told apart
    assert overlay.geometry is None  # drawn at the next frame shown
    overlay.amount = 0.25
    overlay.show_frame(3)
    expected = teaching_geometry(small, 1, 3, 0.25)
    np.testing.assert_array_equal(_points(chain), expected.chain)
    np.testing.assert_array_equal(_points(pre), expected.pre)
    np.testing.assert_array_equal(_points(post), expected.post)
    np.testing.assert_array_equal(overlay.geometry.post, expected.post)
    overlay.set_visible(True)
    assert overlay.geometry is not None and chain.visible
    overlay.set_visible(False)  # hidden: no geometry to show
    assert overlay.geometry is None and not chain.visible


def test_no_drawing_without_a_joint_of_the_motion(small):
    scene, overlay = StandInScene(small), TeachOverlay()
    overlay.shown = True
    for joint in (None, -1, 5):
        overlay.joint = joint
        assert not overlay.wanted(scene)
        overlay.build(scene)
        overlay.show_frame(0)
        assert overlay.parts == {} and overlay.geometry is None
    overlay.joint = 4
    overlay.build(scene)
    assert overlay.wanted(scene) and set(overlay.parts) == {"chain", "pre", "post"}
    overlay.joint = 9  # the joint gone (another motion): the parts kept but not written
    before = _points(overlay.parts["chain"]).copy()
    overlay.show_frame(2)
    np.testing.assert_array_equal(_points(overlay.parts["chain"]), before)
    assert overlay.geometry is None
    scene.snapshot = None
    overlay.joint = 0
    assert not overlay.wanted(scene)


def test_a_new_overlay_draws_the_posed_bones_and_the_root_too(small):
    scene, overlay = StandInScene(small), TeachOverlay()
    overlay.shown, overlay.joint = True, 0  # the root: a joint like any other
    assert overlay.wanted(scene)
    overlay.build(scene)
    overlay.show_frame(5)  # a new overlay's amount is 1: the pose itself
    positions = small.positions[5]
    np.testing.assert_allclose(_points(overlay.parts["post"]), [positions[0], positions[1]], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(_points(overlay.parts["pre"]), [positions[0], positions[0]])


def test_the_overlays_box_is_the_documents_joints_grown_by_its_size_and_holds_the_turned_bones(small):
    """A bone turned about its joint stays within its length of the joint: the box of the
    document's joints at every frame grown by the motion's size holds every bone drawn at any
    amount; nothing built (the dock hidden): the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of
    from tests.tiny_scene import scene_of

    with scene_of(small) as scene:
        overlay = TeachOverlay()
        overlay.joint = 1
        scene.add_drawable(overlay)
        np.testing.assert_array_equal(overlay.extent(), EMPTY_BOX)
        overlay.shown = True
        scene.redraw(overlay)
        box = overlay.extent()
        size = small.motion.size
        np.testing.assert_allclose(box, box_of(small.positions, size), rtol=0, atol=1e-12)
        for amount in (-1.0, 0.5, 2.0):
            overlay.amount = amount
            for frame in range(N_FRAMES):
                overlay.show_frame(frame)
                drawn = np.concatenate([overlay.geometry.chain, overlay.geometry.pre, overlay.geometry.post])
                assert (drawn >= box[0]).all() and (drawn <= box[1]).all(), (amount, frame)
