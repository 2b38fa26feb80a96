"""The window's layout rules (app/window/layout.py) on a small main window of plain widgets: the
side column's width, the view's share, the timeline strip, the analysis docks tabbed when
shown, the docks fitted back around a squeezed view, and the saved layout's version."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from PyQt6.QtCore import QSettings, QSize, Qt
from PyQt6.QtWidgets import QDockWidget, QLabel, QMainWindow, QSizePolicy, QWidget

from gmr_studio.app.docks.frame_follow import seen
from gmr_studio.app.window import layout

pytestmark = pytest.mark.gui
RIGHT, BOTTOM = Qt.DockWidgetArea.RightDockWidgetArea, Qt.DockWidgetArea.BottomDockWidgetArea
HORIZONTAL, VERTICAL = Qt.Orientation.Horizontal, Qt.Orientation.Vertical


def test_the_side_column_is_a_fifth_of_the_window_within_its_limits():
    widths = {800: 230, 1150: 230, 1151: 230, 1160: 232, 1500: 300, 1799: 359, 1800: 360, 1806: 360, 2600: 360}
    assert {w: layout.side_width(w) for w in widths} == widths
    assert all(isinstance(layout.side_width(w), int) for w in widths)


def _sized(width: int, height: int) -> SimpleNamespace:
    return SimpleNamespace(width=lambda: width, height=lambda: height)


def test_the_views_share_of_the_window_area():
    assert layout.view_share(_sized(1000, 500), _sized(600, 400)) == pytest.approx(0.48, abs=1e-15)
    assert layout.view_share(_sized(0, 500), _sized(0, 400)) == 0.0  # a window not laid out yet


class Hinted(QLabel):
    def sizeHint(self) -> QSize:
        return QSize(300, 37)


def test_the_timeline_strip_is_as_tall_as_its_widgets_need(qtbot):
    dock = QDockWidget("Timeline")
    qtbot.addWidget(dock)
    dock.setWidget(Hinted("frames"))
    layout.make_strip(dock)
    policy = dock.widget().sizePolicy()
    assert policy.verticalPolicy() == QSizePolicy.Policy.Fixed
    assert policy.horizontalPolicy() == QSizePolicy.Policy.Preferred
    assert dock.widget().maximumHeight() == 37


def _window(qtbot, size=(1400, 900)) -> tuple[QMainWindow, QWidget, list[QDockWidget], list[QDockWidget]]:
    """A main window: a view, a Forest/Inspector column on the right, three hidden bottom docks."""
    window = QMainWindow()
    qtbot.addWidget(window)
    view = QLabel("view")
    window.setCentralWidget(view)
    docks = {}
    for name, area in (
        ("forest", RIGHT),
        ("inspector", RIGHT),
        ("curves", BOTTOM),
        ("contacts", BOTTOM),
        ("error", BOTTOM),
    ):
        dock = docks[name] = QDockWidget(name, window)
        dock.setObjectName(name)
        dock.setWidget(QLabel(name))
        window.addDockWidget(area, dock)
    window.splitDockWidget(docks["forest"], docks["inspector"], VERTICAL)
    bottom = [docks["curves"], docks["contacts"], docks["error"]]
    for dock in bottom:
        dock.hide()
    window.resize(*size)
    window.show()
    qtbot.waitExposed(window)
    return window, view, [docks["forest"], docks["inspector"]], bottom


def test_analysis_docks_open_at_a_usable_height_and_tab_together(qtbot):
    window, _, _, (curves, contacts, error) = _window(qtbot)
    layout.tab_when_shown(window, [curves, contacts, error])
    curves.show()  # the first: the area opens 240 pixels high
    qtbot.waitUntil(lambda: curves.height() == 240)
    assert window.tabifiedDockWidgets(curves) == []
    contacts.show()  # the second: a tab of the first, in front
    qtbot.waitUntil(lambda: seen(contacts) and not seen(curves))
    assert window.tabifiedDockWidgets(curves) == [contacts]
    curves.raise_()
    error.setFloating(True)
    error.show()  # floating: a window of its own, not a tab
    qtbot.waitUntil(error.isVisible)
    assert error not in window.tabifiedDockWidgets(curves) and seen(curves)
    error.setFloating(False)  # docked again while another is shown: a tab, in front
    qtbot.waitUntil(lambda: error in window.tabifiedDockWidgets(curves) and seen(error))
    assert not seen(curves) and window.tabifiedDockWidgets(curves) == [contacts, error]
    curves.hide(), contacts.hide(), error.hide()
    curves.setFloating(True)
    contacts.show()  # the others hidden or floating: a first dock again, not a tab
    qtbot.waitUntil(lambda: contacts.height() == 240)


def test_a_tall_enough_analysis_dock_is_left_as_the_user_made_it(qtbot):
    window, _, _, (curves, _, _) = _window(qtbot)
    layout.tab_when_shown(window, [curves])
    window.resizeDocks([curves], [400], VERTICAL)
    curves.show()
    qtbot.waitUntil(lambda: seen(curves))
    qtbot.wait(20)
    assert curves.height() > 240


def test_the_column_gives_way_to_the_view_and_comes_back_when_squeezed(qtbot):
    window, view, side, bottom = _window(qtbot)
    target = layout.side_width(1400)  # 280
    window.resizeDocks(side, [700, 700], HORIZONTAL)  # the view has a third of the window
    qtbot.waitUntil(lambda: side[0].width() == 700)
    layout.fit_docks(window, view, side, bottom)
    qtbot.waitUntil(lambda: side[0].width() == target)
    assert layout.view_share(window, view) >= layout.VIEW_AREA_SHARE - 0.03
    window.resizeDocks(side, [150, 150], HORIZONTAL)  # squeezed below 200: widened again
    qtbot.waitUntil(lambda: side[0].width() == 150)
    layout.fit_docks(window, view, side, bottom)
    qtbot.waitUntil(lambda: side[0].width() == target)
    window.resizeDocks(side, [420, 420], HORIZONTAL)  # wider, the view keeps 60%: left alone
    qtbot.waitUntil(lambda: side[0].width() == 420)
    assert layout.view_share(window, view) >= layout.VIEW_AREA_SHARE
    layout.fit_docks(window, view, side, bottom)
    qtbot.wait(20)
    assert side[0].width() == 420
    side[0].hide(), side[1].setFloating(True)  # no docked column: nothing to fit
    side[1].resize(700, 300)
    layout.fit_docks(window, view, side, bottom)
    qtbot.wait(20)
    assert side[1].width() == 700


def test_a_narrow_column_beside_a_narrow_view_is_left_narrow(qtbot):
    window, view, side, bottom = _window(qtbot, (560, 500))
    window.resizeDocks(side, [150, 150], HORIZONTAL)  # the view about 400 wide: 230 more would leave it under 200
    qtbot.waitUntil(lambda: side[0].width() == 150)
    layout.fit_docks(window, view, side, bottom)
    qtbot.wait(20)
    assert side[0].width() == 150


def test_tall_analysis_docks_give_the_view_its_room_back(qtbot):
    window, view, side, (curves, contacts, error) = _window(qtbot)
    curves.show(), contacts.show()
    window.splitDockWidget(curves, contacts, HORIZONTAL)
    window.resizeDocks([curves, contacts], [700, 700], VERTICAL)
    qtbot.waitUntil(lambda: curves.height() == 700)
    assert layout.view_share(window, view) < layout.RESTORED_MINIMUM_SHARE
    layout.fit_docks(window, view, side, [curves, contacts, error])
    qtbot.waitUntil(lambda: curves.height() == 240 and contacts.height() == 240)
    window.resizeDocks([curves], [400], VERTICAL)  # taller than 240, the view keeps its minimum: left so
    qtbot.waitUntil(lambda: curves.height() == 400)
    assert layout.view_share(window, view) >= layout.RESTORED_MINIMUM_SHARE
    layout.fit_docks(window, view, side, [curves, contacts, error])
    qtbot.wait(20)
    assert curves.height() == 400


def test_a_layout_is_restored_only_from_this_version(qtbot, tmp_path):
    window, _, side, _ = _window(qtbot)
    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat)
    assert not layout.restore_layout(window, settings)  # nothing saved
    layout.save_layout(window, settings)
    assert settings.value("window/layout_version") in (2, "2")  # this version's layouts are version 2
    assert layout.restore_layout(window, settings)
    settings.setValue("window/layout_version", 1)
    assert not layout.restore_layout(window, settings)
    settings.remove("window/layout_version")  # saved before the version key
    assert not layout.restore_layout(window, settings)
    settings.setValue("window/layout_version", "2")  # as read back from the file
    settings.setValue("window/state", window.saveState(2))
    assert layout.restore_layout(window, settings)
    settings.setValue("window/state", window.saveState(1))  # the state's own version must match too
    assert not layout.restore_layout(window, settings)
    side[1].hide()
    settings.setValue("window/state", window.saveState(2))
    side[1].show()
    assert layout.restore_layout(window, settings) and side[1].isHidden()  # the saved state applied
