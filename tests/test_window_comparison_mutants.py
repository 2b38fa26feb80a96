"""The comparison layers wired into the window (issue 24, the mutants of
app/window/comparison.py): the Layers and Error docks hidden until a layer is added (the
Error dock not for a marker layer, neither shown again for a mere change), where they go,
File > Compare with..., and the inspector's comparison section."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication, QDockWidget, QFrame, QMainWindow, QScrollArea

from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.window import layout
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.markers import read_markers
from tests import app_fixtures

studio = app_fixtures.studio
pytestmark = pytest.mark.gui


@pytest.fixture(scope="module")
def walk():
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
        assert dock.widget().minimumWidth() == layout.DOCK_MINIMUM == 100
        assert dock.toggleViewAction() in studio.view_menu.actions()
    assert studio.ghosts in studio.view.scene.drawables


def test_a_layer_shows_the_docks_once(studio, walk):
    layers_dock, error_dock = docks(studio)
    studio.state.open_document(Snapshot.of(walk), None)
    layers = studio.layers
    layers.add(Snapshot.of(walk), "twin.gmr")
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
    layers.add(Snapshot.of(walk), "again.gmr")  # after removals: a new layer again
    assert layers_dock.isVisible() and error_dock.isVisible()


def test_the_first_layer_shares_the_column_with_the_inspector_evenly(studio, walk, qtbot):
    layers_dock, _ = docks(studio)
    inspector = studio.inspector_dock
    studio.state.open_document(Snapshot.of(walk), None)
    QApplication.processEvents()
    studio.layers.add(Snapshot.of(walk), "twin.gmr")
    # once laid out: even (the Layers tab's bar, about 25 pixels, above its dock)
    qtbot.waitUntil(lambda: 0 <= inspector.height() - layers_dock.height() <= 40, timeout=3000)
    assert layers_dock.height() > 100
    studio.resizeDocks([layers_dock, inspector], [120, 400], Qt.Orientation.Vertical)  # the user's split
    qtbot.waitUntil(lambda: inspector.height() - layers_dock.height() > 150, timeout=3000)
    before = inspector.height()
    studio.layers.add(Snapshot.of(walk), "third.gmr")  # the Layers tab in sight already: left as it is
    qtbot.wait(50)
    assert inspector.height() == before
    layers_dock.hide()  # closed, then brought back by a new layer: shared evenly again
    studio.layers.add(Snapshot.of(walk), "fourth.gmr")
    qtbot.waitUntil(lambda: 0 <= inspector.height() - layers_dock.height() <= 40, timeout=3000)


def test_file_compare_with(studio):
    file_menu = studio.menuBar().actions()[0].menu()
    texts = [a.text().replace("&", "") for a in file_menu.actions()[:3]]
    assert texts[0].startswith("Open") and texts[1].startswith("Open recent") and texts[2] == "Compare with..."
    action = file_menu.actions()[2]
    assert action is studio.compare_action and action in QMainWindow.actions(studio)  # its shortcut works in the window
    assert action.shortcut().toString() == "Ctrl+Shift+O"


def test_the_inspector_follows_the_layers(studio, walk):
    state = studio.state
    state.open_document(Snapshot.of(walk), None)
    state.set_frame(10)
    state.select(0)
    assert "Compared with" not in studio.inspector.text()
    studio.layers.add(Snapshot.of(walk), "twin.gmr")
    text = studio.inspector.text()
    assert "Compared with twin.gmr" in text and "Position error" in text


def test_the_dock_and_the_menu_ask_for_a_file_and_the_error_view_toggles(studio, walk, monkeypatch):
    from gmr_studio.app.window import files

    asked = []
    monkeypatch.setattr(files.QFileDialog, "getOpenFileName", lambda *args: asked.append(args[1]) or ("", ""))
    studio.state.open_document(Snapshot.of(walk), None)
    studio.compare_action.trigger()
    studio.layers_panel.compare_requested.emit()
    assert asked == ["Compare with", "Compare with"]
    shown = studio.ghosts.show_errors
    studio.layers_panel.errors_toggled.emit(not shown)
    assert studio.ghosts.show_errors == (not shown)
