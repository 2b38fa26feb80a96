"""Marker alignment dialog: adjust what the automatic alignment cannot know.

Scale, translation, a turn about the up axis and a frame offset, previewed live in the view;
Auto recomputes :func:`app.alignment.auto_alignment`, Cancel restores what was there.
The turn is about the vertical line through the figure's centre (the pelvis at the current
frame, :func:`app.alignment.figure_centre_joint`), drawn in the view while the dialog is
open, so a quarter turn spins the markers in place instead of throwing them away.
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

from gmr_studio.app.model.state import StudioState
from gmr_studio.app.scene.highlight import PIVOT_COLOR, PivotMarker
from gmr_studio.core.markers.alignment import MarkerAlignment, auto_alignment, figure_centre_joint, turned_about
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.space.up_axis import up_axis_of

__all__ = ["PIVOT_COLOR", "AlignmentDialog"]

#: name and colour of the pivot drawn in the view while the dialog is open


class AlignmentDialog(QDialog):
    """Edits the state's marker alignment in place (Cancel puts the old one back)."""

    def __init__(self, state: StudioState, parent: QWidget | None = None, scene=None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Marker alignment")
        self.state = state
        self.original = state.marker_overlay.alignment
        self.base = self.original
        self.up_axis = up_axis_of(state.snapshot.motion)
        size = state.motion.size
        layout = QFormLayout(self)
        self.method = QLabel(self.original.method)
        self.method.setWordWrap(True)
        layout.addRow("Found by", self.method)
        self.scale = QDoubleSpinBox(decimals=6, minimum=1e-6, maximum=1e6, value=self.original.transform.scale)
        self.scale.setToolTip("Motion units per marker unit")
        layout.addRow("Scale", self.scale)
        self.translation = []
        row = QHBoxLayout()
        for axis in range(3):
            start = float(self.original.transform.translation[axis])
            box = QDoubleSpinBox(decimals=3, minimum=-1e6, maximum=1e6, value=start)
            box.setSingleStep(size / 100)
            self.translation.append(box)
            row.addWidget(box)
        layout.addRow("Translation X Y Z", row)
        self.turn = QDoubleSpinBox(decimals=1, minimum=-180, maximum=180, value=0.0, suffix=" deg")
        self.turn.setSingleStep(90)
        self.pivot_joint = figure_centre_joint(state.motion.names, state.motion.tree_roots)
        pivot_name = state.motion.names[self.pivot_joint]
        self.turn.setToolTip(
            f"An extra turn about the up axis ({self.up_axis.upper()}) through {pivot_name} at the current frame"
        )
        layout.addRow("Turn about up", self.turn)
        self.pivot_label = QLabel()
        layout.addRow("Turns about", self.pivot_label)
        self.scene = scene
        self._pivot_marker = PivotMarker()
        self._show_pivot()
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
        for box in [self.scale, self.turn, *self.translation]:
            box.valueChanged.connect(self._on_edited)
        self.frames.valueChanged.connect(self._on_edited)

    def alignment(self) -> MarkerAlignment:
        """The alignment the fields describe (a field left as shown keeps its exact value,
        not the value rounded to the box's decimals)."""
        base = self.base.transform
        fields = self.base.replace(
            transform=Similarity(
                base.rotation,
                _exact(self.scale, base.scale),
                np.array([_exact(box, value) for box, value in zip(self.translation, base.translation)]),
            ),
            frame_offset=self.frames.value(),
            method=self.base.method if self._untouched() else f"{self.base.method}; adjusted by hand",
        )
        if self.turn.value() == 0:
            return fields
        return turned_about(fields, self.up_axis, self.turn.value(), self.pivot())

    def pivot(self) -> np.ndarray:
        """(3,) the point the turn is about: the figure's centre at the current frame."""
        return np.array(self.state.positions[self.state.frame, self.pivot_joint])

    def _show_pivot(self) -> None:
        """Say where the pivot is, and draw it (a sphere on a vertical line) in the view."""
        pivot = self.pivot()
        where = " ".join(f"{v:.4g}" for v in pivot)
        self.pivot_label.setText(f"{self.state.motion.names[self.pivot_joint]} at frame {self.state.frame} ({where})")
        if self.scene is None:
            return
        if self._pivot_marker not in self.scene.drawables:
            self.scene.add_drawable(self._pivot_marker)
        self._pivot_marker.point = pivot
        self.scene.redraw(self._pivot_marker)

    def _hide_pivot(self) -> None:
        if self.scene is not None:
            self.scene.remove_drawable(self._pivot_marker)

    def done(self, result: int) -> None:
        self._hide_pivot()
        super().done(result)

    def _untouched(self) -> bool:
        return (
            self.turn.value() == 0
            and np.isclose(self.scale.value(), self.base.transform.scale)
            and np.allclose([b.value() for b in self.translation], self.base.transform.translation, atol=1e-3)
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
        widgets = [self.scale, self.turn, self.frames, *self.translation]
        for widget in widgets:
            widget.blockSignals(True)
        self.scale.setValue(self.base.transform.scale)
        self.turn.setValue(0.0)
        self.frames.setValue(0)
        for axis, box in enumerate(self.translation):
            box.setValue(float(self.base.transform.translation[axis]))
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
