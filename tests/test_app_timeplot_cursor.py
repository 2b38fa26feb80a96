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


def _long_plot(qtbot, frames: int = 3000) -> TimePlot:
    plot = TimePlot()
    qtbot.addWidget(plot)
    plot.resize(600, 240)
    x = np.arange(frames)
    plot.set_curves(x, ["a"], np.sin(x / 50)[:, None], "cm")
    plot.autoscale()
    plot.show()
    qtbot.waitExposed(plot)
    QApplication.processEvents()
    return plot


def _pixels(plot: TimePlot, x: float) -> float:
    from PyQt6.QtCore import QPointF

    return plot.view_box.mapViewToDevice(QPointF(x, 0)).x()


def test_the_cursor_moves_only_when_it_would_be_drawn_half_a_pixel_away(qtbot):
    plot = _long_plot(qtbot)
    per_frame = _pixels(plot, 1) - _pixels(plot, 0)
    assert 0.1 < per_frame < 0.3  # several frames a pixel
    plot.set_cursor(100)
    moves = []
    move = plot._move_cursor

    def noted(x: float) -> None:
        moves.append(x)
        move(x)

    plot._move_cursor = noted
    for frame in range(101, 131):
        plot.set_cursor(frame)
        assert plot.cursor_frame == frame
        off = abs(_pixels(plot, plot.cursor.value()) - _pixels(plot, frame))
        assert off < 0.5, (frame, off)  # drawn within half a pixel of its frame
    expected = round(30 * per_frame / 0.5)  # a move each time the line is half a pixel off
    assert 0 < len(moves) <= expected + 1 < 30
    assert all(float(v).is_integer() for v in moves)  # moved onto frames, never in between


def test_a_zoom_puts_the_cursor_exactly_on_its_frame(qtbot):
    plot = _long_plot(qtbot)
    plot.set_cursor(1000)
    plot.set_cursor(1002)  # within half a pixel: the line stays on 1000
    assert plot.cursor.value() == pytest.approx(1000)
    plot.view_box.setXRange(990, 1010, padding=0)  # 30 pixels a frame
    QApplication.processEvents()
    assert plot.cursor.value() == pytest.approx(1002)
    plot.set_cursor(1003)  # a frame is many pixels now: every frame moves it
    assert plot.cursor.value() == pytest.approx(1003)
    plot.resize(300, 240)  # narrower: the pixels per frame change with the size
    QApplication.processEvents()
    per_frame = _pixels(plot, 1004) - _pixels(plot, 1003)
    assert plot._pixels_per_x == pytest.approx(per_frame, rel=0.05)
