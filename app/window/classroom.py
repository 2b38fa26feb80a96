"""The classroom wired into a window: the Teach dock and its overlay in the 3D view.

The overlay draws only while the dock is shown, for the selected joint at the current frame,
with the dock's rotation slider.
"""

from __future__ import annotations

from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QDockWidget, QMainWindow

from gmr_studio.app.docks.teach_dock import TeachDock
from gmr_studio.app.model.state import StudioState
from gmr_studio.app.scene.teach_overlay import TeachOverlay

WIDTH = 560  # the dock's width when shown: the 3D view keeps the rest


class Classroom:
    """Owns the Teach dock and the overlay; ``dock`` is the QDockWidget added to ``window``."""

    def __init__(self, window: QMainWindow, state: StudioState, scene, beside: QDockWidget | None = None) -> None:
        self.state = state
        self.window = window
        self.panel = TeachDock(state)
        self.overlay = TeachOverlay(scene.plotter, scene.render)
        self.dock = QDockWidget("Teach", window)
        self.dock.setObjectName("teach")
        self.dock.setWidget(self.panel)
        window.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, self.dock)
        if beside is not None:  # a tab beside the inspector: the 3D view keeps its width
            window.tabifyDockWidget(beside, self.dock)
        self.dock.hide()
        for signal in (state.selection_changed, state.frame_changed):
            signal.connect(lambda *_: self.update())
        for signal in (state.document_changed, state.motion_changed):
            signal.connect(self.update)
        self.panel.amount_changed.connect(lambda _: self.update())
        self.dock.visibilityChanged.connect(lambda _: self.update())

    def show(self) -> None:
        """Show the dock in front of its tab group."""
        self.dock.show()
        self.dock.raise_()
        self.window.resizeDocks([self.dock], [WIDTH], Qt.Orientation.Horizontal)

    def update(self) -> None:
        if not self.dock.isVisible():
            self.overlay.clear()
            return
        frame = min(self.state.frame, max(0, self.state.n_frames - 1))
        self.overlay.show(self.state.snapshot, self.state.selected, frame, self.panel.amount_value)
