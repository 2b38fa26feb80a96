"""The desktop entry point starts a real Qt window (under Xvfb in CI) and shows a file."""

from __future__ import annotations

import pytest

from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.test_bvh_reader import SMALL

pytestmark = pytest.mark.gui
studio = app_fixtures.studio


def test_window_opens_on_a_small_file(qtbot, studio, tmp_path):
    path = tmp_path / "small.bvh"
    path.write_text(SMALL)
    open_file(studio, path)
    assert studio.windowTitle() == "small.bvh[*] \u2014 GMR Studio"
    assert studio.forest.topLevelItemCount() == 1
    assert "3 joints" in studio.status.text() and "2 frames" in studio.status.text()
    assert studio.view.scene.is_shown("joints") and studio.view.scene.is_shown("bones")


@pytest.mark.gui
def test_the_theme_gives_an_icon_and_a_style(qapp):
    from gmr_studio.app.window.theme import ICON, STYLE, apply_theme

    previous = qapp.styleSheet(), qapp.windowIcon()
    try:
        apply_theme(qapp)
        assert not qapp.windowIcon().isNull() and ICON.exists()
        assert "QDockWidget::title" in qapp.styleSheet() and STYLE.exists()
        assert qapp.windowIcon().pixmap(64, 64).toImage().pixelColor(32, 11).blue() > 150  # the blue head
    finally:
        qapp.setStyleSheet(previous[0])
        qapp.setWindowIcon(previous[1])
