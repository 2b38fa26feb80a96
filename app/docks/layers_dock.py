"""The Layers dock: the document and its comparison layers (motions and marker sets), each
with its colour and visibility; under the table, the chosen layer: its name, the alignment it
was compared with (offset, units, fit, RMS), its opacity, remove, and its alignment,
adjustable (:class:`~app.layer_alignment.LayerAlignmentBox`).

It lives in the side column beside the view (a tab of the Forest), so everything is laid
out to be read at the column's width: two narrow columns in the table, the name taking
the rest (the full name on hover), the chosen layer's text wrapped under it.

Rows are rebuilt from :class:`~app.layers.Layers` whenever it changes; the widgets only call
its methods. "Error colours" asks for the error view (:attr:`LayersDock.errors_toggled`; the window
wires it to :class:`~app.scene.ghost_layer.GhostLayers`).
"""

from __future__ import annotations

import html

from PyQt6.QtCore import QEvent, Qt, QTimer, pyqtSignal
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

COLUMNS = ("", "shown", "layer")
SWATCH = 18  # pixels: the colour button's side
SHOWN_ROWS = 6  # rows the table grows to before it scrolls
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
        header = self.table.horizontalHeader()
        header.setStretchLastSection(True)  # the name takes the column's width
        header.setMinimumSectionSize(SWATCH + 6)
        self.table.setTextElideMode(Qt.TextElideMode.ElideMiddle)
        self.table.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        # a name longer than its cell wraps, its row as tall as its lines, whatever the width
        self._refit = QTimer(self, singleShot=True, interval=0)
        self._refit.timeout.connect(self._fit_rows)
        self.table.viewport().installEventFilter(self)
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
        # the chosen layer: name, alignment in one line, opacity and remove
        self.chosen_name = QLabel()
        self.chosen_name.setWordWrap(True)
        self.chosen_text = QLabel()
        self.chosen_text.setWordWrap(True)
        self.opacity = QSpinBox()
        self.opacity.setRange(5, 100)
        self.opacity.setSingleStep(5)
        self.opacity.setSuffix(" %")
        self.opacity.setToolTip("the chosen layer's opacity")
        self.opacity.valueChanged.connect(self._on_opacity_chosen)
        self.remove_button = QPushButton("Remove")
        self.remove_button.setToolTip("remove the chosen layer (the document stays)")
        self.remove_button.clicked.connect(self._on_remove_clicked)
        row = QHBoxLayout()
        row.addWidget(self.add_button)
        row.addWidget(self.errors)
        row.addStretch(1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(row)
        layout.addWidget(self.table)
        layout.addWidget(self.chosen_name)
        layout.addWidget(self.chosen_text)
        controls = QHBoxLayout()
        self.opacity_label = QLabel("opacity")
        controls.addWidget(self.opacity_label)
        controls.addWidget(self.opacity)
        controls.addStretch(1)
        controls.addWidget(self.remove_button)
        layout.addLayout(controls)
        layout.addWidget(self.alignment)
        layout.addWidget(self.summary)
        layout.addStretch(1)
        self.table.itemSelectionChanged.connect(self._on_selection_changed)
        layers.changed.connect(self.refresh)
        layers.appearance_changed.connect(lambda _index: self.refresh())
        layers.state.document_changed.connect(self.refresh)
        self.refresh()

    def eventFilter(self, watched, event) -> bool:  # noqa: N802 (Qt's name)
        if event.type() == QEvent.Type.Resize and watched is self.table.viewport():
            self._refit.start()  # once the layout has settled at the new width
        return super().eventFilter(watched, event)

    def _fit_rows(self) -> None:
        """Rows as tall as their names' lines; the table as tall as its rows (at least its
        first three: the document and a layer are seen together; at most
        :data:`SHOWN_ROWS`, then it scrolls), the chosen layer's part right under it."""
        table = self.table
        table.resizeRowsToContents()
        frame = table.horizontalHeader().sizeHint().height() + 2 * table.frameWidth()
        heights = [table.rowHeight(r) for r in range(table.rowCount())]
        table.setMinimumHeight(max(60, frame + sum(heights[:3])))
        table.setMaximumHeight(max(60, frame + sum(heights[:SHOWN_ROWS])))

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
        document_item.setToolTip(f"{name}: the motion you edit; the layers below are read-only")
        self.table.setItem(0, 2, document_item)
        for i, layer in enumerate(self.layers.layers, start=1):
            index = i - 1
            swatch = QPushButton()
            swatch.setFixedSize(SWATCH, SWATCH)
            swatch.setToolTip("the layer's colour (click to change)")
            swatch.setStyleSheet(f"background-color: {QColor.fromRgbF(*layer.colour).name()}")
            swatch.clicked.connect(lambda _=False, k=index: self._choose_colour(k))
            self.table.setCellWidget(i, 0, swatch)
            shown = QCheckBox()
            shown.setToolTip("show the layer")
            shown.setChecked(layer.visible)
            shown.toggled.connect(lambda on, k=index: self.layers.set_visible(k, on))
            self.table.setCellWidget(i, 1, shown)
            kind, tip = layer_kind(layer)
            item = QTableWidgetItem(layer.name + kind)
            item.setToolTip(f"{layer.name}{kind}: {layer.alignment_text}{tip}")
            self.table.setItem(i, 2, item)
        for column in (0, 1):
            self.table.resizeColumnToContents(column)
        self._fit_rows()
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
        self._show_chosen(layer)

    def _show_chosen(self, layer) -> None:
        """The chosen layer's name, alignment line and opacity under the table (hidden for none)."""
        for widget in (self.chosen_name, self.chosen_text, self.opacity_label, self.opacity, self.remove_button):
            widget.setVisible(layer is not None)
        if layer is None:
            return
        kind, tip = layer_kind(layer)
        self.chosen_name.setText(f"<b>{html.escape(layer.name)}</b>{kind}")
        self.chosen_name.setToolTip(tip.removeprefix("; "))
        self.chosen_text.setText(html.escape(layer.alignment_text))
        self.opacity.blockSignals(True)
        self.opacity.setValue(round(layer.opacity * 100))
        self.opacity.blockSignals(False)

    def _on_opacity_chosen(self, percent: int) -> None:
        if self.chosen in self.layers.layers:
            self.layers.set_opacity(self.layers.layers.index(self.chosen), percent / 100)

    def _on_remove_clicked(self) -> None:
        if self.chosen in self.layers.layers:
            self.layers.remove(self.layers.layers.index(self.chosen))

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


def layer_kind(layer) -> tuple[str, str]:
    """What a layer's name is followed by (``" (markers, 0.74% computed)"``) and a tooltip's
    note on the computed samples (empty when none are)."""
    if not isinstance(layer, MarkerLayer):
        return "", ""
    computed = layer.markers.computed
    if not computed.any():
        return " (markers)", ""
    share = f" (markers, {100 * computed.mean():.2g}% computed)"
    return share, f"; {int(computed.sum())} samples computed by the capture software (filled in), not measured"
