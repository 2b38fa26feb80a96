"""One shape for everything drawn (a drawable, updated in place, drawn at every frame), and a
native render window (its renders a frame: the view bench, app/tools/view_bench.py)."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.scene import render_widget
from tests import app_fixtures
from tests.conftest import shared_path

studio = app_fixtures.studio
BVH = "cmu/subject01/01_01.bvh"
METHODS = ("build", "show_frame", "wanted", "set_visible", "remove")


@pytest.mark.parametrize(
    ("environ", "kind"),
    [
        ({}, "native"),
        ({"DISPLAY": ":1"}, "native"),
        ({"QT_QPA_PLATFORM": "xcb", "XDG_SESSION_TYPE": "wayland"}, "native"),  # X asked for explicitly
        ({"QT_QPA_PLATFORM": "offscreen"}, "native"),
        ({"QT_QPA_PLATFORM": "Wayland-EGL", "DISPLAY": ":0"}, "framebuffer"),  # Qt on Wayland, whatever else
        ({"QT_QPA_PLATFORM": "wayland"}, "framebuffer"),
        ({"XDG_SESSION_TYPE": "Wayland"}, "framebuffer"),  # a Wayland session without XWayland
        ({"XDG_SESSION_TYPE": "wayland", "WAYLAND_DISPLAY": "w"}, "framebuffer"),
        ({"XDG_SESSION_TYPE": "x11"}, "native"),
        ({"XDG_SESSION_TYPE": "wayland", "DISPLAY": ":0"}, "native"),  # XWayland
        ({"GMR_STUDIO_VIEW": " Framebuffer ", "DISPLAY": ":0"}, "framebuffer"),
        ({"GMR_STUDIO_VIEW": "native", "QT_QPA_PLATFORM": "wayland"}, "native"),
        ({"GMR_STUDIO_VIEW": "  ", "QT_QPA_PLATFORM": "wayland"}, "framebuffer"),  # blank: not asked
    ],
)
def test_the_view_kind_follows_the_session(environ, kind):
    assert render_widget.preferred_kind(environ) == kind


def test_an_unknown_view_kind_is_refused_naming_the_variable_and_the_kinds():
    with pytest.raises(ValueError, match=r"GMR_STUDIO_VIEW='opengl': expected one of native, framebuffer"):
        render_widget.preferred_kind({"GMR_STUDIO_VIEW": "OpenGL"})
    with pytest.raises(ValueError, match=r"unknown view kind 'qt': expected one of native, framebuffer"):
        render_widget.interactor_class("qt")


def test_the_first_view_fixes_the_kind_for_the_process_and_the_other_is_refused(monkeypatch):
    """The kind of this test session's views (chosen by its first view, or here): fixed for
    the process, VTK's base set to match, the other kind refused. (The framebuffer kind in a
    process of its own: the view bench, tests/test_view_bench.py.)"""
    import pyvistaqt
    import vtkmodules.qt

    interactor = render_widget.interactor_class()
    kind = render_widget.current_kind()
    other = "framebuffer" if kind == "native" else "native"
    assert interactor is pyvistaqt.QtInteractor and vtkmodules.qt.QVTKRWIBase == render_widget.BASES[kind]
    assert render_widget.interactor_class(kind) is interactor  # the same kind again
    with pytest.raises(RuntimeError, match=f"the view is already {kind}"):
        render_widget.interactor_class(other)
    assert vtkmodules.qt.QVTKRWIBase == render_widget.BASES[kind] and render_widget.current_kind() == kind
    monkeypatch.setenv("GMR_STUDIO_VIEW", other)
    assert render_widget.preferred_kind() == kind  # fixed for the process
    assert render_widget.preferred_kind({"GMR_STUDIO_VIEW": other}) == other  # a given environment is still judged


def _props(renderer) -> list[str]:
    props = renderer.GetViewProps()
    props.InitTraversal()
    return [props.GetNextProp().__this__ for _ in range(props.GetNumberOfItems())]


@pytest.mark.gui
def test_every_drawn_thing_is_a_drawable_updated_in_place_and_drawn_at_each_frame(studio):
    walk = shared_path(BVH)
    studio.files.open_path(str(walk), markers=str(walk.with_suffix(".c3d")), ask=False, wait=True)
    studio.files.compare_path(str(walk.with_suffix(".amc")), joint_map="cmu", wait=True)
    state, scene = studio.state, studio.view.scene
    assert render_widget.current_kind() == "native"
    studio.onion.toggle.setChecked(True)
    state.select(state.motion.joint_index("LeftHand"))
    for name in ("axes", "trails", "labels"):
        state.set_overlay(name, True)
    QApplication.processEvents()
    kinds = {type(d).__name__ for d in scene.drawables}
    assert {"SkeletonFigure", "Ground", "Markers", "GhostLayers", "OnionSkins", "LayerOnions", "TeachOverlay"} <= kinds
    for drawable in scene.drawables:
        assert all(callable(getattr(drawable, m, None)) for m in METHODS), type(drawable).__name__
    renders = []
    scene.plotter.ren_win.AddObserver("EndEvent", lambda *_: renders.append(1))
    renderer = scene.plotter.renderer
    props = _props(renderer)
    points = {name: part.mesh.GetPoints().__this__ for name, part in scene.parts.items() if part.n_points}
    for frame in (500, 501, 900):
        renders.clear()
        state.set_frame(frame)
        QApplication.processEvents()
        assert renders, "a new frame was not drawn"  # how many renders a frame: the view bench's figure
        assert _props(renderer) == props  # nothing added or removed: points rewritten in place
        # every drawable says where it may draw: the planes fit that box, no actor measured
        box = scene.world_box()
        assert box is not None and renderer.GetCullers().GetNumberOfItems() == 0
        bounds = np.array(renderer.ComputeVisiblePropBounds())  # VTK's own measure of this frame
        assert (bounds[0::2] >= box[0] - 1e-9).all() and (bounds[1::2] <= box[1] + 1e-9).all(), frame
    # the same point arrays (the markers' set is replaced: gaps change how many are drawn)
    for name, address in points.items():
        if name != "markers":
            assert scene.parts[name].mesh.GetPoints().__this__ == address, name
    bones = scene.parts["bones"]
    positions = state.snapshot.positions[900]
    assert bones.mesh.points == pytest.approx(positions[bones.pairs].mean(axis=1))
    from PyQt6.QtOpenGLWidgets import QOpenGLWidget

    assert not isinstance(studio.view.interactor, QOpenGLWidget)  # a native window, no framebuffer
    assert studio.view.interactor.testAttribute(Qt.WidgetAttribute.WA_NativeWindow) or studio.view.interactor.winId()


def _drawn_pixels(part_of, points, view=(200, 200)):
    """(H, W) bool: the pixels ``part_of(points)``'s actor covers, in an off-screen window
    looking down -Z at the unit square (parallel projection, 100 pixels per unit)."""
    import numpy as np
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=view)
    plotter.set_background((0, 0, 0))
    part = part_of(points)
    plotter.renderer.AddActor(part.actor)
    plotter.enable_parallel_projection()
    plotter.camera.position, plotter.camera.focal_point, plotter.camera.up = (0, 0, 10), (0, 0, 0), (0, 1, 0)
    plotter.camera.parallel_scale = 1.0
    image = plotter.screenshot(return_img=True)
    plotter.close()
    return np.asarray(image).max(axis=2) > 40


@pytest.mark.gui
def test_imposter_spheres_cover_their_disc_and_a_missing_point_draws_nothing():
    import numpy as np

    from gmr_studio.app.scene import vtk_parts as parts

    def spheres(points):
        part = parts.sphere_part(len(points), 0.1, color=(1.0, 1.0, 1.0))
        part.set_points(points)
        return part

    shown = _drawn_pixels(spheres, np.array([[0.5, 0.5, 0.0], [np.nan, 0.0, 0.0], [-0.5, -0.5, 0.0]]))
    # two discs of radius 10 pixels (about 314 pixels each) at (150, 50) and (50, 150) in
    # image rows/columns; nothing at the origin, where the missing point's zeros would be
    area = np.pi * 10**2
    assert (
        abs(shown[40:61, 140:161].sum() - area) < 0.15 * area and abs(shown[140:161, 40:61].sum() - area) < 0.15 * area
    )
    assert shown.sum() == shown[40:61, 140:161].sum() + shown[140:161, 40:61].sum()
    assert not shown[90:111, 90:111].any()


@pytest.mark.gui
def test_imposter_bones_run_from_joint_to_joint():
    import numpy as np

    from gmr_studio.app.scene import vtk_parts as parts

    def bone(points):
        part = parts.bone_part(np.array([[0, 1]]), 0.05, color=(1.0, 1.0, 1.0))
        part.set_joints(points)
        return part

    shown = _drawn_pixels(bone, np.array([[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0]]))
    rows, columns = np.nonzero(shown)
    # a bar 100 pixels long (columns 50 to 150) and 10 high (rows 95 to 105), ends flat
    assert abs(columns.min() - 50) <= 1 and abs(columns.max() - 149) <= 1
    assert abs(rows.min() - 95) <= 1 and abs(rows.max() - 104) <= 1
    assert shown.sum() > 0.9 * 100 * 10


@pytest.mark.gui
def test_the_screen_shows_the_frame_vtk_rendered_copied_without_its_depth(studio):
    """The view copies only colour to its window (render_widget.blit_colour_only): what the X
    server shows of the view is VTK's image of the frame, pixel for pixel, and a new frame
    reaches the screen. (Another test's window on the same X display may cover the view for
    a moment: the window is raised and grabbed again, a few times at most.)"""
    import time

    from PyQt6.QtGui import QGuiApplication

    from gmr_studio.app.media.video import image_pixels, scene_image

    app_fixtures.open_file(studio, shared_path(BVH))
    state, interactor = studio.state, studio.view.interactor
    assert interactor.ren_win.GetFrameBlitMode() == interactor.ren_win.BlitToCurrent
    state.select(state.motion.joint_index("LeftHand"))

    def screen_matches(rendered: np.ndarray) -> np.ndarray | None:
        for _attempt in range(20):
            studio.raise_()
            QApplication.processEvents()
            interactor.ren_win.Render()  # what the widget's paint does, finished before the grab
            grabbed = image_pixels(QGuiApplication.primaryScreen().grabWindow(int(interactor.winId())).toImage())
            if grabbed.shape == rendered.shape and np.array_equal(grabbed, rendered):
                return grabbed
            time.sleep(0.05)
        return None

    shown = {}
    for frame in (300, 1200):
        state.set_frame(frame)
        QApplication.processEvents()
        rendered = scene_image(studio.view.scene)
        figure = np.any(np.abs(rendered.astype(int) - (40, 43, 51)) > 12, axis=-1)  # not the background
        assert figure.mean() > 0.01  # the figure and the ground are there, not an empty view
        shown[frame] = screen_matches(rendered)
        assert shown[frame] is not None, f"frame {frame}: the screen never showed VTK's image"
    moved = np.any(shown[300] != shown[1200], axis=-1)
    assert moved.sum() > 500  # the figure walked: the second frame reached the screen
