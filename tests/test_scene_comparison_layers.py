"""The comparison layers as drawn (app/scene/ghost_layer.py, app/scene/legend.py) on the tiny
synthetic skeleton (:mod:`tests.tiny_scene`): a ghost B of the figure, 0.05 nearer (+z) with
its Hand 0.1 higher, over A's first four frames of six; the error view of the active layer
(the figure's joints in the error's colours, lines to their matches, the legend at the view's
right); a marker set layer; the colour map and its scale."""

from __future__ import annotations

from contextlib import contextmanager
from types import SimpleNamespace

import numpy as np
import pytest

from gmr_studio.app.model.layers import ComparisonLayer, Layers
from gmr_studio.app.model.marker_layers import MarkerLayer
from gmr_studio.app.model.state import MarkerOverlay, StudioState
from gmr_studio.app.scene.figure import BONE_RADIUS, JOINT_RADIUS
from gmr_studio.app.scene.ghost_layer import (
    ERROR_JOINT_RADIUS,
    LINE_COLOUR,
    GhostLayers,
    error_colours,
    error_scale_top,
)
from gmr_studio.app.scene.labels import box_corners
from gmr_studio.app.scene.legend import EDGE, LABEL_GAP, label_texts, legend_fit, legend_layout, legend_part
from gmr_studio.app.scene.vtk_parts import rgb_bytes
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.compare.clock import ghost_positions
from gmr_studio.core.markers import MarkerSet
from tests.tiny_scene import (
    FIGURE_NAMES,
    FIGURE_PARENTS,
    FIGURE_SIZE,
    FIGURE_SOFT_PARENTS,
    figure_motion,
    figure_world,
    holds,
    picture,
    posed_motion,
    scene_of,
    snapshot_of,
)

pytestmark = pytest.mark.gui  # a QApplication (the layers' signals)
GREEN, YELLOW, RED, GREY = (0.2, 0.75, 0.35), (1.0, 0.85, 0.1), (0.9, 0.15, 0.1), (0.5, 0.5, 0.5)
HAND_ERROR = np.hypot(0.05, 0.1)  # B's Hand: 0.05 nearer and 0.1 higher


def b_motion(names=FIGURE_NAMES):
    """B: the figure's first four frames, 0.05 nearer, its Hand 0.1 higher (joints ``names``)."""
    world = figure_world(4) + np.array([0.0, 0.0, 0.05])
    world[:, 5, 1] += 0.1
    keep = [FIGURE_NAMES.index(name) for name in names]
    parents = [keep.index(FIGURE_PARENTS[j]) if FIGURE_PARENTS[j] in keep else -1 for j in keep]
    soft = [keep.index(FIGURE_SOFT_PARENTS[j]) if FIGURE_SOFT_PARENTS[j] in keep else -1 for j in keep]
    return posed_motion(names, parents, world[:, keep], soft)


@contextmanager
def compared(qtbot, oit: bool = False, size: tuple[int, int] = (160, 160)):
    """(scene, state, layers, ghosts): A (six frames) in a scene, B added as a layer."""
    state = StudioState()
    state.open_document(snapshot_of(figure_motion(6)), "a.gmr")
    layers = Layers(state)
    with scene_of(state.snapshot, size=size) as scene:
        scene.plotter.renderer.SetUseOIT(oit)
        ghosts = GhostLayers(state, layers)
        scene.add_drawable(ghosts)
        layers.add(snapshot_of(b_motion()), "b.gmr", offset=0.0, align="none")
        yield scene, state, layers, ghosts


def test_the_colour_map_from_green_to_red_and_grey_for_no_error():
    errors = np.array([0.0, 0.5, 1.0, 2.0, 4.0, 8.0, -1.0, np.nan])
    rgb = error_colours(errors, 4.0)
    green, yellow = np.array(GREEN), np.array(YELLOW)
    quarter, half = green + 0.25 * (yellow - green), (green + yellow) / 2
    expected = [GREEN, quarter, half, YELLOW, RED, RED, GREEN, GREY]  # over [0, 4], clipped
    np.testing.assert_allclose(rgb, np.array(expected), atol=1e-12)
    assert error_colours(np.zeros((2, 3)), 4.0).shape == (2, 3, 3)
    # a scale of 0 (everything agrees): 0 is green, anything more red
    np.testing.assert_allclose(error_colours(np.array([0.0, 1e-9]), 0.0), [GREEN, RED])
    np.testing.assert_allclose(error_colours(np.array([0.25]), 0.5), [YELLOW])


def test_the_scale_tops_at_the_largest_error_or_a_thousandth_of_the_size():
    def top(largest, size):
        return error_scale_top(SimpleNamespace(comparison=SimpleNamespace(position=SimpleNamespace(max=largest))), size)

    assert top(0.3, 2.0) == 0.3 and isinstance(top(np.float32(0.3), 2.0), float)
    assert top(3e-6, 2.0) == 3e-6  # above a millionth of the size: the largest error
    assert top(2e-6, 2.0) == pytest.approx(2e-3)  # a millionth exactly: everything agrees
    assert top(0.0, 2.0) == pytest.approx(2e-3) and top(np.nan, 2.0) == pytest.approx(2e-3)


def test_a_new_ghost_drawing_has_no_error_colours(qtbot):
    state = StudioState()
    ghosts = GhostLayers(state, Layers(state))
    assert ghosts.show_errors is True and ghosts.ghosts == [] and ghosts.error_rgb.shape == (0, 0, 3)
    assert ghosts.error_joints is None and ghosts.legend is None


def test_a_layer_is_a_translucent_ghost_in_its_colour_at_the_documents_frame(qtbot):
    with compared(qtbot) as (scene, _state, layers, ghosts):
        layer = layers[0]
        bones, joints = ghosts.parts["ghost_0_0"], ghosts.parts["ghost_0_1"]
        assert ghosts.ghosts == [(bones, joints)]
        assert bones.pairs.tolist() == [[2, 1], [3, 2], [5, 4]]  # the anchor's bone left out
        assert bones.radius < BONE_RADIUS * FIGURE_SIZE  # thinner than the figure's
        # a sphere only where no bone reaches: the anchor (joint 0), its bone left out
        assert ghosts.loose[0].tolist() == [0] and ghosts.loose[0].dtype.kind == "i"
        assert joints.n_points == 1 and joints.radius < JOINT_RADIUS * FIGURE_SIZE
        for part in (bones, joints):
            assert holds(scene.plotter.renderer, part.actor) and part.visible
            assert part.actor.GetProperty().GetOpacity() == pytest.approx(layer.opacity)
        np.testing.assert_array_equal(bones.mesh.point_data["colors"], rgb_bytes(np.tile(layer.colour, (3, 1))))
        assert joints.actor.GetProperty().GetColor() == pytest.approx(layer.colour)
        for frame in (0, 3):
            scene.show_frame(frame)
            np.testing.assert_allclose(joints.mesh.points, layer.ghost[frame][[0]])
            np.testing.assert_allclose(bones.mesh.points, layer.ghost[frame][[[2, 1], [3, 2], [5, 4]]].mean(axis=1))
            assert joints.visible and bones.visible
        scene.show_frame(5)  # beyond B's last frame: not drawn, the points left as they were
        assert not joints.visible and not bones.visible
        np.testing.assert_allclose(joints.mesh.points, layer.ghost[3][[0]])
        scene.show_frame(1)
        assert joints.visible and bones.visible
        ghosts.set_visible(False)
        scene.show_frame(2)
        assert not joints.visible and not bones.visible
        ghosts.set_visible(True)  # shown again: at the scene's frame at once
        assert joints.visible and bones.visible
        np.testing.assert_allclose(joints.mesh.points, layer.ghost[2][[0]])


def test_a_ghost_of_lone_joints_draws_a_sphere_at_each_and_no_bones(qtbot):
    """Joints no bone reaches (each a root of its own, as after splitting every joint off)
    are spheres, so such a ghost still shows; the figure's bones' ends are not."""
    with compared(qtbot) as (scene, _state, layers, ghosts):
        world = figure_world(4) + np.array([0.0, 0.0, 0.05])
        lone = layers.add(snapshot_of(posed_motion(FIGURE_NAMES, [-1] * 6, world)), "lone.gmr", offset=0.0)
        (b_bones, b_joints), (bones, joints) = ghosts.ghosts
        assert b_joints.n_points == 1 and ghosts.loose[0].tolist() == [0]  # B: its anchor alone
        assert bones.n_points == 0 and not bones.visible  # nothing to draw: hidden, not an empty actor
        assert ghosts.loose[1].tolist() == [0, 1, 2, 3, 4, 5] and joints.n_points == 6 and joints.visible
        for frame in (2, 0):
            scene.show_frame(frame)
            np.testing.assert_allclose(joints.mesh.points, lone.ghost[frame])
            assert joints.visible and not bones.visible and b_bones.visible and b_joints.visible
        layers.set_visible(1, False)
        assert [part.visible for part in ghosts.ghosts[1]] == [False, False]
        # a ghost of one bone and no joint it leaves out: the bone drawn, no spheres
        pair = posed_motion(FIGURE_NAMES[1:3], [-1, 0], world[:, 1:3])
        layers.add(snapshot_of(pair), "pair.gmr", offset=0.0)
        bones, joints = ghosts.ghosts[2]
        assert bones.n_points == 1 and joints.n_points == 0 and ghosts.loose[2].size == 0
        scene.show_frame(1)
        assert bones.visible and not joints.visible


def test_the_layers_appearance_rebuilds_the_ghost(qtbot):
    with compared(qtbot) as (scene, _state, layers, ghosts):
        layers.set_colour(0, (0.1, 0.2, 0.3))
        assert ghosts.parts["ghost_0_1"].actor.GetProperty().GetColor() == pytest.approx((0.1, 0.2, 0.3))
        layers.set_opacity(0, 0.25)
        assert ghosts.parts["ghost_0_0"].actor.GetProperty().GetOpacity() == pytest.approx(0.25)
        layers.set_visible(0, False)  # hidden: no ghost drawn, no active layer, no error view
        assert not ghosts.parts["ghost_0_0"].visible and not ghosts.parts["ghost_0_1"].visible
        assert ghosts.error_joints is None and "error_joints" not in ghosts.parts
        scene.show_frame(1)
        assert not ghosts.parts["ghost_0_1"].visible
        layers.remove(0)
        assert ghosts.parts == {} and ghosts.ghosts == []
        scene.show_frame(2)  # nothing to write


def test_ghosts_are_blended_in_drawing_order_and_the_renderers_setting_comes_back(qtbot):
    with compared(qtbot, oit=True) as (scene, _state, layers, ghosts):
        renderer = scene.plotter.renderer
        assert not renderer.GetUseOIT()  # ghosts shown: no order-independent translucency
        layers.remove(0)
        assert renderer.GetUseOIT()  # no ghost: the renderer's own setting
        layers.add(snapshot_of(b_motion()), "b.gmr", offset=0.0, align="none")
        assert not renderer.GetUseOIT()
        scene.remove_drawable(ghosts)
        assert renderer.GetUseOIT()
    with compared(qtbot, oit=False) as (scene, _state, layers, ghosts):
        layers.remove(0)
        assert not scene.plotter.renderer.GetUseOIT()


def test_the_error_view_colours_the_matched_joints_and_links_them_to_their_matches(qtbot):
    with compared(qtbot) as (scene, state, layers, ghosts):
        comparison = layers[0].comparison
        assert ghosts.top == pytest.approx(HAND_ERROR)
        joints, lines = scene.figure.parts["joints"], ghosts.error_lines
        own = rgb_bytes(scene.tree_colors.colors(state.motion))  # the joints' own colours
        assert lines is ghosts.parts["error_lines"] and "error_joints" not in ghosts.parts
        np.testing.assert_array_equal(ghosts.error_joints, np.arange(6))  # the document's matched joints
        assert lines.n_points == 12
        cells = lines.mesh.lines.reshape(-1, 3)
        np.testing.assert_array_equal(cells, np.column_stack([np.full(6, 2), np.arange(6), 6 + np.arange(6)]))
        assert lines.actor.GetProperty().GetColor() == pytest.approx(LINE_COLOUR)
        expected = rgb_bytes(error_colours(np.array([0.05] * 5 + [HAND_ERROR]), HAND_ERROR))
        np.testing.assert_array_equal(ghosts.error_rgb[:4], np.broadcast_to(expected, (4, 6, 3)))
        assert (expected[:5] != expected[5]).any()  # the Hand's colour is another
        scene.show_frame(2)
        # the figure's own spheres in the error's colours, a little larger, at the document's joints
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], expected)
        np.testing.assert_allclose(joints.mesh.point_data["radius"], ERROR_JOINT_RADIUS * FIGURE_SIZE, rtol=1e-6)
        assert ERROR_JOINT_RADIUS > JOINT_RADIUS  # larger than the joints: their colour shows
        np.testing.assert_allclose(joints.mesh.points, comparison.positions_a[2])
        np.testing.assert_allclose(lines.mesh.points, np.concatenate([comparison.positions_a[2], layers[0].ghost[2]]))
        scene.show_frame(4)  # B has no sample: grey, the lines of no length
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], np.full((6, 3), 128))
        a = state.snapshot.positions[4]
        np.testing.assert_allclose(lines.mesh.points, np.concatenate([a, a]))
        ghosts.set_show_errors(False)  # the joints in their own colours and size again
        assert ghosts.show_errors is False and ghosts.error_joints is None and ghosts.error_lines is None
        assert not {"error_lines", "error_legend"} & set(ghosts.parts)
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], own)
        np.testing.assert_allclose(joints.mesh.point_data["radius"], JOINT_RADIUS * FIGURE_SIZE, rtol=1e-6)
        assert scene.figure.tint is None
        ghosts.set_show_errors(True)
        assert ghosts.error_joints is not None and ghosts.parts["error_legend"] is ghosts.legend
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], np.full((6, 3), 128))  # at once
        ghosts.set_visible(False)  # the layers hidden: the figure's own colours
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], own)
        ghosts.set_visible(True)
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], np.full((6, 3), 128))
        scene.redraw(scene.figure)  # the figure rebuilt alone (new parts): tinted as it was
        joints = scene.figure.parts["joints"]
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], np.full((6, 3), 128))
        np.testing.assert_allclose(joints.mesh.point_data["radius"], ERROR_JOINT_RADIUS * FIGURE_SIZE, rtol=1e-6)
        scene.remove_drawable(ghosts)  # no layers drawn: no tint left behind
        np.testing.assert_array_equal(scene.figure.parts["joints"].mesh.point_data["colors"], own)


def test_a_frame_not_compared_shows_the_documents_joints_in_grey(qtbot):
    state = StudioState()
    state.open_document(snapshot_of(figure_motion(6)), "a.gmr")
    layers = Layers(state)
    with scene_of(state.snapshot) as scene:
        ghosts = GhostLayers(state, layers)
        scene.add_drawable(ghosts)
        b = snapshot_of(b_motion(FIGURE_NAMES[1:]))  # no Root: A's joints 1 to 5 matched
        layer = ComparisonLayer(b, "b.gmr", (0.3, 0.6, 0.9), offset=0.0)
        layer.comparison = compare_motions(state.motion, b.motion, offset=0.0, frames=(0, 3), label_b="b.gmr")
        layer.compared_with = state.snapshot
        a = state.motion
        layer.ghost = ghost_positions(
            b.positions, a.n_frames, a.frame_rate, b.motion.frame_rate, layer.comparison.alignment
        )
        layers.layers.append(layer)
        layers.changed.emit()
        assert layer.comparison.index_a.tolist() == [1, 2, 3, 4, 5] and layer.comparison.row_of_frame(3) is None
        joints = scene.figure.parts["joints"]
        own = np.array(joints.colors[0])
        scene.show_frame(1)
        np.testing.assert_array_equal(joints.mesh.point_data["colors"][1:], ghosts.error_rgb[1])
        np.testing.assert_array_equal(joints.mesh.point_data["colors"][0], own)  # the Root, not matched: its own
        radii = np.asarray(joints.mesh.point_data["radius"])
        np.testing.assert_allclose(
            radii, [JOINT_RADIUS * FIGURE_SIZE] + [ERROR_JOINT_RADIUS * FIGURE_SIZE] * 5, rtol=1e-6
        )
        scene.show_frame(3)
        np.testing.assert_array_equal(joints.mesh.point_data["colors"][1:], np.full((5, 3), 128))
        points = state.snapshot.positions[3, 1:]
        np.testing.assert_allclose(ghosts.error_lines.mesh.points, np.concatenate([points, points]))


def test_the_legends_labels_run_from_zero_to_the_top_in_three_digits():
    assert label_texts(3.8) == ["0", "0.95", "1.9", "2.85", "3.8"]
    assert label_texts(HAND_ERROR) == ["0", "0.028", "0.0559", "0.0839", "0.112"]


def test_a_marker_layer_is_spheres_in_its_colour_gaps_not_drawn(qtbot):
    state = StudioState()
    state.open_document(snapshot_of(figure_motion(6)), "a.gmr")
    layers = Layers(state)
    points = np.arange(6 * 2 * 3, dtype=float).reshape(6, 2, 3) / 10
    points[2, 1] = np.nan  # a gap
    markers = MarkerSet(labels=("m0", "m1"), positions=points, rate=30.0, units="m")
    layer = MarkerLayer(markers, "m.trc", (0.9, 0.1, 0.5), overlay=MarkerOverlay(markers, None, points))
    with scene_of(state.snapshot) as scene:
        ghosts = GhostLayers(state, layers)
        scene.add_drawable(ghosts)
        layers.layers.append(layer)
        layers.changed.emit()
        (spheres,) = ghosts.ghosts[0]
        assert ghosts.parts["ghost_0_0"] is spheres and spheres.n_points == 2
        assert 0 < spheres.radius < JOINT_RADIUS * FIGURE_SIZE  # smaller than the figure's joints
        prop = spheres.actor.GetProperty()
        assert prop.GetColor() == pytest.approx((0.9, 0.1, 0.5)) and 0.5 < prop.GetOpacity() <= 1.0
        assert ghosts.error_joints is None  # a marker set is drawn, not compared
        for frame in (1, 5):
            scene.show_frame(frame)
            np.testing.assert_allclose(spheres.mesh.points, points[frame])
            assert spheres.visible and spheres.drawn.all()
        scene.show_frame(2)
        assert spheres.drawn.tolist() == [True, False]
        layers.set_visible(0, False)  # rebuilt: a new part, hidden at every frame
        scene.show_frame(3)
        assert not ghosts.parts["ghost_0_0"].visible
        layers.set_visible(0, True)
        (spheres,) = ghosts.ghosts[0]
        ghosts.set_visible(False)
        ghosts.show_frame(4)
        assert not spheres.visible
        ghosts.set_visible(True)
        assert spheres.visible
        np.testing.assert_allclose(spheres.mesh.points, points[3])


def test_no_document_no_ghost(qtbot):
    state = StudioState()
    layers = Layers(state)
    with scene_of(None) as scene:
        ghosts = GhostLayers(state, layers)
        scene.add_drawable(ghosts)
        assert ghosts.parts == {} and ghosts.ghosts == [] and ghosts.error_joints is None
        ghosts.set_visible(True)  # no snapshot: no frame to show
        ghosts.show_frame(0)


def test_a_ghost_or_marker_layer_shorter_than_the_document_shows_its_last_frame(qtbot):
    """After an edit that lengthens the document (an undone trim), the view rebuilds before
    the layers recompute (its slots are connected first): for that moment a layer has fewer
    frames than the document and shows its last one. A marker layer before a motion layer
    does not stop the motion layer's frame."""
    state = StudioState()
    state.open_document(snapshot_of(figure_motion(6)), "a.gmr")
    layers = Layers(state)
    points = np.arange(4 * 2 * 3, dtype=float).reshape(4, 2, 3) / 10  # four frames of six
    markers = MarkerSet(labels=("m0", "m1"), positions=points, rate=30.0, units="m")
    with scene_of(state.snapshot) as scene:
        ghosts = GhostLayers(state, layers)
        scene.add_drawable(ghosts)
        layers.layers.append(
            MarkerLayer(markers, "m.trc", (0.9, 0.1, 0.5), overlay=MarkerOverlay(markers, None, points))
        )
        whole = posed_motion(
            FIGURE_NAMES, FIGURE_PARENTS, figure_world(6) + np.array([0.0, 0.0, 0.05]), FIGURE_SOFT_PARENTS
        )
        layer = layers.add(snapshot_of(whole), "b.gmr", offset=0.0, align="none")
        (spheres,), (_, joints) = ghosts.ghosts
        scene.show_frame(5)  # the ghost's last frame (B has all six)
        np.testing.assert_allclose(joints.mesh.points, layer.ghost[5][[0]])
        np.testing.assert_allclose(spheres.mesh.points, points[3])
        scene.show_frame(1)
        np.testing.assert_allclose(joints.mesh.points, layer.ghost[1][[0]])
        np.testing.assert_allclose(spheres.mesh.points, points[1])
        layer.ghost = layer.ghost[:3]  # as computed for a three-frame document
        scene.redraw(ghosts)
        (spheres,), (bones, joints) = ghosts.ghosts
        scene.show_frame(4)
        np.testing.assert_allclose(joints.mesh.points, layer.ghost[2][[0]])
        np.testing.assert_allclose(bones.mesh.points, layer.ghost[2][bones.pairs].mean(axis=1))  # its last frame
        assert not np.allclose(layer.ghost[1][bones.pairs].mean(axis=1), bones.mesh.points)  # not the one before
        np.testing.assert_allclose(spheres.mesh.points, points[3])


def test_hiding_writes_no_frame_and_needs_no_scene(qtbot):
    state = StudioState()
    lone = GhostLayers(state, Layers(state))
    lone.set_visible(False)  # not in a scene yet: nothing to write
    lone.set_visible(True)
    assert lone.visible and lone.parts == {}
    with compared(qtbot) as (scene, _state, layers, ghosts):
        bones = ghosts.parts["ghost_0_0"]
        ghost = layers[0].ghost
        assert not np.allclose(ghost[1][bones.pairs].mean(axis=1), ghost[2][bones.pairs].mean(axis=1))
        scene.show_frame(1)
        ghosts.set_visible(False)
        scene.show_frame(2)  # hidden drawables are skipped...
        ghosts.set_visible(False)  # ... and hiding again writes nothing either
        np.testing.assert_allclose(bones.mesh.points, ghost[1][bones.pairs].mean(axis=1))


def test_the_layers_box_is_their_ghosts_markers_and_the_compared_joints_grown_by_an_error_joint(qtbot):
    """The box the layers may draw in at any frame: each layer's ghost (or markers) at every
    frame and, in the error view, both ends of the error lines (A's and B's compared joints),
    grown by an error joint's radius; measured once a build; no layer: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of, union_box

    state = StudioState()
    state.open_document(snapshot_of(figure_motion(6)), "a.gmr")
    with scene_of(state.snapshot) as scene:
        ghosts = GhostLayers(state, Layers(state))
        scene.add_drawable(ghosts)
        np.testing.assert_array_equal(ghosts.extent(), EMPTY_BOX)
    with compared(qtbot) as (scene, state, layers, ghosts):
        pad = ERROR_JOINT_RADIUS * FIGURE_SIZE
        comparison = layers[0].comparison
        ends = [box_of(comparison.positions_a, pad), box_of(comparison.positions_b, pad)]
        box = ghosts.extent()
        np.testing.assert_array_equal(box, union_box([box_of(layers[0].ghost, pad), *ends]))
        for frame in range(6):
            scene.show_frame(frame)
            for part in (*ghosts.ghosts[0], ghosts.error_lines):
                points = part.mesh.points
                assert (points >= box[0]).all() and (points <= box[1]).all(), frame
        ghosts.set_show_errors(False)  # no error lines: the ghost alone
        np.testing.assert_array_equal(ghosts.extent(), box_of(layers[0].ghost, pad))
        points = np.full((6, 1, 3), 7.0)
        markers = MarkerSet(labels=("m0",), positions=points, rate=30.0, units="m")
        overlay = MarkerOverlay(markers, None, points)
        layers.layers.append(MarkerLayer(markers, "m.trc", (0.9, 0.1, 0.5), overlay=overlay))
        layers.changed.emit()
        np.testing.assert_array_equal(ghosts.extent(), union_box([box_of(layers[0].ghost, pad), box_of(points, pad)]))


# ------------------------------------------------------------------------ the legend
def ramp(values: np.ndarray, top: float = 2.0) -> np.ndarray:
    """A colour map that tells every value of [0, top] apart by its red: (N,) -> (N, 3)."""
    t = np.asarray(values) / top
    return np.column_stack([t, 1.0 - t, 0.25 + 0.5 * t])


def piece_centre(box) -> np.ndarray:
    x0, y0, x1, y1 = box
    return np.array([(x0 + x1) / 2, (y0 + y1) / 2])


@pytest.mark.parametrize(("top", "units"), [(2.0, "a unit with a long name"), (1234.5, "m")])
def test_the_legend_is_a_bar_from_zero_at_the_bottom_to_the_top_with_its_labels_beside_it(top, units):
    """The picture (rows bottom first): the colour map's bar from 0 at its bottom to ``top``
    at its top, each label beside the bar at its value's height, the title centred above;
    nothing drawn outside these pieces, and no empty margin around them."""
    image, boxes = legend_layout(top, units, lambda v: ramp(v, top))
    height, width = image.shape[:2]
    assert image.dtype == np.uint8 and image.shape[2] == 4 and boxes.shape == (7, 4)
    bar, labels, title = boxes[0], boxes[1:6], boxes[6]
    x0, y0, x1, y1 = bar
    assert x0 == 0 and x1 - x0 >= 10 and y1 - y0 >= 100  # a bar, taller than wide, at the left
    rows = image[y0:y1, x0:x1]
    assert (rows[..., 3] == 255).all() and (rows == rows[:, :1]).all()  # opaque, one colour a row
    values = rows[:, 0, 0] / 255 * top  # each row's value, read back from the ramp's red
    assert (np.diff(values) >= 0).all() and values[0] < 0.01 * top and values[-1] > 0.99 * top
    for k, label in enumerate(labels):  # 0, a quarter of the top, ... the top
        assert label[0] >= x1 + 2  # right of the bar, a gap between
        level = y0 + k / 4 * (y1 - y0)  # where the bar reaches the label's value
        assert abs(piece_centre(label)[1] - level) <= 1, k  # the label's middle within a pixel
    assert (labels[:, 0] == labels[0, 0]).all()  # one column of labels
    assert title[3] == height  # the title at the top, just above the top label, the gap between
    assert LABEL_GAP <= title[1] - labels[:, 3].max() <= LABEL_GAP + 1
    assert abs(piece_centre(title)[0] - width / 2) <= 1
    assert boxes[:, 2].max() == width and boxes[:, 1].min() <= 1  # no margin but the lowest label's half row
    inside = np.zeros((height, width), bool)
    for a, b, c, d in boxes:
        inside[b:d, a:c] = True
    assert not image[~inside].any()  # every texel drawn is in a piece
    letters = image[labels[0, 1] : labels[0, 3], labels[0, 0] : labels[0, 2]]
    written = letters[letters[..., 3] > 0][:, :3]
    assert (written == written[:, :1]).all() and written.max() > 200  # light grey text


def test_the_legend_is_drawn_one_texel_a_pixel_at_the_views_lower_right_upright():
    part = legend_part(2.0, "m", ramp)
    height, width = part.image.shape[:2]
    assert part.top == 2.0 and isinstance(part.top, float)
    assert not part.outline.any()  # not placed yet
    pieces = legend_layout(2.0, "m", ramp)[1]  # each quad holds its piece and a texel around it
    assert (part.boxes[:, :2] <= pieces[:, :2]).all() and (part.boxes[:, 2:] >= pieces[:, 2:]).all()
    assert (part.boxes[:, :2] >= pieces[:, :2] - 2).all() and (part.boxes[:, 2:] <= pieces[:, 2:] + 2).all()
    assert (
        (part.boxes >= 0).all() and (part.boxes[:, [0, 2]] <= width).all() and (part.boxes[:, [1, 3]] <= height).all()
    )
    assert part.draw_last and not part.actor.GetUseBounds()
    size = (800, 600)
    with scene_of(None, size=size) as scene:
        scene.plotter.set_background((0, 0, 0))
        scene.plotter.renderer.AddActor(part.actor)
        scene.plotter.renderer.ResetCameraClippingRange()
        part.place(size)
        image = picture(scene)
    left, bottom, right, top = part.outline
    assert (right - left, top - bottom) == (width, height)  # room enough: one texel a pixel
    assert left > 0.6 * size[0] and right <= size[0] - EDGE  # at the right, off its edge
    assert 0.05 * size[1] < bottom < 0.2 * size[1]  # low, a margin below it
    np.testing.assert_allclose(part.corners, np.array([left, bottom]) + box_corners(part.boxes))
    x0, y0 = round(left), round(bottom)
    drawn = image[size[1] - y0 - height : size[1] - y0, x0 : x0 + width][::-1]  # rows bottom first
    over_black = part.image[..., :3].astype(int) * part.image[..., 3:].astype(int) // 255
    assert np.abs(drawn - over_black).max() <= 3  # upright: its bottom row at the bottom
    outside = image.copy()
    outside[size[1] - y0 - height : size[1] - y0, x0 : x0 + width] = 0
    assert not outside.any()


@pytest.mark.parametrize("view", [(1000, 1000), (1000, 200), (200, 1000), (300, 200), (10, 1000), (120, 90)])
def test_a_legend_is_shrunk_never_enlarged_and_moved_to_stay_in_the_view(view):
    legend = (100, 200)
    shift, scale = legend_fit(view, legend)
    assert 0 < scale <= 1
    if view[0] >= 3 * legend[0] and view[1] >= 2 * legend[1]:
        assert (shift, scale) == (0.0, 1.0)  # room enough: as drawn
    part = legend_part(2.0, "m", ramp)
    width, height = part.image.shape[1], part.image.shape[0]
    part.place(view)
    left, bottom, right, top = part.outline
    assert left >= -1e-9 and right <= view[0] + 1e-9 and bottom >= 0 and top <= view[1]  # inside the view
    assert right <= view[0] - EDGE + 1e-9 or left == pytest.approx(0.0)  # off the right side unless too narrow
    assert right - left == pytest.approx(part.fitted[1] * width) and top - bottom == pytest.approx(
        part.fitted[1] * height
    )


def test_a_shrunk_legend_is_smoothed_and_comes_back_sharp_with_room():
    part = legend_part(2.0, "m", ramp)
    height, width = part.image.shape[:2]
    assert part.fitted == (0.0, 1.0)  # as built: one texel a pixel
    part.fit((2000, 2000))  # room enough: as built
    assert part.fitted == (0.0, 1.0) and not part.actor.GetTexture().GetInterpolate()
    part.place((300, 200))
    shift, scale = part.fitted
    assert scale < 1 and shift > 0 and part.actor.GetTexture().GetInterpolate()
    left, bottom = part.outline[:2]
    np.testing.assert_allclose(part.outline[2:], [left + scale * width, bottom + scale * height])
    np.testing.assert_allclose(part.corners, (left, bottom) + scale * box_corners(part.boxes))  # each piece with it
    part.place((2000, 2000))  # room again: one texel a pixel
    np.testing.assert_allclose(part.outline[2:] - part.outline[:2], [width, height])
    assert not part.actor.GetTexture().GetInterpolate()


def test_the_error_views_legend_is_the_maps_bar_at_the_views_right_green_below_red_above(qtbot):
    with compared(qtbot, size=(400, 400)) as (scene, _state, _layers, ghosts):
        for overlay in ("ground", "soft_links"):
            scene.set_overlay(overlay, False)
        legend = ghosts.legend
        assert ghosts.parts["error_legend"] is legend and holds(scene.plotter.renderer, legend.actor)
        assert legend.top == pytest.approx(HAND_ERROR, rel=1e-12)
        image = picture(scene)
        (x0, y0), (x1, _), (_, y1) = legend.corners[0, :3]  # the bar's quad: its texel around it too
        x = int((x0 + x1) / 2)
        low, high = 400 - 1 - int(y0 + 3), 400 - 1 - int(y1 - 3)  # image rows, from the top
        green, red = rgb_bytes(error_colours(np.array([0.0, HAND_ERROR]), HAND_ERROR))
        assert np.abs(image[low, x] - green).max() <= 8 and np.abs(image[high, x] - red).max() <= 8
        assert x > 0.6 * 400 and legend.outline[2] <= 400 - EDGE
        assert np.abs(image[400 - 1 - int(y0 - 4), x] - image[2, 2]).max() <= 2  # below the bar: the background
        ghosts.set_show_errors(False)
        assert np.abs(picture(scene)[high, x] - image[2, 2]).max() <= 2


def test_in_a_small_view_the_error_views_legend_is_shrunk_and_kept_off_the_right_side(qtbot):
    with compared(qtbot, size=(200, 150)) as (scene, _state, _layers, ghosts):
        for overlay in ("ground", "soft_links"):
            scene.set_overlay(overlay, False)
        image = picture(scene)  # rendered: the legend fitted before the render
        legend = ghosts.legend
        shift, scale = legend.fitted
        assert scale < 1 and shift > 0 and legend.actor.GetTexture().GetInterpolate()
        background = image[2, 2]
        drawn = np.abs(image - background).max(axis=-1) > 30
        drawn[:, :120] = False  # the figure is at the view's left and centre
        columns, rows = np.flatnonzero(drawn.any(axis=0)), np.flatnonzero(drawn.any(axis=1))
        assert columns.max() <= 200 - EDGE and rows.min() >= 150 - legend.outline[3] - 2
        red = rgb_bytes(error_colours(np.array([ghosts.top]), ghosts.top))[0]
        assert (np.abs(image[rows.min() : rows.min() + 40, 120:] - red).max(axis=-1) <= 12).any()  # the bar's top
