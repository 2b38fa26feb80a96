"""The alignment of one comparison layer, shown and adjustable in the Layers dock.

Like the marker alignment (:mod:`app.alignment_dialog`), but for a read-only layer: the
kind (none, rigid, similarity) and the time offset (found, or a given number of A's frames)
are set through :meth:`app.layers.Layers.set_alignment`, which compares the layer again
(ghost, error colours and error plot follow its ``changed`` signal). The document and its
undo stack are never touched. Under the controls, the resulting parameters: RMS before and
after, the fitted turn, translation and scale, offset and units (matrices in the tooltip).
A marker-set layer shows its marker alignment, read-only.
"""

from __future__ import annotations

from PyQt6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QGridLayout,
    QGroupBox,
    QLabel,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.model.layers import ComparisonLayer, Layers
from gmr_studio.core.compare import ALIGN_KINDS

OFFSET_LIMIT = 1e6  # frames either way
DETAIL_LINES = 5  # room kept for the parameters under the controls
MINIMUM_BOX_WIDTH = 70  # pixels the kind and offset boxes may be squeezed to


class LayerAlignmentBox(QGroupBox):
    """Kind, offset (auto or frames) and the resulting parameters of layer ``index`` (its
    name is shown above the box, where it may wrap: a group box's title is cut)."""

    def __init__(self, layers: Layers) -> None:
        super().__init__("Alignment")
        self.layers = layers
        self.index: int | None = None
        self.kind = QComboBox()
        self.kind.addItems(ALIGN_KINDS)
        self.kind.setToolTip("fitted after units and up axis: none, rigid (turn + move), similarity (+ scale)")
        self.auto = QCheckBox("auto")
        self.auto.setToolTip("find the time offset from the whole body (every matched joint; then keep it)")
        self.offset = QDoubleSpinBox(decimals=2, minimum=-OFFSET_LIMIT, maximum=OFFSET_LIMIT, suffix=" frames")
        self.offset.setKeyboardTracking(False)  # typed numbers apply on Enter, arrows at once
        self.offset.setToolTip("B's time minus the document's, in the document's frames")
        for box in (self.kind, self.offset):  # they may give way to a narrow column (their text fits)
            box.setMinimumWidth(MINIMUM_BOX_WIDTH)
        self.details = QLabel()
        self.details.setWordWrap(True)
        self.details.setMinimumHeight(DETAIL_LINES * self.details.fontMetrics().lineSpacing() + 4)
        self.controls = QWidget()  # hidden for a marker-set layer
        # two rows, narrow enough for the side column the Layers dock lives in
        rows = QGridLayout(self.controls)
        rows.setContentsMargins(0, 0, 0, 0)
        rows.addWidget(QLabel("kind"), 0, 0)
        rows.addWidget(self.kind, 0, 1)
        rows.addWidget(QLabel("offset"), 1, 0)
        rows.addWidget(self.offset, 1, 1)
        rows.addWidget(self.auto, 1, 2)
        rows.setColumnStretch(3, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addWidget(self.controls)
        layout.addWidget(self.details)
        self.kind.currentTextChanged.connect(self._on_kind_chosen)
        self.auto.toggled.connect(self._on_auto_toggled)
        self.offset.valueChanged.connect(self._on_offset_chosen)
        self.show_layer(None)

    def show_layer(self, index: int | None) -> None:
        """Show layer ``index`` (None: nothing chosen) without changing it."""
        self.index = index
        layer = None if index is None or index >= len(self.layers) else self.layers[index]
        editable = isinstance(layer, ComparisonLayer) and layer.comparison is not None
        for widget in (self.kind, self.auto, self.offset):
            widget.blockSignals(True)
        if editable:
            self.kind.setCurrentText(layer.align)
            self.auto.setChecked(layer.auto_offset)
            self.offset.setValue(layer.comparison.alignment.offset_frames)
        for widget in (self.kind, self.auto, self.offset):
            widget.blockSignals(False)
            widget.setEnabled(editable)
        self.offset.setEnabled(editable and not layer.auto_offset)
        self.controls.setVisible(layer is None or editable)
        if layer is None:
            self.details.setText("Choose a layer in the table.")
            self.details.setToolTip("")
            return
        line, tooltip = layer.alignment_details
        self.details.setText(line)
        self.details.setToolTip(tooltip)

    def _on_kind_chosen(self, kind: str) -> None:
        if self.index is not None:
            self.layers.set_alignment(self.index, kind=kind)

    def _on_auto_toggled(self, on: bool) -> None:
        if self.index is not None:  # off: the offset found is kept, now as a given number
            self.layers.set_alignment(self.index, offset="auto" if on else self.offset.value())

    def _on_offset_chosen(self, frames: float) -> None:
        if self.index is not None and not self.auto.isChecked():
            self.layers.set_alignment(self.index, offset=float(frames))
