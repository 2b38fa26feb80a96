"""The widget the 3D view renders through: a native window, or a framebuffer where none works.

pyvistaqt's ``QtInteractor`` is the bridge between pyvista's plotter and Qt (building the
scene, picking, screenshots, resizing all go through it). Its base class is chosen once, when
pyvistaqt is first imported, by VTK's documented switch ``vtkmodules.qt.QVTKRWIBase``:

- ``"QWidget"`` (**native**, the default under X11 and offscreen): VTK renders straight into
  the widget's own native window; Qt composites nothing, so a frame costs about what plain
  VTK's does (``python -m gmr_studio.app.tools.bench`` compares the two).
- ``"QOpenGLWidget"`` (**framebuffer**): VTK renders into an OpenGL framebuffer object that
  Qt then composites into the window. It works where a foreign native window cannot be
  embedded (Wayland), at the price of the composition.

pyvistaqt 0.13 dropped the native base for everyone (its ``rwi.py`` says: for Wayland);
the project pins pyvistaqt 0.12.0, whose interactor honours the switch, and picks the base
here: ``GMR_STUDIO_VIEW=native|framebuffer`` forces one, else a Wayland session without
XWayland (``QT_QPA_PLATFORM`` or ``XDG_SESSION_TYPE`` saying ``wayland``) gets the
framebuffer and everything else the native window.

The choice must be made before pyvistaqt is imported anywhere: :func:`interactor_class`
does both, and nothing else in the app imports pyvistaqt.
"""

from __future__ import annotations

import os

NATIVE = "native"
FRAMEBUFFER = "framebuffer"
BASES = {NATIVE: "QWidget", FRAMEBUFFER: "QOpenGLWidget"}
ENVIRONMENT = "GMR_STUDIO_VIEW"

_chosen: str | None = None


def preferred_kind(environ: dict[str, str] | None = None) -> str:
    """``native`` or ``framebuffer``: what ``GMR_STUDIO_VIEW`` asks for, else what the
    session can show (see the module docstring)."""
    if environ is None and _chosen is not None:
        return _chosen  # fixed for this process (see interactor_class)
    environ = os.environ if environ is None else environ
    asked = environ.get(ENVIRONMENT, "").strip().lower()
    if asked:
        if asked not in BASES:
            raise ValueError(f"{ENVIRONMENT}={asked!r}: expected one of {', '.join(BASES)}")
        return asked
    platform = environ.get("QT_QPA_PLATFORM", "").lower()
    if platform.startswith("wayland"):
        return FRAMEBUFFER
    if not platform and environ.get("XDG_SESSION_TYPE", "").lower() == "wayland" and not environ.get("DISPLAY"):
        return FRAMEBUFFER
    return NATIVE


def interactor_class(kind: str | None = None):
    """pyvistaqt's ``QtInteractor`` on the base for ``kind`` (default: :func:`preferred_kind`).

    The base is fixed for the process once pyvistaqt is imported: asking for the other kind
    later raises ``RuntimeError`` (the bench runs each kind in its own process)."""
    global _chosen
    kind = kind or preferred_kind()
    if kind not in BASES:
        raise ValueError(f"unknown view kind {kind!r}: expected one of {', '.join(BASES)}")
    if _chosen is None:
        import vtkmodules.qt

        vtkmodules.qt.QVTKRWIBase = BASES[kind]
        _chosen = kind
    elif kind != _chosen:
        raise RuntimeError(f"the view is already {_chosen}: its base is fixed once pyvistaqt is imported")
    from pyvistaqt import QtInteractor

    return QtInteractor


def blit_colour_only(render_window) -> None:
    """Copy only the colour of each finished frame to the widget, not the depth.

    VTK renders into a framebuffer of its own and, at the end of every frame, copies it to
    the widget's buffer (``FrameBlitMode``). Its default, ``BlitToHardware``, also writes the
    depth buffer there with a full-view shader pass, for drawing more over VTK's image with
    depth tests outside VTK; nothing does that here (screenshots, video and picking read
    VTK's own framebuffer), so ``BlitToCurrent`` copies the colour alone into the buffer
    current when the frame ends: the native window's back buffer, or the framebuffer the Qt
    widget renders into. The screen shows the same pixels, without the extra pass
    (``tests/test_app_drawables.py`` compares the screen with VTK's image)."""
    render_window.SetFrameBlitModeToBlitToCurrent()


def current_kind() -> str | None:
    """The kind chosen in this process, or None before the first view."""
    return _chosen
