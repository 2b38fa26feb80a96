"""The alignment of a comparison layer, shown and adjusted from the Layers dock (and the CLI)."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.arguments import build_arguments
from gmr_studio.app.model import commands
from gmr_studio.app.screenshots import add_comparison
from gmr_studio.core.compare import compare_motions
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
pytestmark = pytest.mark.gui

BVH = "cmu/subject01/01_01.bvh"
AMC = "cmu/subject01/01_01.amc"
FRAME = 1518


def _changed_pixels(before: np.ndarray, after: np.ndarray) -> int:
    return int((np.abs(before.astype(int) - after.astype(int)).max(axis=-1) > 20).sum())


def _expected(studio, align: str, offset):
    """What core.compare gives for the layer with these parameters."""
    layer = studio.layers[0]
    return compare_motions(
        studio.state.snapshot.motion, layer.snapshot.motion, joint_map="cmu", offset=offset, align=align
    )


def _assert_same(layer, expected) -> None:
    c = layer.comparison
    np.testing.assert_array_equal(c.position_error, expected.position_error)
    np.testing.assert_array_equal(c.positions_b, expected.positions_b)
    np.testing.assert_array_equal(c.alignment.fit.rotation, expected.alignment.fit.rotation)
    np.testing.assert_array_equal(c.alignment.fit.translation, expected.alignment.fit.translation)
    assert c.alignment.fit.scale == expected.alignment.fit.scale
    assert c.alignment.kind == expected.alignment.kind
    assert c.alignment.offset_frames == expected.alignment.offset_frames
    # the ghost drawn is B as the comparison placed it
    np.testing.assert_allclose(layer.ghost[c.frames][:, c.index_b], c.positions_b, atol=1e-9, equal_nan=True)


def _ghost_bones(studio) -> np.ndarray:
    """(B, 3) the middles of the ghost's bones as drawn."""
    return np.array(studio.ghosts.ghosts[0][0].mesh.points)


def test_kind_and_offset_from_the_dock_recompute_the_layer(studio):
    open_file(studio, shared_path(BVH))
    state = studio.state
    state.set_frame(FRAME)
    studio.files.compare_path(str(shared_path(AMC)), joint_map="cmu", wait=True)
    QApplication.processEvents()
    document, history = state.snapshot, state.undo_stack.count()
    layer, box = studio.layers[0], studio.layers_panel.alignment
    assert box.index == 0 and studio.layers_panel.chosen_name.text() == "<b>01_01.amc</b>"
    assert box.kind.currentText() == "none" and box.auto.isChecked() and box.offset.value() == -1.0
    assert not box.offset.isEnabled()  # found: the number is shown, not editable
    _assert_same(layer, _expected(studio, "none", "auto"))
    ghost_none, image_none = _ghost_bones(studio), screen_image(studio)

    # rigid: as core.compare with align="rigid" at the offset found (-1)
    box.kind.setCurrentText("rigid")
    QApplication.processEvents()
    expected = _expected(studio, "rigid", -1.0)
    _assert_same(layer, expected)
    a = expected.alignment
    assert a.rms_before == pytest.approx(1.532, abs=1e-3) and a.rms_after == pytest.approx(1.265, abs=1e-3)
    assert layer.comparison.position.mean == pytest.approx(1.16, abs=0.01)  # docs/compare.md
    details = box.details.text()
    assert details.startswith(f"rigid: RMS {a.rms_before:.4g} -> {a.rms_after:.4g} file units")
    assert "offset -1 frames" in details and "translation (" in details
    assert "rotation:" in box.details.toolTip()
    assert "align rigid" in studio.layers_panel.chosen_text.text()
    # what is drawn follows: the ghost's bones, the error colours' scale, the error plot
    ghost_rigid = _ghost_bones(studio)
    pairs = studio.ghosts.ghosts[0][0].pairs
    np.testing.assert_allclose(ghost_rigid, layer.ghost[FRAME][pairs].mean(axis=1), atol=1e-9)
    moved = np.linalg.norm(ghost_rigid - ghost_none, axis=1)
    assert moved.max() > 0.5  # file units: the fit moves B by about its translation
    assert studio.ghosts.top == pytest.approx(expected.position.max)
    np.testing.assert_array_equal(studio.error_plot.plot.values[:, 0], expected.position.per_frame)
    assert _changed_pixels(image_none, screen_image(studio)) > 100

    # a given offset: auto off keeps -1 (now given), then +5 frames
    in_step = layer.comparison.position.mean
    box.auto.setChecked(False)
    assert box.offset.isEnabled() and layer.offset == -1.0 and not layer.auto_offset
    assert "(found)" not in studio.layers_panel.chosen_text.text()
    box.offset.setValue(5.0)
    QApplication.processEvents()
    expected = _expected(studio, "rigid", 5.0)
    _assert_same(layer, expected)
    assert layer.comparison.position.mean > in_step + 0.2  # six frames (50 ms) out of step
    np.testing.assert_allclose(_ghost_bones(studio), layer.ghost[FRAME][pairs].mean(axis=1), atol=1e-9)
    assert np.linalg.norm(_ghost_bones(studio) - ghost_rigid, axis=1).max() > 0.5

    # similarity, then auto again: the offset is found again (-1) and kept
    box.kind.setCurrentText("similarity")
    _assert_same(layer, _expected(studio, "similarity", 5.0))
    box.auto.setChecked(True)
    expected = _expected(studio, "similarity", "auto")
    _assert_same(layer, expected)
    assert layer.offset == -1.0 and layer.auto_offset and expected.alignment.fit.scale != 1.0
    assert box.offset.value() == -1.0 and "(found)" in studio.layers_panel.chosen_text.text()

    # never the document: same snapshot, same history, not modified
    assert state.snapshot is document and state.undo_stack.count() == history and not state.modified
    # an edit keeps the layer's alignment
    assert commands.shift_root_to(state, state.motion.joint_index("LeftHand"))
    assert layer.comparison.alignment.kind == "similarity" and layer.offset == -1.0
    assert box.kind.currentText() == "similarity"


def test_a_refused_alignment_keeps_the_layer(studio):
    """An offset that leaves no overlap cannot be fitted: the layer stays as it was."""
    open_file(studio, shared_path(BVH))
    studio.files.compare_path(str(shared_path(AMC)), joint_map="cmu", wait=True)
    layer, box = studio.layers[0], studio.layers_panel.alignment
    box.kind.setCurrentText("rigid")
    before = layer.comparison
    messages: list[str] = []
    studio.state.message.connect(messages.append)
    assert not studio.layers.set_alignment(0, offset=100000.0)
    assert layer.comparison is before and layer.offset == -1.0 and layer.auto_offset
    assert "Cannot align 01_01.amc that way" in messages[-1] and "share no time" in messages[-1]
    assert box.auto.isChecked() and box.offset.value() == -1.0


def test_command_line_alignment(studio):
    """--compare-align and --compare-offset reach the layer; bad values are refused."""
    open_file(studio, shared_path(BVH))
    flags = ["--map", "cmu", "--compare-align", "similarity", "--compare-offset", "2.5"]
    args = build_arguments().parse_args([str(shared_path(BVH)), "--compare", str(shared_path(AMC)), *flags])
    assert args.compare_align == "similarity" and args.compare_offset == 2.5
    assert add_comparison(studio, args) is None
    layer = studio.layers[0]
    assert layer.align == "similarity" and not layer.auto_offset
    _assert_same(layer, _expected(studio, "similarity", 2.5))
    assert build_arguments().parse_args(["A", "--compare", "B", "--compare-offset", "AUTO"]).compare_offset == "auto"
    for bad in (["--compare-align", "affine"], ["--compare-offset", "soon"], ["--compare-offset", "nan"]):
        with pytest.raises(SystemExit):
            build_arguments().parse_args(["A", "--compare", "B", *bad])
