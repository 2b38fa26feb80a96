"""A reusable plot of curves over frames (pyqtgraph): cursor, scrubbing, zoom, ranges, export.

:class:`TimePlot` knows nothing of motions: it is given x as frame numbers (F,) and named
columns (F, C) and draws them, each in its own colour, with pyqtgraph's peak
downsampling and clip-to-view so that a 100,000-frame curve redraws in a few
milliseconds. Interaction:

- a cursor line at the current frame (:meth:`TimePlot.set_cursor`, cheap: it only moves
  the line, and only when it would be drawn half a pixel or more from where it is: a long
  take has several frames a pixel, and a move repaints the plot under the line);
- left click or left drag in the plot, or dragging the cursor: :attr:`TimePlot.frame_requested`
  with the frame under the pointer (the owner sets the frame; the plot does not);
- Shift + left drag: selects a frame range, shown shaded; :attr:`TimePlot.range_selected`
  ``(start, stop)`` half-open, ``(-1, -1)`` when cleared; the range's edges can be dragged;
- wheel or right drag: zoom; middle drag: pan; :meth:`TimePlot.autoscale` fits everything;
- x in frames or seconds (:meth:`TimePlot.set_x_unit`);
- :meth:`TimePlot.export_csv` writes what is plotted within the visible x range,
  :meth:`TimePlot.export_png` the plot as it looks.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyqtgraph as pg
from PyQt6.QtCore import QBuffer, QIODevice, Qt, pyqtSignal
from PyQt6.QtGui import QColor
from PyQt6.QtWidgets import QGraphicsItem, QVBoxLayout, QWidget

from gmr_studio.core.analysis.curves import Curves
from gmr_studio.core.analysis.curves_table import curves_csv_text
from gmr_studio.core.atomic import atomic_write_bytes, atomic_write_text

LEGEND_TEXT = "#e6e6e6"
LEGEND_BOX = (20, 21, 24, 210)
#: colours of successive columns (colour-blind-safe Tableau 10)
PALETTE = ("#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7", "#9c755f")
CURSOR_COLOUR = "#ffd400"
RANGE_BRUSH = (255, 212, 0, 40)
SPAN_BRUSH = (200, 60, 60, 50)


class _ScrubViewBox(pg.ViewBox):
    """A ViewBox whose left button scrubs (and with Shift selects a range) instead of panning."""

    def __init__(self, plot: TimePlot) -> None:
        super().__init__()
        self._plot = plot

    def mouseClickEvent(self, ev) -> None:  # noqa: N802 (pyqtgraph's name)
        if ev.button() == Qt.MouseButton.LeftButton:
            ev.accept()
            self._plot._seek_to_x(self.mapSceneToView(ev.scenePos()).x())
        else:
            super().mouseClickEvent(ev)

    def mouseDragEvent(self, ev, axis=None) -> None:  # noqa: N802
        if ev.button() != Qt.MouseButton.LeftButton:
            super().mouseDragEvent(ev, axis)
            return
        ev.accept()
        x = self.mapSceneToView(ev.scenePos()).x()
        if ev.modifiers() & Qt.KeyboardModifier.ShiftModifier:
            start = self.mapSceneToView(ev.buttonDownScenePos()).x()
            self._plot._drag_range(start, x, finished=ev.isFinish())
        else:
            self._plot._seek_to_x(x)


class TimePlot(QWidget):
    """Curves over frames with a cursor at the current frame; see the module docstring."""

    frame_requested = pyqtSignal(int)
    range_selected = pyqtSignal(int, int)  # half-open [start, stop); (-1, -1): no range

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.view_box = _ScrubViewBox(self)
        self.plot_widget = pg.PlotWidget(viewBox=self.view_box, background="#1e1f22")
        self.plot_item = self.plot_widget.getPlotItem()
        self.plot_item.showGrid(x=True, y=True, alpha=0.25)
        # the axes draw the grid, so their bounds cover the plot and every cursor move would
        # repaint them: cached as pixmaps, a move only blits two strips
        for side in ("left", "bottom"):
            self.plot_item.getAxis(side).setCacheMode(QGraphicsItem.CacheMode.DeviceCoordinateCache)
        self.plot_item.setMenuEnabled(False)
        # light text on a dark box: readable over the dark plot and its grid
        self.legend = self.plot_item.addLegend(
            offset=(8, 8), labelTextSize="8pt", labelTextColor=LEGEND_TEXT, brush=pg.mkBrush(LEGEND_BOX)
        )
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.plot_widget)
        self.cursor = pg.InfiniteLine(
            angle=90, movable=True, pen=pg.mkPen(CURSOR_COLOUR, width=1.5), hoverPen=pg.mkPen(CURSOR_COLOUR, width=3)
        )
        self.cursor.setZValue(10)
        self.cursor.sigDragged.connect(lambda line: self._seek_to_x(line.value()))
        self.plot_item.addItem(self.cursor, ignoreBounds=True)
        self.region = pg.LinearRegionItem(brush=pg.mkBrush(*RANGE_BRUSH), movable=True)
        self.region.setZValue(5)
        self.region.hide()
        self.region.sigRegionChangeFinished.connect(self._on_region_moved)
        self.plot_item.addItem(self.region, ignoreBounds=True)
        self.frames = np.zeros(0, np.int64)
        self.columns: tuple[str, ...] = ()
        self.values = np.zeros((0, 0))
        self.scale = 1.0  # x per frame: 1 (frames) or the frame time (seconds)
        self.frame_time = 1.0
        self.x_unit = "frames"
        self.n_frames = 0
        self.unit = ""
        self.cursor_frame = 0
        self._pixels_per_x = 0.0  # the plot's width over its x range (0: not laid out yet)
        self.view_box.sigRangeChanged.connect(self._place_cursor)
        self.view_box.sigResized.connect(self._place_cursor)
        self.range: tuple[int, int] | None = None
        self._items: list[pg.PlotDataItem] = []
        self._colours: list[str] = []
        self._styles: list[Qt.PenStyle] = []
        self._spans: list[pg.LinearRegionItem] = []
        self._span_frames = np.zeros((0, 2), np.int64)
        self._set_labels()

    # ----------------------------------------------------------------- data
    def set_curves(
        self,
        frames: np.ndarray,
        columns: Sequence[str],
        values: np.ndarray,
        unit: str = "",
        colours: Sequence[str] | None = None,
        styles: Sequence[Qt.PenStyle] | None = None,
    ) -> None:
        """Plot ``values`` (F, C) named ``columns`` against frame numbers ``frames`` (F,)
        (NaN values leave gaps). ``colours``: one per column (default: :data:`PALETTE`);
        ``styles``: one line style per column (default: solid)."""
        self.frames = np.asarray(frames, dtype=np.int64)
        self.columns = tuple(columns)
        self.values = np.asarray(values, dtype=np.float64).reshape(self.frames.size, len(self.columns))
        self.n_frames = int(self.frames[-1]) + 1 if self.frames.size else 0
        self.unit = unit
        self._colours = [colours[c] if colours else PALETTE[c % len(PALETTE)] for c in range(len(self.columns))]
        self._styles = [styles[c] if styles else Qt.PenStyle.SolidLine for c in range(len(self.columns))]
        for item in self._items:
            self.plot_item.removeItem(item)
        self.legend.clear()
        self._items = []
        x = self.frames * self.scale
        for c, name in enumerate(self.columns):
            pen = pg.mkPen(self._colours[c], width=1.2, style=self._styles[c])
            item = pg.PlotDataItem(pen=pen, name=name, connect="finite")
            self.plot_item.addItem(item)  # empty first: pyqtgraph 0.14 clips to a view only once in one
            item.setDownsampling(auto=True, method="peak")
            item.setClipToView(True)
            # drawn once into a pixmap until the data or the view change: a cursor move then
            # repaints a thin strip from it instead of re-rasterising every curve
            item.curve.setCacheMode(QGraphicsItem.CacheMode.DeviceCoordinateCache)
            item.setData(x, self.values[:, c])  # downsampled once, with every option set
            self._items.append(item)
        self._set_labels()

    def set_spans(self, spans: np.ndarray, brush: tuple[int, int, int, int] = SPAN_BRUSH) -> None:
        """Shade frame ranges (G, 2) half-open (a marker's gaps); an empty array clears them."""
        for item in self._spans:
            self.plot_item.removeItem(item)
        self._spans = []
        self._span_frames = np.asarray(spans, dtype=np.int64).reshape(-1, 2)
        for start, stop in self._span_frames:
            item = pg.LinearRegionItem(
                (start * self.scale, stop * self.scale), movable=False, brush=pg.mkBrush(*brush), pen=pg.mkPen(None)
            )
            item.setZValue(-5)
            self.plot_item.addItem(item, ignoreBounds=True)
            self._spans.append(item)

    @property
    def spans(self) -> np.ndarray:
        """(G, 2) the shaded frame ranges, half-open, as last given to :meth:`set_spans`."""
        return self._span_frames.copy()

    def set_x_unit(self, unit: str, frame_time: float) -> None:
        """Show x in ``"frames"`` or ``"seconds"`` (``frame_time`` seconds per frame)."""
        if unit not in ("frames", "seconds"):
            raise ValueError(f"x unit must be 'frames' or 'seconds', not {unit!r}")
        view = self.view_box.viewRange()[0]
        old = self.scale
        self.x_unit, self.frame_time = unit, float(frame_time)
        self.scale = self.frame_time if unit == "seconds" else 1.0
        self.set_curves(self.frames, self.columns, self.values, self.unit, self._colours, self._styles)
        self.set_spans(self._span_frames)
        self.set_cursor(self.cursor_frame)
        self._show_range()
        self.view_box.setXRange(view[0] / old * self.scale, view[1] / old * self.scale, padding=0)

    def autoscale(self) -> None:
        """Fit every curve: x over all frames, y over all finite values (computed here, not by
        pyqtgraph, whose bounds of a clipped-to-view curve are those of the clipped part)."""
        if not self.frames.size:
            return
        x_range = (self.frames[0] * self.scale, max(self.frames[-1], self.frames[0] + 1) * self.scale)
        finite = self.values[np.isfinite(self.values)]
        low, high = (float(finite.min()), float(finite.max())) if finite.size else (-1.0, 1.0)
        margin = 0.05 * (high - low) if high > low else max(abs(high), 1.0) * 0.05
        self.view_box.setRange(xRange=x_range, yRange=(low - margin, high + margin), padding=0)  # one update

    def _set_labels(self) -> None:
        self.plot_item.setLabel("bottom", "time (s)" if self.x_unit == "seconds" else "frame")
        self.plot_item.setLabel("left", self.unit or "")

    # ------------------------------------------------------------- cursor, seeking
    def set_cursor(self, frame: int) -> None:
        """Move the cursor to ``frame`` (no signal). The line is moved only when it would be
        drawn half a pixel or more away (with 2752 frames on 1000 pixels, one frame in three):
        a move repaints the plot under the line's old and new places."""
        self.cursor_frame = int(frame)
        x = self.cursor_frame * self.scale
        if abs(x - self.cursor.value()) * self._pixels_per_x >= 0.5 or not self._pixels_per_x:
            self._move_cursor(x)

    def _move_cursor(self, x: float) -> None:
        self.cursor.blockSignals(True)
        self.cursor.setValue(x)
        self.cursor.blockSignals(False)

    def _place_cursor(self, *_) -> None:
        """The view's range or size changed: a pixel is another length of x, and the cursor
        goes exactly to its frame."""
        (x0, x1), width = self.view_box.viewRange()[0], self.view_box.width()
        self._pixels_per_x = width / (x1 - x0) if x1 > x0 and width > 0 else 0.0
        self._move_cursor(self.cursor_frame * self.scale)

    def frame_at_x(self, x: float) -> int:
        """The frame nearest x (in the plot's unit), clamped to the frames plotted."""
        last = max(self.n_frames - 1, 0)
        return int(min(max(round(x / self.scale), 0), last))

    def _seek_to_x(self, x: float) -> None:
        frame = self.frame_at_x(x)
        self.set_cursor(frame)
        self.frame_requested.emit(frame)

    # ---------------------------------------------------------------------- ranges
    def set_range(self, start: int, stop: int) -> None:
        """Show the half-open frame range ``[start, stop)`` (start < 0: no range); no signal."""
        self.range = (int(start), int(stop)) if 0 <= start < stop else None
        self._show_range()

    def _show_range(self) -> None:
        self.region.blockSignals(True)
        if self.range is None:
            self.region.hide()
        else:
            start, stop = self.range
            self.region.setRegion(((start - 0.5) * self.scale, (stop - 0.5) * self.scale))
            self.region.show()
        self.region.blockSignals(False)

    def _frames_between(self, x0: float, x1: float) -> tuple[int, int]:
        lo, hi = sorted((x0, x1))
        start = self.frame_at_x(lo)
        return start, max(self.frame_at_x(hi) + 1, start + 1)

    def _drag_range(self, x0: float, x1: float, finished: bool) -> None:
        self.range = self._frames_between(x0, x1)
        self._show_range()
        if finished:
            self.range_selected.emit(*self.range)

    def _on_region_moved(self) -> None:
        lo, hi = self.region.getRegion()
        self.range = self._frames_between(lo + 0.5 * self.scale, hi - 0.5 * self.scale)
        self._show_range()
        self.range_selected.emit(*self.range)

    # ---------------------------------------------------------------------- export
    def visible_frames(self) -> np.ndarray:
        """Indices into the plotted rows whose frames lie in the visible x range."""
        lo, hi = self.view_box.viewRange()[0]
        x = self.frames * self.scale
        return np.flatnonzero((x >= lo) & (x <= hi))

    def csv_text(self) -> str:
        """What is plotted within the visible x range: ``frame,time,COLUMNS...`` rows, written
        as ``gmr curves`` writes them (:func:`core.analysis.curves_table.curves_csv_text`: names
        quoted, gaps empty)."""
        rows = self.visible_frames()
        return curves_csv_text(Curves(self.columns, self.values[rows], self.unit), self.frames[rows], self.frame_time)

    def export_csv(self, path: str | Path) -> None:
        atomic_write_text(path, self.csv_text())

    def export_png(self, path: str | Path) -> None:
        """The plot as shown, as a PNG."""
        image = self.plot_widget.grab()
        buffer = QBuffer()
        buffer.open(QIODevice.OpenModeFlag.WriteOnly)
        image.save(buffer, "PNG")
        atomic_write_bytes(path, bytes(buffer.data()))

    def colour_of(self, column: int) -> QColor:
        return QColor(self._colours[column])
