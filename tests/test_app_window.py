"""The real window under Xvfb: open, click, edit, undo, overlays, markers, pelvis, keys.

Every test gets a fresh main window (``studio``) that fails the test if it leaks a window
or a VTK render window.
"""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPoint, Qt

from gmr_studio.app.scene.scene import TREE_COLORS
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio  # the fixture: a main window that must not leak

CMU = "cmu/subject01/01_01.bvh"


def joint_point(window, joint: int) -> QPoint:
    x, y, _ = window.view.scene.joint_screen_positions()[joint]
    return QPoint(round(x), round(y))


def hover(widget, point: QPoint) -> None:
    """A mouse move with no button, sent to the widget itself (moving the real cursor would
    reach whichever window is on top of the X server that test workers share)."""
    from PyQt6.QtCore import QPointF
    from PyQt6.QtGui import QMouseEvent
    from PyQt6.QtWidgets import QApplication

    local = QPointF(point)
    event = QMouseEvent(
        QEvent.Type.MouseMove,
        local,
        QPointF(widget.mapToGlobal(point)),
        Qt.MouseButton.NoButton,
        Qt.MouseButton.NoButton,
        Qt.KeyboardModifier.NoModifier,
    )
    QApplication.sendEvent(widget, event)


def press(qtbot, window, key) -> None:
    """A key press as the user makes it: window shortcuts need the window to be active."""
    if not window.isActiveWindow():
        window.activateWindow()
        qtbot.waitUntil(window.isActiveWindow, timeout=3000)
    qtbot.keyClick(window.view.interactor, key)


def click(qtbot, window, point: QPoint, button=Qt.MouseButton.LeftButton) -> None:
    qtbot.mouseClick(window.view.interactor, button, Qt.KeyboardModifier.NoModifier, point)


def test_the_demo_opens_with_its_markers_and_shows_the_skeleton(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE, demo_folder() / MARKERS_FILE)
    state = studio.state
    assert state.motion.n_joints == 31 and state.marker_overlay is not None
    assert "walk.gmr" in studio.windowTitle() and "GMR Studio" in studio.windowTitle()
    state.set_frame(200)
    image = screen_image(studio).astype(int)
    assert image.std() > 5  # not a blank picture
    scale = image.shape[1] / studio.view.interactor.width()
    blue = TREE_COLORS[0] * 255
    screen = studio.view.scene.joint_screen_positions()
    hits = 0
    for x, y, _ in screen:
        px, py = round(x * scale), round(y * scale)
        patch = image[max(py - 2, 0) : py + 3, max(px - 2, 0) : px + 3].reshape(-1, 3)
        hits += bool((np.abs(patch - blue).max(axis=1) < 40).any())
    assert hits >= 0.8 * len(screen)  # the tree's colour where (nearly) every joint projects
    background = image[2, 2]
    assert np.abs(background - blue).max() > 60


def test_a_click_on_a_joint_selects_it_in_the_view_and_the_forest(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    head = studio.state.motion.joint_index("head")
    click(qtbot, studio, joint_point(studio, head))
    assert studio.state.selected == head
    item = studio.forest.item_for(head)
    assert item.isSelected() and studio.forest.currentItem() is item
    assert "head" in studio.inspector.text()
    assert studio.view.scene.is_shown("selection")
    # selecting in the forest selects in the view
    knee = studio.state.motion.joint_index("lfemur")
    studio.forest.setCurrentItem(studio.forest.item_for(knee))
    assert studio.state.selected == knee
    # a click on empty space clears the selection
    click(qtbot, studio, QPoint(5, 5))
    assert studio.state.selected is None and not studio.forest.selectedItems()


def test_edit_a_real_file_by_the_actions_and_undo_all(qtbot, studio):
    path = shared_path(CMU)
    open_file(studio, path)
    state, actions = studio.state, studio.actions
    original = state.positions
    camera = studio.view.scene.plotter.camera_position
    size = state.motion.size
    names = state.motion.names

    def select_by_click(name: str) -> None:
        joint = names.index(name)
        click(qtbot, studio, joint_point(studio, joint))
        assert state.selected == joint, name

    select_by_click("LeftFoot")
    assert actions["shift_root"].isEnabled() and not actions["join"].isEnabled()
    actions["shift_root"].trigger()
    assert state.motion.roots.tolist() == [names.index("LeftFoot")]
    select_by_click("RightForeArm")
    actions["split"].trigger()
    assert len(state.motion.roots) == 2 and actions["join"].isEnabled()
    for snapshot_positions in (state.positions,):
        np.testing.assert_allclose(snapshot_positions, original, rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(  # the view does not jump
        np.array(studio.view.scene.plotter.camera_position.to_list()),
        np.array(camera.to_list()),
        rtol=0,
        atol=1e-9 * size,
    )
    roots = studio.forest.topLevelItemCount()
    assert roots == 2 and "\u21e2 RightArm" in studio.forest.item_for(names.index("RightForeArm")).text(1)
    actions["join"].trigger()
    assert len(state.motion.roots) == 1
    np.testing.assert_allclose(state.positions, original, rtol=0, atol=1e-9 * size)
    assert studio.isWindowModified() and state.undo_stack.count() == 3
    assert studio.history.model().rowCount() == 4  # "<opened>" and three edits
    for _ in range(3):
        actions["undo"].trigger()
        np.testing.assert_allclose(state.positions, original, rtol=0, atol=1e-9 * size)
    assert state.positions is original and not studio.isWindowModified()
    assert state.motion.roots.tolist() == [0]


def test_joining_the_last_root_is_refused_in_the_status_bar(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    before = studio.state.snapshot
    studio.state.select(0)
    assert not studio.actions["join"].isEnabled()
    studio.actions["join_all"].setEnabled(True)
    from gmr_studio.app.model import commands

    commands.join_to_parent(studio.state, 0)
    assert "last root of the forest" in studio.status.text()
    assert studio.state.snapshot is before and studio.state.undo_stack.count() == 0


def test_overlays_switch_their_actors_on_and_off(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE, demo_folder() / MARKERS_FILE)
    scene = studio.view.scene
    studio.state.select(studio.state.motion.joint_index("lwrist"))
    for name in ("ground", "axes", "trails", "labels", "markers", "soft_links"):
        action = studio.actions[f"overlay_{name}"]
        for shown in (True, False, True):
            action.setChecked(shown)
            assert studio.state.overlays[name] is shown
            assert scene.is_shown(name) is shown, name
    # the trail follows the selected joint over the last second
    studio.state.set_frame(300)
    trail = scene.parts["trails"].mesh.points
    np.testing.assert_allclose(trail[-1], studio.state.positions[300, studio.state.selected])
    np.testing.assert_allclose(trail[0], studio.state.positions[300 - 120, studio.state.selected])
    # joint axes are the world rotation's columns
    axes = scene.parts["axes"].mesh.points.reshape(-1, 3, 2, 3)
    j = 7
    direction = (axes[j, :, 1] - axes[j, :, 0]) / np.linalg.norm(axes[j, 0, 1] - axes[j, 0, 0])
    np.testing.assert_allclose(direction.T, studio.state.rotations[300, j], atol=1e-9)


def test_joint_frames_are_made_when_first_shown_and_held_by_the_document_shown(qtbot, studio):
    from gmr_studio.app.model import commands

    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    studio.inspector_dock.show()
    state.select(state.motion.joint_index("lwrist"))  # the inspector shows this frame's own
    state.set_frame(40)
    qtbot.waitUntil(lambda: "lwrist" in studio.inspector.text())
    assert not state.snapshot.holds_rotations  # the figure is drawn from the positions alone
    bare = screen_image(studio)
    studio.actions["overlay_axes"].setChecked(True)
    qtbot.waitUntil(lambda: np.any(screen_image(studio) != bare, axis=-1).sum() > 200)  # the triads
    shown = screen_image(studio)
    opened = state.snapshot
    assert opened.holds_rotations
    assert commands.scale_by(state, 2.0)
    assert not opened.holds_rotations  # the history's snapshot lets them go
    state.undo_stack.undo()
    qtbot.waitUntil(lambda: np.any(screen_image(studio) != shown, axis=-1).mean() < 0.001)  # made again


def test_markers_skip_gaps_and_label_the_hovered_one(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE, demo_folder() / MARKERS_FILE)
    state, scene = studio.state, studio.view.scene
    n_markers = state.marker_overlay.markers.n_markers
    spheres = scene.parts["markers"]  # one sphere per marker; a missing one is not drawn
    state.set_frame(50)
    assert spheres.mesh.n_points == n_markers and spheres.drawn.all()
    state.set_frame(110)  # LWRA is missing from frame 100 to 131
    lwra = state.marker_overlay.markers.labels.index("LWRA")
    assert spheres.mesh.n_points == n_markers and np.flatnonzero(~spheres.drawn).tolist() == [lwra]
    state.set_overlay("joints", False) if "joints" in state.overlays else None
    m = state.marker_overlay.markers.labels.index("LASI")
    x, y, _ = scene.marker_screen_positions()[m]
    hover(studio.view.interactor, QPoint(round(x), round(y)))
    assert scene.hovered_marker == m
    assert scene.is_shown("marker_labels")
    click(qtbot, studio, QPoint(round(x), round(y)))
    assert state.selected_marker == m and "Marker LASI" in studio.inspector.text()


def test_pelvis_frames_are_recovered_and_drawn_as_a_triad_with_the_residual(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE, demo_folder() / MARKERS_FILE)
    state, scene = studio.state, studio.view.scene
    assert state.pelvis is not None and "pelvis frames recovered" in studio.status.text()
    assert scene.is_shown("pelvis") and studio.actions["recover_pelvis"].isEnabled()
    state.set_frame(77)
    triad = scene.parts["pelvis"].mesh.points.reshape(3, 2, 3)
    np.testing.assert_allclose(triad[:, 0], np.broadcast_to(state.pelvis.origins[77], (3, 3)))
    axes = (triad[:, 1] - triad[:, 0]).T / np.linalg.norm(triad[0, 1] - triad[0, 0])
    np.testing.assert_allclose(axes, state.pelvis.rotations[77], atol=1e-9)
    assert "residual" in studio.inspector.text() and f"{state.pelvis.residuals[77]:.3g}" in studio.inspector.text()
    studio.actions["overlay_pelvis"].setChecked(False)
    assert not scene.is_shown("pelvis") and "residual" not in studio.inspector.text()


def test_remove_dummy_joints_on_the_cmu_bvh(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    before = state.snapshot
    action = studio.actions["remove_dummies"]
    assert action.isEnabled()
    action.trigger()
    motion = state.motion
    removed = set(before.motion.names) - set(motion.names)
    assert {"LHipJoint", "RHipJoint"} <= removed and "Removed" in studio.status.text()
    kept = [before.motion.names.index(name) for name in motion.names]
    np.testing.assert_allclose(state.positions, before.positions[:, kept], atol=1e-9 * motion.size)
    studio.actions["undo"].trigger()
    assert state.snapshot is before
    assert studio.forest.item_for(before.motion.joint_index("LHipJoint")) is not None


def test_keys_step_jump_and_play(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    studio.view.interactor.setFocus()
    press(qtbot, studio, Qt.Key.Key_Right)
    assert state.frame == 1
    press(qtbot, studio, Qt.Key.Key_End)
    assert state.frame == state.n_frames - 1
    press(qtbot, studio, Qt.Key.Key_Left)
    assert state.frame == state.n_frames - 2
    press(qtbot, studio, Qt.Key.Key_Home)
    assert state.frame == 0
    press(qtbot, studio, Qt.Key.Key_BracketRight)
    assert studio.player.speed == 2.0 and studio.timeline.speed_box.currentText() == "2x"
    press(qtbot, studio, Qt.Key.Key_Space)
    assert studio.player.playing
    qtbot.waitUntil(lambda: state.frame > 20, timeout=3000)
    press(qtbot, studio, Qt.Key.Key_Space)
    assert not studio.player.playing
    assert studio.timeline.slider.value() == state.frame


def test_inspector_shows_the_local_transform_both_ways(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    j = state.motion.joint_index("ltibia")
    state.select(j)
    state.set_frame(42)
    text = studio.inspector.text()
    rotation = state.motion.rotations[42, j]
    t = state.motion.translations[42, j]
    flat = " ".join(text.split())
    assert "pre-rotation" in flat and "post-rotation" in flat and "Parent lfemur" in flat
    assert f"{(rotation @ t)[1]:.4f}" in text  # R t, the pre-rotation translation
    assert f"{t[1]:.4f}" in text  # t, the post-rotation translation
    assert f"{state.positions[42, j, 2]:.4f}" in text


def test_the_camera_follows_the_figure_or_stays(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    state, camera = studio.state, studio.view.scene.plotter.camera
    assert state.overlays["follow"]
    before = np.array(camera.focal_point)
    state.set_frame(240)
    moved = np.array(camera.focal_point) - before
    walked = state.positions[240].mean(axis=0) - state.positions[0].mean(axis=0)
    walked[1] = 0  # only along the floor (Y is up in the demo)
    np.testing.assert_allclose(moved, walked, atol=1e-9)
    studio.actions["overlay_follow"].setChecked(False)
    still = np.array(camera.focal_point)
    state.set_frame(400)
    np.testing.assert_allclose(np.array(camera.focal_point), still)


def test_the_joint_menu_opens_on_a_right_click(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    knee = studio.state.motion.joint_index("rfemur")
    click(qtbot, studio, joint_point(studio, knee), Qt.MouseButton.RightButton)
    menu = studio.joint_menu
    qtbot.waitUntil(menu.isVisible, timeout=2000)
    assert studio.state.selected == knee
    enabled = {a.text().replace("&", "") for a in menu.actions() if a.isEnabled() and a.text()}
    assert {"Shift root", "Split here", "Split all"} <= enabled and "Join to parent" not in enabled
    menu.close()


def test_the_alignment_dialog_adjusts_live_and_cancel_restores(qtbot, studio):
    from gmr_studio.app.dialogs.alignment_dialog import AlignmentDialog

    open_file(studio, demo_folder() / MOTION_FILE, demo_folder() / MARKERS_FILE)
    state = studio.state
    original = state.marker_overlay
    dialog = AlignmentDialog(state, studio)
    qtbot.addWidget(dialog)
    dialog.translation[0].setValue(float(original.alignment.transform.translation[0]) + 10.0)
    shift = dialog.translation[0].value() - original.alignment.transform.translation[0]  # 10, to the box's decimals
    assert shift == pytest.approx(10.0, abs=1e-3)
    np.testing.assert_allclose(state.marker_overlay.positions[:, :, 0], original.positions[:, :, 0] + shift, atol=1e-9)
    dialog.turn.setValue(90.0)  # a quarter turn about the up axis (Y) through the pelvis
    pivot = state.positions[state.frame, dialog.pivot_joint]
    turned = state.marker_overlay.positions[5, 0] - pivot
    before = original.positions[5, 0] + np.array([shift, 0, 0]) - pivot
    np.testing.assert_allclose(turned, [before[2], before[1], -before[0]], atol=1e-6)
    assert "adjusted by hand" in state.marker_overlay.alignment.method
    dialog.frames.setValue(3)
    np.testing.assert_allclose(state.marker_overlay.positions[0, :, 1], original.positions[3, :, 1], atol=1e-6)
    dialog.reject()
    np.testing.assert_array_equal(state.marker_overlay.positions, original.positions)  # NaN gaps compare equal
