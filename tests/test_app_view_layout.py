"""The window's layout (app/window/layout.py): the view takes the room, small windows keep a
usable view and slider, saved layouts come back usable and older ones are replaced; and the
layout's rules on a small main window of plain widgets: the side column's width, the view's
share, the timeline strip, the analysis docks tabbed when shown at a usable height, and the
docks fitted back around a squeezed view."""

from __future__ import annotations

import contextlib
import gc
from types import SimpleNamespace

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QSettings, QSize, Qt
from PyQt6.QtWidgets import QApplication, QDockWidget, QLabel, QMainWindow, QSizePolicy, QTabBar, QWidget

from gmr_studio.app.docks.frame_follow import seen
from gmr_studio.app.tools.gallery import figure_mask
from gmr_studio.app.window import layout
from gmr_studio.app.window.main_window import SLIDER_MINIMUM, VIEW_MINIMUM, MainWindow
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio
RIGHT, BOTTOM = Qt.DockWidgetArea.RightDockWidgetArea, Qt.DockWidgetArea.BottomDockWidgetArea
HORIZONTAL, VERTICAL = Qt.Orientation.Horizontal, Qt.Orientation.Vertical
WALK = "cmu/subject01/01_01.bvh"


def _settle(qtbot, window, size) -> None:
    """Resize and wait for the X server's answer, then for the docks' fit queued after it."""
    window.resize(*size)
    least = window.minimumSizeHint()
    expected = (max(size[0], least.width()), max(size[1], least.height()))
    qtbot.waitUntil(lambda: (window.width(), window.height()) == expected, timeout=5000)
    qtbot.wait(100)


def _share(window) -> float:
    return layout.view_share(window, window.view)


def _column_usable(window) -> bool:
    target = layout.side_width(window.width())
    return all(abs(d.width() - target) <= 3 for d in (window.forest_dock, window.inspector_dock))


@contextlib.contextmanager
def _window(settings_path):
    window = MainWindow(settings=QSettings(str(settings_path), QSettings.Format.IniFormat))
    window.files.quiet = True
    try:
        yield window
    finally:
        window.state.undo_stack.setClean()
        window.close()
        window.deleteLater()
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)
        gc.collect()


@pytest.mark.parametrize("size", [(1280, 800), (1920, 1080)])
def test_the_default_layout_gives_the_view_the_room(qtbot, tmp_path, size):
    with _window(tmp_path / "settings.ini") as window:
        window.resize(*size)
        window.show()
        qtbot.waitExposed(window)
        open_file(window, shared_path(WALK))
        _settle(qtbot, window, size)
        assert _share(window) >= layout.VIEW_AREA_SHARE, f"the view has {_share(window):.0%} of {size}"
        # the timeline is a strip under the view; Forest above Inspector beside it
        timeline = window.timeline_dock
        assert timeline.height() < 90 and timeline.y() > window.view.y() + window.view.height() - 5
        forest, inspector = window.forest_dock, window.inspector_dock
        assert forest.isVisible() and inspector.isVisible()
        assert forest.x() >= window.view.x() + window.view.width() and forest.y() < inspector.y()
        assert _column_usable(window)
        # Curves, Foot contacts and Error: hidden until asked, then tabs of one area
        assert not any(d.isVisible() for d in window.analysis_docks)
        window.curves_dock.show()
        window.contacts_dock.show()
        qtbot.wait(50)
        assert window.contacts_dock in window.tabifiedDockWidgets(window.curves_dock)
        assert window.curves_dock.height() >= 150
        assert _share(window) >= 0.35
        assert figure_mask(screen_image(window)).sum() > 500, "no figure in the view"


def test_a_small_window_keeps_the_view_and_the_slider_and_the_column_comes_back(qtbot, studio):
    open_file(studio, shared_path(WALK))
    _settle(qtbot, studio, (500, 350))
    view = studio.view
    assert view.width() >= VIEW_MINIMUM[0] and view.height() >= VIEW_MINIMUM[1]
    assert studio.timeline.slider.width() >= SLIDER_MINIMUM > 4 * studio.timeline.slider.height()
    assert figure_mask(screen_image(studio)).sum() > 200, "no figure drawn in the small view"
    _settle(qtbot, studio, (1400, 900))
    qtbot.waitUntil(lambda: _share(studio) >= layout.VIEW_AREA_SHARE, timeout=5000)


def test_a_layout_saved_squeezed_is_restored_usable(qtbot, tmp_path):
    path = tmp_path / "settings.ini"
    with _window(path) as first:
        first.show()
        qtbot.waitExposed(first)
        _settle(qtbot, first, (1400, 900))
        first.curves_dock.show()
        qtbot.wait(20)
        first.resizeDocks([first.curves_dock], [800], Qt.Orientation.Vertical)  # the view squeezed
        first.resizeDocks([first.forest_dock, first.inspector_dock], [700, 700], Qt.Orientation.Horizontal)
        qtbot.wait(20)
        assert _share(first) < layout.RESTORED_MINIMUM_SHARE
    with _window(path) as again:  # the layout saved when the first window closed
        again.show()
        qtbot.waitExposed(again)
        qtbot.waitUntil(lambda: _share(again) >= layout.RESTORED_MINIMUM_SHARE, timeout=5000)
        assert again.curves_dock.isVisible()  # the user's docks kept, only given their sizes back


def test_a_layout_from_an_older_version_is_upgraded(qtbot, tmp_path):
    """A layout saved before the version key (the view under three bottom docks) is
    replaced by the default, never restored with its tiny view."""
    path = tmp_path / "settings.ini"
    with _window(path) as old:
        old.resize(1280, 800)
        old.show()
        qtbot.waitExposed(old)
        for dock in old.analysis_docks[:2]:
            dock.show()
        old.resizeDocks(old.analysis_docks[:2], [500, 500], Qt.Orientation.Vertical)
        qtbot.wait(20)
    settings = QSettings(str(path), QSettings.Format.IniFormat)
    settings.remove("window/layout_version")  # as an older version wrote it
    settings.sync()
    with _window(path) as window:
        window.resize(1280, 800)
        window.show()
        qtbot.waitExposed(window)
        qtbot.wait(50)
        assert not any(d.isVisible() for d in window.analysis_docks)
        assert _share(window) >= layout.VIEW_AREA_SHARE
    assert str(QSettings(str(path), QSettings.Format.IniFormat).value("window/layout_version")) == str(
        layout.LAYOUT_VERSION
    )


def test_a_comparison_added_keeps_the_analysis_area_and_the_view_as_they_were(qtbot, studio):
    """Adding a comparison shows the Error dock as a tab of the Curves at the area's height:
    shown beside the Curves before being tabbed, it squeezed the area to its size hint (240
    pixels down to 175) and the view jumped 65 pixels taller."""
    from gmr_studio.app.docks.frame_follow import seen
    from gmr_studio.app.model.state import Snapshot
    from gmr_studio.core.demo import MOTION_FILE, demo_folder
    from gmr_studio.core.formats import load_gmr

    open_file(studio, demo_folder() / MOTION_FILE)
    studio.curves_dock.show()
    qtbot.waitUntil(lambda: studio.curves_dock.height() == layout.BOTTOM_HEIGHT)
    view_height = studio.view.interactor.height()
    studio.layers.add(Snapshot.of(load_gmr(demo_folder() / MOTION_FILE)), "walk.gmr")
    qtbot.waitUntil(lambda: seen(studio.error_dock) and not seen(studio.curves_dock))
    qtbot.wait(50)
    assert studio.error_dock in studio.tabifiedDockWidgets(studio.curves_dock)
    assert studio.view.interactor.height() == view_height  # the area (tab bar included) kept its 240 pixels
    assert layout.BOTTOM_HEIGHT - 40 < studio.error_dock.height() < layout.BOTTOM_HEIGHT


# ---------------------------------------------- the rules on a window of plain widgets
def test_the_side_column_is_a_share_of_the_window_within_its_limits():
    low, high = layout.SIDE_LIMITS
    widths = np.arange(400, 3000, 7)
    columns = np.array([layout.side_width(int(w)) for w in widths])
    assert all(isinstance(layout.side_width(int(w)), int) for w in widths[::50])
    assert (columns >= low).all() and (columns <= high).all() and (np.diff(columns) >= 0).all()
    between = (layout.SIDE_SHARE * widths > low) & (layout.SIDE_SHARE * widths < high)
    assert between.any() and (np.abs(columns - layout.SIDE_SHARE * widths)[between] <= 1).all()
    assert columns[0] == low and columns[-1] == high


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


def plain_window(
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
    window, _, _, (curves, contacts, error) = plain_window(qtbot)
    layout.tab_when_shown(window, [curves, contacts, error])
    curves.show()  # the first: the area opens at the usable height
    qtbot.waitUntil(lambda: curves.height() == layout.BOTTOM_HEIGHT)
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
    qtbot.waitUntil(lambda: contacts.height() == layout.BOTTOM_HEIGHT)


def test_a_tall_enough_analysis_dock_is_left_as_the_user_made_it(qtbot):
    window, _, _, (curves, _, _) = plain_window(qtbot)
    layout.tab_when_shown(window, [curves])
    window.resizeDocks([curves], [400], VERTICAL)
    curves.show()
    qtbot.waitUntil(lambda: seen(curves))
    qtbot.wait(20)
    assert curves.height() > layout.BOTTOM_HEIGHT


def test_the_column_gives_way_to_the_view_and_comes_back_when_squeezed(qtbot):
    window, view, side, bottom = plain_window(qtbot)
    target = layout.side_width(1400)
    window.resizeDocks(side, [700, 700], HORIZONTAL)  # the view has a third of the window
    qtbot.waitUntil(lambda: side[0].width() == 700)
    layout.fit_docks(window, view, side, bottom)
    qtbot.waitUntil(lambda: side[0].width() == target)
    assert layout.view_share(window, view) >= layout.VIEW_AREA_SHARE - 0.03
    window.resizeDocks(side, [150, 150], HORIZONTAL)  # squeezed: widened again
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
    window, view, side, bottom = plain_window(qtbot, (560, 500))
    window.resizeDocks(side, [150, 150], HORIZONTAL)  # the view about 400 wide: a full column would leave it too little
    qtbot.waitUntil(lambda: side[0].width() == 150)
    layout.fit_docks(window, view, side, bottom)
    qtbot.wait(20)
    assert side[0].width() == 150


def test_tall_analysis_docks_give_the_view_its_room_back(qtbot):
    window, view, side, (curves, contacts, error) = plain_window(qtbot)
    curves.show(), contacts.show()
    window.splitDockWidget(curves, contacts, HORIZONTAL)
    window.resizeDocks([curves, contacts], [700, 700], VERTICAL)
    qtbot.waitUntil(lambda: curves.height() == 700)
    assert layout.view_share(window, view) < layout.RESTORED_MINIMUM_SHARE
    layout.fit_docks(window, view, side, [curves, contacts, error])
    usable = layout.BOTTOM_HEIGHT
    qtbot.waitUntil(lambda: curves.height() == usable and contacts.height() == usable)
    window.resizeDocks([curves], [400], VERTICAL)  # taller, but the view keeps its least share: left so
    qtbot.waitUntil(lambda: curves.height() == 400)
    assert layout.view_share(window, view) >= layout.RESTORED_MINIMUM_SHARE
    layout.fit_docks(window, view, side, [curves, contacts, error])
    qtbot.wait(20)
    assert curves.height() == 400


def test_a_layout_is_restored_only_from_this_version(qtbot, tmp_path):
    window, _, side, _ = plain_window(qtbot)
    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat)
    assert not layout.restore_layout(window, settings)  # nothing saved
    layout.save_layout(window, settings)
    assert str(settings.value("window/layout_version")) == str(layout.LAYOUT_VERSION)
    assert layout.restore_layout(window, settings)
    settings.setValue("window/layout_version", layout.LAYOUT_VERSION - 1)
    assert not layout.restore_layout(window, settings)
    settings.remove("window/layout_version")  # saved before the version key
    assert not layout.restore_layout(window, settings)
    settings.setValue("window/layout_version", str(layout.LAYOUT_VERSION))  # as read back from the file
    settings.setValue("window/state", window.saveState(layout.LAYOUT_VERSION))
    assert layout.restore_layout(window, settings)
    settings.setValue("window/state", window.saveState(layout.LAYOUT_VERSION - 1))  # its own version must match
    assert not layout.restore_layout(window, settings)
    side[1].hide()
    settings.setValue("window/state", window.saveState(layout.LAYOUT_VERSION))
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


def test_the_column_gives_way_to_a_view_short_of_its_share_only():
    target = layout.side_width(1000)
    column = [StubDock(300, 400), StubDock(300, 400)]  # wider than its width
    assert _fit((500, 1000), column, []) == [(column, [target, target], HORIZONTAL)]  # the view at half
    assert _fit((700, 1000), column, []) == []  # the view has more than its share: kept
    hidden = [StubDock(300, 400, visible=False), StubDock(400, 400, floating=True)]
    assert _fit((500, 1000), hidden, []) == []  # no docked column: nothing to fit
    docked = StubDock(250, 400)
    assert _fit((500, 1000), [*hidden, docked], []) == [([docked], [target], HORIZONTAL)]  # its width alone counts


def test_a_squeezed_column_comes_back_only_beside_a_view_wide_enough_to_lose_it():
    target = layout.side_width(1000)

    def widened(width: int, view: int) -> bool:
        return bool(_fit((view, 1000), [StubDock(width, 400)], [], window=(1000, 1000)))

    squeezed = layout.DOCK_MINIMUM  # narrower than twice the least a dock may have
    assert widened(squeezed, 900) and not widened(2 * layout.DOCK_MINIMUM + 20, 900)
    assert not widened(squeezed, target + layout.VIEW_MINIMUM[0] - 10)  # the view would fall below its least


def test_tall_bottom_docks_go_back_to_the_usable_height_only_when_the_view_is_squeezed():
    tall, short = StubDock(1000, 500), StubDock(1000, 100)
    hidden, floating = StubDock(1000, 600, visible=False), StubDock(1000, 600, floating=True)
    bottom = [tall, short, hidden, floating]
    squeezed = int(layout.RESTORED_MINIMUM_SHARE * 1000) - 50
    assert _fit((1000, squeezed), [], bottom) == [([tall], [layout.BOTTOM_HEIGHT], VERTICAL)]  # the tall one alone
    assert _fit((1000, 600), [], bottom) == []  # the view keeps its least share: kept
    assert _fit((1000, squeezed), [], [short, hidden, floating]) == []


def test_a_dock_shown_beside_two_apart_joins_the_first_ones_tabs(qtbot):
    window, _, _, (curves, contacts, error) = plain_window(qtbot)
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
    """At any window size the view keeps its least size, the frame slider its least width,
    and the Forest and Inspector their least content."""
    view = studio.view
    assert (view.minimumWidth(), view.minimumHeight()) == layout.VIEW_MINIMUM
    assert studio.timeline.slider.minimumWidth() == layout.SLIDER_MINIMUM
    docks = (studio.forest_dock, studio.inspector_dock)
    assert [d.widget().minimumWidth() for d in docks] == [layout.DOCK_MINIMUM] * 2


def test_a_single_analysis_dock_opens_at_a_usable_height(qtbot):
    window, _, _, (curves, _, _) = plain_window(qtbot)
    layout.tab_when_shown(window, [curves])
    curves.show()
    qtbot.waitUntil(lambda: curves.height() == layout.BOTTOM_HEIGHT)


def _tabs(window: QMainWindow) -> list[list[str]]:
    """The titles on each tab bar of the window's dock areas."""
    bars = [bar for bar in window.findChildren(QTabBar) if bar.count() > 1]
    return [[bar.tabText(i) for i in range(bar.count())] for bar in bars]


def test_a_dock_shown_again_comes_back_to_its_place_among_its_tabs_in_front(qtbot):
    names = ("curves", "error", "problems", "contacts")  # the dock apart last: listed after the tabs
    window, _, _, (curves, error, problems, contacts) = plain_window(qtbot, bottom=names, tabbed=True)
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
    """A tab group lower than the usable height (a user's, or squeezed by a dock shown beside
    it before tabbing) is given that height, tab bar included, as soon as the tabs are laid
    out; a hidden or floating dock, or one in the side column, is left alone."""
    window, view, (forest, _), (curves, contacts, error) = plain_window(qtbot)
    placer = layout.TabWhenShown(window, [curves, contacts, error])
    window.resizeDocks([forest], [150], VERTICAL)
    qtbot.waitUntil(lambda: forest.height() < layout.BOTTOM_HEIGHT)
    side = forest.height()
    placer.usable_height(forest)  # the side column's split is not the analysis area's
    qtbot.wait(20)
    assert forest.height() == side
    curves.show()
    qtbot.waitUntil(lambda: curves.height() == layout.BOTTOM_HEIGHT)
    window.resizeDocks([curves], [150], VERTICAL)
    qtbot.waitUntil(lambda: curves.height() == 150)
    low_view = view.height()
    error.show()  # tabbed, then the area back to the usable height
    qtbot.waitUntil(lambda: view.height() == low_view - (layout.BOTTOM_HEIGHT - 150))
    assert window.tabifiedDockWidgets(curves) == [error]
    assert layout.BOTTOM_HEIGHT - 40 < error.height() < layout.BOTTOM_HEIGHT
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
    qtbot.waitUntil(lambda: view.height() == low_view - (layout.BOTTOM_HEIGHT - 150))


def test_tabs_exactly_at_the_usable_height_are_left_as_they_are(qtbot):
    """The rule lifts tabs below the usable height only: a tab group whose dock is exactly
    that high (more with its tab bar) is not brought down to it with its tab bar."""
    window, _, _, (curves, contacts, error) = plain_window(qtbot)
    placer = layout.TabWhenShown(window, [curves, contacts, error])
    usable = layout.BOTTOM_HEIGHT
    curves.show()
    qtbot.waitUntil(lambda: curves.height() == usable)
    error.show()
    qtbot.waitUntil(lambda: seen(error) and window.tabifiedDockWidgets(curves) == [error])
    tab_bar = usable - error.height()
    assert 0 < tab_bar < 40
    window.resizeDocks([error], [usable + tab_bar], VERTICAL)
    qtbot.waitUntil(lambda: error.height() == usable)
    placer.usable_height(error)
    qtbot.wait(20)
    assert error.height() == usable
