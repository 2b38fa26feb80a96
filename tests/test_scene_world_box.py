"""The near and far planes fitted to the box everything shown may occupy over the take
(app/scene/drawable.py box_of, union_box, Drawable.extent; SkeletonScene.world_box), not to
VTK's measure of every actor at every render; VTK's frustum culler taken out."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing, box_of, union_box
from gmr_studio.app.scene.figure import JOINT_RADIUS
from gmr_studio.app.scene.overlays import AXIS_LENGTH
from tests.tiny_scene import (
    FIGURE_NAMES,
    FIGURE_PARENTS,
    FIGURE_SIZE,
    FIGURE_SOFT_PARENTS,
    figure_motion,
    figure_world,
    posed_motion,
    scene_of,
    snapshot_of,
)

pytestmark = pytest.mark.gui


def test_a_box_holds_the_finite_points_grown_by_its_pad_and_a_union_holds_every_box():
    points = np.array([[[0.0, 1.0, 2.0], [np.nan, 5.0, 5.0]], [[-1.0, 3.0, 0.5], [2.0, np.inf, 1.0]]])
    np.testing.assert_array_equal(box_of(points), [[-1.0, 1.0, 0.5], [0.0, 3.0, 2.0]])  # a point with NaN or inf out
    np.testing.assert_array_equal(box_of(points, 0.5), [[-1.5, 0.5, 0.0], [0.5, 3.5, 2.5]])
    np.testing.assert_array_equal(box_of(np.full((2, 3), np.nan)), EMPTY_BOX)
    np.testing.assert_array_equal(box_of(np.zeros((0, 3))), EMPTY_BOX)
    a, b = np.array([[0.0, 0, 0], [1, 1, 1]]), np.array([[-1.0, 0.5, 2], [0.5, 3, 4]])
    np.testing.assert_array_equal(union_box([a, b]), [[-1.0, 0, 0], [1, 3, 4]])
    np.testing.assert_array_equal(union_box([a, EMPTY_BOX]), a)
    np.testing.assert_array_equal(union_box([]), EMPTY_BOX)
    assert not np.isfinite(union_box([])).any()


def _render(scene) -> None:
    """A render of the scene (the clipping planes fitted just before it)."""
    scene.render(now=True)
    scene.plotter.ren_win.Render()


def _vtk_bounds(scene) -> np.ndarray:
    bounds = np.array(scene.plotter.renderer.ComputeVisiblePropBounds())
    return np.stack([bounds[0::2], bounds[1::2]])


def test_the_planes_fit_the_takes_box_which_holds_everything_drawn_at_every_frame():
    with scene_of(snapshot_of(figure_motion(5))) as scene:
        assert scene.plotter.renderer.GetCullers().GetNumberOfItems() == 0  # no frustum culler
        scene.set_selection(5)
        for name in ("axes", "trails", "labels"):
            scene.set_overlay(name, True)
        box = scene.world_box()
        world = figure_world(5)
        ring = 2.0 * JOINT_RADIUS * FIGURE_SIZE
        low, high = world.reshape(-1, 3).min(axis=0), world.reshape(-1, 3).max(axis=0)
        ground = scene.ground.box
        np.testing.assert_allclose(box[0], np.minimum(low - max(ring, AXIS_LENGTH * FIGURE_SIZE), ground[0]))
        np.testing.assert_allclose(box[1], np.maximum(high + max(ring, AXIS_LENGTH * FIGURE_SIZE), ground[1]))
        camera = scene.plotter.renderer.GetActiveCamera()
        for frame in range(5):
            scene.show_frame(frame)
            _render(scene)
            drawn = _vtk_bounds(scene)  # VTK's own measure of what is drawn at this frame
            assert (drawn[0] >= box[0] - 1e-12).all() and (drawn[1] <= box[1] + 1e-12).all(), frame
            near, far = camera.GetClippingRange()
            scene.plotter.renderer.ResetCameraClippingRange(*box.T.ravel())
            assert camera.GetClippingRange() == pytest.approx((near, far))  # fitted to the box
            scene.plotter.renderer.ResetCameraClippingRange()
            tight = camera.GetClippingRange()
            assert near <= tight[0] and far >= tight[1]  # so nothing drawn is clipped


def test_the_box_leaves_out_what_is_hidden_and_follows_a_new_document():
    with scene_of(snapshot_of(figure_motion(3))) as scene:
        with_ground = scene.world_box()
        scene.set_overlay("ground", False)
        without = scene.world_box()
        np.testing.assert_allclose(without, box_of(figure_world(3), 2.0 * JOINT_RADIUS * FIGURE_SIZE))
        assert (with_ground[0] <= without[0]).all() and (with_ground[1] >= without[1]).all()
        assert not np.array_equal(with_ground, without)
        world = figure_world(3)
        world[:, 1:, 0] += 10.0  # all but the fixed root 10 further along x
        moved = posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS)
        scene.set_snapshot(snapshot_of(moved), reset_camera=False)
        assert scene.world_box()[1, 0] == pytest.approx(without[1, 0] + 10.0)


FAR = (0.0, 0.0, -40.0)  # far beyond the figure, in front of the camera


class _Unknown(Drawing):
    """A drawing that cannot say where it draws (extent None)."""

    def build(self, scene) -> None:
        super().build(scene)
        self.add("far", _far_part())

    def show_frame(self, frame: int) -> None:
        pass


def _far_part():
    from gmr_studio.app.scene import vtk_parts as parts

    part = parts.sphere_part(1, 0.1)
    part.set_points(np.array([FAR]))
    return part


def test_a_drawable_or_a_prop_that_cannot_say_where_it_draws_has_vtk_measure_everything():
    with scene_of(snapshot_of(figure_motion(3))) as scene:
        assert scene.world_box() is not None
        camera = scene.plotter.renderer.GetActiveCamera()
        _render(scene)
        depth = np.dot(np.subtract(FAR, camera.GetPosition()), camera.GetDirectionOfProjection())
        assert camera.GetClippingRange()[1] < 30 < depth  # the take's box ends well before it
        unknown = _Unknown()
        scene.add_drawable(unknown)
        assert scene.world_box() is None
        _render(scene)
        assert depth < camera.GetClippingRange()[1]  # VTK measured the far sphere: it is not clipped
        unknown.set_visible(False)
        assert scene.world_box() is not None  # hidden: it draws nothing
        scene.remove_drawable(unknown)
        actor = scene.plotter.add_mesh(pv.Sphere(center=FAR))  # a prop no drawable made
        assert scene.world_box() is None
        scene.plotter.remove_actor(actor)
        assert scene.world_box() is not None


def test_every_part_sends_its_points_unshifted_and_a_figure_far_from_the_origin_draws_the_same():
    """Drawing.add turns VTK's shift and scale off (vtk_parts.unshifted): every mapper in the
    scene takes its points as they are. A figure moved 2000 of its sizes from the origin,
    with the camera moved alike, draws the same picture as at the origin (float32 keeps
    ~1e-4 of the size there)."""
    from vtkmodules.vtkRenderingCore import vtkPolyDataMapper

    from tests.tiny_scene import look_down_at, picture

    shift = np.array([1600.0, 0.0, -1200.0])
    images = []
    for offset in (np.zeros(3), shift):
        world = figure_world(3) + offset
        with scene_of(
            snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS)), (300, 300)
        ) as scene:
            props = scene.plotter.renderer.GetViewProps()
            mappers = [props.GetItemAsObject(i).GetMapper() for i in range(props.GetNumberOfItems())]
            methods = {m.GetVBOShiftScaleMethod() for m in mappers if hasattr(m, "GetVBOShiftScaleMethod")}
            assert methods == {vtkPolyDataMapper.DISABLE_SHIFT_SCALE}
            look_down_at(scene, offset + np.array([0.05, 0.2, 0.0]), 0.3)  # chest, head and arm
            scene.show_frame(1)
            images.append(picture(scene))
    differing = np.abs(images[0] - images[1]).max(axis=-1) > 40
    figure = np.abs(images[0] - images[0][0, 0]).max(axis=-1) > 20  # not the background
    assert figure.sum() > 300  # the figure is in the picture
    assert differing.sum() <= 12  # a few edge pixels at most


class _InFront(Drawing):
    """A drawing in the front layer that says where it draws (a dot at (0, 5, 0))."""

    front = True

    def build(self, scene) -> None:
        from gmr_studio.app.scene import vtk_parts as parts

        super().build(scene)
        dot = parts.sphere_part(1, 0.1)
        dot.set_points(np.array([[0.0, 5.0, 0.0]]))
        self.add("dot", dot)

    def show_frame(self, frame: int) -> None:
        pass

    def extent(self) -> np.ndarray:
        return box_of(np.array([[0.0, 5.0, 0.0]]), 0.1)


def test_a_front_layer_drawing_counts_in_the_box_but_not_among_the_main_renderers_props():
    """The main renderer holds the props of the drawables not in front; a front drawing's
    parts are in the front layer, and its box joins the others'."""
    with scene_of(snapshot_of(figure_motion(3))) as scene:
        before = scene.world_box()
        props = scene.plotter.renderer.GetViewProps().GetNumberOfItems()
        front = _InFront()
        scene.add_drawable(front)
        assert scene.plotter.renderer.GetViewProps().GetNumberOfItems() == props  # its dot not in the main renderer
        np.testing.assert_array_equal(scene.world_box(), union_box([before, box_of(np.array([[0.0, 5.0, 0.0]]), 0.1)]))
        front.set_visible(False)
        np.testing.assert_array_equal(scene.world_box(), before)


def test_the_documents_box_is_measured_once_a_snapshot(monkeypatch):
    from gmr_studio.app.scene import scene as scene_module

    measured = []
    monkeypatch.setattr(scene_module, "box_of", lambda points: measured.append(points) or box_of(points))
    with scene_of(snapshot_of(figure_motion(3))) as scene:
        measured.clear()
        first = scene.document_box()
        np.testing.assert_array_equal(first, box_of(scene.snapshot.positions))
        np.testing.assert_array_equal(scene.document_box(0.5), [first[0] - 0.5, first[1] + 0.5])
        assert len(measured) <= 1  # measured at most once (maybe already, while the scene was built)
        scene.document_box()
        assert len(measured) <= 1
        scene.set_snapshot(snapshot_of(figure_motion(4)), reset_camera=False)
        measured.clear()
        np.testing.assert_array_equal(scene.document_box(), box_of(scene.snapshot.positions))
        assert scene.document_box()[1, 0] == pytest.approx(0.8 + 0.15)  # the four frames' (the hand at 0.8 + 0.05 f)
        scene.document_box(1.0)
        assert len(measured) <= 1
        scene.document_box()
        assert len(measured) <= 1
