"""The window's layout: the view takes the room (issue 26, item 5), small windows keep a
usable view and slider (issue 13), and saved layouts come back usable, older ones upgraded."""

from __future__ import annotations

import contextlib
import gc

import pytest
from PyQt6.QtCore import QEvent, QSettings, Qt
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.tools.gallery import figure_mask
from gmr_studio.app.window import layout
from gmr_studio.app.window.main_window import SLIDER_MINIMUM, VIEW_MINIMUM, MainWindow
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio
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


def test_a_layout_saved_squeezed_is_restored_usable(qtbot, studio):
    _settle(qtbot, studio, (1400, 900))
    studio.curves_dock.show()
    qtbot.wait(20)
    studio.resizeDocks([studio.curves_dock], [800], Qt.Orientation.Vertical)  # the view squeezed
    studio.resizeDocks([studio.forest_dock, studio.inspector_dock], [700, 700], Qt.Orientation.Horizontal)
    qtbot.wait(20)
    assert _share(studio) < layout.RESTORED_MINIMUM_SHARE
    studio._save_settings()
    with _window(studio.settings.fileName()) as again:
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
        old._save_settings()
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
        window._save_settings()
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
