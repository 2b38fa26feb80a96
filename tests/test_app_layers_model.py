"""Comparison layers without a window (app/model/layers.py): the joint map guessed for a
dropped file, layers added, re-aligned, recoloured and removed, the dock's lines, marker
layers, layers kept or dropped when the document changes, a 60 Hz layer over a 120 Hz
document, and the offset found again for another document and kept once found."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.layers import (
    GHOST_OPACITY,
    LAYER_COLOURS,
    ComparisonLayer,
    Layers,
    best_joint_map,
    compare_layer,
)
from gmr_studio.app.model.marker_layers import MARKER_LAYER_OPACITY, MarkerLayer
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.app.model.tree_colors import PALETTE
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.compare.clock import ghost_positions
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.jointmap import load_joint_map
from gmr_studio.core.markers import read_markers
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import UNITS

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


@pytest.fixture(scope="module")
def short_walk():
    """The demo walk's first second (120 frames)."""
    return load_gmr(demo_folder() / MOTION_FILE).frame_slice(slice(0, 120))


def as_bvh(motion):
    """The motion with the CMU BVH names of the joints the shipped map pairs (the others keep
    their ASF names)."""
    to_bvh = load_joint_map("cmu").b_to_a
    return motion.replace(names=tuple(to_bvh.get(name, name) for name in motion.names))


def with_layers(motion=None) -> tuple[StudioState, Layers, list[str], list[str]]:
    """A state (with ``motion`` open, if any), its layers, and what they said: the messages
    and the signals, in order."""
    state = StudioState()
    if motion is not None:
        state.open_document(Snapshot.of(motion), "a.gmr")
    layers = Layers(state)
    said, signals = [], []
    state.message.connect(said.append)
    layers.changed.connect(lambda: signals.append("changed"))
    layers.appearance_changed.connect(lambda index: signals.append(f"appearance {index}"))
    return state, layers, said, signals


def test_the_map_guessed_for_a_dropped_file(qtbot, short_walk):
    same = Snapshot.of(short_walk)
    assert best_joint_map(same, same) is None  # the map pairs as many, not more: by name
    bvh = Snapshot.of(as_bvh(short_walk))
    assert best_joint_map(same, bvh) == "cmu" and best_joint_map(bvh, same) == "cmu"
    stranger = Snapshot.of(short_walk.replace(names=tuple(f"x{j}" for j in range(short_walk.n_joints))))
    assert best_joint_map(same, stranger) is None  # nothing pairs either way


def test_a_layer_is_its_comparison_and_its_ghost(qtbot, short_walk):
    state, layers, said, signals = with_layers(short_walk)
    later = short_walk.frame_slice(slice(10, None))
    layer = layers.add(Snapshot.of(as_bvh(later)), "/some/where/later.bvh", offset=-10.0, align="rigid")
    assert signals == ["changed"] and said == []
    assert layer.name == "later.bvh" and layer.joint_map == "cmu" and layer.colour == LAYER_COLOURS[0]
    assert layer.align == "rigid" and layer.offset == -10.0 and not layer.auto_offset
    assert layer.visible and layer.opacity == GHOST_OPACITY
    expected = compare_motions(short_walk, as_bvh(later), joint_map="cmu", offset=-10.0, align="rigid")
    np.testing.assert_array_equal(layer.comparison.position_error, expected.position_error)
    assert layer.comparison.label_b == "later.bvh" and layer.comparison.names_a == short_walk.names
    ghost = ghost_positions(Snapshot.of(as_bvh(later)).positions, 120, 120.0, 120.0, expected.alignment)
    np.testing.assert_array_equal(layer.ghost, ghost)
    assert layer.ghost.shape == (120, short_walk.n_joints, 3)
    np.testing.assert_allclose(layer.ghost[10:], state.positions[10:], atol=1e-9)  # B is A from frame 10
    assert np.isnan(layer.ghost[:10]).all()
    again, ghost_again = compare_layer(state.snapshot, layer)
    np.testing.assert_array_equal(ghost_again, layer.ghost)
    np.testing.assert_array_equal(again.position_error, layer.comparison.position_error)
    assert layers.active is layer and len(layers) == 1 and layers[0] is layer
    found = layers.add(Snapshot.of(later), "later.gmr", joint_map="cmu")  # the map given is kept
    assert found.auto_offset and found.offset == pytest.approx(-10.0) and isinstance(found.offset, float)
    assert found.joint_map == "cmu" and found.colour == LAYER_COLOURS[1] and layers.active is found
    assert found.offset == found.comparison.alignment.offset_frames
    by_name = layers.add(Snapshot.of(later), "same.gmr", offset=-10.0)
    assert by_name.joint_map is None and not by_name.auto_offset


def test_the_dock_lines(qtbot, short_walk):
    bare = ComparisonLayer(Snapshot.of(short_walk), "b.gmr", LAYER_COLOURS[0])
    assert bare.alignment_text == "not compared" and bare.alignment_details == ("not compared", "")
    assert bare.auto_offset and bare.offset == "auto" and bare.align == "none"
    twin = ComparisonLayer(bare.snapshot, "b.gmr", LAYER_COLOURS[0])  # compared by identity, hashable
    assert bare == bare and bare != twin and len({bare, twin}) == 2
    state, layers, _, _ = with_layers(short_walk)
    inches = short_walk.replace(facts=FileFacts(unit=UNITS["in"]))
    document = short_walk.replace(facts=FileFacts(unit=UNITS["cm"]))
    state.open_document(Snapshot.of(document), "a.gmr")
    layer = layers.add(Snapshot.of(inches), "b.gmr", offset=2.0, align="similarity")
    a = layer.comparison.alignment
    assert layer.alignment_text == f"offset +2 frames, x2.54 units, align similarity, RMS {a.rms_after:.3g}"
    line, tooltip = layer.alignment_details
    assert line.startswith(f"similarity: RMS {a.rms_before:.4g} -> {a.rms_after:.4g} cm\nturn ")
    assert f"scale {a.fit.scale:.6g}, offset +2 frames (+0.01667 s), units x2.54" in line
    assert "translation (" + " ".join(format(float(v), ".4g") for v in a.fit.translation) + ")" in line
    assert "  [+1 +0 +0]\n  [+0 +1 +0]\n  [+0 +0 +1]" in tooltip  # the up rotation (Y up both)
    assert "offset: +2 frames = +0.0166667 s (given)\n" in tooltip
    assert f"scale: {a.fit.scale:.9g}\nunits scale: 2.54\n" in tooltip and tooltip.endswith("\n".join(a.notes))
    rows = tooltip.split("rotation:\n")[1].split("\ntranslation")[0].splitlines()
    shown = [[float(v) for v in row.strip(" []").split()] for row in rows]
    np.testing.assert_allclose(shown, a.fit.rotation, atol=1e-6)
    found = layers.add(Snapshot.of(short_walk), "c.gmr", offset="auto")
    assert found.alignment_text.startswith("offset +0 frames (found), align none, RMS ")
    assert "(found)\n" in found.alignment_details[1] and ", x" not in found.alignment_text


def test_colours_cycle_and_appearance_is_clamped(qtbot, short_walk):
    # RGB in [0, 1], four of them, and a ghost seen through (within the opacity a dock may set)
    assert len(set(LAYER_COLOURS)) == 4 and all(0.0 <= c <= 1.0 for colour in LAYER_COLOURS for c in colour)
    assert all(len(colour) == 3 for colour in LAYER_COLOURS) and 0.05 <= GHOST_OPACITY < 1.0
    # none of them a tree colour of the document: each lighter (mean of RGB) than any tree colour
    assert min(np.mean(LAYER_COLOURS, axis=1)) > max(np.mean(PALETTE, axis=1)) + 0.03
    _, layers, _, signals = with_layers(short_walk)
    for k in range(len(LAYER_COLOURS) + 1):
        layers.add(Snapshot.of(short_walk), f"{k}.gmr", offset=0.0)
    assert [layer.colour for layer in layers.layers] == [*LAYER_COLOURS, LAYER_COLOURS[0]]
    signals.clear()
    layers.set_visible(1, 0)
    layers.set_opacity(2, 0.0)
    layers.set_opacity(3, 7.0)
    layers.set_opacity(0, 0.3)
    layers.set_colour(4, (1, 0, 0.5))
    assert layers[1].visible is False and layers[2].opacity == 0.05 and layers[3].opacity == 1.0
    assert layers[0].opacity == 0.3 and layers[4].colour == (1.0, 0.0, 0.5)
    assert all(isinstance(c, float) for c in layers[4].colour)
    assert signals == ["appearance 1", "appearance 2", "appearance 3", "appearance 0", "appearance 4"]
    assert layers.active is layers[4]
    layers.set_visible(4, False)
    assert layers.active is layers[3]
    layers.remove(3)
    assert signals[-1] == "changed" and len(layers) == 4 and layers.active is layers[2]
    for index in range(4):
        layers.set_visible(index, False)
    assert layers.active is None


def test_another_alignment_or_offset_and_a_refused_one(qtbot, short_walk):
    state, layers, said, signals = with_layers(short_walk)
    layer = layers.add(Snapshot.of(short_walk), "b.gmr", offset=0.0)
    signals.clear()
    assert layers.set_alignment(0, kind="rigid")
    assert layer.align == "rigid" and layer.offset == 0.0 and not layer.auto_offset
    assert layer.comparison.alignment.kind == "rigid" and signals == ["changed"]
    assert layers.set_alignment(0, offset=3)
    assert layer.align == "rigid" and layer.offset == 3.0 and layer.comparison.alignment.offset_frames == 3.0
    assert layers.set_alignment(0, offset="auto")
    assert layer.auto_offset and layer.offset == pytest.approx(0.0, abs=1e-6) and isinstance(layer.offset, float)
    with pytest.raises(ValueError, match="alignment must be one of none, rigid, similarity, not 'affine'"):
        layers.set_alignment(0, kind="affine")
    with pytest.raises(TypeError):
        layers.set_alignment(0, "rigid")
    kept = layer.comparison
    signals.clear()
    assert not layers.set_alignment(0, kind="similarity", offset=1000.0)  # no shared time: refused
    assert (layer.align, layer.offset, layer.comparison) == ("rigid", pytest.approx(0.0, abs=1e-6), kept)
    assert layer.auto_offset and signals == ["changed"]
    assert said == [said[0]] and said[0].startswith("Cannot align b.gmr that way: the two motions share no time")
    markers = layers.add_markers(read_markers(demo_folder() / MARKERS_FILE), "walk.trc")
    assert not layers.set_alignment(1, kind="rigid") and markers.comparison is None
    state.snapshot = None
    assert not layers.set_alignment(0, kind="none") and layer.align == "rigid"


def test_marker_layers(qtbot, short_walk):
    _, empty, _, _ = with_layers()
    markers = read_markers(demo_folder() / MARKERS_FILE)
    with pytest.raises(ValueError, match="open a motion before comparing markers"):
        empty.add_markers(markers, "walk.trc")
    with pytest.raises(ValueError, match="open a motion before comparing another"):
        empty.add(Snapshot.of(short_walk), "b.gmr")
    assert len(empty) == 0
    _, layers, _, signals = with_layers(short_walk)
    layer = layers.add_markers(markers, "/x/walk.trc", document_bound=True)
    assert isinstance(layer, MarkerLayer) and layer.name == "walk.trc" and layer.document_bound
    assert layer.opacity == MARKER_LAYER_OPACITY and layer.colour == LAYER_COLOURS[0]
    assert layer.overlay is not None and layer.positions.shape == (120, markers.n_markers, 3)
    assert signals == ["changed"] and layers.active is None  # drawn, not compared
    loose = layers.add_markers(markers, "loose.trc")
    assert not loose.document_bound and loose.colour == LAYER_COLOURS[1]
    with pytest.raises(TypeError):
        layers.add_markers(markers, "again.trc", None)
    with pytest.raises(TypeError):
        layers.add(Snapshot.of(short_walk), "b.gmr", None, "none")


def test_another_document_drops_its_own_layers_and_finds_offsets_again(qtbot, short_walk):
    state, layers, said, signals = with_layers(short_walk)
    markers = read_markers(demo_folder() / MARKERS_FILE)
    layers.add_markers(markers, "bound.trc", document_bound=True)
    loose = layers.add_markers(markers, "loose.trc")
    given = layers.add(Snapshot.of(short_walk.frame_slice(slice(20, None))), "b.gmr", offset=4.0)
    first_overlay = loose.overlay
    signals.clear()
    state.open_document(Snapshot.of(short_walk.frame_slice(slice(30, None))), "other.gmr")
    assert [layer.name for layer in layers.layers] == ["loose.trc", "b.gmr"]
    assert signals == ["changed"]  # once: recomputed (the layers kept)
    assert given.auto_offset and given.offset == pytest.approx(10.0, abs=1e-6)  # A = B from frame 10
    assert loose.overlay is not first_overlay and loose.positions.shape[0] == 90
    assert said == []
    # a document whose joints pair with none of B's: the comparison goes, with a message
    strangers = short_walk.replace(names=tuple(f"x{j}" for j in range(short_walk.n_joints)))
    state.open_document(Snapshot.of(strangers), "strangers.gmr")
    assert [layer.name for layer in layers.layers] == ["loose.trc"]
    assert len(said) == 1 and said[0].startswith("Removed the comparison with b.gmr: no joints matched")
    # no layer at all: another document changes nothing the dock shows
    _, none, _, none_signals = with_layers(short_walk)
    none.state.open_document(Snapshot.of(short_walk), "again.gmr")
    assert none_signals == []
    # only bound layers: they go, and the dock hears it before the (empty) recompute
    _, only, _, only_signals = with_layers(short_walk)
    only.add_markers(markers, "bound.trc", document_bound=True)
    only_signals.clear()
    only.state.open_document(Snapshot.of(short_walk), "again.gmr")
    assert len(only) == 0 and only_signals == ["changed"]


def test_recompute_keeps_a_marker_layers_alignment_through_edits(qtbot, short_walk):
    state, layers, said, signals = with_layers(short_walk)
    loose = layers.add_markers(read_markers(demo_folder() / MARKERS_FILE), "loose.trc")
    alignment = loose.overlay.alignment
    signals.clear()
    layers.recompute()
    assert loose.overlay.alignment == alignment and signals == ["changed"]
    loose.overlay = None  # not aligned yet: an automatic alignment
    layers.recompute()
    assert loose.overlay is not None
    state.snapshot = None  # no document: every layer goes, each with a message
    layers.layers.append(ComparisonLayer(Snapshot.of(short_walk), "b.gmr", LAYER_COLOURS[1]))
    layers.recompute()
    assert len(layers) == 0 and said == [
        "Removed the comparison with loose.trc: no document",
        "Removed the comparison with b.gmr: no document",
    ]
    signals.clear()
    layers.recompute()  # nothing to recompute: nothing said
    assert signals == [] and len(said) == 2
