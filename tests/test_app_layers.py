"""Comparison layers in the window: ghosts, the error view, the error plot, live after edits;
the Layers and Error docks hidden until a layer is added (the Error dock not for a marker
layer, neither shown again for a mere change) and where they go, File > Compare with..., and
the inspector's comparison section."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication, QDockWidget, QFrame, QMainWindow, QScrollArea

from gmr_studio.app.model import commands
from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene.ghost_layer import error_colours
from gmr_studio.app.scene.vtk_parts import rgb_bytes
from gmr_studio.app.window import layout
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr, read_motion, write_motion
from gmr_studio.core.markers import read_markers
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
pytestmark = pytest.mark.gui

BVH = "cmu/subject01/01_01.bvh"
AMC = "cmu/subject01/01_01.amc"


def _compare(window, path, joint_map=None) -> None:
    window.files.compare_path(str(path), joint_map=joint_map, wait=True)
    QApplication.processEvents()


def _changed_pixels(before: np.ndarray, after: np.ndarray) -> int:
    return int((np.abs(before.astype(int) - after.astype(int)).max(axis=-1) > 20).sum())


def test_a_first_layer_shares_the_right_column_with_the_inspector(studio, qtbot):
    open_file(studio, shared_path(BVH))
    studio.state.select(studio.state.motion.joint_index("LeftHand"))
    inspector = studio.inspector_dock
    _compare(studio, shared_path(AMC), "cmu")
    layers_dock = studio.layers_panel.parentWidget()
    while not hasattr(layers_dock, "setFloating"):  # the panel sits in a scroll area in its dock
        layers_dock = layers_dock.parentWidget()
    # even, the tab bar under the Layers tab counted with it (about 25 pixels)
    qtbot.waitUntil(lambda: abs(layers_dock.height() - inspector.height()) <= 40, timeout=3000)
    column = layers_dock.height() + inspector.height()
    assert inspector.height() >= 0.45 * column and layers_dock.isVisible()
    table = studio.layers_panel.table  # the layer's row in sight, under the document's
    assert table.rowCount() == 2 and table.visualRect(table.model().index(1, 2)).bottom() <= table.viewport().height()
    assert studio.layers_panel.minimumSizeHint().height() > layers_dock.height() - 40  # the rest scrolls
    _compare(studio, shared_path(AMC), "cmu")  # a second layer: the column as the user left it
    QApplication.processEvents()
    assert abs(layers_dock.height() - inspector.height()) <= 40


def test_bvh_against_its_amc_as_a_ghost(studio):
    open_file(studio, shared_path(BVH))
    document = studio.state.snapshot
    studio.state.set_frame(1518)
    _compare(studio, shared_path(AMC), "cmu")
    assert studio.layers_panel.isVisible() and studio.error_plot.isVisible()  # shown once a layer is added
    layers = studio.layers
    assert len(layers) == 1 and studio.state.snapshot is document  # the document untouched
    layer = layers[0]
    c = layer.comparison
    # what gmr compare measures (docs/compare.md): 28 pairs, offset -1 found, MPJPE 1.0641
    a, b = read_motion(shared_path(BVH)), read_motion(shared_path(AMC))
    expected = compare_motions(a, b, joint_map="cmu", offset="auto")
    assert c.n_pairs == expected.n_pairs == 28
    assert c.alignment.offset_frames == -1.0
    assert c.position.mean == pytest.approx(expected.position.mean, rel=1e-9)
    assert c.position.mean == pytest.approx(1.0641, abs=1e-4)
    # the ghost is B on A's frames: its matched joints are the comparison's B positions
    rows = c.frames
    np.testing.assert_allclose(layer.ghost[rows][:, c.index_b], c.positions_b, atol=1e-9, equal_nan=True)
    assert np.isnan(layer.ghost[0]).all()  # A's frame 0 is before B's first frame (offset -1)
    # the dock: the document and the layer, with the alignment
    table = studio.layers_panel.table
    assert table.rowCount() == 2 and table.item(1, 2).text() == "01_01.amc"
    assert "offset -1 frames (found)" in studio.layers_panel.chosen_text.text()
    # pixels: the ghost and the error view change the picture; hiding the layer takes it away
    shown = screen_image(studio)
    magenta = (shown[..., 0] > 170) & (shown[..., 1] < 140) & (shown[..., 2] > 150)
    assert magenta.sum() > 12  # the ghost's own colour (its bones where they leave A's: 26 pixels)
    layers.set_visible(0, False)
    without = screen_image(studio)  # no ghost, no error view
    assert _changed_pixels(without, shown) > 300
    magenta = (without[..., 0] > 170) & (without[..., 1] < 140) & (without[..., 2] > 150)
    assert magenta.sum() == 0
    layers.set_visible(0, True)
    assert _changed_pixels(shown, screen_image(studio)) < 10
    layers.set_opacity(0, 1.0)
    assert _changed_pixels(shown, screen_image(studio)) > 20
    layers.remove(0)
    assert len(layers) == 0 and table.rowCount() == 1
    assert _changed_pixels(without, screen_image(studio)) < 10


def test_error_view_inspector_and_plot(studio, qtbot):
    open_file(studio, shared_path(BVH))
    _compare(studio, shared_path(AMC), "cmu")
    layer, state = studio.layers[0], studio.state
    c = layer.comparison
    frame = 1518
    state.set_frame(frame)
    # joint colours: the error recomputed here from the document and the ghost
    positions = state.snapshot.positions[frame, c.index_a]
    errors = np.linalg.norm(positions - layer.ghost[frame][c.index_b], axis=1)
    np.testing.assert_allclose(c.position_error[c.row_of_frame(frame)], errors, atol=1e-9)
    ghosts = studio.ghosts
    assert ghosts.top == pytest.approx(c.position.max)
    shown = np.asarray(studio.view.scene.figure.parts["joints"].mesh.point_data["colors"])[ghosts.error_joints]
    np.testing.assert_array_equal(shown, rgb_bytes(error_colours(errors, c.position.max)))
    # the worst joint of the frame is red, the legs (agreeing to 1e-4) green
    worst = int(np.argmax(errors))
    assert shown[worst, 0] > 200 and shown[worst, 1] < 60
    foot = c.names_a.index("LeftFoot")
    assert shown[foot, 1] > 150 and shown[foot, 0] < 80
    # the legend: a colour bar with red and green pixels at the view's right; gone when switched off
    image = screen_image(studio)
    right = image[:, int(0.8 * image.shape[1]) :].astype(int)
    red = (right[..., 0] > 200) & (right[..., 1] < 80) & (right[..., 2] < 80)
    assert red.sum() > 100
    studio.layers_panel.errors.setChecked(False)
    right = screen_image(studio)[:, int(0.8 * image.shape[1]) :].astype(int)
    assert ((right[..., 0] > 200) & (right[..., 1] < 80) & (right[..., 2] < 80)).sum() < 5
    studio.layers_panel.errors.setChecked(True)
    # the inspector: both positions, the error and the rotation error of the selected joint
    hand = state.motion.joint_index("LeftHand")
    state.select(hand)
    pair = list(c.index_a).index(hand)
    text = " ".join(studio.inspector.text().split())
    assert "Compared with 01_01.amc" in text and f"Match {c.names_b[pair]}" in text
    assert f"Position error {errors[pair]:.4g} file units" in text
    assert f"Rotation error {c.rotation_error[c.row_of_frame(frame), pair]:.4g} deg" in text
    # the error plot: MPJPE and the selected joint, cursor at the frame, a click seeks
    plot = studio.error_plot.plot
    assert plot.columns == ("MPJPE", "LeftHand")
    np.testing.assert_allclose(plot.values[:, 0], c.position.per_frame, equal_nan=True)
    np.testing.assert_allclose(plot.values[:, 1], c.position_error[:, pair], equal_nan=True)
    assert plot.cursor_frame == frame
    plot.frame_requested.emit(400)
    assert state.frame == 400 and plot.cursor_frame == 400
    picture = plot.plot_widget.grab().toImage()
    colours = {picture.pixelColor(x, y).name() for x in range(0, picture.width(), 2) for y in range(picture.height())}
    assert "#4e79a7" in colours or any(_near(c_, (0x4E, 0x79, 0xA7)) for c_ in colours)


def _near(name: str, rgb: tuple[int, int, int]) -> bool:
    value = tuple(int(name[i : i + 2], 16) for i in (1, 3, 5))
    return max(abs(a - b) for a, b in zip(value, rgb)) < 25


def test_edits_keep_the_comparison_live(studio):
    """A motion against itself: zero everywhere, also after shift root, split and join."""
    open_file(studio, shared_path(BVH))
    _compare(studio, shared_path(BVH))
    state, layers = studio.state, studio.layers
    size = state.motion.size
    assert layers[0].comparison.alignment.offset_frames == 0.0
    assert layers[0].comparison.position.max <= 1e-9 * size
    assert np.nanmax(layers[0].comparison.rotation_error) <= 1e-6  # degrees
    for edit, joint in (
        (commands.shift_root_to, "LeftHand"),
        (commands.split_here, "Spine1"),
        (commands.join_to_parent, "Spine1"),
        (commands.shift_root_to, "RightFoot"),
    ):
        before = layers[0].comparison
        assert edit(state, state.motion.joint_index(joint))
        c = layers[0].comparison
        assert c is not before  # recomputed
        assert c.n_pairs == state.motion.n_joints  # every joint still pairs by name
        assert c.position.max <= 1e-9 * size
    state.undo_stack.undo()
    assert layers[0].comparison.position.max <= 1e-9 * size
    np.testing.assert_array_equal(studio.error_plot.plot.values[:, 0] <= 1e-9 * size, True)


def test_a_bad_file_leaves_everything_as_it_was(studio, tmp_path):
    open_file(studio, shared_path(BVH))
    document = studio.state.snapshot
    bad = tmp_path / "broken.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n")
    messages: list[str] = []
    studio.state.message.connect(messages.append)
    _compare(studio, bad)
    assert len(studio.layers) == 0 and studio.state.snapshot is document
    assert any("broken.bvh" in m for m in messages)
    # no joint in common: refused with a message, nothing added
    motion = document.motion.frame_slice(slice(0, 30))
    renamed = dataclasses.replace(motion, names=tuple(f"other_{n}" for n in motion.names))
    write_motion(renamed, tmp_path / "renamed.gmr")
    _compare(studio, tmp_path / "renamed.gmr")
    assert len(studio.layers) == 0 and studio.state.snapshot is document
    assert "Cannot compare with renamed.gmr: no joints matched" in messages[-1]


def test_a_shift_drop_compares_with_the_shipped_map(studio, qtbot):
    """A file dropped with Shift is compared, not opened; without a map, the shipped map
    that pairs the most joints is used."""
    from PyQt6.QtCore import QMimeData, QPointF, Qt, QUrl
    from PyQt6.QtGui import QDropEvent

    open_file(studio, shared_path(BVH))
    document = studio.state.snapshot
    data = QMimeData()
    data.setUrls([QUrl.fromLocalFile(str(shared_path(AMC)))])
    event = QDropEvent(
        QPointF(10, 10), Qt.DropAction.CopyAction, data, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.ShiftModifier
    )
    studio.dropEvent(event)
    qtbot.waitUntil(lambda: not studio.files.busy(), timeout=60000)
    QApplication.processEvents()
    assert studio.state.snapshot is document and studio.state.path.name == "01_01.bvh"
    assert len(studio.layers) == 1
    assert studio.layers[0].joint_map == "cmu" and studio.layers[0].comparison.n_pairs == 28


def test_command_line_compare_to_a_window_screenshot(tmp_path):
    """gmr-studio A --compare B --map cmu --screenshot OUT [--window]: the ghost is in the
    picture (window and view alone); an unreadable B is refused with status 2."""
    import subprocess
    import sys

    from tests.test_app_cli import read_png

    studio_cmd = [sys.executable, "-m", "gmr_studio.app.main", str(shared_path(BVH))]
    out = tmp_path / "compare.png"
    options = ["--map", "cmu", "--screenshot", str(out), "--window", "--size", "900x600", "--frame", "1518"]
    result = subprocess.run(
        [*studio_cmd, "--compare", str(shared_path(AMC)), *options], capture_output=True, text=True, timeout=180
    )
    assert result.returncode == 0, result.stderr
    image = read_png(out).astype(int)
    magenta = (image[..., 0] > 170) & (image[..., 1] < 140) & (image[..., 2] > 150)
    assert magenta.sum() > 4  # the ghost's bones where they leave the document's figure (10 pixels)
    # off screen (the view alone, no window): the ghost and the error legend are drawn too
    view_only = tmp_path / "compare-view.png"
    view_options = ["--map", "cmu", "--screenshot", str(view_only), "--size", "900x600", "--frame", "1518"]
    result = subprocess.run(
        [*studio_cmd, "--compare", str(shared_path(AMC)), *view_options], capture_output=True, text=True, timeout=180
    )
    assert result.returncode == 0, result.stderr
    image = read_png(view_only).astype(int)
    assert image.shape[:2] == (600, 900)
    magenta = (image[..., 0] > 170) & (image[..., 1] < 140) & (image[..., 2] > 150)
    red = (image[..., 0] > 200) & (image[..., 1] < 80) & (image[..., 2] < 80)  # the worst joints, the legend's top
    assert magenta.sum() > 30 and red.sum() > 30, (magenta.sum(), red.sum())
    bad = tmp_path / "broken.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n")
    result = subprocess.run([*studio_cmd, "--compare", str(bad), *options], capture_output=True, text=True, timeout=180)
    assert result.returncode == 2 and "--compare" in result.stderr and "broken.bvh" in result.stderr


@pytest.mark.parametrize("width", [1280, 1600])
def test_the_layers_dock_shows_its_names_and_text_whole_in_the_side_column(studio, qtbot, width):
    """Issue 40.8b: in the side column of a window 1280 (and 1600) pixels wide, nothing in
    the Layers dock runs past its right edge: every name is whole in its cell (wrapped if
    need be), the chosen layer's name and alignment wrap in the column, and the dock never
    needs scrolling sideways."""
    from PyQt6.QtCore import QRect, Qt
    from PyQt6.QtWidgets import QScrollArea

    studio.resize(width, 820)
    studio.default_layout()
    open_file(studio, shared_path(BVH))
    _compare(studio, shared_path(AMC), "cmu")
    panel = studio.layers_panel
    area = panel.parentWidget()
    while not isinstance(area, QScrollArea):
        area = area.parentWidget()
    qtbot.wait(50)  # the column laid out, the rows fitted to their names
    assert area.horizontalScrollBar().maximum() == 0
    assert panel.width() <= area.viewport().width()
    table = panel.table
    names = [table.item(row, 2) for row in range(table.rowCount())]
    assert [n.text() for n in names] == ["01_01.bvh (the document)", "01_01.amc"]
    for name in names:
        cell = table.visualItemRect(name)
        needed = table.fontMetrics().boundingRect(
            QRect(0, 0, cell.width() - 8, 10_000), Qt.TextFlag.TextWordWrap, name.text()
        )
        assert needed.width() <= cell.width() - 8 and needed.height() <= cell.height()
        assert cell.right() <= table.viewport().width()
    for label in (panel.chosen_name, panel.chosen_text, panel.summary, panel.alignment.details):
        assert label.wordWrap() and label.geometry().right() <= panel.width()
        assert label.heightForWidth(label.width()) <= label.height()
    assert "01_01.amc" in panel.chosen_name.text() and "offset -1 frames" in panel.chosen_text.text()


def test_an_edit_that_drops_joints_under_an_error_view_colours_the_new_documents_joints(studio):
    """Removing dummy joints (38 joints become 31) while a comparison's error view is shown:
    the view is drawn for the new document before the layer is compared with it, and must
    not colour joints by the old document's indices (an IndexError in the event loop, which
    pytest-qt reports); once compared, the error view colours the new document's joints."""
    from gmr_studio.app.model import commands

    open_file(studio, shared_path(BVH))
    _compare(studio, shared_path(AMC), "cmu")
    state = studio.state
    state.set_frame(1518)
    before = state.motion.n_joints
    commands.remove_dummy_joints(state)
    QApplication.processEvents()
    layer = studio.layers[0]
    assert state.motion.n_joints < before and layer.compared_with is state.snapshot
    np.testing.assert_array_equal(studio.ghosts.error_joints, layer.comparison.index_a)
    assert studio.ghosts.error_joints.max() < state.motion.n_joints
    image = screen_image(studio)
    assert ((image[..., 0] > 200) & (image[..., 1] < 80) & (image[..., 2] < 80)).sum() > 0  # the worst in red


# ------------------------------------------------------------ the window's wiring
@pytest.fixture(scope="module")
def short_walk():
    return load_gmr(demo_folder() / MOTION_FILE).frame_slice(slice(0, 60))


def docks(window) -> tuple[QDockWidget, QDockWidget]:
    return window.findChild(QDockWidget, "layers"), window.findChild(QDockWidget, "error")


def test_the_docks_made_hidden_and_where_they_go(studio):
    layers_dock, error_dock = docks(studio)
    scroll = layers_dock.widget()  # the Layers panel scrolls, grown to its dock's size
    assert isinstance(scroll, QScrollArea) and scroll.widget() is studio.layers_panel
    assert scroll.widgetResizable() and scroll.frameShape() == QFrame.Shape.NoFrame
    assert error_dock.widget() is studio.error_plot
    assert studio.error_dock is error_dock and studio.layers_panel.layers is studio.layers
    assert layers_dock.isHidden() and error_dock.isHidden()
    assert studio.dockWidgetArea(layers_dock) == Qt.DockWidgetArea.RightDockWidgetArea
    assert studio.dockWidgetArea(error_dock) == Qt.DockWidgetArea.BottomDockWidgetArea
    for dock in (layers_dock, error_dock):
        assert dock.widget().minimumWidth() == layout.DOCK_MINIMUM
        assert dock.toggleViewAction() in studio.view_menu.actions()
    assert studio.ghosts in studio.view.scene.drawables


def test_a_layer_shows_the_docks_once(studio, short_walk):
    layers_dock, error_dock = docks(studio)
    studio.state.open_document(Snapshot.of(short_walk), None)
    layers = studio.layers
    layers.add(Snapshot.of(short_walk), "twin.gmr")
    QApplication.processEvents()
    assert layers_dock.isVisible() and error_dock.isVisible()
    assert layers_dock in studio.tabifiedDockWidgets(studio.forest_dock)  # a tab of the Forest
    layers_dock.hide()
    error_dock.hide()
    layers.set_alignment(0, kind="rigid")  # a change, not a new layer: the docks stay hidden
    layers.set_opacity(0, 0.5)
    assert layers_dock.isHidden() and error_dock.isHidden()
    layers.add_markers(read_markers(demo_folder() / MARKERS_FILE), "walk.trc")  # no error to plot
    assert layers_dock.isVisible() and error_dock.isHidden()
    layers_dock.hide()
    layers.remove(1)
    layers.remove(0)
    assert layers_dock.isHidden()
    layers.add(Snapshot.of(short_walk), "again.gmr")  # after removals: a new layer again
    assert layers_dock.isVisible() and error_dock.isVisible()


def test_the_first_layer_shares_the_column_with_the_inspector_evenly(studio, short_walk, qtbot):
    layers_dock, _ = docks(studio)
    inspector = studio.inspector_dock
    studio.state.open_document(Snapshot.of(short_walk), None)
    QApplication.processEvents()
    studio.layers.add(Snapshot.of(short_walk), "twin.gmr")
    # once laid out: even (the Layers tab's bar, about 25 pixels, above its dock)
    qtbot.waitUntil(lambda: 0 <= inspector.height() - layers_dock.height() <= 40, timeout=3000)
    assert layers_dock.height() > 100
    studio.resizeDocks([layers_dock, inspector], [120, 400], Qt.Orientation.Vertical)  # the user's split
    qtbot.waitUntil(lambda: inspector.height() - layers_dock.height() > 150, timeout=3000)
    before = inspector.height()
    studio.layers.add(Snapshot.of(short_walk), "third.gmr")  # the Layers tab in sight already: left as it is
    qtbot.wait(50)
    assert inspector.height() == before
    layers_dock.hide()  # closed, then brought back by a new layer: shared evenly again
    studio.layers.add(Snapshot.of(short_walk), "fourth.gmr")
    qtbot.waitUntil(lambda: 0 <= inspector.height() - layers_dock.height() <= 40, timeout=3000)


def test_file_compare_with(studio):
    file_menu = studio.menuBar().actions()[0].menu()
    texts = [a.text().replace("&", "") for a in file_menu.actions()[:3]]
    assert texts[0].startswith("Open") and texts[1].startswith("Open recent") and texts[2] == "Compare with..."
    action = file_menu.actions()[2]
    assert action is studio.compare_action and action in QMainWindow.actions(studio)  # its shortcut works in the window
    assert action.shortcut().toString() == "Ctrl+Shift+O"


def test_the_inspector_follows_the_layers(studio, short_walk):
    state = studio.state
    state.open_document(Snapshot.of(short_walk), None)
    state.set_frame(10)
    state.select(0)
    assert "Compared with" not in studio.inspector.text()
    studio.layers.add(Snapshot.of(short_walk), "twin.gmr")
    text = studio.inspector.text()
    assert "Compared with twin.gmr" in text and "Position error" in text


def test_the_dock_and_the_menu_ask_for_a_file_and_the_error_view_toggles(studio, short_walk, monkeypatch):
    from gmr_studio.app.window import files

    asked = []
    monkeypatch.setattr(files.QFileDialog, "getOpenFileName", lambda *args: asked.append(args[1]) or ("", ""))
    studio.state.open_document(Snapshot.of(short_walk), None)
    studio.compare_action.trigger()
    studio.layers_panel.compare_requested.emit()
    assert asked == ["Compare with", "Compare with"]
    shown = studio.ghosts.show_errors
    studio.layers_panel.errors_toggled.emit(not shown)
    assert studio.ghosts.show_errors == (not shown)
