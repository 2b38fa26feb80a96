"""The scene's rendering (app/scene/scene.py, issue 24) on the tiny synthetic skeleton
(:mod:`tests.tiny_scene`): a render asked of the widget or made at once, the near and far
planes fitted just before the render the scene asked for, the drawables' hooks, the front
layer drawn over the scene, and the options given by keyword only."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gmr_studio.app.scene.scene import SkeletonScene
from gmr_studio.app.scene.vtk_parts import sphere_part
from tests.test_scene_scene_mutants import Probe, repaints
from tests.tiny_scene import figure_motion, scene_of, snapshot_of

pytestmark = pytest.mark.gui


def test_a_render_asks_the_widget_to_repaint_unless_now():
    with scene_of(snapshot_of(figure_motion())) as scene:
        window = scene.plotter.ren_win
        rendered: list = []
        window.AddObserver("EndEvent", lambda *_: rendered.append(1))
        calls = repaints(scene)
        scene.render()
        assert calls == [1] and rendered == []
        scene.render(now=True)
        assert calls == [1] and scene._clipping_stale  # the plotter renders only once shown


def test_the_near_and_far_planes_are_fitted_just_before_a_render_only_after_the_scene_asked():
    with scene_of(snapshot_of(figure_motion())) as scene:
        camera, window = scene.plotter.camera, scene.plotter.ren_win
        window.Render()
        fitted = camera.GetClippingRange()
        assert fitted[0] < camera.GetDistance() < fitted[1]
        for now in (True, False):
            repaints(scene)
            camera.SetClippingRange(1000.0, 1001.0)  # planes that clip the whole figure
            scene.render(now=now)
            assert scene._clipping_stale
            window.Render()
            assert camera.GetClippingRange() == pytest.approx(fitted) and not scene._clipping_stale
        camera.SetClippingRange(1000.0, 1001.0)
        window.Render()  # a render the scene did not ask for keeps the planes
        assert camera.GetClippingRange() == pytest.approx((1000.0, 1001.0))


def test_hooks_before_a_render_run_for_visible_drawables_only():
    with scene_of(snapshot_of(figure_motion())) as scene:
        shown, hidden = Probe(), Probe(shown=False)
        scene.add_drawable(shown)
        scene.add_drawable(hidden)
        scene.plotter.ren_win.Render()
        assert shown.hooks == 1 and hidden.hooks == 0


def test_the_front_layer_is_made_once_with_the_scenes_camera_and_drawn_only_when_it_has_something():
    with scene_of(snapshot_of(figure_motion())) as scene:
        window = scene.plotter.ren_win
        front = scene.front_renderer
        assert scene.front_renderer is front
        assert front.GetLayer() == 1 and window.GetNumberOfLayers() == 2
        assert front.GetActiveCamera() is scene.plotter.renderer.GetActiveCamera()
        assert not front.GetInteractive()
        assert front.GetViewport() == pytest.approx(scene.plotter.renderer.GetViewport())
        renderers = window.GetRenderers()
        assert any(renderers.GetItemAsObject(i) is front for i in range(renderers.GetNumberOfItems()))
        window.Render()
        assert not front.GetDraw()  # an empty layer is left undrawn
        part = sphere_part(1, 0.05)
        part.set_points(np.zeros((1, 3)))
        front.AddViewProp(part.actor)
        window.Render()
        assert front.GetDraw()
        part.set_visible(False)
        window.Render()
        assert not front.GetDraw()


def test_a_drawable_without_a_dict_of_parts_adds_none():
    with scene_of(snapshot_of(figure_motion())) as scene:
        before = dict(scene.parts)
        odd = SimpleNamespace(
            parts=["joints"], build=lambda s: None, wanted=lambda s: True, visible=True, set_visible=lambda v: None
        )
        odd.show_frame = lambda frame: None
        scene.drawables.append(odd)
        assert scene.parts.keys() == before.keys() and scene.parts["joints"] is before["joints"]


def test_a_window_of_one_layer_gets_a_second_for_the_front():
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow

    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    renderer = vtkRenderer()
    window.AddRenderer(renderer)
    assert window.GetNumberOfLayers() == 1
    bare = SimpleNamespace(plotter=SimpleNamespace(render_window=window, renderer=renderer), _front=None)
    front = SkeletonScene.front_renderer.fget(bare)
    assert front.GetLayer() == 1 and window.GetNumberOfLayers() == 2 and bare._front is front


def test_the_options_are_keywords_only():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        probe = Probe()
        with pytest.raises(TypeError):
            scene.set_snapshot(snapshot, True)
        with pytest.raises(TypeError):
            scene.add_drawable(probe, scene.figure)
        assert probe not in scene.drawables
        scene.add_drawable(probe)
        with pytest.raises(TypeError):
            scene.redraw(probe, False)
