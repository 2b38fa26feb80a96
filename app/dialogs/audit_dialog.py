"""Tools > Audit round trips: the open document through every path (core.compare.audit), as a table.

One row per path: worst position error, relative to the skeleton's size, the documented
tolerance, ok or FAIL (failing rows in red), and the worst joint. Choosing a row selects its
worst joint in the view (and goes to its frame), and rings every joint the path moved beyond
its tolerance (:attr:`AuditPath.failing_joints`) in red in the view
(:class:`FailingJointsHighlight`, its own actors), so a failing path points at where it fails.
"""

from __future__ import annotations

import numpy as np
from PyQt6.QtCore import Qt
from PyQt6.QtGui import QBrush, QColor
from PyQt6.QtWidgets import (
    QApplication,
    QDialog,
    QDialogButtonBox,
    QLabel,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.model.state import StudioState
from gmr_studio.app.scene.highlight import JointsHighlight
from gmr_studio.core.compare.audit import AuditPath, audit_motion

COLUMNS = ("path", "max error", "relative", "tolerance", "result", "worst joint", "frame")
FAIL_COLOUR = QColor(200, 60, 60)


class FailingJointsHighlight:
    """The failing joints ringed in the scene (a :class:`~app.scene.highlight.JointsHighlight`
    drawable added while the dialog is open)."""

    def __init__(self, state: StudioState, scene) -> None:
        self.state = state
        self.scene = scene
        self.drawing = JointsHighlight()
        if scene is not None:
            scene.add_drawable(self.drawing)

    @property
    def part(self):
        return self.drawing.part

    @property
    def joints(self) -> np.ndarray:
        return self.drawing.joints

    def show(self, names: tuple[str, ...]) -> None:
        """Ring the joints named ``names`` (those the document has); an empty tuple clears."""
        self.drawing.names = tuple(names)
        if self.scene is not None:
            self.scene.redraw(self.drawing)

    def clear(self) -> None:
        self.show(())

    def disconnect(self) -> None:
        if self.scene is not None:
            self.scene.remove_drawable(self.drawing)


class AuditDialog(QDialog):
    """The audit of ``state``'s document; ``paths`` holds the results shown."""

    def __init__(self, state: StudioState, parent: QWidget | None = None, scene=None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Audit round trips")
        self.state = state
        self.highlight = FailingJointsHighlight(state, scene)
        self.finished.connect(lambda _result: self.highlight.disconnect())
        self.paths: list[AuditPath] = []
        self.summary = QLabel()
        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.setSelectionBehavior(QTableWidget.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QTableWidget.SelectionMode.SingleSelection)
        self.table.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.itemSelectionChanged.connect(self._on_row_chosen)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Close)
        buttons.rejected.connect(self.reject)
        layout = QVBoxLayout(self)
        layout.addWidget(self.summary)
        layout.addWidget(self.table)
        layout.addWidget(buttons)
        self.resize(820, 520)

    def run_audit(self) -> list[AuditPath]:
        """Audit the document now (seconds on a long motion: a wait cursor meanwhile)."""
        motion = self.state.motion
        if motion is None:
            self.paths = []
            self.summary.setText("No document open.")
            self.table.setRowCount(0)
            return self.paths
        QApplication.setOverrideCursor(Qt.CursorShape.WaitCursor)
        try:
            # the file's own paths (the ASF rest pose of an AMC) only while the document is the file
            source = self.state.path if not self.state.modified else None
            self.paths = audit_motion(motion, source)
        finally:
            QApplication.restoreOverrideCursor()
        self._fill()
        return self.paths

    def _fill(self) -> None:
        failed = [p for p in self.paths if not p.ok]
        self.summary.setText(
            f"{len(self.paths) - len(failed)} of {len(self.paths)} paths keep every joint within tolerance"
            + (f"; failing: {', '.join(p.name for p in failed)}" if failed else ".")
        )
        self.table.setRowCount(len(self.paths))
        for row, p in enumerate(self.paths):
            cells = (
                p.name,
                f"{p.max_error:.3g}",
                f"{p.relative_error:.2e}",
                f"{p.tolerance:.0e}",
                "ok" if p.ok else "FAIL",
                p.worst_joint or p.error,
                str(p.worst_frame) if p.worst_frame >= 0 else "-",
            )
            for column, text in enumerate(cells):
                item = QTableWidgetItem(text)
                if not p.ok:
                    item.setForeground(QBrush(FAIL_COLOUR))
                self.table.setItem(row, column, item)
        self.table.resizeColumnsToContents()

    def _on_row_chosen(self) -> None:
        rows = {index.row() for index in self.table.selectedIndexes()}
        motion = self.state.motion
        if len(rows) != 1 or motion is None:
            return
        path = self.paths[rows.pop()]
        self.highlight.show(tuple(path.failing_joints))
        if path.worst_joint in motion.names:
            if path.worst_frame >= 0:
                self.state.set_frame(path.worst_frame)
            self.state.select(motion.joint_index(path.worst_joint))
