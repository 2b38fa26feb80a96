"""Marker sets (TRC, C3D) as read-only comparison layers: listed, drawn, hidden, removed."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication, QMessageBox

from gmr_studio.app.model.marker_layers import MarkerLayer
from gmr_studio.core.markers import read_markers
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
pytestmark = pytest.mark.gui

BVH = "cmu/subject01/01_01.bvh"
C3D = "cmu/subject01/01_01.c3d"
FRAME = 1518


def _magenta(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels of the first layer colour (1, 0.45, 0.9), lit or shaded."""
    image = image.astype(int)
    return (image[..., 0] > 150) & (image[..., 1] < 0.75 * image[..., 0]) & (image[..., 2] > 0.7 * image[..., 0])


def _near_figure(studio, mask: np.ndarray) -> int:
    """Pixels of ``mask`` inside the figure's screen box (its joints), widened by a fifth."""
    joints = studio.view.scene.joint_screen_positions()[:, :2]
    low, high = joints.min(axis=0), joints.max(axis=0)
    margin = 0.2 * (high - low)
    (x0, y0), (x1, y1) = np.floor(low - margin).astype(int), np.ceil(high + margin).astype(int)
    return int(mask[max(y0, 0) : y1, max(x0, 0) : x1].sum())


def test_a_c3d_over_its_bvh_as_a_marker_layer(studio):
    open_file(studio, shared_path(BVH))
    state = studio.state
    state.set_frame(FRAME)
    document, history = state.snapshot, state.undo_stack.count()
    before = screen_image(studio)
    assert _magenta(before).sum() == 0
    studio.files.compare_path(str(shared_path(C3D)), wait=True)
    QApplication.processEvents()
    layers = studio.layers
    assert len(layers) == 1 and isinstance(layers[0], MarkerLayer)
    layer = layers[0]
    # listed like a motion layer, its alignment shown (controls for kind and offset hidden)
    panel = studio.layers_panel
    table = panel.table
    assert table.rowCount() == 2 and table.item(1, 2).text() == "01_01.c3d (markers, 0.74% computed)"
    assert panel.chosen_name.text() == "<b>01_01.c3d</b> (markers, 0.74% computed)"
    assert panel.chosen_text.text().startswith("42 markers, x0.01772")
    assert panel.opacity.value() == 90 and panel.remove_button.isVisible()
    box = panel.alignment
    assert box.controls.isHidden()
    assert "frame offset -1" in box.details.text()  # the BVH's added T-pose frame
    # read-only: the document, its history and the single marker overlay untouched
    assert state.snapshot is document and state.undo_stack.count() == history and not state.modified
    assert state.marker_overlay is None and studio.view.scene.markers is None
    # on the document's clock and in its space as the marker overlay puts them: the same numbers
    markers = read_markers(shared_path(C3D))
    state.set_markers(markers)
    np.testing.assert_array_equal(layer.positions, state.marker_overlay.positions)
    state.set_markers(None)
    # near the skeleton: LANK by the left ankle (47 mm = 0.83 units, PROVENANCE.md)
    lank = layer.markers.labels.index("LANK")
    ankle = document.positions[FRAME, document.motion.joint_index("LeftFoot")]
    assert np.linalg.norm(layer.positions[FRAME, lank] - ankle) < 1.5
    # drawn: the markers present at the frame, as spheres of the layer's colour by the figure
    present = np.isfinite(layer.positions[FRAME]).all(axis=1)
    spheres = studio.ghosts.ghosts[0][0]
    np.testing.assert_array_equal(spheres.drawn, present)
    np.testing.assert_array_equal(np.asarray(spheres.mesh.points)[present], layer.positions[FRAME][present])
    assert present.sum() >= 35
    shown = screen_image(studio)
    assert _near_figure(studio, _magenta(shown)) > 200
    assert _near_figure(studio, _magenta(shown)) >= 0.9 * _magenta(shown).sum()  # nearly all by the figure
    # the next frame moves them
    state.set_frame(FRAME + 30)
    present = np.isfinite(layer.positions[FRAME + 30]).all(axis=1)
    np.testing.assert_array_equal(spheres.drawn, present)
    np.testing.assert_array_equal(np.asarray(spheres.mesh.points)[present], layer.positions[FRAME + 30][present])
    state.set_frame(FRAME)
    # visibility off: no pixel of its colour; on: back; remove: gone from the list and the view
    layers.set_visible(0, False)
    assert _magenta(screen_image(studio)).sum() == 0
    table.cellWidget(1, 1).setChecked(True)  # the dock's "shown" box
    assert layer.visible and _near_figure(studio, _magenta(screen_image(studio))) > 200
    panel.remove_button.click()
    QApplication.processEvents()
    assert len(layers) == 0 and table.rowCount() == 1
    assert _magenta(screen_image(studio)).sum() == 0
    assert state.snapshot is document and state.undo_stack.count() == history


def test_a_trc_layer_and_a_shift_drop(studio, qtbot):
    """A TRC is a marker layer too; a marker file dropped with Shift becomes a layer, not
    the marker overlay."""
    from PyQt6.QtCore import QMimeData, QPointF, Qt, QUrl
    from PyQt6.QtGui import QDropEvent

    open_file(studio, shared_path(BVH))
    trc = shared_path("trc/opensim_gait2392_subject01_walk1.trc")
    studio.files.compare_path(str(trc), wait=True)
    layer = studio.layers[0]
    assert isinstance(layer, MarkerLayer) and layer.markers.n_markers == 41
    assert layer.positions.shape == (studio.state.motion.n_frames, 41, 3)
    data = QMimeData()
    data.setUrls([QUrl.fromLocalFile(str(shared_path(C3D)))])
    event = QDropEvent(
        QPointF(10, 10), Qt.DropAction.CopyAction, data, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.ShiftModifier
    )
    studio.dropEvent(event)
    qtbot.waitUntil(lambda: not studio.files.busy(), timeout=60000)
    QApplication.processEvents()
    assert [type(x).__name__ for x in studio.layers.layers] == ["MarkerLayer", "MarkerLayer"]
    assert studio.layers[1].name == "01_01.c3d" and studio.layers[1].colour != layer.colour
    assert studio.state.marker_overlay is None and studio.state.path.name == "01_01.bvh"


@pytest.mark.parametrize(
    ("name", "content"),
    [("broken.c3d", b"\x02\x50" + b"\x00" * 30), ("broken.trc", b"PathFileType\t4\t(X/Y/Z)\tbroken.trc\nnonsense\n")],
)
def test_a_bad_marker_file_shows_the_dialog_and_changes_nothing(studio, tmp_path, monkeypatch, name, content):
    open_file(studio, shared_path(BVH))
    state = studio.state
    document, history = state.snapshot, state.undo_stack.count()
    bad = tmp_path / name
    bad.write_bytes(content)
    dialogs: list[str] = []
    monkeypatch.setattr(QMessageBox, "exec", lambda box: dialogs.append(box.text()) or 0)
    studio.files.quiet = False  # the dialog the user would see (its exec recorded, not run)
    studio.files.compare_path(str(bad), wait=True)
    QApplication.processEvents()
    assert len(dialogs) == 1 and dialogs[0].startswith(f"Cannot read {name}")
    assert len(studio.layers) == 0 and studio.layers_panel.table.rowCount() == 1
    assert state.snapshot is document and state.undo_stack.count() == history and state.marker_overlay is None
