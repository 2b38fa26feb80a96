"""Marker alignment dialog: adjust what the automatic alignment cannot know.

Scale, offset, a turn about the up axis and a frame offset, previewed live in the view;
Auto recomputes :func:`app.alignment.auto_alignment`, Cancel restores what was there.
"""

from __future__ import annotations

import numpy as np
from PyQt6.QtWidgets import (
    QDialog,
    QDialogButtonBox,
    QDoubleSpinBox,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QSpinBox,
    QWidget,
)

from gmr_studio.app.alignment import MarkerAlignment, auto_alignment, rotation_about
from gmr_studio.app.scene import up_axis_of
from gmr_studio.app.state import StudioState


class AlignmentDialog(QDialog):
    """Edits the state's marker alignment in place (Cancel puts the old one back)."""

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Marker alignment")
        self.state = state
        self.original = state.marker_overlay.alignment
        self.base = self.original
        self.up_axis = up_axis_of(state.snapshot)
        size = state.motion.size
        layout = QFormLayout(self)
        self.method = QLabel(self.original.method)
        self.method.setWordWrap(True)
        layout.addRow("Found by", self.method)
        self.scale = QDoubleSpinBox(decimals=6, minimum=1e-6, maximum=1e6, value=self.original.scale)
        self.scale.setToolTip("Motion units per marker unit")
        layout.addRow("Scale", self.scale)
        self.offset = []
        row = QHBoxLayout()
        for axis in range(3):
            box = QDoubleSpinBox(decimals=3, minimum=-1e6, maximum=1e6, value=float(self.original.offset[axis]))
            box.setSingleStep(size / 100)
            self.offset.append(box)
            row.addWidget(box)
        layout.addRow("Offset X Y Z", row)
        self.turn = QDoubleSpinBox(decimals=1, minimum=-180, maximum=180, value=0.0, suffix=" deg")
        self.turn.setSingleStep(90)
        self.turn.setToolTip(f"An extra turn about the up axis ({'XYZ'[self.up_axis]})")
        layout.addRow("Turn about up", self.turn)
        self.frames = QSpinBox(minimum=-100000, maximum=100000, value=self.original.frame_offset)
        self.frames.setToolTip("Marker frame shown at motion frame f is f + this")
        layout.addRow("Frame offset", self.frames)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        auto = QPushButton("Auto")
        auto.setToolTip("Recompute the automatic alignment")
        buttons.addButton(auto, QDialogButtonBox.ButtonRole.ResetRole)
        auto.clicked.connect(self.auto)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        layout.addRow(buttons)
        for box in [self.scale, self.turn, *self.offset]:
            box.valueChanged.connect(self._on_edited)
        self.frames.valueChanged.connect(self._on_edited)

    def alignment(self) -> MarkerAlignment:
        """The alignment the fields describe (a field left as shown keeps its exact value,
        not the value rounded to the box's decimals)."""
        turn = rotation_about(self.up_axis, self.turn.value())
        return self.base.replace(
            rotation=turn @ self.base.rotation,
            scale=_exact(self.scale, self.base.scale),
            offset=np.array([_exact(box, value) for box, value in zip(self.offset, self.base.offset)]),
            frame_offset=self.frames.value(),
            method=self.base.method if self._untouched() else f"{self.base.method}; adjusted by hand",
        )

    def _untouched(self) -> bool:
        return (
            self.turn.value() == 0
            and np.isclose(self.scale.value(), self.base.scale)
            and np.allclose([b.value() for b in self.offset], self.base.offset, atol=1e-3)
            and self.frames.value() == self.base.frame_offset
        )

    def _on_edited(self, *_args) -> None:
        self.state.set_alignment(self.alignment())

    def auto(self) -> None:
        overlay = self.state.marker_overlay
        markers = overlay.markers.resampled(self.state.motion.frame_rate)
        self.base = auto_alignment(
            markers.positions, markers.labels, self.state.positions, self.state.motion.names, markers.units
        )
        widgets = [self.scale, self.turn, self.frames, *self.offset]
        for widget in widgets:
            widget.blockSignals(True)
        self.scale.setValue(self.base.scale)
        self.turn.setValue(0.0)
        self.frames.setValue(0)
        for axis, box in enumerate(self.offset):
            box.setValue(float(self.base.offset[axis]))
        for widget in widgets:
            widget.blockSignals(False)
        self.method.setText(self.base.method)
        self.state.set_alignment(self.base)

    def reject(self) -> None:
        self.state.set_alignment(self.original)
        super().reject()


def _exact(box: QDoubleSpinBox, value: float) -> float:
    """``value`` if the box still shows it (rounded to its decimals), else the box's value."""
    return float(value) if box.value() == round(float(value), box.decimals()) else box.value()
