"""The Problems dock on its own, without the window (app/docks/problems_dock.py): the table's
rows and how each column sorts, the summary, choosing a finding and stepping through them,
the severity filter, the settings table's edits, and where things are in the dock.

The checks are stood in for (:func:`dock`'s ``checks_find``) so that the dock lists known
findings; the model runs the stand-in in its worker as it runs the real checks."""

from __future__ import annotations

import math

import pytest
from PyQt6.QtCore import Qt

from gmr_studio.app.docks.problems_dock import COLUMNS, NEVER, ProblemsDock, parse_limit
from gmr_studio.app.model import problems as problems_module
from gmr_studio.app.model.problems import LEVEL_COLOURS, LIMITS, Problems
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.checks import KINDS, CheckSettings, Finding
from tests.test_app_problems_model import knocked_walk

pytestmark = pytest.mark.gui  # widgets

ENABLED_SELECTABLE = Qt.ItemFlag.ItemIsEnabled | Qt.ItemFlag.ItemIsSelectable
WALK = knocked_walk()


def finding(kind, severity, start, end=None, joints=(), value=1.0) -> Finding:
    names = tuple(f"J{j}" for j in joints)
    return Finding(kind, tuple(joints), names, start, start if end is None else end, severity, value, "cm")


#: each column's order differs from its text's and from the list's: kinds (checks' order pop,
#: duplicate, teleport), severities (duplicate info, teleport warning, pop error), frames
#: (5, 9, 10 as numbers), values (2, 9.5, 100 as numbers)
FOUND = [
    finding("teleport", "warning", 5, 6, (0,), 9.5),
    finding("pop", "error", 9, 9, (4, 5), 100.0),
    finding("duplicate", "info", 10, 12, (), 2.0),
]


class Checks:
    """A stand-in for the checks: every run finds :attr:`found`, or fails with :attr:`failure`."""

    def __init__(self, found: list[Finding]) -> None:
        self.found, self.failure = list(found), ""

    def __call__(self, motion, settings, positions=None, threads=None) -> list[Finding]:
        if self.failure:
            raise RuntimeError(self.failure)
        return list(self.found)


def check_again(dock, found: list[Finding] | None = None, failure: str = "", *, wait: bool = True) -> None:
    """The walk opened afresh with the checks finding ``found`` (or failing with ``failure``)."""
    dock.checks.found, dock.checks.failure = list(found or []), failure
    dock.state.open_document(Snapshot.of(WALK), None)
    if wait:
        dock.problems.wait()


@pytest.fixture
def dock(qtbot, monkeypatch):
    """A dock of a state with the 30-frame walk open and :data:`FOUND` listed."""
    checks = Checks(FOUND)
    monkeypatch.setattr(problems_module, "run_checks", checks)
    state = StudioState()
    problems = Problems(state)
    widget = ProblemsDock(problems)
    widget.checks = checks
    qtbot.addWidget(widget)
    check_again(widget, FOUND)
    yield widget
    problems.wait()  # a settings change started a run: a running thread must not be collected


def rows(dock) -> list[tuple[str, ...]]:
    table = dock.table
    return [tuple(table.item(r, c).text() for c in range(len(COLUMNS))) for r in range(table.rowCount())]


def test_the_rows_sorted_by_frames_and_their_cells(dock):
    assert rows(dock) == [
        ("teleport", "warning", "5-6", "J0", "9.5 cm"),
        ("pop", "error", "9", "J4, J5", "100 cm"),
        ("duplicate", "info", "10-12", "(whole pose)", "2 cm"),
    ]
    table = dock.table
    for row, level in enumerate((2, 3, 1)):
        severity = table.item(row, 1)
        assert severity.background().color().getRgbF()[:3] == pytest.approx(LEVEL_COLOURS[level], abs=1 / 255)
        assert severity.foreground().color().name() == ("#ffffff" if level == 3 else "#000000")
        assert all(table.item(row, c).flags() == ENABLED_SELECTABLE for c in range(len(COLUMNS)))
    assert [dock.finding_at(r) for r in range(3)] == FOUND
    assert dock.finding_at(3) is None


@pytest.mark.parametrize(
    ("column", "ascending"),
    [
        (0, ["pop", "duplicate", "teleport"]),  # the checks' order, not the alphabet's
        (1, ["duplicate", "teleport", "pop"]),  # info, warning, error
        (2, ["teleport", "pop", "duplicate"]),  # 5, 9, 10 as numbers
        (3, ["duplicate", "teleport", "pop"]),  # (whole pose), J0, J4 as text
        (4, ["duplicate", "teleport", "pop"]),  # 2, 9.5, 100 as numbers
    ],
)
def test_each_column_sorts_by_its_meaning(dock, column, ascending):
    dock.table.sortByColumn(column, Qt.SortOrder.AscendingOrder)
    assert [r[0] for r in rows(dock)] == ascending
    dock.table.sortByColumn(column, Qt.SortOrder.DescendingOrder)
    assert [r[0] for r in rows(dock)] == ascending[::-1]
    by_kind = {r[0]: r for r in rows(dock)}  # each row's cells are still one finding's
    assert by_kind["teleport"][1:] == ("warning", "5-6", "J0", "9.5 cm")
    assert dock.finding_at([r[0] for r in rows(dock)].index("pop")) == FOUND[1]


def test_a_refill_while_sorted_by_value_keeps_rows_whole(dock):
    dock.table.sortByColumn(4, Qt.SortOrder.DescendingOrder)
    check_again(dock, FOUND[::-1])
    assert rows(dock) == [
        ("pop", "error", "9", "J4, J5", "100 cm"),
        ("teleport", "warning", "5-6", "J0", "9.5 cm"),
        ("duplicate", "info", "10-12", "(whole pose)", "2 cm"),
    ]


def test_findings_of_one_frame_keep_the_checks_order_when_sorted(qtbot):
    """A pop and its stretched bone at frame 12 (sort keys equal by frames): listed as the
    checks list them, pop first; sorted by frames again, equal keys keep the order they had."""
    state = StudioState()
    problems = Problems(state)
    state.open_document(Snapshot.of(knocked_walk(12)), None)
    problems.wait()
    dock = ProblemsDock(problems)
    qtbot.addWidget(dock)
    assert [r[0] for r in rows(dock)] == ["pop", "bone-length"]
    dock.table.sortByColumn(0, Qt.SortOrder.DescendingOrder)
    assert [r[0] for r in rows(dock)] == ["bone-length", "pop"]
    dock.table.sortByColumn(2, Qt.SortOrder.AscendingOrder)
    assert [r[0] for r in rows(dock)] == ["bone-length", "pop"]


def test_the_summary(dock):
    problems = dock.problems
    assert dock.summary.text() == "3 findings: 1 error, 1 warning, 1 info"
    problems.set_min_level(2)
    assert dock.summary.text() == "3 findings: 1 error, 1 warning, 1 info (1 not listed)"
    assert [r[0] for r in rows(dock)] == ["teleport", "pop"]
    assert dock.filter_box.currentIndex() == 1  # the filter follows the level set elsewhere
    check_again(dock, [], wait=False)
    assert dock.summary.text() == "Checking\u2026" and dock.table.rowCount() == 0
    problems.wait()
    assert dock.summary.text() == "0 findings: none"
    check_again(dock, failure="boom")
    assert dock.summary.text() == "checks failed: RuntimeError: boom"
    problems.state.snapshot = None
    problems.refresh()
    assert dock.summary.text() == "No motion"


def test_the_filter_sets_the_level_shown(dock):
    for index, level in ((2, 3), (0, 1), (1, 2)):
        dock.filter_box.setCurrentIndex(index)
        assert dock.problems.min_level == level
    assert [r[0] for r in rows(dock)] == ["teleport", "pop"]
    dock.problems.set_min_level(3)
    assert dock.filter_box.currentIndex() == 2 and [r[0] for r in rows(dock)] == ["pop"]
    dock.filter_box.setCurrentIndex(0)  # the box still speaks after following the model
    assert dock.problems.min_level == 1


def test_choosing_a_finding(dock):
    state, framed = dock.state, []
    dock.joint_framed.connect(framed.append)
    dock.choose_row(0)  # the teleport of joint 0 at 5-6
    assert (state.frame, state.selected, framed) == (5, 0, [0])
    dock.choose_row(1)  # the pop of J4, J5 at 9: the first joint
    assert (state.frame, state.selected, framed) == (9, 4, [0, 4])
    dock.choose_row(2)  # the whole pose: the selection kept, the figure framed
    assert (state.frame, state.selected, framed) == (10, 4, [0, 4, -1])
    dock.choose_row(5)  # no such row: nothing
    assert framed == [0, 4, -1]
    dock.table.cellClicked.emit(0, 3)
    assert (state.frame, state.selected, framed[-1]) == (5, 0, 0)
    dock.table.cellActivated.emit(1, 0)  # Enter
    assert (state.frame, framed[-1]) == (9, 4)


def test_stepping_through_the_findings(dock):
    state, table = dock.state, dock.table
    state.set_frame(7)
    dock.step_buttons[1].click()  # after 7: the pop at 9
    assert (state.frame, dock.finding_at(table.currentRow())) == (9, FOUND[1])
    dock.step_buttons[1].click()  # after 9: the duplicate at 10
    assert (state.frame, dock.finding_at(table.currentRow())) == (10, FOUND[2])
    dock.step_buttons[1].click()  # none after 10: round to the first, the teleport at 5
    assert (state.frame, dock.finding_at(table.currentRow())) == (5, FOUND[0])
    dock.step_buttons[-1].click()  # none before 5: round to the last
    assert (state.frame, dock.finding_at(table.currentRow())) == (10, FOUND[2])
    dock.step_buttons[-1].click()  # before 10: 9
    assert dock.finding_at(table.currentRow()) == FOUND[1]
    assert dock.choose_next(-1) == FOUND[0] and state.frame == 5
    check_again(dock, [])
    assert dock.choose_next(1) is None and dock.choose_next(-1) is None


def test_the_settings_panel_shows_the_settings(dock, qtbot):
    dock.show()
    qtbot.waitExposed(dock)
    assert not dock.settings_panel.isVisible()
    dock.settings_button.click()
    assert dock.settings_panel.isVisible()
    limits = dock.limits_table
    assert (limits.rowCount(), limits.columnCount()) == (len(KINDS), 5)
    assert [limits.item(r, 0).text() for r in range(len(KINDS))] == list(KINDS)
    assert [limits.item(r, 4).text() for r in range(len(KINDS))] == [LIMITS[k].unit for k in KINDS]
    pop, rest = KINDS.index("pop"), KINDS.index("rest-pose")
    assert [limits.item(pop, c).text() for c in (1, 2, 3)] == ["0.5", "1", "3"]
    assert [limits.item(rest, c).text() for c in (1, 2, 3)] == ["1", "1", NEVER]
    assert all(limits.item(r, 0).checkState() == Qt.CheckState.Checked for r in range(len(KINDS)))
    assert limits.item(pop, 0).flags() == Qt.ItemFlag.ItemIsEnabled | Qt.ItemFlag.ItemIsUserCheckable
    assert limits.item(pop, 4).flags() == Qt.ItemFlag.ItemIsEnabled
    dock.problems.set_settings(CheckSettings(kinds=("flip",), pop_limits=(0.02, 0.03, 0.05)))
    assert [limits.item(pop, c).text() for c in (1, 2, 3)] == ["2", "3", "5"]
    checked = [limits.item(r, 0).checkState() == Qt.CheckState.Checked for r in range(len(KINDS))]
    assert checked == [k == "flip" for k in KINDS]
    dock.settings_button.click()
    assert not dock.settings_panel.isVisible()


def test_editing_the_limits(dock):
    problems, limits, said = dock.problems, dock.limits_table, []
    problems.state.message.connect(said.append)
    flip, rest, pop = KINDS.index("flip"), KINDS.index("rest-pose"), KINDS.index("pop")
    limits.item(flip, 3).setText(" 170.50 ")
    assert problems.settings.flip_limits == (45.0, 90.0, 170.5)
    assert limits.item(flip, 3).text() == "170.5"  # as stored
    limits.item(rest, 2).setText("never")
    assert problems.settings.rest_limits == (1.0, math.inf, math.inf)
    limits.item(pop, 1).setText("2")  # above the warning limit (1 %): refused, the old value back
    assert problems.settings.pop_limits == CheckSettings().pop_limits
    assert limits.item(pop, 1).text() == "0.5" and said[-1].startswith("pop limits: ")
    limits.item(pop, 2).setText("lots")
    assert limits.item(pop, 2).text() == "1" and said[-1].startswith("pop limits: ")
    limits.item(pop, 0).setCheckState(Qt.CheckState.Unchecked)
    assert "pop" not in problems.settings.kinds
    limits.item(pop, 0).setCheckState(Qt.CheckState.Checked)
    assert problems.settings.kinds == KINDS


def test_the_settings_cells_are_edited_in_place(dock):
    """An edit's own signal refills the table: the cell being edited must stay the one shown."""
    limits = dock.limits_table
    cells = [limits.item(KINDS.index("pop"), c) for c in range(5)]
    dock.problems.set_settings(CheckSettings(pop_limits=(0.02, 0.03, 0.05)))
    assert [limits.item(KINDS.index("pop"), c) for c in range(5)] == cells
    assert cells[1].text() == "2"
    cells[3].setText("6")  # edited in place: the refill keeps the edited cell
    assert dock.problems.settings.pop_limits == pytest.approx((0.02, 0.03, 0.06)) and cells[3].text() == "6"


def test_limits_typed(qtbot):
    assert [parse_limit(t) for t in ("", " never ", "INF", "Never")] == [math.inf] * 4
    assert parse_limit(" 2.5 ") == 2.5
    with pytest.raises(ValueError):
        parse_limit("often")


def test_where_things_are_in_the_dock(dock, qtbot):
    """The step buttons, the summary, the filter and the settings button in a row along the
    top, the summary taking the width; the list under them taking the height, the joints'
    column its width; the settings beside the list, narrower; the filter's levels in order;
    the rows a line of text high at least."""
    dock.resize(1000, 400)
    dock.show()
    qtbot.waitExposed(dock)
    dock.settings_button.click()
    qtbot.waitUntil(dock.settings_panel.isVisible)
    top = [dock.step_buttons[-1], dock.step_buttons[1], dock.summary, dock.filter_box, dock.settings_button]
    xs = [widget.mapTo(dock, widget.rect().topLeft()).x() for widget in top]
    assert xs == sorted(xs) and all(w.mapTo(dock, w.rect().topLeft()).y() < 40 for w in top)
    assert dock.summary.width() > max(w.width() for w in top if w is not dock.summary)
    table, panel = dock.table, dock.settings_panel
    assert table.mapTo(dock, table.rect().topLeft()).y() >= dock.summary.height()
    assert table.height() > dock.height() - 2 * dock.summary.height() - 20
    assert panel.mapTo(dock, panel.rect().topLeft()).x() > table.mapTo(dock, table.rect().topLeft()).x()
    assert panel.width() < table.width()
    widths = [table.columnWidth(c) for c in range(len(COLUMNS))]
    assert widths[3] == max(widths)  # the joints' column takes the room
    assert [dock.filter_box.itemData(i) for i in range(3)] == [1, 2, 3]
    for view in (table, dock.limits_table):
        assert view.verticalHeader().defaultSectionSize() >= dock.fontMetrics().height()
