"""The view's widget kind (app/scene/render_widget.py): a native window unless the session is
Wayland without XWayland or ``GMR_STUDIO_VIEW`` says otherwise; the kind chosen once per
process, VTK's base switch set to match, and a later request for the other kind refused.

The choice is process-wide state: each test starts from "nothing chosen" and puts VTK's switch
back (monkeypatch). pyvistaqt is imported here first, on VTK's default base (the native
``QWidget``, as the app's tests use), so that setting the switch in a test never changes the
base of the views later tests open.
"""

from __future__ import annotations

import pytest
import pyvistaqt  # imported here, on the default base, before any test sets the switch
import vtkmodules.qt

from gmr_studio.app.scene import render_widget


@pytest.fixture
def unchosen(monkeypatch):
    """No kind chosen yet in this process, VTK's switch restored afterwards."""
    monkeypatch.setattr(render_widget, "_chosen", None)
    monkeypatch.setattr(vtkmodules.qt, "QVTKRWIBase", vtkmodules.qt.QVTKRWIBase)
    for name in ("GMR_STUDIO_VIEW", "QT_QPA_PLATFORM", "XDG_SESSION_TYPE", "WAYLAND_DISPLAY", "DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    return monkeypatch


@pytest.mark.parametrize(
    ("environ", "kind"),
    [
        ({}, "native"),
        ({"DISPLAY": ":1"}, "native"),
        ({"QT_QPA_PLATFORM": "xcb", "XDG_SESSION_TYPE": "wayland"}, "native"),  # X asked for explicitly
        ({"QT_QPA_PLATFORM": "offscreen"}, "native"),
        ({"QT_QPA_PLATFORM": "Wayland-EGL", "DISPLAY": ":0"}, "framebuffer"),  # Qt on Wayland, whatever else
        ({"XDG_SESSION_TYPE": "Wayland"}, "framebuffer"),  # a Wayland session without XWayland
        ({"XDG_SESSION_TYPE": "x11"}, "native"),
        ({"XDG_SESSION_TYPE": "wayland", "DISPLAY": ":0"}, "native"),  # XWayland
        ({"GMR_STUDIO_VIEW": " Framebuffer ", "DISPLAY": ":0"}, "framebuffer"),
        ({"GMR_STUDIO_VIEW": "native", "QT_QPA_PLATFORM": "wayland"}, "native"),
        ({"GMR_STUDIO_VIEW": "  ", "QT_QPA_PLATFORM": "wayland"}, "framebuffer"),  # blank: not asked
    ],
)
def test_the_kind_for_a_session(environ, kind, unchosen):
    assert render_widget.preferred_kind(environ) == kind


def test_an_unknown_kind_is_refused_naming_the_variable_and_the_kinds(unchosen):
    with pytest.raises(ValueError, match=r"GMR_STUDIO_VIEW='opengl': expected one of native, framebuffer"):
        render_widget.preferred_kind({"GMR_STUDIO_VIEW": "OpenGL"})
    with pytest.raises(ValueError, match=r"unknown view kind 'qt': expected one of native, framebuffer"):
        render_widget.interactor_class("qt")
    assert render_widget.current_kind() is None and vtkmodules.qt.QVTKRWIBase == "QWidget"


def test_without_an_environment_the_process_environment_decides_until_a_kind_is_chosen(unchosen):
    unchosen.setenv("XDG_SESSION_TYPE", "wayland")
    assert render_widget.preferred_kind() == "framebuffer"
    unchosen.setenv("DISPLAY", ":5")
    assert render_widget.preferred_kind() == "native"
    unchosen.setattr(render_widget, "_chosen", "framebuffer")  # chosen: fixed for the process
    assert render_widget.preferred_kind() == "framebuffer"
    assert render_widget.preferred_kind({"DISPLAY": ":5"}) == "native"  # a given environment is still judged


def test_the_first_view_fixes_the_base_and_the_other_kind_is_refused(unchosen):
    assert render_widget.current_kind() is None
    interactor = render_widget.interactor_class("framebuffer")
    assert interactor is pyvistaqt.QtInteractor
    assert vtkmodules.qt.QVTKRWIBase == "QOpenGLWidget" and render_widget.current_kind() == "framebuffer"
    assert render_widget.interactor_class("framebuffer") is pyvistaqt.QtInteractor  # the same kind again
    assert render_widget.interactor_class() is pyvistaqt.QtInteractor  # none asked: the one chosen
    with pytest.raises(RuntimeError, match="the view is already framebuffer"):
        render_widget.interactor_class("native")
    assert vtkmodules.qt.QVTKRWIBase == "QOpenGLWidget" and render_widget.current_kind() == "framebuffer"


def test_with_no_kind_asked_the_session_chooses(unchosen):
    unchosen.setenv("GMR_STUDIO_VIEW", "native")
    unchosen.setenv("QT_QPA_PLATFORM", "wayland")
    assert render_widget.interactor_class() is pyvistaqt.QtInteractor
    assert render_widget.current_kind() == "native" and vtkmodules.qt.QVTKRWIBase == "QWidget"
    unchosen.setattr(render_widget, "_chosen", None)
    unchosen.setenv("GMR_STUDIO_VIEW", "framebuffer")
    render_widget.interactor_class()
    assert render_widget.current_kind() == "framebuffer" and vtkmodules.qt.QVTKRWIBase == "QOpenGLWidget"
