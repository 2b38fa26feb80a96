"""A C3D or TRC opened alone: the skeleton built from its markers is the document (issue 22, item 5).

Every shared marker file opens: with a known marker set as the built skeleton, its markers
and pelvis frames (and the lab model's joint centres as a layer when the file stores them);
without one, with a message naming what is missing and the document kept. Markers > Build
skeleton replaces a motion by the built skeleton as one undoable edit; the built skeleton is
edited like any motion.
"""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.model import commands
from gmr_studio.app.model.marker_document import FILE_SPACE, build_document, segment_frame_labels
from gmr_studio.app.model.marker_layers import MarkerLayer
from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.sets import identify_marker_set
from gmr_studio.core.shared_data import shared_data_dir
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
pytestmark = pytest.mark.gui

MARKER_FILES = sorted(
    str(p.relative_to(shared_data_dir()))
    for pattern in ("c3d/*.c3d", "trc/*.trc", "cmu/*/*.c3d")
    for p in shared_data_dir().glob(pattern)
) or ["c3d/c3dorg_s03_gait-pig.c3d"]  # data absent: one case, which skips saying so
PIG_LOWER = "c3d/c3dorg_s03_gait-pig.c3d"  # Plug-in Gait lower body with the model's PELO, LFEP...
BVH = "cmu/subject01/01_01.bvh"
C3D = "cmu/subject01/01_01.c3d"
SMALL_BVH = "bvh/bvh-python_test_freebvh.bvh"


def _expected(path):
    """The core's own verdict on the file: its built document, or the refusal's text."""
    markers = read_markers(path)
    try:
        return build_document(markers), None
    except OperationError as exc:
        return None, str(exc)


@pytest.mark.parametrize("relative", MARKER_FILES)
def test_every_shared_marker_file_opens(studio, relative):
    path = shared_path(relative)
    expected, refusal = _expected(path)
    messages: list[str] = []
    studio.state.message.connect(messages.append)
    studio.files.open_path(str(path), ask=False, wait=True)
    state = studio.state
    if expected is None:  # no known set, or one the skeleton cannot be built from: said, nothing opened
        assert state.motion is None and state.path is None
        assert refusal.split(" (nearest")[0] in messages[-1] and "open a motion" in messages[-1]
        if identify_marker_set(read_markers(path)) is None:
            assert "no known marker set fits these labels (nearest:" in messages[-1]
        return
    # the document is the built skeleton: the same motion the core builds, on the markers' frames
    motion = state.motion
    assert state.path == path and not state.modified and state.undo_stack.count() == 0
    assert motion.names == expected.snapshot.motion.names
    np.testing.assert_array_equal(state.positions, expected.snapshot.positions)
    assert motion.n_frames == expected.markers.n_frames and motion.frame_rate == pytest.approx(expected.markers.rate)
    # the markers in the file's own space (mm), and the pelvis frames the root was solved from
    overlay = state.marker_overlay
    assert overlay.alignment.method == FILE_SPACE and overlay.markers.labels == expected.markers.labels
    in_mm = expected.markers.in_units("mm").positions
    np.testing.assert_allclose(overlay.positions, in_mm, rtol=1e-12, atol=1e-9)
    assert state.pelvis is not None and np.isfinite(state.pelvis.origins).any()
    root = int(motion.roots[0])
    recovered = np.isfinite(state.pelvis.origins).all(axis=1)
    np.testing.assert_allclose(state.pelvis.origins[recovered], state.positions[recovered, root], atol=1e-6)
    # the joints are near the markers: each joint's nearest marker within 20 cm (the hip centres
    # lie deep in the pelvis), knees and ankles within 12 cm (median over frames; files with no
    # lateral knee or ankle marker in most frames place them from their clusters) ...
    # (frames where the markers give a pelvis: the others copy the nearest such frame)
    valid = expected.built.result.frame_valid
    assert valid.any() and state.frame == int(np.argmax(valid))  # shown from the first of them
    gaps = np.linalg.norm(state.positions[valid, :, None] - overlay.positions[valid, None], axis=-1)
    nearest = np.nanmedian(np.nanmin(np.where(np.isnan(gaps), np.inf, gaps), axis=2), axis=0)
    assert (nearest < 200.0).all(), dict(zip(motion.names, nearest.round(1)))
    distal = [motion.joint_index(n) for n in ("LKJC", "RKJC", "LAJC", "RAJC")]
    assert (nearest[distal] < 120.0).all(), dict(zip(motion.names, nearest.round(1)))
    # ... and on the joint centres the core placed from them (bone lengths fixed: within 3 cm)
    centres = expected.built.built.centres
    off = np.nanmedian(np.linalg.norm(state.positions[valid] - centres[valid], axis=-1), axis=0)
    assert (off < 30.0).all(), dict(zip(motion.names, off.round(1)))
    assert "skeleton built from marker set" in messages[-1]
    assert studio.actions["build_skeleton"].isEnabled()


def test_no_known_set_keeps_the_document(studio):
    open_file(studio, shared_path(SMALL_BVH))
    document = studio.state.snapshot
    messages: list[str] = []
    studio.state.message.connect(messages.append)
    studio.files.open_path(str(shared_path("c3d/ezc3d_Vicon.c3d")), ask=False, wait=True)
    assert studio.state.snapshot is document and studio.state.path.name == SMALL_BVH.rsplit("/", 1)[-1]
    text = messages[-1]
    assert "ezc3d_Vicon.c3d" in text and "no known marker set fits these labels" in text
    assert "missing" in text and "Markers > Add markers" in text


def test_build_skeleton_over_a_motion_and_undo(studio):
    open_file(studio, shared_path(BVH), markers=shared_path(C3D))
    state = studio.state
    state.set_frame(1500)
    before, overlay, pelvis = state.snapshot, state.marker_overlay, state.pelvis
    assert overlay is not None and overlay.alignment.method != FILE_SPACE
    studio.files.build_skeleton(wait=True)
    built = state.snapshot
    assert built is not before and "LHJC" in built.motion.names and state.undo_stack.count() == 1
    assert state.marker_overlay.alignment.method == FILE_SPACE and state.modified
    assert state.frame == 1500 and built.motion.n_frames == overlay.markers.n_frames
    # the built skeleton's left knee by the CMU set's LKNE marker (mm, the file's axes)
    lkne = state.marker_overlay.markers.labels.index("LKNE")
    knee = built.motion.joint_index("LKJC")
    assert np.linalg.norm(built.positions[1500, knee] - state.marker_overlay.positions[1500, lkne]) < 120.0
    assert "Build skeleton (cmu)" in studio.actions["undo"].toolTip()
    # undo: the very same motion, markers where they were, pelvis frames back
    state.undo_stack.undo()
    assert state.snapshot is before and not state.modified
    assert state.marker_overlay.alignment == overlay.alignment
    np.testing.assert_array_equal(state.marker_overlay.positions, overlay.positions)
    assert pelvis is not None and state.pelvis is not None
    np.testing.assert_array_equal(state.pelvis.rotations, pelvis.rotations)
    state.undo_stack.redo()
    assert state.snapshot is built and state.marker_overlay.alignment.method == FILE_SPACE


def test_the_built_skeleton_is_edited_like_any_motion(studio):
    open_file(studio, shared_path(PIG_LOWER))
    state = studio.state
    before = state.positions
    size = state.motion.size
    knee = state.motion.joint_index("LKJC")
    assert commands.shift_root_to(state, knee)
    assert int(state.motion.roots[0]) == knee
    np.testing.assert_allclose(state.positions, before, rtol=0, atol=1e-9 * size)
    assert commands.split_here(state, state.motion.joint_index("RAJC"))
    np.testing.assert_allclose(state.positions, before, rtol=0, atol=1e-9 * size)
    state.undo_stack.undo()
    state.undo_stack.undo()
    assert state.positions is before and not state.modified


def _pink(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels of the first layer colour (1, 0.45, 0.9), lit or shaded."""
    image = image.astype(int)
    return (image[..., 0] > 150) & (image[..., 1] < 0.75 * image[..., 0]) & (image[..., 2] > 0.7 * image[..., 0])


def test_the_lab_model_points_as_a_layer(studio):
    path = shared_path(PIG_LOWER)
    open_file(studio, path)
    QApplication.processEvents()
    state, layers = studio.state, studio.layers
    assert len(layers) == 1 and isinstance(layers[0], MarkerLayer)
    layer = layers[0]
    file_points = read_markers(path)
    # the model's joint centres and segment origins, at the file's numbers (mm, no alignment fitted)
    assert layer.markers.labels == ("PELO", "LFEO", "LFEP", "LTIO", "RFEO", "RFEP", "RTIO")
    for m, label in enumerate(layer.markers.labels):
        np.testing.assert_array_equal(layer.positions[:, m], file_points.positions[:, file_points.index(label)])
    # segment-frame points are neither markers nor layer points
    shown = set(state.marker_overlay.markers.labels)
    assert not shown & segment_frame_labels(file_points.labels) and "LTOE" in shown and "PELA" not in shown
    # our hip centres within a few centimetres of the lab model's (LFEP: its femur's proximal point)
    ours = state.positions[:, state.motion.joint_index("LHJC")]
    theirs = layer.positions[:, layer.markers.labels.index("LFEP")]
    assert np.nanmedian(np.linalg.norm(ours - theirs, axis=1)) < 30.0
    # drawn by the figure in the layer's colour, and gone when hidden
    state.set_frame(70)
    image = screen_image(studio)
    assert _pink(image).sum() > 20
    layers.set_visible(0, False)
    QApplication.processEvents()
    assert _pink(screen_image(studio)).sum() == 0


def _drop(studio, path) -> None:
    from PyQt6.QtCore import QMimeData, QPointF, Qt, QUrl
    from PyQt6.QtGui import QDropEvent

    data = QMimeData()
    data.setUrls([QUrl.fromLocalFile(str(path))])
    event = QDropEvent(
        QPointF(10, 10), Qt.DropAction.CopyAction, data, Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier
    )
    studio.dropEvent(event)


def test_drop_recent_files_menu_and_refinement(qtbot, studio):
    path = shared_path(PIG_LOWER)
    # dropped on an empty window: the marker file opens as the document (in the worker)
    _drop(studio, path)
    qtbot.waitUntil(lambda: studio.state.motion is not None and not studio.files.busy(), timeout=30000)
    state = studio.state
    assert state.path == path and "LHJC" in state.motion.names
    closed_form = state.positions
    # the Markers menu holds the marker actions, Build skeleton among them
    menus = {a.text().replace("&", ""): a.menu() for a in studio.menuBar().actions()}
    texts = [a.text().replace("&", "") for a in menus["Markers"].actions()]
    assert texts[:4] == ["Add markers...", "Marker alignment...", "Recover pelvis frames", "Remove markers"]
    assert "Build skeleton" in texts and "Refine the fit" in texts
    assert str(path.resolve()) == studio.files.recent_files()[0]
    # with Refine the fit (a setting), opening again refines: same skeleton, markers nearer
    studio.actions["refine_markers"].setChecked(True)
    assert studio.files.refine_markers()
    messages: list[str] = []
    state.message.connect(messages.append)
    studio.files.open_path(studio.files.recent_files()[0], ask=False, wait=True)
    assert state.motion.names == expected_names(path)
    assert not np.array_equal(state.positions, closed_form) and "refined: marker residual median" in messages[-1]
    offsets = state.motion.offsets
    np.testing.assert_array_equal(offsets, build_document(read_markers(path)).snapshot.motion.offsets)
    # a marker file dropped over a motion opened from another marker file opens in its place
    _drop(studio, shared_path("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d"))
    qtbot.waitUntil(lambda: state.path.name.startswith("c3dorg_s00") and not studio.files.busy(), timeout=30000)
    assert "LSJC" in state.motion.names


def expected_names(path) -> tuple[str, ...]:
    return build_document(read_markers(path)).snapshot.motion.names


def test_the_lab_layer_goes_with_its_document(studio):
    open_file(studio, shared_path(PIG_LOWER))
    assert len(studio.layers) == 1 and studio.layers[0].document_bound
    studio.files.compare_path(str(shared_path("trc/opensim-core_markers_walk.trc")), wait=True)
    assert len(studio.layers) == 2
    open_file(studio, shared_path(SMALL_BVH))  # another document: the lab's points of the C3D go, the rest stay
    assert [layer.name for layer in studio.layers] == ["opensim-core_markers_walk.trc"]
    assert studio.layers_panel.table.rowCount() == 2
    open_file(studio, shared_path("c3d/opensim-core_walking5.c3d"))
    assert [layer.name for layer in studio.layers][-1] == "opensim-core_walking5.c3d: lab model"
    assert studio.layers[-1].markers.labels == ("LAJC", "LHJC", "LKJC", "RAJC", "RHJC", "RKJC")


def test_the_inspector_says_how_a_built_joint_was_placed(studio):
    path = shared_path(PIG_LOWER)
    open_file(studio, path)
    state = studio.state
    state.select(state.motion.joint_index("LKJC"))
    built = build_document(read_markers(path)).built.built
    j = built.skeleton.names.index("LKJC")
    text = studio.inspector.text()
    assert f"Built from markers (set {built.set_match.definition.name})" in text
    assert f"placed by {built.methods['LKJC']}" in text
    assert f"bone {built.lengths[j]:.1f} mm" in text and f"RMS spread {built.spread[j]:.1f} mm" in text
    # a motion that is not the built skeleton says nothing of it
    open_file(studio, shared_path(SMALL_BVH))
    state.select(1)
    assert "Built from markers" not in studio.inspector.text()


def test_marker_layers_follow_build_skeleton_into_the_new_space(studio):
    open_file(studio, shared_path(BVH), markers=shared_path(C3D))
    state, layers = studio.state, studio.layers
    studio.files.compare_path(str(shared_path(C3D)), wait=True)  # the same markers as a layer
    layer = layers[0]
    np.testing.assert_array_equal(layer.positions, state.marker_overlay.positions)
    studio.files.build_skeleton(wait=True)
    # in the built skeleton's space (mm, the file's axes) the layer is aligned afresh: on the markers
    gap = np.linalg.norm(layer.positions - state.marker_overlay.positions, axis=-1)
    assert np.nanmedian(gap) < 0.05 * state.motion.size
    state.undo_stack.undo()
    gap = np.linalg.norm(layer.positions - state.marker_overlay.positions, axis=-1)
    assert np.nanmedian(gap) < 0.05 * state.motion.size
    # an edit that keeps the space keeps the layer's alignment
    alignment = layer.overlay.alignment
    assert commands.split_here(state, 1)
    assert layer.overlay.alignment == alignment  # the same rotation and offset arrays


def test_build_skeleton_shows_the_lab_points_of_the_markers(studio):
    open_file(studio, shared_path(PIG_LOWER))
    # the same file's markers over the built skeleton (as Add markers would put them), with its model points
    studio.files.add_markers_path(str(shared_path(PIG_LOWER)), wait=True)
    assert "LFEP" in studio.state.marker_overlay.markers.labels
    studio.files.build_skeleton(wait=True)
    studio.files.build_skeleton(wait=True)  # twice: still one layer of the file's lab points
    names = [layer.name for layer in studio.layers]
    assert names == [f"{PIG_LOWER.rsplit('/', 1)[-1]}: lab model"]
    assert "LFEP" not in studio.state.marker_overlay.markers.labels and studio.state.undo_stack.count() == 2


def test_build_skeleton_from_markers_of_no_known_set_is_refused(studio):
    from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder

    folder = demo_folder()
    open_file(studio, folder / MOTION_FILE, markers=folder / MARKERS_FILE)  # markers named like the joints
    state = studio.state
    document, overlay = state.snapshot, state.marker_overlay
    messages: list[str] = []
    state.message.connect(messages.append)
    studio.files.build_skeleton(wait=True)
    assert state.snapshot is document and state.marker_overlay is overlay and state.undo_stack.count() == 0
    assert messages[-1].startswith(f"Build skeleton from {MARKERS_FILE}: no known marker set fits these labels")
    assert "missing" in messages[-1]
