"""The scene itself (app/scene/scene.py, issue 24) on the tiny synthetic skeleton
(:mod:`tests.tiny_scene`): its list of drawables in drawing order, built for a new document
or an edit, a frame written into every visible drawable and rendered once, the overlays'
and the selection's switches (the rendering itself: ``tests/test_scene_render_mutants.py``)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import pyvista as pv

from gmr_studio.app.model.state import OVERLAYS
from gmr_studio.app.scene.drawable import Drawing
from gmr_studio.app.scene.figure import SkeletonFigure, SoftLinks
from gmr_studio.app.scene.overlays import Ground, JointAxes, JointLabels, Markers, PelvisTriad, Trail
from gmr_studio.app.scene.scene import BACKGROUND, SkeletonScene, another_space
from gmr_studio.app.scene.vtk_parts import sphere_part
from gmr_studio.core.space.up_axis import up_axis_of
from tests.tiny_scene import (
    FIGURE_NAMES,
    FIGURE_PARENTS,
    FIGURE_SOFT_PARENTS,
    figure_motion,
    figure_world,
    holds,
    posed_motion,
    scene_of,
    snapshot_of,
)

pytestmark = pytest.mark.gui


class Probe(Drawing):
    """A drawable that counts what the scene asks of it: one sphere at joint ``joint``."""

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


def repaints(scene) -> list:
    """The repaint requests the scene makes from now on (one item each)."""
    calls: list = []
    scene.request_repaint = lambda: calls.append(1)
    return calls


def scaled(factor: float, n_frames: int = 3):
    """The figure ``factor`` times as large (its size too)."""
    world = figure_world(n_frames) * factor
    return snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS))


def z_up(n_frames: int = 3):
    """The figure stood up along z (y and z swapped)."""
    world = figure_world(n_frames)[..., [0, 2, 1]]
    return snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS))


def camera_of(scene) -> tuple:
    camera = scene.plotter.camera
    return camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp()


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
        assert scene.up_axis == 1 and scene.request_repaint is None
        kinds = [Ground, SkeletonFigure, SoftLinks, JointAxes, Trail, JointLabels, Markers, PelvisTriad]
        assert [type(d) for d in scene.drawables] == kinds
        assert scene.drawables[0] is scene.ground and scene.drawables[1] is scene.figure
        assert scene.drawables[6] is scene.marker_drawing and scene.drawables[7] is scene.pelvis_drawing
        assert scene.parts == {} and not scene.is_shown("joints")
        assert scene.markers is None and scene.pelvis is None
        assert scene.hovered_marker is None and scene.selected_marker is None
        assert scene.ground_bounds is None
        scene.show_frame(2)  # nothing to show
        assert scene.frame == 0


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
        assert scene.figure_positions().shape == (3, 5, 3)  # the anchor left out
        np.testing.assert_allclose(scene.figure_positions(), snapshot.positions[:, 1:])


def test_a_z_up_document_gets_a_z_up_camera():
    with scene_of(z_up()) as scene:
        assert scene.up_axis == 2
        assert camera_of(scene)[2] == pytest.approx((0.0, 0.0, 1.0))


def test_a_frame_is_clamped_and_written_into_the_visible_drawables_only():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        shown, hidden = Probe(), Probe(shown=False)
        scene.add_drawable(shown)
        scene.add_drawable(hidden)
        calls = repaints(scene)
        scene.show_frame(7)
        assert scene.frame == 2 and shown.frames[-1] == 2 and hidden.frames == []
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, snapshot.positions[2])
        assert calls == [1]
        scene.show_frame(-4)
        assert scene.frame == 0 and shown.frames[-1] == 0
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, snapshot.positions[0])
        scene.show_frame(1, render=False)
        assert scene.frame == 1 and isinstance(scene.frame, int) and shown.frames[-1] == 1 and calls == [1, 1]
        scene.show_frame(np.int64(2))
        assert type(scene.frame) is int and scene.frame == 2


def test_an_added_drawable_is_built_shown_at_the_frame_in_drawing_order_without_a_render():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        scene.show_frame(1)
        calls = repaints(scene)
        last, first = Probe(), Probe(joint=5)
        scene.add_drawable(last)
        scene.add_drawable(first, before=scene.figure)
        assert scene.drawables.index(first) == 1 and scene.drawables[-1] is last
        for probe in (first, last):
            assert probe.builds == 1 and probe.frames == [1] and probe.visible
            assert holds(scene.plotter.renderer, probe.parts["probe"].actor)
        np.testing.assert_allclose(first.parts["probe"].mesh.points, snapshot.positions[1, [5]])
        assert calls == []
        unwanted = Probe(shown=False)
        scene.add_drawable(unwanted)
        assert not unwanted.visible and unwanted.frames == [] and not unwanted.parts["probe"].visible


def test_a_removed_drawable_takes_its_actors_out_and_renders_once():
    with scene_of(snapshot_of(figure_motion())) as scene:
        probe = Probe()
        scene.add_drawable(probe)
        actor = probe.parts["probe"].actor
        calls = repaints(scene)
        scene.remove_drawable(probe)
        assert probe not in scene.drawables and not holds(scene.plotter.renderer, actor) and calls == [1]
        scene.remove_drawable(probe)  # not drawn any more: nothing to do
        assert calls == [1]


def test_redrawing_builds_again_and_renders_when_asked():
    with scene_of(snapshot_of(figure_motion())) as scene:
        probe = Probe()
        scene.add_drawable(probe)
        scene.show_frame(2)
        calls = repaints(scene)
        scene.redraw(probe)
        assert probe.builds == 2 and probe.frames[-1] == 2 and calls == [1]
        scene.redraw(probe, render=False)
        assert probe.builds == 3 and calls == [1]
        probe.shown = False
        frames = len(probe.frames)
        scene.redraw(probe)
        assert not probe.visible and len(probe.frames) == frames and calls == [1, 1]
    with scene_of(None) as scene:  # no document: built, never shown
        probe = Probe()
        scene.add_drawable(probe)
        assert probe.builds == 1 and probe.frames == [] and probe.parts == {}


def test_an_edit_keeps_the_ground_and_camera_a_new_document_makes_them_afresh():
    with scene_of(snapshot_of(figure_motion())) as scene:
        scene.set_overlay("follow", False)  # the camera stays where it is unless made afresh
        ground, camera = scene.parts["ground"].actor, camera_of(scene)
        bounds = scene.ground_bounds
        scene.set_snapshot(scaled(2.0), reset_camera=False)  # an edit in the same space
        assert scene.parts["ground"].actor is ground and camera_of(scene) == camera
        assert scene.new_document is False
        scene.set_snapshot(z_up(), reset_camera=False)  # an edit that stands it up along z: the view stays
        assert scene.up_axis == 1 and scene.parts["ground"].actor is ground
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
        assert scene._followed is None
        scene.set_snapshot(z_up(), reset_camera=False)
        assert scene.up_axis == 2 and scene.is_shown("ground") and scene.new_document is False


def test_a_new_document_shorter_than_the_frame_is_framed_at_its_last_frame():
    with scene_of(snapshot_of(figure_motion(6))) as scene:
        scene.show_frame(5)
        shorter = snapshot_of(figure_motion(3))
        scene.set_snapshot(shorter, reset_camera=True)  # following: framed at frame 2
        assert scene.frame == 2
        np.testing.assert_allclose(scene._followed[0], shorter.positions[2, 1:, 0].mean())


def test_a_scene_not_yet_given_a_snapshot_builds_for_a_new_document():
    plotter = pv.Plotter(off_screen=True, window_size=(80, 80))
    try:
        scene = SkeletonScene(plotter)
        assert scene.new_document is True and scene._followed is None and scene._front is None
        assert not scene._clipping_stale
    finally:
        plotter.close()


def test_a_shorter_document_clamps_the_frame_and_none_takes_everything_out():
    with scene_of(snapshot_of(figure_motion(6))) as scene:
        scene.show_frame(5)
        shorter = snapshot_of(figure_motion(3))
        scene.set_snapshot(shorter, reset_camera=False)
        assert scene.frame == 2
        np.testing.assert_allclose(scene.parts["joints"].mesh.points, shorter.positions[2])
        actors = [part.actor for part in scene.parts.values()]
        calls = repaints(scene)
        scene.set_snapshot(None, reset_camera=False)
        assert scene.snapshot is None and scene.parts == {} and calls == [1]
        assert not any(holds(scene.plotter.renderer, actor) for actor in actors)


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


def test_following_moves_the_camera_with_the_figure_along_the_floor():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        focal = np.array(camera_of(scene)[1])
        scene.show_frame(2)  # the figure moved 0.1 along x, the camera with it
        np.testing.assert_allclose(np.array(camera_of(scene)[1]) - focal, [0.1, 0.0, 0.0], atol=1e-9)
        scene.set_overlay("follow", False)
        assert scene._followed is None
        scene.show_frame(0)
        np.testing.assert_allclose(np.array(camera_of(scene)[1]) - focal, [0.1, 0.0, 0.0], atol=1e-9)
        scene.set_overlay("follow", True)  # from where the figure is now: no jump
        centroid = snapshot.positions[0, 1:].mean(axis=0)
        np.testing.assert_allclose(scene._followed, [centroid[0], scene.ground_bounds[2], centroid[2]])
        np.testing.assert_allclose(np.array(camera_of(scene)[1]) - focal, [0.1, 0.0, 0.0], atol=1e-9)
        scene.show_frame(1)
        np.testing.assert_allclose(np.array(camera_of(scene)[1]) - focal, [0.15, 0.0, 0.0], atol=1e-9)


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


def test_the_scene_is_lit_by_one_headlight_and_a_sphere_is_brightest_where_it_faces_the_camera():
    from tests.tiny_scene import look_down_at, picture

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
