"""The window's layout rules (app/window/layout.py) on a small main window of plain widgets: the
side column's width, the view's share, the timeline strip, the analysis docks tabbed when
shown, the docks fitted back around a squeezed view, and the saved layout's version."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from PyQt6.QtCore import QSettings, QSize, Qt
from PyQt6.QtWidgets import QDockWidget, QLabel, QMainWindow, QSizePolicy, QTabBar, QWidget

from gmr_studio.app.docks.frame_follow import seen
from gmr_studio.app.window import layout
from tests import app_fixtures

pytestmark = pytest.mark.gui
RIGHT, BOTTOM = Qt.DockWidgetArea.RightDockWidgetArea, Qt.DockWidgetArea.BottomDockWidgetArea
HORIZONTAL, VERTICAL = Qt.Orientation.Horizontal, Qt.Orientation.Vertical
studio = app_fixtures.studio


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


def _window(
    qtbot, size=(1400, 900), bottom=("curves", "contacts", "error"), *, tabbed: bool = False
) -> tuple[QMainWindow, QWidget, list[QDockWidget], list[QDockWidget]]:
    """A main window: a view, a Forest/Inspector column on the right, hidden bottom docks
    (tabbed when shown, ``tabbed``, from before the window is shown, as the app does)."""
    window = QMainWindow()
    qtbot.addWidget(window)
    view = QLabel("view")
    window.setCentralWidget(view)
    docks = {}
    for name, area in {"forest": RIGHT, "inspector": RIGHT, **dict.fromkeys(bottom, BOTTOM)}.items():
        dock = docks[name] = QDockWidget(name, window)
        dock.setObjectName(name)
        dock.setWidget(QLabel(name))
        window.addDockWidget(area, dock)
    window.splitDockWidget(docks["forest"], docks["inspector"], VERTICAL)
    hidden = [docks[name] for name in bottom]
    for dock in hidden:
        dock.hide()
    if tabbed:
        layout.tab_when_shown(window, hidden)
    window.resize(*size)
    window.show()
    qtbot.waitExposed(window)
    return window, view, [docks["forest"], docks["inspector"]], hidden


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


class StubDock:
    """What fit_docks reads of a dock: visible, floating, width, height."""

    def __init__(self, width: int = 0, height: int = 0, *, visible: bool = True, floating: bool = False) -> None:
        self.size, self.visible, self.floating = (width, height), visible, floating

    def isVisible(self) -> bool:
        return self.visible

    def isFloating(self) -> bool:
        return self.floating

    def width(self) -> int:
        return self.size[0]

    def height(self) -> int:
        return self.size[1]


class StubWindow(StubDock):
    """A window that records the docks it is asked to resize: (docks, sizes, orientation)."""

    def __init__(self, width: int, height: int) -> None:
        super().__init__(width, height)
        self.resized: list[tuple[list, list[int], Qt.Orientation]] = []

    def resizeDocks(self, docks, sizes, orientation) -> None:
        self.resized.append((list(docks), list(sizes), orientation))


def _fit(view_size: tuple[int, int], side: list[StubDock], bottom: list[StubDock], window=(1000, 1000)) -> list:
    stub = StubWindow(*window)
    layout.fit_docks(stub, StubDock(*view_size), side, bottom)
    return stub.resized


def test_the_column_gives_way_below_59_percent_of_the_area_only():
    column = [StubDock(300, 400), StubDock(300, 400)]  # wider than its 230 pixels
    assert _fit((589, 1000), column, []) == [(column, [230, 230], HORIZONTAL)]
    assert _fit((590, 1000), column, []) == []  # 59% exactly: kept
    assert _fit((600, 1000), column, []) == []
    hidden = [StubDock(300, 400, visible=False), StubDock(400, 400, floating=True)]
    assert _fit((500, 1000), hidden, []) == []  # no docked column: nothing to fit
    docked = StubDock(250, 400)
    assert _fit((500, 1000), [*hidden, docked], []) == [([docked], [230], HORIZONTAL)]  # its width alone counts


def test_a_squeezed_column_comes_back_only_below_199_pixels_beside_a_wide_view():
    def widened(width: int, view: int) -> bool:
        return bool(_fit((view, 1000), [StubDock(width, 400)], [], window=(1000, 1000)))

    assert widened(198, 431) and not widened(199, 431)  # narrower than 2 x 100 - 1 pixels
    assert widened(100, 431) and not widened(100, 430)  # the view keeps more than 200 pixels


def test_tall_bottom_docks_go_back_to_240_pixels_below_35_percent_of_the_area_only():
    tall, short = StubDock(1000, 500), StubDock(1000, 100)
    hidden, floating = StubDock(1000, 600, visible=False), StubDock(1000, 600, floating=True)
    bottom = [tall, short, hidden, floating]
    assert _fit((1000, 349), [], bottom) == [([tall], [240], VERTICAL)]  # only the visible docked tall one
    assert _fit((1000, 350), [], bottom) == []  # 35% exactly: kept
    assert _fit((1000, 349), [], [short, hidden, floating]) == []


def test_a_dock_shown_beside_two_apart_joins_the_first_ones_tabs(qtbot):
    window, _, _, (curves, contacts, error) = _window(qtbot)
    curves.show(), contacts.show()
    window.splitDockWidget(curves, contacts, HORIZONTAL)  # side by side, not tabbed
    qtbot.waitUntil(lambda: seen(curves) and seen(contacts))
    layout.tab_when_shown(window, [curves, contacts, error])
    error.show()
    qtbot.waitUntil(lambda: seen(error) and not seen(curves))
    assert window.tabifiedDockWidgets(curves) == [error] and window.tabifiedDockWidgets(contacts) == []
    assert seen(contacts)
    curves.raise_()  # a tab switch: the docks stay where they are (they were once moved, and Qt crashed)
    qtbot.waitUntil(lambda: seen(curves) and not seen(error))
    error.hide()  # the tab in front hidden: the same
    qtbot.waitUntil(lambda: not error.isVisible())
    assert seen(curves) and seen(contacts) and window.tabifiedDockWidgets(contacts) == []
    error.show()  # back among the curves' tabs, in front
    qtbot.waitUntil(lambda: seen(error) and not seen(curves))
    assert window.tabifiedDockWidgets(curves) == [error] and window.tabifiedDockWidgets(contacts) == []


def test_the_window_never_squeezes_the_view_the_slider_or_the_column_below_their_minimums(studio):
    """Issue 13: at any window size the view keeps 200 x 150 pixels, the frame slider 120
    pixels, and the Forest and Inspector 100 pixels of content."""
    view = studio.view
    assert (view.minimumWidth(), view.minimumHeight()) == (200, 150)
    assert studio.timeline.slider.minimumWidth() == 120
    assert [d.widget().minimumWidth() for d in (studio.forest_dock, studio.inspector_dock)] == [100, 100]


def test_a_single_analysis_dock_opens_at_a_usable_height(qtbot):
    window, _, _, (curves, _, _) = _window(qtbot)
    layout.tab_when_shown(window, [curves])
    curves.show()
    qtbot.waitUntil(lambda: curves.height() == 240)


def _tabs(window: QMainWindow) -> list[list[str]]:
    """The titles on each tab bar of the window's dock areas."""
    bars = [bar for bar in window.findChildren(QTabBar) if bar.count() > 1]
    return [[bar.tabText(i) for i in range(bar.count())] for bar in bars]


def test_a_dock_shown_again_comes_back_to_its_place_among_its_tabs_in_front(qtbot):
    names = ("curves", "error", "problems", "contacts")  # the dock apart last: listed after the tabs
    window, _, _, (curves, error, problems, contacts) = _window(qtbot, bottom=names, tabbed=True)
    curves.show(), contacts.show()
    window.addDockWidget(Qt.DockWidgetArea.LeftDockWidgetArea, contacts)  # put apart by the user
    qtbot.waitUntil(lambda: seen(curves) and seen(contacts))
    error.show(), problems.show()  # tabs of the curves, the first shown
    qtbot.waitUntil(lambda: seen(problems))
    assert _tabs(window) == [["curves", "error", "problems"]] and seen(contacts)
    error.hide()
    qtbot.waitUntil(lambda: not error.isVisible())
    error.show()
    qtbot.waitUntil(lambda: seen(error))  # in front, in its place (not moved to the end)
    assert _tabs(window) == [["curves", "error", "problems"]] and seen(contacts) and not seen(problems)


def test_a_dock_tabbed_into_a_low_area_gets_the_usable_height(qtbot):
    """A tab group lower than 240 pixels (a user's, or squeezed by a dock shown beside it
    before tabbing) is given 240 pixels, tab bar included, as soon as the tabs are laid out;
    a hidden or floating dock, or one in the side column, is left alone."""
    window, view, (forest, _), (curves, contacts, error) = _window(qtbot)
    placer = layout.TabWhenShown(window, [curves, contacts, error])
    window.resizeDocks([forest], [150], VERTICAL)
    qtbot.waitUntil(lambda: forest.height() < 240)
    side = forest.height()
    placer.usable_height(forest)  # the side column's split is not the analysis area's
    qtbot.wait(20)
    assert forest.height() == side
    curves.show()
    qtbot.waitUntil(lambda: curves.height() == 240)
    window.resizeDocks([curves], [150], VERTICAL)
    qtbot.waitUntil(lambda: curves.height() == 150)
    low_view = view.height()
    error.show()  # tabbed, then the area back to 240 pixels
    qtbot.waitUntil(lambda: view.height() == low_view - 90)
    assert window.tabifiedDockWidgets(curves) == [error] and 200 < error.height() < 240
    window.resizeDocks([error], [150], VERTICAL)
    qtbot.waitUntil(lambda: view.height() == low_view)
    contacts.setFloating(True)
    contacts.show()
    qtbot.waitUntil(contacts.isVisible)
    height = contacts.height()
    placer.usable_height(contacts)  # floating: its own window keeps its height
    qtbot.wait(20)
    assert contacts.height() == height and view.height() == low_view
    contacts.hide()
    contacts.setFloating(False)
    placer.usable_height(contacts)  # hidden: nothing
    qtbot.wait(20)
    assert view.height() == low_view
    placer.usable_height(error)
    qtbot.waitUntil(lambda: view.height() == low_view - 90)


def test_tabs_exactly_at_the_usable_height_are_left_as_they_are(qtbot):
    """The rule lifts tabs below 240 pixels only: a tab group whose dock is exactly 240
    pixels high (266 with its tab bar) is not brought down to 240 with its tab bar."""
    window, _, _, (curves, contacts, error) = _window(qtbot)
    placer = layout.TabWhenShown(window, [curves, contacts, error])
    curves.show()
    qtbot.waitUntil(lambda: curves.height() == 240)
    error.show()
    qtbot.waitUntil(lambda: seen(error) and window.tabifiedDockWidgets(curves) == [error])
    tab_bar = 240 - error.height()
    assert 0 < tab_bar < 40
    window.resizeDocks([error], [240 + tab_bar], VERTICAL)
    qtbot.waitUntil(lambda: error.height() == 240)
    placer.usable_height(error)
    qtbot.wait(20)
    assert error.height() == 240
