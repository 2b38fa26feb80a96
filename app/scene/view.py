"""The central 3D view: a pyvistaqt interactor showing the :class:`~app.scene.scene.SkeletonScene`.

The interactor renders into a native window where the platform allows it, else through a
framebuffer (:mod:`app.scene.render_widget`).

It follows the state (document, frame, selection, overlays, markers, pelvis) and writes back
only through it: a left click selects the joint under the mouse (or else a marker), a right
click selects and opens the joint menu, hovering a marker labels it. Dragging still turns,
pans and zooms the camera (VTK's trackball): a press and release within a few pixels is a
click, anything longer is a drag.
"""

from __future__ import annotations

from PyQt6.QtCore import QEvent, QObject, QPoint, Qt, QTimer
from PyQt6.QtGui import QMouseEvent
from PyQt6.QtWidgets import QMenu, QVBoxLayout, QWidget

from gmr_studio.app.model.state import StudioState
from gmr_studio.app.scene import render_widget
from gmr_studio.app.scene.picking import pick_point
from gmr_studio.app.scene.scene import SkeletonScene

CLICK_SLOP = 4  # pixels a press may move and still be a click


class SkeletonView(QWidget):
    """The 3D view of the state's document."""

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        # no multisampling: it multiplies the cost of a frame in software OpenGL (Xvfb, VMs)
        self.kind = render_widget.preferred_kind()
        self.interactor = render_widget.interactor_class(self.kind)(self, auto_update=False, multi_samples=0)
        render_widget.blit_colour_only(self.interactor.ren_win)
        self.interactor.setAcceptDrops(False)  # files dropped here go to the main window
        for key in ("q", "e", "v", "b", "r", "plus", "minus"):  # pyvista's default key bindings
            self.interactor.clear_events_for_key(key, raise_on_missing=False)
        self.scene = SkeletonScene(self.interactor)
        # one render per drawn frame: a native window renders in its paint event, which
        # update() coalesces; a framebuffer widget renders when asked
        native = self.kind == render_widget.NATIVE
        self.scene.request_repaint = self.interactor.update if native else self.interactor.render
        # a new document's first frame drawn: the state starts the work that frame did not need
        state.drawn_by_view = True
        self.scene.after_render = self._after_render
        self.context_menu: QMenu | None = None
        self._press: QPoint | None = None
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.interactor)
        self.interactor.installEventFilter(self)
        state.document_changed.connect(self._on_document_changed)
        state.motion_changed.connect(self._on_motion_changed)
        state.frame_changed.connect(self._on_frame_changed)
        state.selection_changed.connect(self._on_selection_changed)
        state.overlay_changed.connect(self._on_overlay_changed)
        state.markers_changed.connect(self._on_markers_changed)
        state.marker_selection_changed.connect(self._on_marker_selection_changed)
        state.pelvis_changed.connect(self._on_pelvis_changed)

    # ------------------------------------------------------------------ state -> view
    def _on_document_changed(self) -> None:
        self.scene.overlays = dict(self.state.overlays)
        self.scene.frame = self.state.frame
        self.scene.selected = self.state.selected
        self.scene.set_snapshot(self.state.snapshot, reset_camera=True)
        if not self.interactor.isVisible():  # nothing will be drawn until it is shown
            QTimer.singleShot(0, self.state.first_frame_drawn)

    def _after_render(self) -> None:
        """After every render: the first of a new document tells the state, once control is
        back in the event loop (never from inside VTK's render)."""
        if not self.state.shown and self.scene.snapshot is self.state.snapshot:
            QTimer.singleShot(0, self.state.first_frame_drawn)

    def _on_motion_changed(self) -> None:
        self.scene.frame = self.state.frame
        self.scene.set_snapshot(self.state.snapshot, reset_camera=False)

    def _on_frame_changed(self, frame: int) -> None:
        self.scene.show_frame(frame)

    def _on_selection_changed(self, joint: int) -> None:
        self.scene.set_selection(None if joint < 0 else joint)

    def _on_overlay_changed(self, name: str, shown: bool) -> None:
        self.scene.set_overlay(name, shown)

    def _on_markers_changed(self) -> None:
        self.scene.set_markers(self.state.marker_overlay)

    def _on_marker_selection_changed(self, marker: int) -> None:
        self.scene.set_marker_highlight(self.scene.hovered_marker, None if marker < 0 else marker)

    def _on_pelvis_changed(self) -> None:
        self.scene.set_pelvis(self.state.pelvis)

    # ------------------------------------------------------------------ mouse -> state
    def joint_at(self, point: QPoint) -> int | None:
        """The joint drawn under a point of the interactor (logical pixels), or None."""
        return pick_point((point.x(), point.y()), self.scene.joint_screen_positions(), self.scene.pick_radius())

    def marker_at(self, point: QPoint) -> int | None:
        radius = max(6.0, 0.6 * self.scene.pick_radius())
        return pick_point((point.x(), point.y()), self.scene.marker_screen_positions(), radius)

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        if watched is self.interactor and self.state.snapshot is not None:
            kind = event.type()
            if kind == QEvent.Type.MouseButtonPress:
                self._press = event.position().toPoint()
            elif kind == QEvent.Type.MouseButtonRelease and self._press is not None:
                point = event.position().toPoint()
                if (point - self._press).manhattanLength() <= CLICK_SLOP:
                    self._on_click(event, point)
                self._press = None
            elif kind == QEvent.Type.MouseMove and event.buttons() == Qt.MouseButton.NoButton:
                self._on_hover(event.position().toPoint())
        return super().eventFilter(watched, event)

    def _on_click(self, event: QMouseEvent, point: QPoint) -> None:
        joint = self.joint_at(point)
        if event.button() == Qt.MouseButton.LeftButton:
            marker = self.marker_at(point)
            if joint is not None and marker is not None:  # both under the mouse: the nearer wins
                joints, markers = self.scene.joint_screen_positions(), self.scene.marker_screen_positions()
                if _distance(markers[marker], point) < _distance(joints[joint], point):
                    joint = None
                else:
                    marker = None
            self.state.select(joint)
            self.state.select_marker(marker)
        elif event.button() == Qt.MouseButton.RightButton:
            if joint is not None:
                self.state.select(joint)
            if self.context_menu is not None:
                self.context_menu.popup(self.interactor.mapToGlobal(point))

    def _on_hover(self, point: QPoint) -> None:
        if self.state.marker_overlay is None:
            return
        marker = self.marker_at(point)
        if marker != self.scene.hovered_marker:
            self.scene.set_marker_highlight(marker, self.scene.selected_marker)

    # ---------------------------------------------------------------------- closing
    def close_view(self) -> None:
        """Release the render window (always call before the widget goes away)."""
        self.interactor.removeEventFilter(self)
        self.interactor.close()


def _distance(screen_point, point: QPoint) -> float:
    return float(((screen_point[0] - point.x()) ** 2 + (screen_point[1] - point.y()) ** 2) ** 0.5)
