"""The curves dock: a quantity of the selected (and pinned) joints over time, and range actions.

It reads the state and :mod:`core.analysis.curves` computes the values (from the motion and the
cached world positions); the plot (:class:`app.timeplot.TimePlot`) shows them. Each joint
has its own colour, its axes lighter shades of it and their own line style; the selected marker's coordinates are
drawn too, with its gaps shaded. Clicking or dragging in the plot sets the state's frame;
Shift-dragging selects the state's frame range, which the buttons below play, loop, trim
to (an undoable edit, :mod:`app.commands`); resample and mirror are edits too.
"""

from __future__ import annotations

import numpy as np
from PyQt6.QtCore import Qt
from PyQt6.QtGui import QColor
from PyQt6.QtWidgets import (
    QComboBox,
    QDoubleSpinBox,
    QFileDialog,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.docks.frame_follow import follow_frame
from gmr_studio.app.docks.timeplot import PALETTE, TimePlot
from gmr_studio.app.model import commands
from gmr_studio.app.model.channel_labels import channels_caption
from gmr_studio.app.model.playback import Player
from gmr_studio.app.model.state import StudioState
from gmr_studio.core.analysis.curves import UNITS, Curves, gap_spans, joint_curves, marker_curves, quantity_name
from gmr_studio.core.analysis.curves_table import curves_csv_text
from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.edits.mirror import side_partners
from gmr_studio.core.timebase.clock import nominal_rate

#: (label, core quantity) in the order the combo box lists them; the rotation's two
#: conventions are named as in ``gmr curves`` and the inspector (docs/curves.md)
QUANTITY_LABELS = (
    ("channels: the joint's rotation channels (BVH channels, AMC dofs)", "channels"),
    ("gmr-euler: GMR rotation as Euler angles", "gmr-euler"),
    ("angle: GMR rotation angle", "angle"),
    ("quaternion: GMR rotation", "quaternion"),
    ("Local translation, GMR (R t)", "local-pre"),
    ("Local translation, BVH (t)", "local-post"),
    ("World position", "world"),
    ("Speed", "speed"),
    ("Acceleration", "acceleration"),
)
#: line styles of a joint's successive axes
AXIS_STYLES = (Qt.PenStyle.SolidLine, Qt.PenStyle.DashLine, Qt.PenStyle.DotLine, Qt.PenStyle.DashDotLine)
MARKER_COLOUR = "#e8e8e8"
AXIS_HUE_STEP = 55  # degrees of hue between a joint's successive axes


def axis_colour(base: QColor, axis: int) -> str:
    """The colour of a joint's ``axis``-th curve: its joint's colour turned ``AXIS_HUE_STEP``
    degrees of hue per axis (and its own line style), so axes differ by colour, not only dash."""
    hue = (base.hsvHue() + AXIS_HUE_STEP * axis) % 360
    return QColor.fromHsv(hue, max(base.hsvSaturation(), 120), max(base.value(), 200)).name()


class CurvesDock(QWidget):
    """Plot of the selected joints' quantity over time, with range and clip actions."""

    def __init__(self, state: StudioState, player: Player, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.player = player
        self.pinned: list[int] = []
        self._channel_blocks: list[Curves] = []  # the plotted joints' channels, for their note
        self.quantity_box = QComboBox(self)
        for label, quantity in QUANTITY_LABELS:
            self.quantity_box.addItem(label, quantity)
        self.x_unit_box = QComboBox(self)
        self.x_unit_box.addItem("frames", "frames")
        self.x_unit_box.addItem("seconds", "seconds")
        self.pin_button = QPushButton("Pin", self)
        self.pin_button.setToolTip("Keep the selected joint plotted when another is selected")
        self.clear_pins_button = QPushButton("Unpin all", self)
        # what the channels plotted are (the file's own values, or computed: channels_caption)
        self.channels_note = QLabel(self)
        self.channels_note.setWordWrap(True)
        self.csv_button = QPushButton("CSV...", self)
        self.csv_button.setToolTip("Export the curves in the visible range as CSV")
        self.png_button = QPushButton("PNG...", self)
        self.png_button.setToolTip("Export the plot as a PNG")
        top = QHBoxLayout()
        for widget in (self.quantity_box, self.x_unit_box, self.pin_button, self.clear_pins_button):
            top.addWidget(widget)
        top.addWidget(self.channels_note, 1)
        top.addWidget(self.csv_button)
        top.addWidget(self.png_button)
        self.plot = TimePlot(self)
        self.range_label = QLabel(self)
        self.play_range_button = QPushButton("Play range", self)
        self.loop_range_button = QPushButton("Loop range", self)
        self.trim_button = QPushButton("Trim to range", self)
        self.clear_range_button = QPushButton("Clear range", self)
        self.rate_box = QDoubleSpinBox(self)
        self.rate_box.setRange(1.0, 1000.0)
        self.rate_box.setDecimals(3)
        self.rate_box.setSuffix(" Hz")
        self.rate_box.setValue(30.0)
        self.resample_button = QPushButton("Resample", self)
        self.mirror_button = QPushButton("Mirror L/R", self)
        bottom = QHBoxLayout()
        for widget in (self.range_label, self.play_range_button, self.loop_range_button, self.trim_button):
            bottom.addWidget(widget)
        bottom.addWidget(self.clear_range_button)
        bottom.addStretch(1)
        for widget in (self.rate_box, self.resample_button, self.mirror_button):
            bottom.addWidget(widget)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 2, 4, 2)
        layout.addLayout(top)
        layout.addWidget(self.plot, 1)
        layout.addLayout(bottom)
        self._wire()
        self._on_document_changed()

    def _wire(self) -> None:
        state, plot = self.state, self.plot
        self.quantity_box.currentIndexChanged.connect(lambda _: self.refresh(autoscale=True))
        self.x_unit_box.currentIndexChanged.connect(self._on_x_unit_changed)
        self.pin_button.clicked.connect(self.pin_selected)
        self.clear_pins_button.clicked.connect(self.clear_pins)
        self.csv_button.clicked.connect(self._export_csv_dialog)
        self.png_button.clicked.connect(self._export_png_dialog)
        self.play_range_button.clicked.connect(lambda: self.player.play_range(loop=False))
        self.loop_range_button.clicked.connect(lambda: self.player.play_range(loop=True))
        self.trim_button.clicked.connect(self.trim_to_range)
        self.clear_range_button.clicked.connect(lambda: state.set_frame_range(-1, -1))
        self.resample_button.clicked.connect(lambda: commands.resample_to(state, self.rate_box.value()))
        self.mirror_button.clicked.connect(lambda: commands.mirror_left_right(state))
        plot.frame_requested.connect(state.set_frame)
        plot.range_selected.connect(state.set_frame_range)
        self.frame_follower = follow_frame(self, state, plot.set_cursor)  # only while shown
        state.range_changed.connect(self._on_range_changed)
        state.document_changed.connect(self._on_document_changed)
        state.motion_changed.connect(lambda: self.refresh(autoscale=False))
        state.motion_changed.connect(self._update_edit_buttons)
        state.modified_changed.connect(lambda _: self._show_channels_note())
        state.selection_changed.connect(lambda _: self.refresh(autoscale=True))
        state.marker_selection_changed.connect(lambda _: self.refresh(autoscale=True))
        state.markers_changed.connect(lambda: self.refresh(autoscale=False))

    # ------------------------------------------------------------------ contents
    @property
    def quantity(self) -> str:
        return self.quantity_box.currentData()

    def set_quantity(self, quantity: str) -> None:
        """Show ``quantity`` (a :data:`core.analysis.curves.QUANTITIES` name or an alias such as ``euler``)."""
        self.quantity_box.setCurrentIndex(self.quantity_box.findData(quantity_name(quantity)))

    def plotted_joints(self) -> list[int]:
        """The pinned joints, then the selected one (once)."""
        joints = list(self.pinned)
        if self.state.selected is not None and self.state.selected not in joints:
            joints.append(self.state.selected)
        return joints

    def pin_selected(self) -> None:
        if self.state.selected is not None and self.state.selected not in self.pinned:
            self.pinned.append(self.state.selected)
            self.refresh(autoscale=True)

    def clear_pins(self) -> None:
        self.pinned.clear()
        self.refresh(autoscale=True)

    def refresh(self, autoscale: bool = False) -> None:
        """Recompute and redraw the curves (on selection, quantity or motion changes)."""
        snapshot = self.state.snapshot
        if snapshot is None:
            self.plot.set_curves(np.zeros(0), (), np.zeros((0, 0)))
            self._channel_blocks = []
            self._show_channels_note()
            return
        motion = snapshot.motion
        blocks: list[Curves] = []
        colours: list[str] = []
        styles: list[Qt.PenStyle] = []
        for n, joint in enumerate(self.plotted_joints()):
            block = joint_curves(motion, joint, self.quantity, snapshot.positions, self.state.file_channels)
            blocks.append(block)
            base = QColor(PALETTE[n % len(PALETTE)])
            colours += [axis_colour(base, a) for a in range(len(block.columns))]
            styles += [AXIS_STYLES[a % len(AXIS_STYLES)] for a in range(len(block.columns))]
        spans = np.zeros((0, 2), np.int64)
        overlay, marker = self.state.marker_overlay, self.state.selected_marker
        if overlay is not None and marker is not None:
            positions = overlay.positions[:, marker]
            blocks.append(marker_curves(overlay.markers.labels[marker], positions))
            colours += [MARKER_COLOUR] * 3
            styles += list(AXIS_STYLES[:3])
            spans = gap_spans(positions)
        self._channel_blocks = blocks if self.quantity == "channels" else []
        self._show_channels_note()
        curves = Curves.concatenate(blocks)
        unit = UNITS[self.quantity] if self.plotted_joints() else "units"
        values = curves.values if curves.columns else np.zeros((motion.n_frames, 0))
        self.plot.set_curves(np.arange(motion.n_frames), curves.columns, values, unit, colours, styles)
        self.plot.set_spans(spans)
        self.plot.set_cursor(self.state.frame)
        if autoscale:
            self.plot.autoscale()

    def _show_channels_note(self) -> None:
        """Say what the plotted channels are (:func:`app.model.channel_labels.channels_caption`),
        once when every joint's are alike, else joint by joint."""
        captions, motion = {}, self.state.motion
        for joint, block in zip(self.plotted_joints(), self._channel_blocks, strict=False):
            captions[motion.names[joint]] = channels_caption(block, self.state.path, self.state.modified)
        if len(set(captions.values())) == 1:
            text = next(iter(captions.values()))
        else:
            text = "; ".join(f"{name}: {caption}" for name, caption in captions.items())
        self.channels_note.setText(text)
        self.channels_note.setToolTip(text)

    # ---------------------------------------------------------------- handlers
    def _on_document_changed(self) -> None:
        self.pinned.clear()
        motion = self.state.motion
        self.setEnabled(motion is not None)
        if motion is not None:
            self.plot.frame_time = motion.frame_time
            self.rate_box.setValue(round(nominal_rate(motion.frame_time) / 2, 3))
        self._on_x_unit_changed()
        self.refresh(autoscale=True)
        self._on_range_changed(-1, -1)
        self._update_edit_buttons()

    def _update_edit_buttons(self) -> None:
        """Resample and mirror enabled when they apply, as their Edit menu actions."""
        motion = self.state.motion
        self.resample_button.setEnabled(motion is not None and motion.n_frames >= 2)
        self.mirror_button.setEnabled(motion is not None and side_partners(motion.names).pairs.size > 0)

    def _on_x_unit_changed(self, *_args) -> None:
        motion = self.state.motion
        self.plot.set_x_unit(self.x_unit_box.currentData(), motion.frame_time if motion else 1.0)

    def _on_range_changed(self, start: int, stop: int) -> None:
        self.plot.set_range(start, stop)
        has_range = start >= 0
        for button in (self.play_range_button, self.loop_range_button, self.trim_button, self.clear_range_button):
            button.setEnabled(has_range)
        self.range_label.setText(f"Range {start}-{stop - 1}" if has_range else "Shift+drag: range")

    def trim_to_range(self) -> bool:
        selected = self.state.frame_range
        return selected is not None and commands.trim_to_range(self.state, *selected)

    def _export_csv_dialog(self) -> None:
        path, _ = QFileDialog.getSaveFileName(self, "Export curves as CSV", "curves.csv", "CSV (*.csv)")
        if path:
            self.export_csv(path)
            self.state.show_message(f"Curves written to {path}")

    def export_csv(self, path: str) -> None:
        """The plotted curves within the visible range, written as ``gmr curves`` writes them
        (:func:`core.analysis.curves_table.curves_csv_text`: frame, time, then every column)."""
        plot, rows = self.plot, self.plot.visible_frames()
        frame_time = self.state.motion.frame_time if self.state.motion is not None else 1.0
        curves = Curves(tuple(plot.columns), np.asarray(plot.values)[rows], "")
        atomic_write_text(path, curves_csv_text(curves, np.asarray(plot.frames)[rows], frame_time))

    def _export_png_dialog(self) -> None:
        path, _ = QFileDialog.getSaveFileName(self, "Export the plot as PNG", "curves.png", "PNG (*.png)")
        if path:
            self.plot.export_png(path)
            self.state.show_message(f"Plot written to {path}")
