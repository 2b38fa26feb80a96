"""Onion skins as drawn (app/scene/onion.py, app/scene/layer_onion.py) on the tiny synthetic
skeleton (:mod:`tests.tiny_scene`): which frames around the current one, their fading
opacities and slots, the document's poses drawn as lines with the links dashed (blue before,
orange after), and the comparison layers' poses: a ghost B of the figure over A's first four
frames of six (:func:`tests.test_scene_comparison_layers.b_motion`) drawn at the document's
onion frames in the layer's colour with a dot at every joint, fading like the document's and
fainter with a fainter layer; frames B has no sample of left out."""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np
import pytest

from gmr_studio.app.model.layers import Layers
from gmr_studio.app.model.marker_layers import MarkerLayer
from gmr_studio.app.model.state import MarkerOverlay, StudioState
from gmr_studio.app.scene.figure import DASHES, dash_points
from gmr_studio.app.scene.layer_onion import LayerOnions, layer_slot_frames
from gmr_studio.app.scene.onion import (
    COUNTS,
    MAX_OPACITY,
    STEPS,
    OnionSettings,
    OnionSkins,
    ghost_opacity,
    onion_frames,
    pose_lines,
    pose_points,
    slot_of,
)
from gmr_studio.core.markers import MarkerSet
from tests.test_scene_comparison_layers import b_motion
from tests.tiny_scene import figure_motion, figure_world, holds, posed_motion, scene_of, snapshot_of

pytestmark = pytest.mark.gui
N_POINTS = 6 + 2 * DASHES * 2  # six joints, two links of DASHES dashes


def test_onion_frames_step_and_count_of_one_and_the_documents_ends():
    frames, distance = onion_frames(0, 3, 1, 1)
    assert frames.tolist() == [1] and distance.tolist() == [1]
    assert frames.dtype == np.int64 and distance.dtype == np.int64
    frames, distance = onion_frames(4, 9, 2, 2)  # 0 and 8 are the first and last frames
    assert frames.tolist() == [2, 6, 0, 8] and distance.tolist() == [-1, 1, -2, 2]
    frames, distance = onion_frames(4, 8, 2, 3)
    assert frames.tolist() == [2, 6, 0] and distance.tolist() == [-1, 1, -2]
    for step, count in ((0, 1), (1, 0), (-1, 2)):
        with pytest.raises(ValueError, match="at least 1"):
            onion_frames(5, 10, step, count)


def test_opacities_fade_linearly_to_a_fifth_at_count_steps():
    np.testing.assert_allclose(
        ghost_opacity(np.array([-1, 1, -2, 2, -3, 3]), 3), MAX_OPACITY * np.repeat([1.0, 0.6, 0.2], 2)
    )
    np.testing.assert_allclose(ghost_opacity(np.array([1, -2]), 2), MAX_OPACITY * np.array([1.0, 0.2]))
    np.testing.assert_allclose(ghost_opacity(np.array([-1, 1]), 1), [MAX_OPACITY, MAX_OPACITY])
    assert ghost_opacity(np.zeros(0, np.int64), 1).shape == (0,)


def test_slots_alternate_before_and_after_from_the_nearest():
    assert slot_of(np.array([-1, 1, -2, 2, -3, 3])).tolist() == [0, 1, 2, 3, 4, 5]
    assert slot_of([3, -1]).tolist() == [5, 0]


def test_a_pose_is_its_bones_then_the_links_dashes():
    motion = figure_motion()
    pairs, links, n_points = pose_lines(motion)
    assert links.tolist() == [[4, 2], [1, 0]] and n_points == N_POINTS
    assert pairs[:3].tolist() == [[1, 2], [2, 3], [4, 5]] and pairs.dtype == np.int64
    np.testing.assert_array_equal(pairs[3:], 6 + np.arange(4 * DASHES).reshape(-1, 2))
    positions = figure_world(1)[0]
    points = pose_points(positions, links)
    assert points.shape == (N_POINTS, 3)
    np.testing.assert_array_equal(points[:6], positions)
    np.testing.assert_allclose(points[6:], dash_points(positions[[4, 1]], positions[[2, 0]]).reshape(-1, 3))
    world = np.array([[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    pairs, links, n_points = pose_lines(posed_motion(("Hips", "Head"), (-1, 0), world))
    assert pairs.tolist() == [[0, 1]] and links.shape == (0, 2) and n_points == 2
    row = world[0]
    assert pose_points(row, links) is row


def test_the_settings_and_their_frames():
    assert STEPS == (2, 5, 10, 20, 30, 60) and COUNTS == (1, 2, 3, 5, 8)  # the View > Onion skin menu's choices
    settings = OnionSettings()
    assert settings.step in STEPS and settings.count in COUNTS
    assert (settings.shown, settings.step, settings.count, settings.include_layers) == (False, 10, 3, True)
    assert settings.frames(15, 40)[0].tolist() == [5, 25, 35]


def test_the_pool_a_line_actor_per_slot_blue_before_orange_after():
    settings = OnionSettings(shown=True, step=2, count=2)
    snapshot = snapshot_of(figure_motion(9))
    with scene_of(snapshot) as scene:
        skins = OnionSkins(settings)
        scene.add_drawable(skins)
        assert len(skins.pool) == 4 and list(skins.parts) == [f"onion_{slot}" for slot in range(4)]
        for slot, part in enumerate(skins.pool):
            assert skins.parts[f"onion_{slot}"] is part and holds(scene.plotter.renderer, part.actor)
            red, _green, blue = part.actor.GetProperty().GetColor()
            assert (blue > red) if slot % 2 == 0 else (red > blue)  # before: blue; after: orange
            assert part.n_points == N_POINTS
        # frame 0: only the poses after it, two and four frames on
        assert skins.frames.tolist() == [2, 4] and [p.visible for p in skins.pool] == [False, True, False, True]
        assert skins.poses == [skins.pool[1], skins.pool[3]]
        np.testing.assert_allclose(skins.opacities, MAX_OPACITY * np.array([1.0, 0.2]))
        scene.show_frame(4)
        assert skins.frames.tolist() == [2, 6, 0, 8] and all(p.visible for p in skins.pool)
        for slot, frame, alpha in ((0, 2, 1.0), (1, 6, 1.0), (2, 0, 0.2), (3, 8, 0.2)):
            part = skins.pool[slot]
            np.testing.assert_allclose(part.mesh.points, pose_points(snapshot.positions[frame], skins.links))
            assert part.actor.GetProperty().GetOpacity() == pytest.approx(MAX_OPACITY * alpha)
        scene.show_frame(7)
        assert skins.frames.tolist() == [5, 3] and [p.visible for p in skins.pool] == [True, False, True, False]
        skins.set_visible(False)
        scene.show_frame(6)  # a hidden drawing writes nothing
        assert skins.frames.tolist() == [5, 3] and not any(p.visible for p in skins.pool)
        skins.set_visible(True)
        skins.show_frame(6)
        assert [p.visible for p in skins.pool] == [True, True, True, False]


def test_a_new_drawing_shows_no_pose():
    skins = OnionSkins(OnionSettings(shown=True))
    assert skins.pool == [] and skins.poses == [] and skins.parts == {}
    assert skins.frames.shape == (0,) and skins.frames.dtype == np.int64 and skins.opacities.shape == (0,)


def test_no_pool_while_not_shown_or_without_a_document():
    settings = OnionSettings(shown=False, step=2, count=2)
    with scene_of(snapshot_of(figure_motion(9))) as scene:
        skins = OnionSkins(settings)
        scene.add_drawable(skins)
        assert skins.pool == [] and skins.parts == {} and not skins.wanted(scene) and not skins.visible
        skins.show_frame(3)
        assert skins.frames.tolist() == [] and skins.poses == []
        settings.shown = True
        scene.redraw(skins)
        assert len(skins.pool) == 4 and skins.wanted(scene) and skins.visible
        settings.shown = False
        scene.redraw(skins)  # rebuilt: the pool and what it showed forgotten
        assert skins.pool == [] and skins.poses == [] and skins.frames.tolist() == [] and skins.opacities.shape == (0,)
    with scene_of(None) as scene:
        skins = OnionSkins(OnionSettings(shown=True))
        scene.add_drawable(skins)
        assert skins.pool == [] and skins.parts == {}


def test_the_skins_box_is_the_documents_joints_at_every_frame():
    """The poses are the document at other frames (bones and dashes between its joints): the
    box of its joints at every frame holds each; no pool: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of

    settings = OnionSettings(shown=False, step=2, count=2)
    snapshot = snapshot_of(figure_motion(9))
    with scene_of(snapshot) as scene:
        skins = OnionSkins(settings)
        scene.add_drawable(skins)
        np.testing.assert_array_equal(skins.extent(), EMPTY_BOX)
        settings.shown = True
        scene.redraw(skins)
        box = skins.extent()
        np.testing.assert_array_equal(box, box_of(snapshot.positions))
        for frame in range(9):
            scene.show_frame(frame)
            for part in skins.poses:
                assert (part.mesh.points >= box[0]).all() and (part.mesh.points <= box[1]).all(), frame


# ------------------------------------------------------------ the layers' onion skins
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


def test_a_layers_slots_show_the_frames_the_ghost_has_every_joint_of():
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
            assert part.actor.GetProperty().GetColor() == pytest.approx(layers[0].colour)
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


def test_a_new_colour_is_given_to_the_layers_poses_at_the_scenes_frame(qtbot):
    with onions(qtbot) as (scene, layers, drawing):
        actors = [part.actor for part in drawing.pools[0]]
        scene.show_frame(2)
        layers.set_colour(0, (0.1, 0.8, 0.3))
        assert [part.actor for part in drawing.pools[0]] == actors  # recoloured in place
        assert all(a.GetProperty().GetColor() == pytest.approx((0.1, 0.8, 0.3)) for a in actors)
        assert drawing.slot_frames[0].tolist() == [1, 3] and all(part.visible for part in drawing.pools[0])
        drawing.restyle(1)  # no such layer: nothing recoloured
        assert all(a.GetProperty().GetColor() == pytest.approx((0.1, 0.8, 0.3)) for a in actors)
        drawing.set_visible(False)
        drawing.restyle(0)  # hidden: stays hidden
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
