"""The Layers dock: the document and its comparison layers (motions and marker sets), each
with colour, visibility, opacity, remove, and the alignment it was compared with (offset,
units, fit, RMS); under the table, the alignment of the chosen layer, adjustable
(:class:`~app.layer_alignment.LayerAlignmentBox`).

Rows are rebuilt from :class:`~app.layers.Layers` whenever it changes; the widgets only call
its methods. "Error colours" asks for the error view (:attr:`LayersDock.errors_toggled`; the window
wires it to :class:`~app.scene.ghost_layer.GhostLayers`).
"""

from __future__ import annotations

from PyQt6.QtCore import pyqtSignal
from PyQt6.QtGui import QColor
from PyQt6.QtWidgets import (
    QCheckBox,
    QColorDialog,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QSpinBox,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.docks.layer_alignment import LayerAlignmentBox
from gmr_studio.app.model.layers import Layers
from gmr_studio.app.model.marker_layers import MarkerLayer

COLUMNS = ("", "shown", "layer", "opacity %", "alignment", "")
DOCK_MINIMUM = 100  # pixels: as app.main_window.DOCK_MINIMUM


class LayersDock(QWidget):
    """Rows: the document first (not removable), then each comparison layer."""

    compare_requested = pyqtSignal()  # the "Compare with..." button
    errors_toggled = pyqtSignal(bool)

    def __init__(self, layers: Layers, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.layers = layers
        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.verticalHeader().hide()
        self.table.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
        self.table.horizontalHeader().setStretchLastSection(False)
        self.table.setMinimumHeight(60)  # gives way to the alignment box below
        self.table.setSelectionBehavior(QTableWidget.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QTableWidget.SelectionMode.SingleSelection)
        self.chosen = None  # the layer whose alignment the box shows (kept across rebuilds)
        self.alignment = LayerAlignmentBox(layers)
        self.add_button = QPushButton("Compare with...")
        self.add_button.clicked.connect(self.compare_requested)
        self.errors = QCheckBox("Error colours")
        self.errors.setChecked(True)
        self.errors.toggled.connect(self.errors_toggled)
        self.summary = QLabel()
        self.summary.setWordWrap(True)
        row = QHBoxLayout()
        row.addWidget(self.add_button)
        row.addWidget(self.errors)
        row.addStretch(1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(row)
        layout.addWidget(self.table, 1)
        layout.addWidget(self.alignment)
        layout.addWidget(self.summary)
        self.table.itemSelectionChanged.connect(self._on_selection_changed)
        layers.changed.connect(self.refresh)
        layers.appearance_changed.connect(lambda _index: self.refresh())
        layers.state.document_changed.connect(self.refresh)
        self.refresh()

    def _fit_rows(self, rows: int) -> None:
        """The table at least as tall as ``rows`` rows (the document and a layer are seen
        together), the alignment box below taking the rest."""
        table = self.table
        height = (
            table.horizontalHeader().sizeHint().height()
            + rows * table.verticalHeader().defaultSectionSize()
            + table.horizontalScrollBar().sizeHint().height()
            + 2 * table.frameWidth()
        )
        table.setMinimumHeight(max(60, height))

    def refresh(self) -> None:
        document = self.layers.state.snapshot
        self.table.blockSignals(True)
        self.table.setRowCount(0)
        self.table.blockSignals(False)
        if document is None:
            self.summary.setText("No document.")
            self.alignment.show_layer(None)
            return
        name = self.layers.state.path.name if self.layers.state.path else "document"
        self.table.setRowCount(1 + len(self.layers))
        document_item = QTableWidgetItem(f"{name} (the document)")
        document_item.setToolTip("the motion you edit; the layers below are read-only")
        self.table.setItem(0, 2, document_item)
        for i, layer in enumerate(self.layers.layers, start=1):
            index = i - 1
            swatch = QPushButton()
            swatch.setToolTip("the layer's colour (click to change)")
            swatch.setStyleSheet(f"background-color: {QColor.fromRgbF(*layer.colour).name()}")
            swatch.clicked.connect(lambda _=False, k=index: self._choose_colour(k))
            self.table.setCellWidget(i, 0, swatch)
            shown = QCheckBox()
            shown.setChecked(layer.visible)
            shown.toggled.connect(lambda on, k=index: self.layers.set_visible(k, on))
            self.table.setCellWidget(i, 1, shown)
            kind, tip = "", ""
            if isinstance(layer, MarkerLayer):
                computed = layer.markers.computed
                share = f", {100 * computed.mean():.2g}% computed" if computed.any() else ""
                kind = f" (markers{share})"
                if computed.any():
                    tip = f"{int(computed.sum())} samples computed by the capture software (filled in), not measured"
            name_item = QTableWidgetItem(layer.name + kind)
            name_item.setToolTip(tip)
            self.table.setItem(i, 2, name_item)
            opacity = QSpinBox()
            opacity.setRange(5, 100)
            opacity.setSingleStep(5)
            opacity.setValue(round(layer.opacity * 100))
            opacity.valueChanged.connect(lambda v, k=index: self.layers.set_opacity(k, v / 100))
            self.table.setCellWidget(i, 3, opacity)
            alignment = QTableWidgetItem(layer.alignment_text)
            alignment.setToolTip(layer.alignment_details[1])
            self.table.setItem(i, 4, alignment)
            remove = QPushButton("Remove")
            remove.clicked.connect(lambda _=False, k=index: self.layers.remove(k))
            self.table.setCellWidget(i, 5, remove)
        self.table.resizeColumnsToContents()
        self._fit_rows(min(self.table.rowCount(), 3))
        self.choose(self.chosen if self.chosen in self.layers.layers else (self.layers.layers or [None])[-1])
        active = self.layers.active
        if active is None:
            drawn = any(isinstance(layer, MarkerLayer) for layer in self.layers.layers)
            self.summary.setText(
                "Marker-set layers are drawn over the document, not compared joint by joint."
                if drawn
                else "No comparison: File > Compare with... (or drop a file with Shift)."
            )
            return
        c = active.comparison
        p = c.position
        self.summary.setText(
            f"{active.name}: {c.n_pairs} joints matched, MPJPE {p.mean:.4g} {c.units_text}, "
            f"max {p.max:.4g} ({p.max_joint}, frame {p.max_frame}); "
            f"unmatched: {len(c.unmatched_a)} of the document, {len(c.unmatched_b)} of the layer"
        )

    def choose(self, layer) -> None:
        """Select ``layer``'s row (None: none) and show its alignment under the table."""
        self.chosen = layer
        index = self.layers.layers.index(layer) if layer is not None else None
        self.table.blockSignals(True)
        self.table.clearSelection()
        if index is not None:
            self.table.selectRow(index + 1)
        self.table.blockSignals(False)
        self.alignment.show_layer(index)

    def _on_selection_changed(self) -> None:
        rows = {item.row() for item in self.table.selectedItems()} | {
            index.row() for index in self.table.selectionModel().selectedRows()
        }
        row = min(rows) if rows else 0
        if row >= 1:  # row 0 is the document: keep the chosen layer
            self.choose(self.layers[row - 1])

    def _choose_colour(self, index: int) -> None:
        colour = QColorDialog.getColor(QColor.fromRgbF(*self.layers[index].colour), self, "Layer colour")
        if colour.isValid():
            self.layers.set_colour(index, (colour.redF(), colour.greenF(), colour.blueF()))
