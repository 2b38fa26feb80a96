"""The comparison layers' onion skins (app/scene/layer_onion.py, issue 24) on the tiny
synthetic skeleton (:mod:`tests.tiny_scene`): a ghost B of the figure over A's first four
frames of six (:func:`tests.test_scene_ghost_layer_mutants.b_motion`), drawn at the
document's onion frames in the layer's colour with a dot at every joint, fading like the
document's and fainter with a fainter layer; frames B has no sample of left out."""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np
import pytest

from gmr_studio.app.model.layers import Layers
from gmr_studio.app.model.marker_layers import MarkerLayer
from gmr_studio.app.model.state import MarkerOverlay, StudioState
from gmr_studio.app.scene.layer_onion import LayerOnions, layer_slot_frames
from gmr_studio.app.scene.onion import MAX_OPACITY, OnionSettings, onion_frames, pose_points
from gmr_studio.core.markers import MarkerSet
from tests.test_scene_ghost_layer_mutants import b_motion
from tests.tiny_scene import figure_motion, holds, scene_of, snapshot_of

pytestmark = pytest.mark.gui


@contextmanager
def onions(qtbot, settings: OnionSettings | None = None):
    """(scene, layers, onions): A (six frames) in a scene, its onion poses every frame, one
    each side; B added as a layer."""
    state = StudioState()
    state.open_document(snapshot_of(figure_motion(6)), "a.gmr")
    layers = Layers(state)
    settings = settings or OnionSettings(shown=True, step=1, count=1)
    with scene_of(state.snapshot) as scene:
        drawing = LayerOnions(layers, settings)
        scene.add_drawable(drawing)
        layers.add(snapshot_of(b_motion()), "b.gmr", offset=0.0, align="none")
        yield scene, layers, drawing


def test_slots_show_the_frames_the_ghost_has_every_joint_of():
    ghost = np.zeros((5, 2, 3))
    ghost[1, 0, 2] = np.nan
    frames, distance = onion_frames(2, 7, 1, 3)  # 1, 3, 0, 4, (-1), 5
    assert layer_slot_frames(ghost, frames, distance, 3).tolist() == [-1, 3, 0, 4, -1, -1]
    shown = layer_slot_frames(ghost[:4], frames, distance, 3)
    assert shown.tolist() == [-1, 3, 0, -1, -1, -1] and shown.dtype == np.int64
    assert layer_slot_frames(ghost, frames[:0], distance[:0], 2).tolist() == [-1] * 4


def test_each_layer_gets_a_hidden_pool_of_line_actors_with_joint_dots_in_its_colour(qtbot):
    with onions(qtbot, OnionSettings(shown=True, step=1, count=2)) as (scene, layers, drawing):
        (pool,) = drawing.pools
        assert len(pool) == 4 and list(drawing.parts) == [f"layer_onion_0_{slot}" for slot in range(4)]
        assert drawing.links[0].tolist() == [[4, 2], [1, 0]]
        for part in pool:
            assert holds(scene.plotter.renderer, part.actor)
            prop = part.actor.GetProperty()
            assert prop.GetColor() == pytest.approx(layers[0].colour)
            assert prop.GetLineWidth() == pytest.approx(2.5) and prop.GetPointSize() == pytest.approx(5.0)
            assert prop.GetRenderPointsAsSpheres()
            assert part.mesh.n_verts == 6 and part.mesh.verts.tolist() == [1, 0, 1, 1, 1, 2, 1, 3, 1, 4, 1, 5]
        # frame 0: B's frames 1 and 2 after it
        assert drawing.slot_frames[0].tolist() == [-1, 1, -1, 2]
        assert [part.visible for part in pool] == [False, True, False, True]


def test_the_poses_are_the_ghost_at_the_onion_frames_fading_with_distance(qtbot):
    with onions(qtbot, OnionSettings(shown=True, step=1, count=2)) as (scene, layers, drawing):
        layer, pool = layers[0], drawing.pools[0]
        scene.show_frame(2)
        assert drawing.slot_frames[0].tolist() == [1, 3, 0, -1]  # B has no frame 4
        assert [part.visible for part in pool] == [True, True, True, False]
        for slot, frame, fade in ((0, 1, 1.0), (1, 3, 1.0), (2, 0, 0.2)):
            np.testing.assert_allclose(pool[slot].mesh.points, pose_points(layer.ghost[frame], drawing.links[0]))
            assert pool[slot].actor.GetProperty().GetOpacity() == pytest.approx(MAX_OPACITY * fade)
        scene.show_frame(3)  # slot 3 (frame 5) has no sample: its points are left as they were
        np.testing.assert_allclose(pool[1].mesh.points, pose_points(layer.ghost[3], drawing.links[0]))
        assert drawing.slot_frames[0].tolist() == [2, -1, 1, -1] and not pool[1].visible
        scene.show_frame(2)
        layers.set_opacity(0, 0.25)  # half the default: half as opaque
        assert pool[2].actor.GetProperty().GetOpacity() == pytest.approx(MAX_OPACITY * 0.2 * 0.5)
        layers.set_opacity(0, 0.9)  # more opaque than the default: as the document's
        assert pool[0].actor.GetProperty().GetOpacity() == pytest.approx(MAX_OPACITY)
        layers.set_visible(0, False)
        assert not any(part.visible for part in pool) and drawing.slot_frames[0].tolist() == [-1] * 4


def test_a_new_colour_is_given_to_the_layers_actors_and_drawn(qtbot):
    with onions(qtbot) as (scene, layers, drawing):
        calls: list = []
        scene.request_repaint = lambda: calls.append(1)
        actors = [part.actor for part in drawing.pools[0]]
        scene.frame = 2  # the scene moved on without telling the drawing
        layers.set_colour(0, (0.1, 0.8, 0.3))
        assert [part.actor for part in drawing.pools[0]] == actors
        assert all(a.GetProperty().GetColor() == pytest.approx((0.1, 0.8, 0.3)) for a in actors)
        assert drawing.slot_frames[0].tolist() == [1, 3] and calls == [1]
        drawing.restyle(1)  # no such layer: nothing recoloured, the frame drawn again
        assert calls == [1, 1]
        drawing.set_visible(False)
        scene.frame = 1
        drawing.restyle(0)
        assert drawing.slot_frames[0].tolist() == [1, 3] and calls == [1, 1]
        assert not any(part.visible for part in drawing.pools[0])


def test_hidden_drawing_hides_every_pose_until_the_next_frame(qtbot):
    with onions(qtbot) as (scene, _layers, drawing):
        scene.show_frame(2)
        pool = drawing.pools[0]
        assert all(part.visible for part in pool)
        drawing.set_visible(False)
        assert not drawing.visible and not any(part.visible for part in pool)
        drawing.show_frame(1)
        assert not any(part.visible for part in pool) and drawing.slot_frames[0].tolist() == [0, 2]
        drawing.set_visible(True)
        assert drawing.visible and not any(part.visible for part in pool)  # shown again at the next frame
        drawing.show_frame(1)
        assert all(part.visible for part in pool)


def test_no_pools_without_the_onion_skin_its_layers_option_or_a_document(qtbot):
    settings = OnionSettings(shown=True, step=1, count=1, include_layers=False)
    with onions(qtbot, settings) as (scene, layers, drawing):
        assert not drawing.wanted(scene) and drawing.pools == [] and drawing.parts == {}
        drawing.show_frame(1)
        settings.include_layers = True
        layers.changed.emit()  # the layers changed: built again in the scene
        assert drawing.wanted(scene) and len(drawing.pools[0]) == 2
        settings.shown = False
        layers.changed.emit()
        assert drawing.pools == [] and drawing.slot_frames == [] and drawing.parts == {}
    state = StudioState()
    layers = Layers(state)
    drawing = LayerOnions(layers, OnionSettings(shown=True))
    layers.changed.emit()  # in no scene yet: nothing to build
    assert drawing.scene is None and drawing.pools == []
    with scene_of(None) as scene:
        scene.add_drawable(drawing)
        assert drawing.pools == []
        drawing.restyle(0)


def test_a_marker_layer_has_no_onion_poses(qtbot):
    with onions(qtbot) as (scene, layers, drawing):
        points = np.zeros((6, 1, 3))
        markers = MarkerSet(labels=("m0",), positions=points, rate=30.0, units="m")
        layers.layers.insert(
            0, MarkerLayer(markers, "m.trc", (0.9, 0.1, 0.5), overlay=MarkerOverlay(markers, None, points))
        )
        layers.changed.emit()
        assert drawing.pools[0] == [] and drawing.links[0] is None and len(drawing.pools[1]) == 2
        assert sorted(drawing.parts) == ["layer_onion_1_0", "layer_onion_1_1"]
        scene.show_frame(1)
        assert drawing.slot_frames[0].tolist() == [-1, -1] and drawing.slot_frames[1].tolist() == [0, 2]
        assert all(part.visible for part in drawing.pools[1])


def test_a_pool_built_is_hidden_until_a_frame_is_shown(qtbot):
    with onions(qtbot, OnionSettings(shown=True, step=1, count=2)) as (scene, _layers, drawing):
        scene.show_frame(2)
        assert any(part.visible for part in drawing.pools[0])
        drawing.build(scene)
        assert len(drawing.pools[0]) == 4 and not any(part.visible for part in drawing.pools[0])


def test_the_box_is_every_posed_layers_ghost_at_every_frame_measured_once_a_build(qtbot):
    """The poses are a layer's ghost at some of its frames: the box of each comparison
    layer's ghost at every frame holds them (a marker-set layer has none); it is measured
    once a build, so a layer added is in the next one."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of

    with onions(qtbot, OnionSettings(shown=True, step=1, count=2)) as (scene, layers, drawing):
        ghost = layers[0].ghost
        points = np.full((6, 1, 3), 50.0)  # markers far from the figure: not onion poses
        markers = MarkerSet(labels=("m0",), positions=points, rate=30.0, units="m")
        layers.layers.insert(
            0, MarkerLayer(markers, "m.trc", (0.9, 0.1, 0.5), overlay=MarkerOverlay(markers, None, points))
        )
        layers.changed.emit()
        box = drawing.extent()
        np.testing.assert_array_equal(box, box_of(ghost))
        assert drawing.extent() is box  # kept
        for frame in range(6):
            scene.show_frame(frame)
            for part in drawing.pools[1]:
                if part.visible:
                    assert (part.mesh.points >= box[0]).all() and (part.mesh.points <= box[1]).all(), frame
        moved = snapshot_of(b_motion())
        moved.positions[:] += 3.0
        layers.add(moved, "c.gmr", offset=0.0, align="none")  # another layer: built again
        np.testing.assert_array_equal(drawing.extent(), box_of(np.concatenate([ghost, layers[2].ghost])))
        layers.layers.clear()
        layers.changed.emit()
        np.testing.assert_array_equal(drawing.extent(), EMPTY_BOX)
