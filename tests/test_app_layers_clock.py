"""Comparison layers on another clock and across documents, without a window (issue 24): a
60 Hz layer over a 120 Hz document, the offset found again for another document and kept
once found."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.layers import Layers
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr

pytestmark = pytest.mark.gui  # a QApplication (signals)


@pytest.fixture
def walk():
    return load_gmr(demo_folder() / MOTION_FILE)


def every_other_frame(motion):
    """The motion at half its rate: its even frames, twice the frame time."""
    return motion.replace(
        rotations=motion.rotations[::2], translations=motion.translations[::2], frame_time=2 * motion.frame_time
    )


def state_with(qtbot, motion, name: str = "a.gmr") -> tuple[StudioState, Layers]:
    state = StudioState()
    state.open_document(Snapshot.of(motion), name)
    return state, Layers(state)


def test_a_60_hz_layer_over_a_120_hz_document_is_drawn_on_every_frame(qtbot, walk):
    # planted bug: B sampled at A's rate (a 60 Hz layer NaN on half the frames)
    assert walk.frame_rate == 120.0
    state, layers = state_with(qtbot, walk)
    half = every_other_frame(walk)
    layer = layers.add(Snapshot.of(half), "half.gmr", offset=0.0)
    ghost, positions = layer.ghost, state.positions
    assert ghost.shape == positions.shape
    # B's last sample is A's frame 478: only A's last frame lies beyond it
    last = 2 * (half.n_frames - 1)
    assert np.isfinite(ghost[: last + 1]).all() and np.isnan(ghost[last + 1 :]).all()
    # on A's even frames B has a sample: the ghost is A itself
    assert np.abs(ghost[: last + 1 : 2] - positions[: last + 1 : 2]).max() <= 1e-9 * walk.size
    # on odd frames it is halfway between B's neighbouring samples
    middle = 0.5 * (positions[0 : last - 1 : 2] + positions[2 : last + 1 : 2])
    assert np.abs(ghost[1:last:2] - middle).max() <= 1e-9 * walk.size
    assert np.isfinite(layer.comparison.position_error[: last + 1]).all()


def test_another_document_finds_the_layers_offset_again(qtbot, walk):
    # planted bug: the layer keeps the offset found for the previous document
    later = walk.frame_slice(slice(40, None))  # B starts at the walk's frame 40
    state, layers = state_with(qtbot, walk)
    layer = layers.add(Snapshot.of(later), "later.gmr")
    first = compare_motions(walk, later, offset="auto").alignment.offset_frames
    assert layer.offset == first and layer.auto_offset
    other = walk.frame_slice(slice(100, None))  # another document: the walk from frame 100
    state.open_document(Snapshot.of(other), "other.gmr")
    expected = compare_motions(other, later, offset="auto").alignment.offset_frames
    assert expected != first
    assert layer.offset == expected == layer.comparison.alignment.offset_frames
    assert layer.auto_offset


def test_the_offset_found_for_a_new_document_is_stored_and_kept_through_edits(qtbot, walk):
    # planted bug: recompute does not store the offset it found (it stays "auto")
    later = walk.frame_slice(slice(40, None))
    state, layers = state_with(qtbot, walk)
    layer = layers.add(Snapshot.of(later), "later.gmr", offset=5.0)  # given, not found
    assert layer.offset == 5.0 and not layer.auto_offset
    state.open_document(Snapshot.of(walk.frame_slice(slice(100, None))), "other.gmr")
    found = layer.comparison.alignment.offset_frames
    assert isinstance(layer.offset, float) and layer.offset == found and layer.auto_offset
    assert commands.split_here(state, state.motion.joint_index("ltibia"))  # an edit: recomputed
    assert layer.offset == found == layer.comparison.alignment.offset_frames
    assert "(found)" in layer.alignment_text and f"{found:+g} frames" in layer.alignment_text
