"""Issue 26: one shape for everything drawn, one render per frame, a native render window."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.scene import render_widget
from tests import app_fixtures
from tests.conftest import shared_path

studio = app_fixtures.studio
BVH = "cmu/subject01/01_01.bvh"
METHODS = ("build", "show_frame", "wanted", "set_visible", "remove")


def test_the_view_kind_follows_the_session():
    assert render_widget.preferred_kind({"DISPLAY": ":0"}) == "native"
    assert render_widget.preferred_kind({"QT_QPA_PLATFORM": "wayland"}) == "framebuffer"
    assert render_widget.preferred_kind({"XDG_SESSION_TYPE": "wayland", "WAYLAND_DISPLAY": "w"}) == "framebuffer"
    assert render_widget.preferred_kind({"XDG_SESSION_TYPE": "wayland", "DISPLAY": ":0"}) == "native"  # XWayland
    assert render_widget.preferred_kind({"GMR_STUDIO_VIEW": "framebuffer", "DISPLAY": ":0"}) == "framebuffer"
    with pytest.raises(ValueError, match="GMR_STUDIO_VIEW"):
        render_widget.preferred_kind({"GMR_STUDIO_VIEW": "opengl"})


def _props(renderer) -> list[str]:
    props = renderer.GetViewProps()
    props.InitTraversal()
    return [props.GetNextProp().__this__ for _ in range(props.GetNumberOfItems())]


@pytest.mark.gui
def test_every_drawn_thing_is_a_drawable_updated_in_place_and_rendered_once(studio):
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
        assert len(renders) == 1, f"{len(renders)} renders for one frame"
        assert _props(renderer) == props  # nothing added or removed: points rewritten in place
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
