"""A cursor move in a time plot (the Curves and Error docks') repaints the cursor's strips,
not the axes: the axes draw the grid across the whole plot, so without their pixmap cache
every frame of playback repainted them (about 1 ms a frame in the Error dock)."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.docks.timeplot import TimePlot

pytestmark = pytest.mark.gui


def test_moving_the_cursor_paints_no_axis(qtbot, monkeypatch):
    plot = TimePlot()
    qtbot.addWidget(plot)
    plot.resize(600, 240)
    frames = np.arange(500)
    plot.set_curves(frames, ["a", "b"], np.column_stack([np.sin(frames / 20), np.cos(frames / 30)]), "cm")
    plot.set_cursor(0)
    plot.autoscale()
    plot.show()
    qtbot.waitExposed(plot)
    qtbot.wait(50)
    painted: list[str] = []
    paint = pg.AxisItem.paint

    def counted(self, *args):
        painted.append(self.orientation)
        return paint(self, *args)

    monkeypatch.setattr(pg.AxisItem, "paint", counted)
    for frame in range(10, 200, 19):
        plot.set_cursor(frame)
        QApplication.processEvents()
        assert plot.cursor.value() == pytest.approx(frame * plot.scale)
    assert painted == []  # the axes come from their pixmaps
