"""The Error dock: the active comparison's error over time on :class:`~app.timeplot.TimePlot`.

Two curves against the document's frames: the MPJPE (mean over the matched joints) and,
when a matched joint is selected, that joint's position error, both in the document's
units. The cursor follows the current frame; a click or drag in the plot seeks.
"""

from __future__ import annotations

import html

import numpy as np
from PyQt6.QtWidgets import QLabel, QVBoxLayout, QWidget

from gmr_studio.app.docks.frame_follow import follow_frame
from gmr_studio.app.docks.rich_text import slot
from gmr_studio.app.docks.timeplot import TimePlot
from gmr_studio.app.model.formatting import format_lengths
from gmr_studio.app.model.layers import Layers

MPJPE_COLOUR = "#4e79a7"
JOINT_COLOUR = "#f28e2b"


class ErrorDock(QWidget):
    """MPJPE and the selected joint's error of ``layers.active``; empty without a comparison."""

    def __init__(self, layers: Layers, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.layers = layers
        self.state = layers.state
        self.plot = TimePlot()
        self.title = QLabel()
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(self.title)
        layout.addWidget(self.plot, 1)
        self.plot.frame_requested.connect(self.state.set_frame)
        self.frame_follower = follow_frame(self, self.state, self.plot.set_cursor)  # only while shown
        self.state.selection_changed.connect(lambda _joint: self.refresh())
        layers.changed.connect(self.refresh)
        layers.appearance_changed.connect(lambda _index: self.refresh())
        self.refresh()

    def refresh(self) -> None:
        """Plot the curves of the active layer (or nothing)."""
        layer = self.layers.active
        if layer is None or self.state.motion is None:
            self.title.setText("No comparison: File > Compare with...")
            self.plot.set_curves(np.zeros(0, np.int64), (), np.zeros((0, 0)))
            return
        comparison = layer.comparison
        columns, values, colours = ["MPJPE"], [comparison.position.per_frame], [MPJPE_COLOUR]
        joint = self.selected_pair()
        if joint is not None:
            columns.append(comparison.names_a[joint])
            values.append(comparison.position_error[:, joint])
            colours.append(JOINT_COLOUR)
        self.plot.set_curves(comparison.frames, columns, np.stack(values, axis=1), comparison.units_text, colours)
        self.plot.set_cursor(self.state.frame)
        self.plot.autoscale()
        self.title.setText(f"Error of the document against {layer.name} ({comparison.units_text})")

    def selected_pair(self) -> int | None:
        """The column of the selected joint in the active comparison, or None (not matched)."""
        layer, joint = self.layers.active, self.state.selected
        if layer is None or joint is None:
            return None
        hits = np.flatnonzero(layer.comparison.index_a == joint)
        return int(hits[0]) if hits.size else None


def inspector_section(layers: Layers, frame: int, joint: int | None) -> list[str]:
    """The inspector's comparison section (HTML parts): for the selected joint, its position
    and its match's, the position error and the rotation error at ``frame``."""
    layer = layers.active
    if layer is None or joint is None:
        return []
    comparison = layer.comparison
    size = layers.state.motion.size
    name = html.escape(layer.name)
    hits = np.flatnonzero(comparison.index_a == joint)
    if not hits.size:
        return [f"<p><b>Compared with {name}</b>: this joint has no match.</p>"]
    pair, row = int(hits[0]), comparison.row_of_frame(frame)
    if row is None:
        return [f"<p><b>Compared with {name}</b>: frame {frame} not compared.</p>"]
    error = comparison.position_error[row, pair]
    rotation = np.nan if comparison.rotation_error is None else comparison.rotation_error[row, pair]
    units = comparison.units_text
    rows = (
        ("Match", html.escape(comparison.names_b[pair])),
        ("Position (document)", slot(format_lengths(comparison.positions_a[row, pair], size))),
        ("Position (match)", slot(format_lengths(comparison.positions_b[row, pair], size))),
        ("Position error", slot(f"{error:.4g} {units}" if np.isfinite(error) else "not compared (a gap)")),
        ("Rotation error", slot(f"{rotation:.4g} deg" if np.isfinite(rotation) else "none (a root or no rotations)")),
    )
    table = "".join(f"<tr><td><b>{k}</b>&nbsp;</td><td>{v}</td></tr>" for k, v in rows)
    return [f"<p style='margin-bottom:2px'><b>Compared with {name}</b></p><table>{table}</table>"]
