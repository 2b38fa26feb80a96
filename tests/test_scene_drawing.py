"""What the scene draws (app/scene/scene.py, app/scene/drawable.py) on the tiny synthetic
skeleton (:mod:`tests.tiny_scene`): drawables built for a document or an edit, their named
parts in the main renderer or the front layer, a frame written into every visible drawable,
the overlays' and the selection's switches, markers and the pelvis triad, the near and far
planes fitted before a render, the front layer drawn over the scene, and the light."""

from __future__ import annotations

import inspect
from types import SimpleNamespace

import numpy as np
import pytest

from gmr_studio.app.model.state import OVERLAYS
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import Drawing
from gmr_studio.app.scene.scene import BACKGROUND, SkeletonScene, another_space
from gmr_studio.app.scene.vtk_parts import sphere_part
from gmr_studio.core.space.up_axis import Y_TO_Z, up_axis_of
from tests.tiny_scene import (
    FIGURE_NAMES,
    FIGURE_PARENTS,
    FIGURE_SOFT_PARENTS,
    figure_motion,
    figure_world,
    holds,
    look_down_at,
    picture,
    posed_motion,
    props_of,
    scene_of,
    snapshot_of,
)

pytestmark = pytest.mark.gui


class Probe(Drawing):
    """A drawable that notes what the scene asks of it: one sphere at joint ``joint``."""

    def __init__(self, joint: int = 3, shown: bool = True) -> None:
        super().__init__()
        self.joint, self.shown = joint, shown
        self.builds, self.frames, self.hooks = 0, [], 0

    def build(self, scene) -> None:
        super().build(scene)
        self.builds += 1
        if scene.snapshot is not None:
            self.add("probe", sphere_part(1, 0.01))

    def wanted(self, scene) -> bool:
        return self.shown

    def show_frame(self, frame: int) -> None:
        self.frames.append(frame)
        self.parts["probe"].set_points(self.scene.snapshot.positions[frame, [self.joint]])

    def before_render(self) -> None:
        self.hooks += 1


class Dots(Drawing):
    """A sphere at each joint (the part ``dots``), and a one-point part ``spare``."""

    def build(self, scene) -> None:
        super().build(scene)
        self.add("dots", parts.sphere_part(scene.snapshot.motion.n_joints, 0.01))
        self.add("spare", parts.sphere_part(1, 0.01))

    def show_frame(self, frame: int) -> None:
        self.parts["dots"].set_points(self.scene.snapshot.positions[frame])


class FrontDots(Dots):
    front = True


class OnlyDots(Dots):
    """Wants its ``dots`` shown, never its ``spare``."""

    def part_wanted(self, part) -> bool:
        return part is self.parts.get("dots")


def scaled(factor: float, n_frames: int = 3):
    """The figure ``factor`` times as large (its size too)."""
    world = figure_world(n_frames) * factor
    return snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS))


def z_up(n_frames: int = 3):
    """The figure stood up along z (y and z swapped)."""
    world = figure_world(n_frames)[..., [0, 2, 1]]
    return snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS))


def turned_z_up(factor: float = 1.0, n_frames: int = 3):
    """The figure ``factor`` times as large with its world turned Z up, as Edit > Up axis turns it."""
    world = figure_world(n_frames) * factor @ Y_TO_Z.T
    return snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS))


def camera_of(scene) -> tuple:
    camera = scene.plotter.camera
    return camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp()


def window_image(scene) -> np.ndarray:
    """(H, W, 3) int: the render window drawn as it stands (as the widget's repaint draws it),
    without the scene's own render."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    window = scene.plotter.ren_win
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    width, height, _ = grab.GetOutput().GetDimensions()
    pixels = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(height, width, -1)
    return pixels[::-1, :, :3].astype(int)


def drawn_mask(scene, image=None) -> np.ndarray:
    """(H, W) bool: the pixels drawn over the background (in ``image``, else a picture)."""
    image = picture(scene) if image is None else image
    return np.abs(image - np.rint(np.asarray(BACKGROUND) * 255)).max(axis=-1) > 10


# ------------------------------------------------------------------- the document
def test_another_space_is_a_size_changed_fivefold_or_more():
    def moved(before, after):
        return another_space(*(SimpleNamespace(motion=SimpleNamespace(size=s)) for s in (before, after)))

    assert moved(1.0, 5.0) and moved(1.0, 0.2) and moved(1.0, 25.4) and moved(25.4, 1.0)
    assert not moved(1.0, 4.99) and not moved(1.0, 0.201) and not moved(1.0, 1.0) and not moved(2.0, 1.0)
    assert not moved(10.0, 10.0) and not moved(0.1, 0.1)  # the ratio of the sizes, not their product


def test_the_up_axis_is_the_one_the_figure_stands_along():
    assert up_axis_of(snapshot_of(figure_motion()).motion) == "y"
    assert up_axis_of(z_up().motion) == "z"


def test_a_new_scene_draws_nothing_over_its_background():
    with scene_of(None) as scene:
        assert scene.plotter.renderer.GetBackground() == pytest.approx(BACKGROUND, abs=1 / 255)
        assert scene.snapshot is None and scene.frame == 0 and scene.selected is None
        assert scene.overlays == OVERLAYS and scene.overlays is not OVERLAYS
        assert scene.up_axis == 1 and scene.new_document
        assert scene.parts == {} and not scene.is_shown("joints")
        assert scene.markers is None and scene.pelvis is None
        assert scene.hovered_marker is None and scene.selected_marker is None
        assert scene.ground_bounds is None
        scene.show_frame(2)  # nothing to show
        assert scene.frame == 0
        scene.render(now=True)
        assert not drawn_mask(scene).any()


def test_a_document_builds_every_drawable_and_shows_what_the_overlays_ask_for():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        assert scene.snapshot is snapshot and scene.new_document is False and scene.up_axis == 1
        names = {"ground", "joints", "bones", "selection", "soft_links", "axes", "trails", "labels"}
        assert names <= set(scene.parts)
        assert scene.parts["joints"] is scene.figure.parts["joints"]
        assert scene.is_shown("ground") and scene.is_shown("joints") and scene.is_shown("soft_links")
        assert not scene.is_shown("axes") and not scene.is_shown("trails") and not scene.is_shown("labels")
        assert not scene.is_shown("markers")  # no marker overlay: no part
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, snapshot.positions[0])
        np.testing.assert_allclose(scene.figure_positions(), snapshot.positions[:, 1:])  # the anchor left out
        figure = snapshot.positions[:, 1:].reshape(-1, 3)
        np.testing.assert_array_equal(scene.figure_box(), [figure.min(axis=0), figure.max(axis=0)])


def test_a_z_up_document_gets_a_z_up_camera():
    with scene_of(z_up()) as scene:
        assert scene.up_axis == 2
        assert camera_of(scene)[2] == pytest.approx((0.0, 0.0, 1.0))


def test_an_edit_keeps_the_ground_and_camera_a_new_document_makes_them_afresh():
    with scene_of(snapshot_of(figure_motion())) as scene:
        scene.set_overlay("follow", False)  # the camera stays where it is unless made afresh
        ground, camera = scene.parts["ground"].actor, camera_of(scene)
        bounds = scene.ground_bounds
        scene.set_snapshot(scaled(2.0), reset_camera=False)  # an edit in the same space
        assert scene.parts["ground"].actor is ground and camera_of(scene) == camera
        assert scene.new_document is False
        seen = scene.joint_screen_positions()
        scene.set_snapshot(turned_z_up(2.0), reset_camera=False)  # Edit > Up axis: Z up
        assert scene.up_axis == 2 and scene.parts["ground"].actor is not ground  # the floor under it
        np.testing.assert_allclose(scene.joint_screen_positions(), seen, atol=1e-6)  # seen as it was
        scene.set_snapshot(scaled(2.0), reset_camera=False)  # and undone: back on Y, still seen so
        assert scene.up_axis == 1
        np.testing.assert_allclose(scene.joint_screen_positions(), seen, atol=1e-6)
        ground = scene.parts["ground"].actor
        scene.set_snapshot(scaled(10.0), reset_camera=False)  # another space: made afresh
        assert scene.parts["ground"].actor is not ground and camera_of(scene) != camera
        assert scene.ground_bounds[1][0] > 5 * bounds[1][0]
        ground = scene.parts["ground"].actor
        scene.set_snapshot(z_up(), reset_camera=True)  # a new document
        assert scene.up_axis == 2 and scene.parts["ground"].actor is not ground
        assert scene.new_document is False


def test_a_first_document_after_none_is_a_new_document_even_without_a_reset():
    with scene_of(None) as scene:
        scene.set_overlay("follow", True)  # no document to follow
        scene.set_snapshot(z_up(), reset_camera=False)
        assert scene.up_axis == 2 and scene.is_shown("ground") and scene.new_document is False
        assert drawn_mask(scene).any()


def test_a_shorter_document_clamps_the_frame_and_none_takes_everything_out():
    with scene_of(snapshot_of(figure_motion(6))) as scene:
        scene.show_frame(5)
        shorter = snapshot_of(figure_motion(3))
        scene.set_snapshot(shorter, reset_camera=False)
        assert scene.frame == 2
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, shorter.positions[2])
        actors = [part.actor for part in scene.parts.values()]
        scene.set_snapshot(None, reset_camera=False)
        assert scene.snapshot is None and scene.parts == {}
        assert not any(holds(scene.plotter.renderer, actor) for actor in actors)
        assert not drawn_mask(scene).any()


# ------------------------------------------------------------------------ frames
def test_a_frame_is_clamped_and_written_into_the_visible_drawables_only():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        shown, hidden = Probe(), Probe(shown=False)
        scene.add_drawable(shown)
        scene.add_drawable(hidden)
        scene.show_frame(7)
        assert scene.frame == 2 and shown.frames[-1] == 2 and hidden.frames == []
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, snapshot.positions[2])
        scene.show_frame(-4)
        assert scene.frame == 0 and shown.frames[-1] == 0
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, snapshot.positions[0])
        scene.show_frame(1, render=False)
        assert scene.frame == 1 and isinstance(scene.frame, int) and shown.frames[-1] == 1
        scene.show_frame(np.int64(2))
        assert type(scene.frame) is int and scene.frame == 2


def test_an_added_drawable_is_built_and_shown_at_the_frame_in_drawing_order():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        scene.show_frame(1)
        last, first = Probe(), Probe(joint=5)
        scene.add_drawable(last)
        scene.add_drawable(first, before=scene.figure)
        assert scene.drawables.index(first) == scene.drawables.index(scene.figure) - 1
        assert scene.drawables[-1] is last
        for probe in (first, last):
            assert probe.builds == 1 and probe.frames == [1] and probe.visible
            assert holds(scene.plotter.renderer, probe.parts["probe"].actor)
        np.testing.assert_allclose(first.parts["probe"].mesh.points, snapshot.positions[1, [5]])
        unwanted = Probe(shown=False)
        scene.add_drawable(unwanted)
        assert not unwanted.visible and unwanted.frames == [] and not unwanted.parts["probe"].visible


def test_a_removed_drawable_takes_its_actors_out():
    with scene_of(snapshot_of(figure_motion())) as scene:
        probe = Probe()
        scene.add_drawable(probe)
        actor = probe.parts["probe"].actor
        scene.remove_drawable(probe)
        assert probe not in scene.drawables and not holds(scene.plotter.renderer, actor)
        scene.remove_drawable(probe)  # not drawn any more: nothing to do
        assert probe not in scene.drawables


def test_redrawing_builds_again_at_the_frame_shown():
    with scene_of(snapshot_of(figure_motion())) as scene:
        probe = Probe()
        scene.add_drawable(probe)
        scene.show_frame(2)
        scene.redraw(probe)
        assert probe.builds == 2 and probe.frames[-1] == 2
        scene.redraw(probe, render=False)
        assert probe.builds == 3 and probe.frames[-1] == 2
        probe.shown = False
        frames = len(probe.frames)
        scene.redraw(probe)
        assert not probe.visible and len(probe.frames) == frames
    with scene_of(None) as scene:  # no document: built, never shown
        probe = Probe()
        scene.add_drawable(probe)
        assert probe.builds == 1 and probe.frames == [] and probe.parts == {}


def test_the_options_are_keywords_only():
    for method, option in ((SkeletonScene.set_snapshot, "reset_camera"), (SkeletonScene.add_drawable, "before")):
        assert inspect.signature(method).parameters[option].kind == inspect.Parameter.KEYWORD_ONLY
    assert inspect.signature(SkeletonScene.redraw).parameters["render"].kind == inspect.Parameter.KEYWORD_ONLY


# ------------------------------------------------------------- overlays and selection
def test_switching_an_overlay_shows_or_hides_its_part_at_once():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        scene.show_frame(1)
        scene.set_overlay("axes", True)
        assert scene.overlays["axes"] is True and scene.is_shown("axes")
        assert scene.parts["axes"].mesh.points[0] == pytest.approx(snapshot.positions[1, 0])
        scene.set_overlay("ground", 0)
        assert scene.overlays["ground"] is False and not scene.is_shown("ground")
        scene.set_overlay("trails", True)  # a trail needs a selection
        assert not scene.is_shown("trails")
        scene.set_selection(5)
        assert scene.selected == 5 and scene.is_shown("trails") and scene.is_shown("selection")
        np.testing.assert_allclose(scene.parts["selection"].mesh.points, snapshot.positions[1, [5]])
        scene.set_selection(None)
        assert not scene.is_shown("trails") and not scene.is_shown("selection")


def markers_overlay(n_frames: int = 3):
    """Two markers: one 0.1 right of the Head, one missing at frame 1."""
    positions = np.repeat(np.array([[[0.1, 0.6, 0.0], [0.5, 0.2, 0.0]]]), n_frames, axis=0)
    positions[1, 1] = np.nan
    return SimpleNamespace(positions=positions, markers=SimpleNamespace(labels=["HEAD", "ARM"]))


def test_markers_are_drawn_and_their_highlight_forgotten_with_a_new_set():
    with scene_of(snapshot_of(figure_motion())) as scene:
        overlay = markers_overlay()
        scene.set_markers(overlay)
        assert scene.markers is overlay and scene.is_shown("markers")
        np.testing.assert_allclose(scene.parts["markers"].mesh.points, overlay.positions[0])
        scene.set_marker_highlight(0, 1)
        assert scene.hovered_marker == 0 and scene.selected_marker == 1
        assert scene.is_shown("marker_selection") and scene.is_shown("marker_labels")
        scene.show_frame(1)  # the selected marker missing: no ring
        assert not scene.is_shown("marker_selection")
        scene.set_marker_highlight(None, 0)
        assert scene.is_shown("marker_selection")
        np.testing.assert_allclose(scene.parts["marker_selection"].mesh.points, overlay.positions[1, [0]])
        scene.set_markers(markers_overlay())
        assert scene.hovered_marker is None and scene.selected_marker is None
        assert not scene.is_shown("marker_selection") and not scene.is_shown("marker_labels")
        scene.set_overlay("markers", False)
        assert not scene.is_shown("markers")
        scene.set_markers(None)
        assert scene.markers is None and "markers" not in scene.parts


def test_the_pelvis_triad_is_drawn_at_the_frames_it_was_recovered():
    with scene_of(snapshot_of(figure_motion())) as scene:
        origins = np.array([[0.0, -0.2, 0.0], [np.nan] * 3, [0.1, -0.2, 0.0]])
        pelvis = SimpleNamespace(origins=origins, rotations=np.broadcast_to(np.eye(3), (3, 3, 3)))
        scene.set_pelvis(pelvis)
        assert scene.pelvis is pelvis and scene.is_shown("pelvis")
        assert scene.parts["pelvis"].mesh.points[0] == pytest.approx(origins[0])
        scene.show_frame(1)
        assert not scene.is_shown("pelvis")
        scene.set_pelvis(None)
        assert scene.pelvis is None and "pelvis" not in scene.parts


# --------------------------------------------------------------- a drawable's parts
def test_a_drawing_is_wanted_and_visible_until_told_otherwise():
    drawing = Drawing()
    assert drawing.visible is True and drawing.parts == {} and drawing.scene is None
    assert drawing.wanted(None) is True
    assert drawing.part_wanted(parts.Part(1)) is True
    drawing.remove()  # never built: nothing to take out, no scene asked
    assert drawing.parts == {}
    with pytest.raises(AssertionError, match="build the drawable"):
        drawing.add("dots", parts.sphere_part(1, 0.01))


def test_parts_go_into_the_main_renderer_and_are_shown():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = Dots()
        scene.add_drawable(dots)
        main, front = scene.plotter.renderer, scene.front_renderer
        assert set(dots.parts) == {"dots", "spare"}
        for part in dots.parts.values():
            assert holds(main, part.actor) and not holds(front, part.actor)
            assert part.visible
        np.testing.assert_array_equal(dots.parts["dots"].mesh.points, scene.snapshot.positions[0])


def test_a_front_drawing_draws_in_the_front_layer_only():
    with scene_of(snapshot_of(figure_motion())) as scene:
        main_before = props_of(scene.plotter.renderer)
        dots = FrontDots()
        scene.add_drawable(dots)
        for part in dots.parts.values():
            assert holds(scene.front_renderer, part.actor) and part.visible
        assert props_of(scene.plotter.renderer) == main_before
        dots.remove()
        assert props_of(scene.front_renderer) == [] and dots.parts == {}


def test_a_part_added_under_a_taken_name_replaces_the_old_one():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = Dots()
        scene.add_drawable(dots)
        renderer = scene.plotter.renderer
        old = dots.parts["spare"]
        new = dots.add("spare", parts.sphere_part(2, 0.02))
        assert dots.parts["spare"] is new and new.visible
        assert holds(renderer, new.actor) and not holds(renderer, old.actor)
        assert holds(renderer, dots.parts["dots"].actor)  # the other part stays


def test_rebuilding_and_removing_take_the_old_actors_out():
    with scene_of(snapshot_of(figure_motion())) as scene:
        renderer = scene.plotter.renderer
        before = props_of(renderer)
        dots = Dots()
        scene.add_drawable(dots)
        first = [part.actor for part in dots.parts.values()]
        scene.redraw(dots)
        assert not any(holds(renderer, actor) for actor in first)
        assert len(props_of(renderer)) == len(before) + 2
        scene.remove_drawable(dots)
        assert props_of(renderer) == before and dots.parts == {}


def test_one_switch_hides_and_shows_every_part():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = Dots()
        scene.add_drawable(dots)
        dots.set_visible(False)
        assert dots.visible is False and not any(part.visible for part in dots.parts.values())
        dots.build(scene)  # built again while hidden: its new parts hidden too
        assert not any(part.visible for part in dots.parts.values())
        dots.set_visible(1)
        assert dots.visible is True and all(part.visible for part in dots.parts.values())


def test_a_part_not_wanted_stays_hidden_while_the_drawing_is_shown():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = OnlyDots()
        scene.add_drawable(dots)
        assert dots.parts["dots"].visible and not dots.parts["spare"].visible
        dots.set_visible(True)
        assert dots.parts["dots"].visible and not dots.parts["spare"].visible
        dots.set_visible(False)
        assert not dots.parts["dots"].visible and not dots.parts["spare"].visible


def _drawable_classes() -> list[type]:
    """Every class the view draws with: :class:`Drawing` and its subclasses in app/scene."""
    import importlib

    for name in ("figure", "highlight", "problem_marks", "overlays", "ghost_layer", "onion", "layer_onion"):
        importlib.import_module(f"gmr_studio.app.scene.{name}")
    found, todo = [], [Drawing]
    while todo:
        cls = todo.pop()
        found.append(cls)
        todo.extend(cls.__subclasses__())
    return [cls for cls in found if cls.__module__.startswith("gmr_studio.app.scene.")]


def test_every_drawable_has_the_protocols_members_of_the_same_kind():
    """The scene reads ``visible`` as a value (``if drawable.visible:``): a drawable whose
    ``visible`` were a method would always count as shown. Each member is what the protocol
    declares it: a property, or a method."""
    from gmr_studio.app.scene.drawable import Drawable

    members = ("build", "show_frame", "wanted", "visible", "set_visible", "remove")
    declared = {name: isinstance(Drawable.__dict__[name], property) for name in members}
    assert declared == {name: name == "visible" for name in members}
    classes = _drawable_classes()
    assert len(classes) > 8, [cls.__name__ for cls in classes]
    for cls in classes:
        for name, is_property in declared.items():
            member = next(vars(c)[name] for c in cls.__mro__ if name in vars(c))
            assert isinstance(member, property) == is_property, f"{cls.__name__}.{name}"
            assert is_property or callable(member), f"{cls.__name__}.{name}"


# -------------------------------------------------------------------- rendering
def test_a_render_asks_the_widget_to_repaint_unless_now():
    with scene_of(snapshot_of(figure_motion())) as scene:
        window = scene.plotter.ren_win
        rendered: list = []
        window.AddObserver("EndEvent", lambda *_: rendered.append(1))
        asked: list = []
        scene.request_repaint = lambda: asked.append(1)
        scene.render()
        assert asked and rendered == []  # the widget repaints when it can
        asked.clear()
        scene.render(now=True)
        assert asked == []  # at once (before a screenshot), not through the widget


@pytest.mark.parametrize("now", [True, False])
def test_the_near_and_far_planes_are_fitted_again_before_the_scenes_render(now):
    """Planes kept from another camera clip the whole figure away; the next render the scene
    asks for (at once, or by the widget's repaint) fits them to what is drawn again."""
    with scene_of(snapshot_of(figure_motion()), size=(160, 160)) as scene:
        camera = scene.plotter.camera
        scene.render(now=True)
        figure = drawn_mask(scene, window_image(scene))
        fitted = camera.GetClippingRange()
        assert fitted[0] < camera.GetDistance() < fitted[1] and figure.sum() > 500
        scene.request_repaint = lambda: None
        camera.SetClippingRange(1000.0, 1001.0)  # planes that clip the whole figure
        assert not drawn_mask(scene, window_image(scene)).any()
        scene.render(now=now)  # then the widget's repaint
        assert np.array_equal(drawn_mask(scene, window_image(scene)), figure)
        assert camera.GetClippingRange() == pytest.approx(fitted)


def test_hooks_before_a_render_run_for_visible_drawables_only():
    with scene_of(snapshot_of(figure_motion())) as scene:
        shown, hidden = Probe(), Probe(shown=False)
        scene.add_drawable(shown)
        scene.add_drawable(hidden)
        scene.plotter.ren_win.Render()
        assert shown.hooks >= 1 and hidden.hooks == 0


def test_the_front_layer_shares_the_scenes_camera_and_draws_over_the_figure():
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        window = scene.plotter.ren_win
        front = scene.front_renderer
        assert scene.front_renderer is front  # made once
        assert front.GetLayer() == 1 and window.GetNumberOfLayers() == 2
        assert front.GetActiveCamera() is scene.plotter.renderer.GetActiveCamera()
        assert not front.GetInteractive()
        assert front.GetViewport() == pytest.approx(scene.plotter.renderer.GetViewport())
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)  # the chest's sphere, centred
        chest = picture(scene)[100, 100]
        part = sphere_part(1, 0.004)
        part.set_points(np.array([[0.0, 0.2, -0.02]]))  # behind the chest, seen from above
        part.actor.GetProperty().SetColor(1.0, 0.0, 1.0)
        part.actor.GetProperty().LightingOff()
        front.AddViewProp(part.actor)
        scene.render(now=True)
        assert picture(scene)[100, 100].tolist() == [255, 0, 255]  # drawn over it all the same
        part.set_visible(False)
        scene.render(now=True)
        assert np.abs(picture(scene)[100, 100] - chest).max() <= 2


def test_the_scene_is_lit_by_one_headlight_and_a_sphere_is_brightest_where_it_faces_the_camera():
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        lights = scene.plotter.renderer.GetLights()
        assert lights.GetNumberOfItems() == 1 and lights.GetItemAsObject(0).LightTypeIsHeadlight()
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)  # the chest's sphere, 12.8 pixels round
        image = picture(scene).sum(axis=-1)
        centre, rim = image[100, 100], image[100, 100 + 11]
        assert centre > rim + 60  # lit head on at its centre, darker towards its edge
        scene.plotter.camera.position = (-5.0, 0.2, 0.0)  # from the side: the light follows the camera
        side = picture(scene).sum(axis=-1)
        assert side[100, 100] == pytest.approx(centre, abs=12)
