"""The desktop entry point starts a real Qt window (under Xvfb in CI)."""

from __future__ import annotations

import pytest

pytest.importorskip("PyQt6")

from app.main import create_window
from tests.test_bvh_reader import SMALL


@pytest.mark.gui
def test_window_opens_on_a_file(qtbot, tmp_path):
    path = tmp_path / "small.bvh"
    path.write_text(SMALL)
    window = create_window(str(path))
    qtbot.addWidget(window)
    window.show()
    qtbot.waitExposed(window)
    assert window.windowTitle() == "GMR Studio"
    assert "3 joints, 2 frames" in window.centralWidget().text()
