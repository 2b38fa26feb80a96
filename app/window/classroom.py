"""The classroom wired into a window: the Teach dock and its overlay in the 3D view.

The overlay draws only while the dock is shown, for the selected joint at the current frame,
with the dock's rotation slider.
"""

from __future__ import annotations

from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QDockWidget, QFrame, QMainWindow, QScrollArea

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
        self.scene = scene
        self.overlay = TeachOverlay()
        scene.add_drawable(self.overlay)
        self.dock = QDockWidget("Teach", window)
        self.dock.setObjectName("teach")
        scroll = QScrollArea()  # a dock shorter than the panel scrolls instead of overlapping its parts
        scroll.setWidgetResizable(True)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        scroll.setFrameShape(QFrame.Shape.NoFrame)
        scroll.setWidget(self.panel)
        self.dock.setWidget(scroll)
        window.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, self.dock)
        if beside is not None:  # a tab beside the inspector: the 3D view keeps its width
            window.tabifyDockWidget(beside, self.dock)
        self.dock.hide()
        # the scene draws the overlay at every frame; a new joint, amount or dock rebuilds it
        for signal in (state.selection_changed, state.document_changed, state.motion_changed):
            signal.connect(lambda *_: self.update())
        self.panel.amount_changed.connect(lambda _: self.update())
        self.dock.visibilityChanged.connect(lambda _: self.update())

    def show(self) -> None:
        """Show the dock in front of its tab group."""
        self.dock.show()
        self.dock.raise_()
        self.window.resizeDocks([self.dock], [WIDTH], Qt.Orientation.Horizontal)

    def update(self) -> None:
        self.overlay.shown = self.dock.isVisible()
        self.overlay.joint = self.state.selected
        self.overlay.amount = self.panel.amount_value
        self.scene.redraw(self.overlay)
