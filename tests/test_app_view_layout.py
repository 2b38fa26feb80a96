"""Defect 4 of issue 13: small windows keep a usable 3D view and slider, docks come back to
usable widths, and a layout saved squeezed is restored usable."""

from __future__ import annotations

import gc

import pytest
from PyQt6.QtCore import QEvent, QSettings, Qt
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.tools.gallery import figure_mask
from gmr_studio.app.window.main_window import (
    DOCK_MINIMUM,
    DOCK_WIDTHS,
    SLIDER_MINIMUM,
    VIEW_MINIMUM,
    VIEW_SHARE,
    MainWindow,
)
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio


def _settle(qtbot, window, size) -> None:
    """Resize and wait for the X server's answer, then for the docks' fit queued after it."""
    window.resize(*size)
    least = window.minimumSizeHint()
    expected = (max(size[0], least.width()), max(size[1], least.height()))
    qtbot.waitUntil(lambda: (window.width(), window.height()) == expected, timeout=5000)
    qtbot.wait(100)


def _side_docks(window) -> list[int]:
    return [window.forest_dock.width(), window.inspector_dock.width()]


def _usable(window) -> bool:
    return all(w >= u - 2 for w, u in zip(_side_docks(window), DOCK_WIDTHS))


def test_a_small_window_keeps_the_view_and_the_slider_and_the_docks_come_back(qtbot, studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    _settle(qtbot, studio, (500, 350))
    view = studio.view
    assert view.width() >= max(VIEW_MINIMUM[0], VIEW_SHARE * studio.width() - 2)
    assert view.height() >= VIEW_MINIMUM[1]
    assert studio.timeline.slider.width() >= SLIDER_MINIMUM > 4 * studio.timeline.slider.height()
    assert figure_mask(screen_image(studio)).sum() > 200, "no figure drawn in the small view"
    _settle(qtbot, studio, (1400, 900))
    qtbot.waitUntil(lambda: _usable(studio), timeout=5000)
    assert view.width() >= VIEW_SHARE * studio.width()


def test_a_layout_saved_squeezed_is_restored_usable(qtbot, studio, tmp_path):
    _settle(qtbot, studio, (1400, 900))
    studio.resizeDocks([studio.forest_dock, studio.inspector_dock], [40, 40], Qt.Orientation.Horizontal)
    qtbot.wait(10)
    assert max(_side_docks(studio)) <= DOCK_MINIMUM
    studio._save_settings()
    again = MainWindow(settings=QSettings(studio.settings.fileName(), QSettings.Format.IniFormat))
    try:
        again.show()
        qtbot.waitExposed(again)
        qtbot.wait(50)
        qtbot.waitUntil(lambda: _usable(again), timeout=5000)
    finally:
        again.close()
        again.deleteLater()
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)
        gc.collect()
