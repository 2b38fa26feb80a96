"""The time plot on its own (app/docks/timeplot.py, the Curves and Error docks' plot): curves,
their colours and styles, shaded spans, frames or seconds, autoscale, the cursor, seeking,
ranges (set, dragged, the region moved), what is visible and its CSV and PNG. A bare widget
on a small synthetic table: no window, no take."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import QPointF, Qt
from PyQt6.QtGui import QColor, QImage, QPainter
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.docks.timeplot import PALETTE, RANGE_BRUSH, SPAN_BRUSH, TimePlot
from gmr_studio.app.media.video import image_pixels

pytestmark = pytest.mark.gui
LEFT, RIGHT = Qt.MouseButton.LeftButton, Qt.MouseButton.RightButton


def make_plot(qtbot, n_frames: int = 200, first: int = 0) -> TimePlot:
    plot = TimePlot()
    qtbot.addWidget(plot)
    plot.resize(600, 240)
    frames = np.arange(first, first + n_frames)
    values = np.column_stack([np.sin(frames / 20.0), 2.0 + np.cos(frames / 30.0)])
    plot.set_curves(frames, ["a", "b"], values, "cm")
    plot.autoscale()
    plot.show()
    qtbot.waitExposed(plot)
    QApplication.processEvents()
    return plot


def signals(signal) -> list:
    seen = []
    signal.connect(lambda *args: seen.append(args))
    return seen


class FakeMouse:
    """What the view box reads of a pyqtgraph click or drag event, at view x positions."""

    def __init__(self, plot: TimePlot, x: float, button=LEFT, shift=False, down_x=None, finish=True):
        self._box = plot.view_box
        self._x, self._down, self._button, self._finish = x, x if down_x is None else down_x, button, finish
        self._modifiers = Qt.KeyboardModifier.ShiftModifier if shift else Qt.KeyboardModifier.NoModifier
        self.accepted = False

    def _scene(self, x: float) -> QPointF:
        return self._box.mapViewToScene(QPointF(x, 0.0))

    def button(self):
        return self._button

    def scenePos(self):
        return self._scene(self._x)

    def buttonDownScenePos(self, button=None):
        return self._scene(self._down)

    def screenPos(self):
        return self.scenePos()

    def modifiers(self):
        return self._modifiers

    def isFinish(self):
        return self._finish

    def isStart(self):
        return False

    def accept(self):
        self.accepted = True

    def ignore(self):
        self.accepted = False


# ----------------------------------------------------------------------------- curves
def test_curves_are_plotted_one_item_a_column_in_the_palettes_colours(qtbot):
    plot = make_plot(qtbot)
    assert plot.n_frames == 200 and plot.columns == ("a", "b") and plot.values.shape == (200, 2)
    assert [item.name() for item in plot._items] == ["a", "b"]
    assert [plot.colour_of(c).name() for c in range(2)] == [QColor(PALETTE[0]).name(), QColor(PALETTE[1]).name()]
    x, y = plot._items[1].getOriginalDataset()
    np.testing.assert_array_equal(x, np.arange(200))
    np.testing.assert_allclose(y, 2.0 + np.cos(np.arange(200) / 30.0))
    assert all(item.opts["pen"].style() == Qt.PenStyle.SolidLine for item in plot._items)
    assert plot.plot_item.getAxis("left").labelText == "cm"
    assert plot.plot_item.getAxis("bottom").labelText == "frame"


def test_new_curves_replace_the_old_and_colours_wrap_around_the_palette(qtbot):
    plot = make_plot(qtbot)
    n = len(PALETTE) + 2
    frames = np.arange(50)
    plot.set_curves(frames, [f"c{k}" for k in range(n)], np.ones((50, n)), "deg")
    assert len(plot.plot_item.listDataItems()) == n and len(plot._items) == n
    assert plot.colour_of(len(PALETTE)).name() == QColor(PALETTE[0]).name()
    assert plot.colour_of(len(PALETTE) + 1).name() == QColor(PALETTE[1]).name()
    assert plot.n_frames == 50
    assert [label.text for _, label in plot.legend.items] == [f"c{k}" for k in range(n)]


def test_curves_take_their_own_colours_and_styles_and_a_single_column(qtbot):
    plot = make_plot(qtbot)
    frames = np.arange(10, 30)
    dash = Qt.PenStyle.DashLine
    plot.set_curves(frames, ["only"], np.arange(20.0), "mm", colours=["#123456"], styles=[dash])
    assert plot.values.shape == (20, 1) and plot.n_frames == 30  # the last frame + 1
    assert plot.colour_of(0).name() == "#123456"
    assert plot._items[0].opts["pen"].style() == dash
    plot.set_curves(np.zeros(0, np.int64), [], np.zeros((0, 0)))
    assert plot.n_frames == 0 and plot._items == []


def test_spans_are_shaded_regions_in_frames_or_seconds_and_cleared(qtbot):
    plot = make_plot(qtbot)
    plot.set_spans(np.array([[10, 20], [50, 55]]))
    assert [item.getRegion() for item in plot._spans] == [(10.0, 20.0), (50.0, 55.0)]
    assert all(not item.movable and item.zValue() == -5 for item in plot._spans)
    assert plot._spans[0].brush.color().getRgb() == SPAN_BRUSH
    held = set(plot.plot_item.items)
    assert all(item in held for item in plot._spans)
    plot.set_x_unit("seconds", 0.5)
    assert [item.getRegion() for item in plot._spans] == [(5.0, 10.0), (25.0, 27.5)]
    old = plot._spans
    plot.set_spans(np.zeros((0, 2)))
    assert plot._spans == [] and not any(item in set(plot.plot_item.items) for item in old)


# ---------------------------------------------------------------------- x unit, scale
def test_seconds_scale_the_curves_cursor_range_and_view(qtbot):
    plot = make_plot(qtbot)
    plot.set_cursor(40)
    plot.set_range(10, 20)
    plot.view_box.setXRange(20, 120, padding=0)
    plot.set_x_unit("seconds", 0.01)
    assert plot.scale == 0.01 and plot.x_unit == "seconds" and plot.frame_time == 0.01
    np.testing.assert_allclose(plot._items[0].getOriginalDataset()[0], np.arange(200) * 0.01)
    assert plot.cursor.value() == pytest.approx(0.40)
    np.testing.assert_allclose(plot.region.getRegion(), (0.095, 0.195))
    np.testing.assert_allclose(plot.view_box.viewRange()[0], (0.20, 1.20), rtol=1e-6)
    assert plot.plot_item.getAxis("bottom").labelText == "time (s)"
    assert plot.frame_at_x(0.404) == 40
    plot.set_x_unit("frames", 0.01)
    assert plot.scale == 1.0 and plot.cursor.value() == pytest.approx(40)
    np.testing.assert_allclose(plot.view_box.viewRange()[0], (20, 120), rtol=1e-6)
    with pytest.raises(ValueError, match="x unit must be 'frames' or 'seconds', not 'ms'"):
        plot.set_x_unit("ms", 0.001)


# ------------------------------------------------------------------------- autoscale
def test_autoscale_fits_every_frame_and_finite_value_with_a_margin(qtbot):
    plot = make_plot(qtbot, n_frames=100, first=10)
    plot.values[5, 0] = np.nan
    plot.autoscale()
    (x0, x1), (y0, y1) = plot.view_box.viewRange()
    assert (x0, x1) == pytest.approx((10, 109))
    finite = plot.values[np.isfinite(plot.values)]
    low, high = finite.min(), finite.max()
    assert (y0, y1) == pytest.approx((low - 0.05 * (high - low), high + 0.05 * (high - low)))


@pytest.mark.parametrize(
    ("values", "expected"),
    [(np.full((3, 1), 4.0), (3.8, 4.2)), (np.full((3, 1), 0.5), (0.45, 0.55)), (np.full((3, 1), np.nan), (-1.1, 1.1))],
)
def test_autoscale_of_flat_or_empty_curves_keeps_a_margin(qtbot, values, expected):
    plot = make_plot(qtbot)
    plot.set_curves(np.array([7]), ["a"], values[:1], "")
    plot.autoscale()
    (x0, x1), (y0, y1) = plot.view_box.viewRange()
    assert (x0, x1) == pytest.approx((7, 8))  # one frame: a frame wide
    assert (y0, y1) == pytest.approx(expected)  # 5% of the value (at least of 1); no value: -1..1


def test_autoscale_without_curves_leaves_the_view(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.setRange(xRange=(3, 4), yRange=(5, 6), padding=0)
    plot.set_curves(np.zeros(0, np.int64), [], np.zeros((0, 0)))
    plot.autoscale()
    assert plot.view_box.viewRange() == [[3.0, 4.0], [5.0, 6.0]]


# ------------------------------------------------------------------- cursor, seeking
def test_the_cursor_goes_to_its_frame_before_the_plot_is_laid_out_and_on_a_new_view(qtbot):
    plot = TimePlot()
    qtbot.addWidget(plot)
    plot.set_curves(np.arange(100), ["a"], np.zeros(100))
    plot._pixels_per_x = 0.0
    plot.set_cursor(33)
    assert plot.cursor.value() == 33 and plot.cursor_frame == 33
    plot.resize(600, 240)
    plot.show()
    qtbot.waitExposed(plot)
    plot.view_box.setXRange(0, 100, padding=0)
    QApplication.processEvents()
    assert plot._pixels_per_x == pytest.approx(plot.view_box.width() / 100)
    plot.cursor_frame = 34  # as if set_cursor kept the line within half a pixel
    plot.view_box.setXRange(0, 50, padding=0)  # a new range: the line exactly at its frame
    assert plot.cursor.value() == 34


def test_a_plot_of_no_width_or_range_has_no_pixel_size(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.width = lambda: 0.0
    plot._place_cursor()
    assert plot._pixels_per_x == 0.0
    del plot.view_box.width
    plot.view_box.viewRange = lambda: [[5.0, 5.0], [0.0, 1.0]]
    plot._place_cursor()
    assert plot._pixels_per_x == 0.0


def test_a_frame_is_the_nearest_plotted_one(qtbot):
    plot = make_plot(qtbot)
    assert [plot.frame_at_x(x) for x in (-3.0, 0.0, 0.49, 0.51, 10.5, 11.5, 198.6, 250.0)] == [
        0,
        0,
        0,
        1,
        10,
        12,
        199,
        199,
    ]
    plot.set_curves(np.zeros(0, np.int64), [], np.zeros((0, 0)))
    assert plot.frame_at_x(5.0) == 0


def test_clicking_or_dragging_in_the_plot_asks_for_the_frame_under_the_pointer(qtbot):
    plot = make_plot(qtbot)
    asked = signals(plot.frame_requested)
    click = FakeMouse(plot, 42.2)
    plot.view_box.mouseClickEvent(click)
    assert click.accepted and asked == [(42,)] and plot.cursor_frame == 42
    plot.view_box.mouseDragEvent(FakeMouse(plot, 77.8))
    assert asked[-1] == (78,) and plot.cursor_frame == 78
    plot.cursor.sigDragged.emit(plot.cursor)  # the cursor line dragged: seeks where it is
    assert asked[-1] == (78,)
    right = FakeMouse(plot, 10.0, button=RIGHT)
    plot.view_box.mouseClickEvent(right)
    assert len(asked) == 3  # the right button is pyqtgraph's (its menu, off here): no seek


# ----------------------------------------------------------------------------- ranges
def test_a_range_is_shown_only_when_it_holds_a_frame_and_sends_nothing(qtbot):
    plot = make_plot(qtbot)
    sent = signals(plot.range_selected)
    plot.set_range(10, 20)
    assert plot.range == (10, 20) and plot.region.isVisible()
    assert plot.region.getRegion() == (9.5, 19.5)
    plot.set_range(0, 1)
    assert plot.region.getRegion() == (-0.5, 0.5)
    for start, stop in ((-1, 5), (5, 5), (6, 5)):
        plot.set_range(start, stop)
        assert plot.range is None and not plot.region.isVisible()
    assert sent == []


def test_shift_dragging_selects_the_frames_between_both_ends_sent_when_done(qtbot):
    plot = make_plot(qtbot)
    sent = signals(plot.range_selected)
    plot.view_box.mouseDragEvent(FakeMouse(plot, 30.4, shift=True, down_x=60.2, finish=False))
    assert plot.range == (30, 61) and plot.region.getRegion() == (29.5, 60.5) and sent == []
    plot.view_box.mouseDragEvent(FakeMouse(plot, 70.0, shift=True, down_x=60.2, finish=True))
    assert sent == [(60, 71)]
    plot.view_box.mouseDragEvent(FakeMouse(plot, 5.0, shift=True, down_x=5.2, finish=True))
    assert sent[-1] == (5, 6)  # one frame at least


def test_moving_the_ranges_region_selects_the_frames_inside_it(qtbot):
    plot = make_plot(qtbot)
    plot.set_range(10, 20)
    sent = signals(plot.range_selected)
    plot.region.setRegion((29.6, 40.4))  # as a drag of the region leaves it
    assert sent == [(30, 41)] and plot.range == (30, 41)
    assert plot.region.getRegion() == (29.5, 40.5)  # snapped to the frames' edges
    plot.set_x_unit("seconds", 0.1)
    plot.region.setRegion((0.95, 1.95))
    assert sent[-1] == (10, 20) and len(sent) == 2


# ------------------------------------------------------------------------------ export
def test_what_is_visible_is_exported_as_csv_with_gaps_empty(qtbot, tmp_path):
    plot = make_plot(qtbot)
    plot.values[12, 1] = np.nan
    plot.frame_time = 0.25
    plot.view_box.setXRange(10, 13, padding=0)
    np.testing.assert_array_equal(plot.visible_frames(), [10, 11, 12, 13])
    lines = plot.csv_text().splitlines()
    assert lines[0] == "frame,time,a,b"
    assert [line.split(",")[:2] for line in lines[1:]] == [["10", "2.5"], ["11", "2.75"], ["12", "3"], ["13", "3.25"]]
    assert lines[3].split(",")[3] == "" and lines[3].split(",")[2] == f"{np.sin(0.6):.10g}"
    plot.export_csv(tmp_path / "curves.csv")
    assert (tmp_path / "curves.csv").read_text() == plot.csv_text()
    plot.export_png(tmp_path / "curves.png")
    data = (tmp_path / "curves.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    image = QImage.fromData(data)
    assert (image.width(), image.height()) == (plot.plot_widget.width(), plot.plot_widget.height())


def test_the_visible_frames_are_taken_in_the_plots_unit(qtbot):
    plot = make_plot(qtbot)
    plot.set_x_unit("seconds", 0.5)
    plot.view_box.setXRange(5.0, 6.0, padding=0)
    np.testing.assert_array_equal(plot.visible_frames(), [10, 11, 12])


# ----------------------------------------------------------- what the first run let through
BACKGROUND = (0x1E, 0x1F, 0x22)  # the plot's background


def blended(under: tuple[int, int, int], rgba: tuple[int, int, int, int]) -> np.ndarray:
    """(3,) the pixel Qt paints for ``rgba`` over an opaque ``under``."""
    image = QImage(1, 1, QImage.Format.Format_ARGB32_Premultiplied)
    image.fill(QColor(*under))
    painter = QPainter(image)
    painter.fillRect(0, 0, 1, 1, QColor(*rgba))
    painter.end()
    colour = image.pixelColor(0, 0)
    return np.array([colour.red(), colour.green(), colour.blue()])


def plot_pixels(plot: TimePlot) -> np.ndarray:
    QApplication.processEvents()
    return image_pixels(plot.plot_widget.grab().toImage()).astype(int)[..., :3]


def shaded_background(plot: TimePlot, plain: np.ndarray, shaded: np.ndarray, columns: slice) -> np.ndarray:
    """The shaded picture's pixels in ``columns`` of the view box where the plain one shows
    the background (not a grid line, a curve or an axis)."""
    box = plot.view_box.mapRectToScene(plot.view_box.boundingRect())
    top, bottom = plot.plot_widget.mapFromScene(box.topLeft()).y(), plot.plot_widget.mapFromScene(box.bottomRight()).y()
    rows = slice(top + 2, bottom - 2)
    where = (plain[rows, columns] == BACKGROUND).all(axis=-1)
    return shaded[rows, columns][where]


def test_the_plot_as_built(qtbot):
    plot = make_plot(qtbot)
    assert plot.plot_item.getAxis("bottom").grid == 63 and plot.plot_item.getAxis("left").grid == 63  # alpha 0.25
    assert plot.cursor.movable and plot.region.movable
    assert plot.cursor.pen.widthF() == 1.5 and plot.cursor.hoverPen.widthF() == 3.0
    assert (plot.cursor.zValue(), plot.region.zValue()) == (10, 5)  # cursor over range over curves (0)
    assert plot.legend.opts["offset"] == (8, 8)
    assert plot.plot_widget.geometry() == plot.rect()  # no margins round the plot
    for item in plot._items:
        assert item.opts["pen"].widthF() == 1.2
        assert item.opts["autoDownsample"] and item.opts["downsampleMethod"] == "peak"
        assert item.opts["clipToView"]


def test_cursor_range_and_spans_never_widen_the_view(qtbot):
    plot = make_plot(qtbot)
    plot.set_cursor(5000)
    plot.set_range(3000, 4000)
    plot.set_spans(np.array([[6000, 7000]]))
    plot.view_box.autoRange(padding=0)
    (x0, x1), _ = plot.view_box.viewRange()
    assert -2 < x0 < 2 and 197 < x1 < 201  # the curves' frames (and their pens), nothing beyond


def test_setting_the_cursor_sends_no_signal_of_the_line(qtbot):
    plot = make_plot(qtbot)
    moved = signals(plot.cursor.sigPositionChanged)
    plot.set_cursor(120)
    plot.view_box.setXRange(0, 150, padding=0)
    assert moved == [] and plot.cursor.value() == 120


def test_a_fresh_plot(qtbot):
    """Before any curves: no rows, frames of one second, the cursor at frame 0, no spans."""
    plot = TimePlot()
    qtbot.addWidget(plot)
    assert plot.csv_text() == "frame,time\n"
    plot.view_box.setRange(xRange=(3, 4), yRange=(5, 6), padding=0)
    plot.autoscale()
    assert plot.view_box.viewRange() == [[3.0, 4.0], [5.0, 6.0]]
    plot.set_x_unit("seconds", 0.5)
    assert plot._spans == [] and plot.cursor.value() == 0 and plot.cursor_frame == 0
    fresh = TimePlot()
    qtbot.addWidget(fresh)
    fresh.set_curves(np.arange(3), ["a"], np.zeros(3))
    fresh.view_box.setXRange(0, 2, padding=0)
    assert [line.split(",")[:2] for line in fresh.csv_text().splitlines()[1:]] == [["0", "0"], ["1", "1"], ["2", "2"]]
    unlaid = TimePlot()
    qtbot.addWidget(unlaid)
    unlaid.set_cursor(3)  # not laid out: the line goes to its frame
    assert unlaid.cursor.value() == 3


def test_a_view_one_pixel_wide_has_its_pixel_size(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.width = lambda: 1.0
    plot.view_box.setXRange(0, 4, padding=0)
    assert plot._pixels_per_x == pytest.approx(0.25)


def test_in_seconds_autoscale_and_the_cursor_are_in_seconds(qtbot):
    plot = make_plot(qtbot, n_frames=100, first=10)
    plot.set_x_unit("seconds", 0.5)
    plot.autoscale()
    assert plot.view_box.viewRange()[0] == pytest.approx([5.0, 54.5])
    plot.set_cursor(60)
    assert plot.cursor.value() == pytest.approx(30.0)


def test_the_range_and_the_spans_are_shaded_in_their_colours(qtbot):
    """Over the plot's background the range is the cursor's yellow at alpha 40 and a span
    (a marker's gap) red at alpha 50: each pixel as Qt blends them."""
    plot = make_plot(qtbot)
    plot.view_box.setRange(xRange=(0, 199), yRange=(-5, 5), padding=0)
    plot.cursor.hide()
    plain = plot_pixels(plot)
    plot.set_range(40, 80)
    plot.set_spans(np.array([[120, 160]]))
    shaded = plot_pixels(plot)
    x = [round(plot.view_box.mapViewToDevice(QPointF(f, 0)).x()) for f in (40, 79, 120, 159)]
    assert QColor(255, 212, 0).name() == "#ffd400" and RANGE_BRUSH[:3] == (255, 212, 0)
    in_range = shaded_background(plot, plain, shaded, slice(x[0] + 2, x[1] - 2))
    in_span = shaded_background(plot, plain, shaded, slice(x[2] + 2, x[3] - 2))
    assert len(in_range) > 100 and len(in_span) > 100
    assert (in_range == blended(BACKGROUND, (255, 212, 0, 40))).all()
    assert (in_span == blended(BACKGROUND, (200, 60, 60, 50))).all()


def test_the_legend_is_a_dark_box_over_the_plot(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.setRange(xRange=(0, 199), yRange=(-50, 50), padding=0)  # curves far below the box
    pixels = plot_pixels(plot)
    box = plot.legend.mapRectToScene(plot.legend.boundingRect())
    top_left = plot.plot_widget.mapFromScene(box.topLeft())
    bottom_right = plot.plot_widget.mapFromScene(box.bottomRight())
    inside = pixels[top_left.y() + 2 : bottom_right.y() - 2, top_left.x() + 2 : bottom_right.x() - 2].reshape(-1, 3)
    colours, counts = np.unique(inside, axis=0, return_counts=True)
    assert counts.max() > inside.shape[0] / 2  # mostly the box over the background (text, grid elsewhere)
    np.testing.assert_array_equal(colours[counts.argmax()], blended(BACKGROUND, (20, 21, 24, 210)))


def test_the_cursor_moves_at_exactly_half_a_pixel(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.width = lambda: 100.0
    plot.view_box.setXRange(0, 200, padding=0)  # half a pixel a frame
    assert plot._pixels_per_x == 0.5
    plot.set_cursor(50)
    plot.set_cursor(51)  # half a pixel away: moved
    assert plot.cursor.value() == 51


def test_a_plot_in_seconds_before_its_first_layout_moves_the_cursor_to_its_frame(qtbot):
    plot = TimePlot()
    qtbot.addWidget(plot)
    plot.set_x_unit("seconds", 0.01)
    plot.set_cursor(1)
    assert plot.cursor.value() == pytest.approx(0.01)
