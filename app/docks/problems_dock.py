"""The Problems dock: the quality checks' findings of the document, and their settings.

A table of findings (kind, severity, frames, joints, value with units), sortable, filtered
by severity; above it, a line per stretch of frames some checks left out and why (the rest
pose at the ends: :func:`core.checks.skipped_frames`). Choosing a finding (click or Enter)
seeks to its first frame, selects its first joint and asks the window to frame the camera
on it (:attr:`ProblemsDock.joint_framed`: the dock knows nothing of the view). Beside it
(*Settings*), a row per kind with its switch and its three limits (info, warning, error) in
the panel's units (:data:`app.model.problems.LIMITS`), edited in place and remembered by
:class:`~app.model.problems.Problems`. The list follows the document: an edit (trim,
resample, undo) checks it again.
"""

from __future__ import annotations

import math

from PyQt6.QtCore import Qt, pyqtSignal
from PyQt6.QtGui import QColor
from PyQt6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QPushButton,
    QSplitter,
    QTableWidget,
    QTableWidgetItem,
    QToolButton,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.model.problems import (
    LEVEL_COLOURS,
    LIMITS,
    Problems,
    count_text,
    shown_limits,
    skipped_lines,
    with_limits,
)
from gmr_studio.core.checks import KINDS, Finding

COLUMNS = ("Kind", "Severity", "Frames", "Joints", "Value")
#: the severity filter: (text, lowest level shown)
FILTERS = (("All", 1), ("Warnings and errors", 2), ("Errors", 3))
SORT_ROLE = Qt.ItemDataRole.UserRole + 1
NEVER = "never"


class SortItem(QTableWidgetItem):
    """A cell sorted by its :data:`SORT_ROLE` value (frames and values sort as numbers)."""

    def __lt__(self, other: QTableWidgetItem) -> bool:
        mine, theirs = self.data(SORT_ROLE), other.data(SORT_ROLE)
        if mine is None or theirs is None:
            return super().__lt__(other)
        return mine < theirs


def _cell(text: str, key=None) -> SortItem:
    item = SortItem(text)
    item.setFlags(Qt.ItemFlag.ItemIsEnabled | Qt.ItemFlag.ItemIsSelectable)
    if key is not None:
        item.setData(SORT_ROLE, key)
    return item


def _limit_text(value: float) -> str:
    return NEVER if math.isinf(value) else f"{value:g}"


def parse_limit(text: str) -> float:
    """A limit typed in the settings table: a number, or empty / ``never`` for none."""
    text = text.strip().lower()
    return math.inf if text in ("", NEVER, "inf") else float(text)


class ProblemsDock(QWidget):
    """Findings of :class:`Problems` and the check settings."""

    joint_framed = pyqtSignal(int)  # a finding was chosen: frame the camera on this joint (-1: the figure)

    def __init__(self, problems: Problems, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.problems = problems
        self.state = problems.state
        self.shown: list[Finding] = []  # the findings in the table, by their row when filled
        self.summary = QLabel()
        self.skipped_label = QLabel()  # the frames some checks left out, and why
        self.skipped_label.setWordWrap(True)
        self.skipped_label.setVisible(False)
        self.filter_box = QComboBox()
        for text, level in FILTERS:
            self.filter_box.addItem(text, level)
        self.filter_box.setToolTip("Which findings to list, flag on the timeline and colour in the view")
        self.filter_box.setCurrentIndex(self.filter_box.findData(problems.min_level))
        self.filter_box.currentIndexChanged.connect(lambda i: problems.set_min_level(self.filter_box.itemData(i)))
        self.settings_button = QToolButton()
        self.settings_button.setText("Settings")
        self.settings_button.setCheckable(True)
        self.settings_button.setToolTip("Which checks run and their limits (remembered)")
        self.step_buttons = {}
        for step, text, tip in ((-1, "\u25c0", "previous finding"), (1, "\u25b6", "next finding")):
            button = QToolButton()
            button.setText(text)
            button.setToolTip(f"The {tip} (by first frame) from the current frame")
            button.clicked.connect(lambda _checked=False, step=step: self.choose_next(step))
            self.step_buttons[step] = button
        top = QHBoxLayout()
        top.addWidget(self.step_buttons[-1])
        top.addWidget(self.step_buttons[1])
        top.addWidget(self.summary, 1)
        top.addWidget(self.filter_box)
        top.addWidget(self.settings_button)

        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.verticalHeader().hide()
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        self.table.horizontalHeader().setSectionResizeMode(3, QHeaderView.ResizeMode.Stretch)
        self.table.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.table.setSortingEnabled(True)
        self.table.sortByColumn(2, Qt.SortOrder.AscendingOrder)  # by frames, as the checks list them
        self.table.setToolTip("Click a finding: go to its first frame, select its joint, look at it")
        self.table.cellClicked.connect(lambda row, _column: self.choose_row(row))
        self.table.cellActivated.connect(lambda row, _column: self.choose_row(row))

        self.settings_panel = self._settings_panel()
        self.settings_panel.setVisible(False)
        self.settings_button.toggled.connect(self.settings_panel.setVisible)
        splitter = QSplitter(Qt.Orientation.Horizontal)  # the analysis area is wide and short
        splitter.addWidget(self.table)
        splitter.addWidget(self.settings_panel)
        splitter.setStretchFactor(0, 3)
        splitter.setStretchFactor(1, 2)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(top)
        layout.addWidget(self.skipped_label)
        layout.addWidget(splitter, 1)
        problems.changed.connect(self.refresh)
        problems.settings_changed.connect(self.fill_settings)
        self.fill_settings()
        self.refresh()

    # ------------------------------------------------------------------ findings
    def refresh(self) -> None:
        """Fill the table with the findings at or above the filter's level."""
        problems = self.problems
        self.shown = problems.shown
        index = self.filter_box.findData(problems.min_level)
        if index != self.filter_box.currentIndex():
            self.filter_box.blockSignals(True)
            self.filter_box.setCurrentIndex(index)
            self.filter_box.blockSignals(False)
        if self.state.motion is None:
            self.summary.setText("No motion")
        elif problems.running:
            self.summary.setText("Checking\u2026")
        elif problems.error:
            self.summary.setText(problems.error)
        else:
            hidden = len(problems.findings) - len(self.shown)
            more = f" ({hidden} not listed)" if hidden else ""
            self.summary.setText(f"{len(problems.findings)} findings: {count_text(problems.findings)}{more}")
        lines = skipped_lines(problems.skipped) if self.state.motion is not None and not problems.running else []
        self.skipped_label.setText("\n".join(line[0].upper() + line[1:] for line in lines))
        self.skipped_label.setVisible(bool(lines))
        table = self.table
        table.setSortingEnabled(False)
        table.setRowCount(len(self.shown))
        for row, finding in enumerate(self.shown):
            kind = _cell(finding.kind, KINDS.index(finding.kind))
            kind.setData(Qt.ItemDataRole.UserRole, row)  # the finding's index in self.shown
            severity = _cell(finding.severity, finding.level)
            severity.setBackground(QColor.fromRgbF(*LEVEL_COLOURS[finding.level]))  # the timeline's colour
            severity.setForeground(QColor("white" if finding.level == 3 else "black"))
            frames = f"{finding.start}" if finding.start == finding.end else f"{finding.start}-{finding.end}"
            joints = ", ".join(finding.names) if finding.names else "(whole pose)"
            value = _cell(f"{finding.value:.4g} {finding.units}", float(finding.value))
            cells = (kind, severity, _cell(frames, (finding.start, finding.end)), _cell(joints), value)
            for column, item in enumerate(cells):
                table.setItem(row, column, item)
        table.setSortingEnabled(True)

    def finding_at(self, row: int) -> Finding | None:
        item = self.table.item(row, 0)
        index = item.data(Qt.ItemDataRole.UserRole) if item is not None else None
        return self.shown[index] if index is not None and 0 <= index < len(self.shown) else None

    def choose_row(self, row: int) -> None:
        finding = self.finding_at(row)
        if finding is not None:
            self.choose(finding)

    def choose(self, finding: Finding) -> None:
        """Seek to the finding's first frame, select its first joint, frame the camera on it."""
        self.state.set_frame(finding.start)
        joint = finding.joints[0] if finding.joints else -1
        if joint >= 0:
            self.state.select(joint)
        self.joint_framed.emit(joint)

    def choose_next(self, step: int) -> Finding | None:
        """Choose the listed finding starting after (``step`` 1) or before (-1) the current
        frame, the nearest one (the first or last when there is none that way); its row is
        selected. Returns it (None with nothing listed)."""
        if not self.shown:
            return None
        frame = self.state.frame
        order = sorted(range(len(self.shown)), key=lambda i: (self.shown[i].start, i))
        later = [i for i in order if self.shown[i].start > frame]
        earlier = [i for i in order if self.shown[i].start < frame]
        index = (later[0] if later else order[0]) if step > 0 else (earlier[-1] if earlier else order[-1])
        for row in range(self.table.rowCount()):
            if self.table.item(row, 0).data(Qt.ItemDataRole.UserRole) == index:
                self.table.selectRow(row)
                self.table.scrollToItem(self.table.item(row, 0))
        self.choose(self.shown[index])
        return self.shown[index]

    # ------------------------------------------------------------------ settings
    def _settings_panel(self) -> QWidget:
        panel = QWidget()
        self.limits_table = QTableWidget(len(KINDS), 5)
        self.limits_table.setHorizontalHeaderLabels(("Check", "Info", "Warning", "Error", "Unit"))
        self.limits_table.verticalHeader().hide()
        self.limits_table.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.limits_table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        self.limits_table.horizontalHeader().setStretchLastSection(True)
        self.limits_table.setToolTip("Tick the checks to run; a limit is reached at or above the number")
        self.limits_table.itemChanged.connect(self._on_limit_edited)
        defaults = QPushButton("Defaults")
        defaults.setToolTip("Every check, the default limits")
        defaults.clicked.connect(self.problems.reset_settings)
        row = QHBoxLayout()
        row.addWidget(QLabel("Lengths are % of the figure's size; 'never' for no limit"), 1)
        row.addWidget(defaults)
        layout = QVBoxLayout(panel)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.limits_table, 1)
        layout.addLayout(row)
        return panel

    def fill_settings(self) -> None:
        """Show the problems' settings in the table (the cells are made once, then updated:
        this runs inside the table's own edit signal)."""
        settings = self.problems.settings
        table = self.limits_table
        table.blockSignals(True)
        for row, kind in enumerate(KINDS):
            if table.item(row, 0) is None:
                check = QTableWidgetItem(kind)
                check.setFlags(Qt.ItemFlag.ItemIsEnabled | Qt.ItemFlag.ItemIsUserCheckable)
                table.setItem(row, 0, check)
                for column in (1, 2, 3):
                    table.setItem(row, column, QTableWidgetItem())
                unit = QTableWidgetItem(LIMITS[kind].unit)
                unit.setFlags(Qt.ItemFlag.ItemIsEnabled)
                table.setItem(row, 4, unit)
            checked = Qt.CheckState.Checked if kind in settings.kinds else Qt.CheckState.Unchecked
            table.item(row, 0).setCheckState(checked)
            for column, value in enumerate(shown_limits(settings, kind), start=1):
                table.item(row, column).setText(_limit_text(value))
        table.blockSignals(False)
        table.viewport().update()

    def _on_limit_edited(self, item: QTableWidgetItem) -> None:
        kind = KINDS[item.row()]
        if item.column() == 0:
            self.problems.set_kind_enabled(kind, item.checkState() == Qt.CheckState.Checked)
            return
        try:
            shown = tuple(parse_limit(self.limits_table.item(item.row(), c).text()) for c in (1, 2, 3))
            settings = with_limits(self.problems.settings, kind, shown)
        except ValueError as exc:
            self.state.show_message(f"{kind} limits: {exc}")
            self.fill_settings()  # back to the settings in force
            return
        self.problems.set_settings(settings)
        self.fill_settings()  # as stored (e.g. 1.50 shown as 1.5)
