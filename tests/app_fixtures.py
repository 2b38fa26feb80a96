"""Fixtures for the window tests: a real main window that must not leak.

Import them into a test module (``from tests.app_fixtures import studio``). At teardown the
window is closed (edits discarded) and the test fails if a window is left visible, the
interactor was not closed, or a PyVista plotter (a VTK render window) is still alive.
"""

from __future__ import annotations

import gc

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QSettings
from PyQt6.QtWidgets import QApplication
from pyvista.plotting.plotter import _ALL_PLOTTERS

from gmr_studio.app.window.main_window import MainWindow


def live_windows() -> set[int]:
    return {id(w) for w in QApplication.topLevelWidgets() if w.isVisible()}


@pytest.fixture
def studio(qtbot, tmp_path):
    """A shown main window with throwaway settings; errors go to the status bar only."""
    plotters_before = set(_ALL_PLOTTERS)
    windows_before = live_windows()
    window = MainWindow(settings=QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat))
    window.files.quiet = True
    window.resize(1280, 820)
    window.show()
    qtbot.waitExposed(window)
    yield window
    window.state.undo_stack.setClean()
    window.close()
    window.deleteLater()
    QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)  # delete it now, not in a later test
    QApplication.processEvents()
    gc.collect()
    # private: pyvistaqt says whether its interactor closed only through this attribute
    assert window.view.interactor._closed, "the interactor was not closed"
    assert set(_ALL_PLOTTERS) <= plotters_before, "a VTK render window (plotter) leaked"
    assert live_windows() <= windows_before, "a window was left open"


@pytest.fixture
def crash_folder(tmp_path, monkeypatch):
    """The app's config folder (its crash log) moved into the test's temporary folder."""
    folder = tmp_path / "config"
    monkeypatch.setenv("GMR_STUDIO_CONFIG", str(folder))
    return folder


def open_file(window: MainWindow, path, markers=None) -> None:
    """Open a file the way the app does (worker thread), and wait until it is shown."""
    window.files.open_path(str(path), markers=str(markers) if markers else None, ask=False, wait=True)
    assert window.state.path is not None and window.state.path.name == str(path).rsplit("/", 1)[-1]


def screen_image(window: MainWindow) -> np.ndarray:
    from gmr_studio.app.media.video import scene_image

    return scene_image(window.view.scene)
