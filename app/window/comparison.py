"""Comparison layers wired into the window: the model, its drawing, its docks and menu.

:func:`install_comparison` makes :class:`~app.model.layers.Layers`, adds its drawable
(:class:`~app.scene.ghost_layer.GhostLayers`) to the scene, the Layers dock (tabbed with the
Forest) and the Error dock (with the analysis tabs), both hidden until the first layer is
added, File > Compare with... (Ctrl+Shift+O) and the inspector's comparison section.
"""

from __future__ import annotations

import functools

from PyQt6.QtCore import Qt, QTimer
from PyQt6.QtWidgets import QDockWidget, QWidget

from gmr_studio.app.docks.error_dock import ErrorDock, inspector_section
from gmr_studio.app.docks.layers_dock import LayersDock
from gmr_studio.app.model.layers import Layers
from gmr_studio.app.scene.ghost_layer import GhostLayers
from gmr_studio.app.window import layout

DOCK_MINIMUM = 100  # pixels: as app.window.layout.DOCK_MINIMUM


def install_comparison(window, state, scene, files, beside) -> tuple[Layers, GhostLayers, LayersDock, object]:
    """Comparison layers in ``window``: the model, its drawing in ``scene``, the Layers dock
    (to be tabbed with the dock ``beside``) and the Error dock (with Curves), both hidden
    until the first layer is added, File > Compare with... (Ctrl+Shift+O), the inspector's
    comparison section."""
    from PyQt6.QtGui import QAction

    layers = Layers(state, window)
    files.layers = layers
    ghosts = GhostLayers(state, layers)
    scene.add_drawable(ghosts)
    panel = LayersDock(layers)
    panel.compare_requested.connect(files.compare_dialog)
    panel.errors_toggled.connect(ghosts.set_show_errors)
    errors = ErrorDock(layers)
    window.error_plot = errors
    # the Layers tab scrolls rather than asking for its full height (about 300 pixels), so
    # that the Inspector below it keeps its room
    docks = [_hidden_dock(window, "Layers", _scrolled(panel), Qt.DockWidgetArea.RightDockWidgetArea)]
    docks.append(_hidden_dock(window, "Error", errors, Qt.DockWidgetArea.BottomDockWidgetArea))
    # tabbed only when first shown: tabbing hidden docks before the window is shown leaves
    # stray tab bars behind in Qt's layout (the Error dock joins the analysis tabs by
    # app.window.layout.tab_when_shown)
    window.splitDockWidget(window.curves_dock, docks[1], Qt.Orientation.Horizontal)  # the analysis area
    layout.tab_when_shown(window, [beside, docks[0]])  # Layers: a tab of the Forest
    count = [0]

    def share_column() -> None:
        column = [docks[0], window.inspector_dock]
        half = sum(dock.height() for dock in column) // 2
        window.resizeDocks(column, [half, half], Qt.Orientation.Vertical)

    def on_layers_changed() -> None:  # a layer added: show the docks, the plot in front
        if len(layers) > count[0]:  # a marker-set layer has no error to plot: Layers only
            first = not docks[0].isVisible()
            for dock in docks if layers[len(layers) - 1].comparison is not None else docks[:1]:
                dock.show()
                dock.raise_()
            if first:  # the Layers tab and the Inspector share the column evenly, once laid out
                QTimer.singleShot(0, share_column)
        count[0] = len(layers)

    layers.changed.connect(on_layers_changed)
    action = QAction("&Compare with...", window, shortcut="Ctrl+Shift+O")
    action.setStatusTip("show another motion as a ghost compared with the document, joint by joint")
    action.triggered.connect(files.compare_dialog)
    file_menu = window.menuBar().actions()[0].menu()
    file_menu.insertAction(file_menu.actions()[2], action)  # after Open and Open recent
    window.addAction(action)
    window.compare_action = action
    window.inspector.sections.append(functools.partial(inspector_section, layers))
    layers.changed.connect(window.inspector._on_changed)
    return layers, ghosts, panel, docks[1]


def _scrolled(widget: QWidget) -> QWidget:
    """``widget`` in a frameless scroll area that lets it grow to the area's size."""
    from PyQt6.QtWidgets import QFrame, QScrollArea

    area = QScrollArea()
    area.setWidget(widget)
    area.setWidgetResizable(True)
    area.setFrameShape(QFrame.Shape.NoFrame)
    return area


def _hidden_dock(window, title: str, widget: QWidget, area: Qt.DockWidgetArea):
    """A hidden dock in ``area`` listed in View; it gives way to the 3D view like the others."""
    dock = QDockWidget(title, window)
    dock.setObjectName(title.lower())
    dock.setWidget(widget)
    widget.setMinimumWidth(DOCK_MINIMUM)
    window.addDockWidget(area, dock)
    dock.hide()
    window.view_menu.addAction(dock.toggleViewAction())
    return dock
