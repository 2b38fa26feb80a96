"""The time plot on its own (app/docks/timeplot.py, the Curves and Error docks' plot): curves in
their colours and styles, shaded spans, frames or seconds, autoscale, the cursor drawn within
half a pixel of its frame, clicking and dragging to seek, ranges (set, Shift-dragged, the
region moved), what is visible as CSV and PNG, and the shading as it looks. A bare widget on a
small synthetic table, driven by real mouse events: no window, no take."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPointF, Qt
from PyQt6.QtGui import QColor, QImage, QMouseEvent
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.docks.timeplot import LEGEND_BOX, PALETTE, RANGE_BRUSH, SPAN_BRUSH, TimePlot
from gmr_studio.app.media.video import image_pixels

pytestmark = pytest.mark.gui
LEFT, RIGHT, NO_BUTTON = Qt.MouseButton.LeftButton, Qt.MouseButton.RightButton, Qt.MouseButton.NoButton
SHIFT, NONE = Qt.KeyboardModifier.ShiftModifier, Qt.KeyboardModifier.NoModifier
BACKGROUND = (0x1E, 0x1F, 0x22)  # the plot's background
TOLERANCE = 3  # per channel: Qt's blending rounds


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


def long_plot(qtbot, frames: int = 3000) -> TimePlot:
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


def signals(signal) -> list:
    seen = []
    signal.connect(lambda *args: seen.append(args))
    return seen


def curves(plot: TimePlot) -> list:
    return plot.plot_item.listDataItems()


def device_x(plot: TimePlot, x: float) -> float:
    """Where ``x`` (in the plot's unit) is drawn, in the widget's pixels."""
    return plot.view_box.mapViewToDevice(QPointF(x, 0)).x()


def send(plot: TimePlot, kind: QEvent.Type, x: float, button=LEFT, modifiers=NONE) -> None:
    """A mouse event over ``x`` (in the plot's unit), half way up the plot."""
    QApplication.processEvents()  # the plot laid out as it will be when the event arrives
    viewport = plot.plot_widget.viewport()
    low, high = plot.view_box.viewRange()[1]
    point = plot.plot_widget.mapFromScene(plot.view_box.mapViewToScene(QPointF(x, (low + high) / 2)))
    held = NO_BUTTON if kind == QEvent.Type.MouseButtonRelease else button
    pressed = NO_BUTTON if kind == QEvent.Type.MouseMove else button
    event = QMouseEvent(kind, QPointF(point), QPointF(viewport.mapToGlobal(point)), pressed, held, modifiers)
    QApplication.sendEvent(viewport, event)
    QApplication.processEvents()


def drag(plot: TimePlot, xs, modifiers=NONE, release: bool = True) -> None:
    send(plot, QEvent.Type.MouseButtonPress, xs[0], modifiers=modifiers)
    for x in xs[1:]:
        send(plot, QEvent.Type.MouseMove, x, modifiers=modifiers)
    if release:
        send(plot, QEvent.Type.MouseButtonRelease, xs[-1], modifiers=modifiers)


def click(plot: TimePlot, x: float, button=LEFT) -> None:
    send(plot, QEvent.Type.MouseButtonPress, x, button)
    send(plot, QEvent.Type.MouseButtonRelease, x, button)


# ----------------------------------------------------------------------------- curves
def test_curves_are_plotted_one_a_column_in_the_palettes_colours(qtbot):
    plot = make_plot(qtbot)
    assert plot.n_frames == 200 and plot.columns == ("a", "b") and plot.values.shape == (200, 2)
    assert [item.name() for item in curves(plot)] == ["a", "b"]
    assert [plot.colour_of(c).name() for c in range(2)] == [QColor(PALETTE[0]).name(), QColor(PALETTE[1]).name()]
    x, y = curves(plot)[1].getOriginalDataset()
    np.testing.assert_array_equal(x, np.arange(200))
    np.testing.assert_allclose(y, 2.0 + np.cos(np.arange(200) / 30.0))
    assert all(item.opts["pen"].style() == Qt.PenStyle.SolidLine for item in curves(plot))
    assert plot.plot_item.getAxis("left").labelText == "cm"
    assert plot.plot_item.getAxis("bottom").labelText == "frame"


def test_new_curves_replace_the_old_and_colours_wrap_around_the_palette(qtbot):
    plot = make_plot(qtbot)
    n = len(PALETTE) + 2
    frames = np.arange(50)
    plot.set_curves(frames, [f"c{k}" for k in range(n)], np.ones((50, n)), "deg")
    assert len(curves(plot)) == n
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
    assert curves(plot)[0].opts["pen"].style() == dash
    plot.set_curves(np.zeros(0, np.int64), [], np.zeros((0, 0)))
    assert plot.n_frames == 0 and curves(plot) == []


def test_the_plot_fills_its_widget_the_cursor_over_the_range_over_the_curves(qtbot):
    plot = make_plot(qtbot)
    assert plot.plot_widget.geometry() == plot.rect()  # no margins round the plot
    assert plot.cursor.movable and plot.region.movable
    assert plot.cursor.zValue() > plot.region.zValue() > max(item.zValue() for item in curves(plot))


# ------------------------------------------------------------------------------ spans
def test_spans_are_the_frame_ranges_given_in_frames_or_seconds_and_cleared(qtbot):
    plot = make_plot(qtbot)
    plot.set_spans(np.array([[10, 20], [50, 55]]))
    np.testing.assert_array_equal(plot.spans, [[10, 20], [50, 55]])
    plot.set_x_unit("seconds", 0.5)
    np.testing.assert_array_equal(plot.spans, [[10, 20], [50, 55]])  # frames, whatever the unit
    plot.set_spans(np.zeros((0, 2)))
    assert plot.spans.shape == (0, 2)


def plot_pixels(plot: TimePlot) -> np.ndarray:
    QApplication.processEvents()
    return image_pixels(plot.plot_widget.grab().toImage()).astype(int)[..., :3]


def over_background(rgba) -> np.ndarray:
    """(3,) ``rgba`` (alpha 0-255) blended over the plot's background."""
    alpha = rgba[3] / 255
    return np.asarray(BACKGROUND) + (np.asarray(rgba[:3]) - np.asarray(BACKGROUND)) * alpha


def background_columns(plot: TimePlot, plain: np.ndarray, shaded: np.ndarray, first: float, last: float):
    """The shaded picture's pixels between frames ``first`` and ``last`` where the plain one
    shows the background (not a grid line, a curve or an axis)."""
    box = plot.view_box.mapRectToScene(plot.view_box.boundingRect())
    top, bottom = plot.plot_widget.mapFromScene(box.topLeft()).y(), plot.plot_widget.mapFromScene(box.bottomRight()).y()
    rows = slice(top + 2, bottom - 2)
    columns = slice(round(device_x(plot, first)) + 2, round(device_x(plot, last)) - 2)
    where = (plain[rows, columns] == BACKGROUND).all(axis=-1)
    return shaded[rows, columns][where]


def test_the_range_is_shaded_yellow_and_the_spans_red_over_their_frames_only(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.setRange(xRange=(0, 199), yRange=(-5, 5), padding=0)
    plot.cursor.hide()
    plain = plot_pixels(plot)
    plot.set_range(40, 80)
    plot.set_spans(np.array([[120, 160]]))

    def shades_drawn() -> bool:  # the scene lays the new items out when it next paints
        picture = plot_pixels(plot)
        return all(
            (background_columns(plot, plain, picture, a, b) != BACKGROUND).any() for a, b in ((40, 79), (120, 159))
        )

    qtbot.waitUntil(shades_drawn)
    shaded = plot_pixels(plot)
    in_range = background_columns(plot, plain, shaded, 40, 79)
    in_span = background_columns(plot, plain, shaded, 120, 159)
    between = background_columns(plot, plain, shaded, 85, 115)
    assert len(in_range) > 100 and len(in_span) > 100 and len(between) > 100
    assert np.abs(in_range - over_background(RANGE_BRUSH)).max() <= TOLERANCE
    assert np.abs(in_span - over_background(SPAN_BRUSH)).max() <= TOLERANCE
    assert (between == BACKGROUND).all()
    assert RANGE_BRUSH[:3] == (255, 212, 0) and SPAN_BRUSH[0] > 2 * max(SPAN_BRUSH[1:3])  # yellow; red


def test_the_legend_is_a_dark_box_over_the_plot(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.setRange(xRange=(0, 199), yRange=(-50, 50), padding=0)  # curves far below the box
    pixels = plot_pixels(plot)
    box = plot.legend.mapRectToScene(plot.legend.boundingRect())
    top_left = plot.plot_widget.mapFromScene(box.topLeft())
    bottom_right = plot.plot_widget.mapFromScene(box.bottomRight())
    assert top_left.x() < plot.width() / 4 and top_left.y() < 40  # at the top left
    inside = pixels[top_left.y() + 2 : bottom_right.y() - 2, top_left.x() + 2 : bottom_right.x() - 2].reshape(-1, 3)
    colours, counts = np.unique(inside, axis=0, return_counts=True)
    assert counts.max() > inside.shape[0] / 2  # mostly the box over the background (text, grid elsewhere)
    assert np.abs(colours[counts.argmax()] - over_background(LEGEND_BOX)).max() <= TOLERANCE
    assert colours[counts.argmax()].sum() < sum(BACKGROUND)  # darker than the plot


# ---------------------------------------------------------------------- x unit, scale
def test_seconds_scale_the_curves_cursor_range_and_view(qtbot):
    plot = make_plot(qtbot)
    plot.set_cursor(40)
    plot.set_range(10, 20)
    plot.view_box.setXRange(20, 120, padding=0)
    plot.set_x_unit("seconds", 0.01)
    assert plot.scale == 0.01 and plot.x_unit == "seconds" and plot.frame_time == 0.01
    np.testing.assert_allclose(curves(plot)[0].getOriginalDataset()[0], np.arange(200) * 0.01)
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


def test_in_seconds_autoscale_and_the_cursor_are_in_seconds(qtbot):
    plot = make_plot(qtbot, n_frames=100, first=10)
    plot.set_x_unit("seconds", 0.5)
    plot.autoscale()
    assert plot.view_box.viewRange()[0] == pytest.approx([5.0, 54.5])
    plot.set_cursor(60)
    assert plot.cursor.value() == pytest.approx(30.0)


# ------------------------------------------------------------------------- autoscale
def test_autoscale_fits_every_frame_and_finite_value_with_a_margin(qtbot):
    plot = make_plot(qtbot, n_frames=100, first=10)
    plot.values[5, 0] = np.nan
    plot.autoscale()
    (x0, x1), (y0, y1) = plot.view_box.viewRange()
    assert (x0, x1) == pytest.approx((10, 109))
    finite = plot.values[np.isfinite(plot.values)]
    low, high = finite.min(), finite.max()
    assert y0 < low and y1 > high and max(low - y0, y1 - high) < 0.1 * (high - low)  # a small margin


@pytest.mark.parametrize("value", [4.0, 0.5, -3.0, np.nan])
def test_autoscale_of_flat_or_empty_curves_keeps_a_margin(qtbot, value):
    plot = make_plot(qtbot)
    plot.set_curves(np.array([7]), ["a"], np.full((1, 1), value), "")
    plot.autoscale()
    (x0, x1), (y0, y1) = plot.view_box.viewRange()
    assert (x0, x1) == pytest.approx((7, 8))  # one frame: a frame wide
    centre = 0.0 if np.isnan(value) else value  # no value: around 0
    assert y0 < centre < y1 and y1 - y0 < max(abs(centre), 1.0) * 3  # around the value, not lost in a huge range
    assert y1 - centre == pytest.approx(centre - y0)


def test_autoscale_without_curves_leaves_the_view(qtbot):
    plot = make_plot(qtbot)
    plot.view_box.setRange(xRange=(3, 4), yRange=(5, 6), padding=0)
    plot.set_curves(np.zeros(0, np.int64), [], np.zeros((0, 0)))
    plot.autoscale()
    assert plot.view_box.viewRange() == [[3.0, 4.0], [5.0, 6.0]]


def test_cursor_range_and_spans_never_widen_the_view(qtbot):
    plot = make_plot(qtbot)
    plot.set_cursor(5000)
    plot.set_range(3000, 4000)
    plot.set_spans(np.array([[6000, 7000]]))
    plot.view_box.autoRange(padding=0)
    (x0, x1), _ = plot.view_box.viewRange()
    assert -2 < x0 < 2 and 197 < x1 < 201  # the curves' frames (and their pens), nothing beyond


# ------------------------------------------------------------------- cursor, seeking
def test_a_fresh_plot(qtbot):
    """Before any curves: no rows, frames of one second, the cursor at frame 0, no spans."""
    plot = TimePlot()
    qtbot.addWidget(plot)
    assert plot.csv_text() == "frame,time\n"
    plot.view_box.setRange(xRange=(3, 4), yRange=(5, 6), padding=0)
    plot.autoscale()
    assert plot.view_box.viewRange() == [[3.0, 4.0], [5.0, 6.0]]
    plot.set_x_unit("seconds", 0.5)
    assert plot.spans.shape == (0, 2) and plot.cursor.value() == 0 and plot.cursor_frame == 0
    fresh = TimePlot()
    qtbot.addWidget(fresh)
    fresh.set_curves(np.arange(3), ["a"], np.zeros(3))
    fresh.view_box.setXRange(0, 2, padding=0)
    assert [line.split(",")[:2] for line in fresh.csv_text().splitlines()[1:]] == [["0", "0"], ["1", "1"], ["2", "2"]]


def test_the_cursor_goes_to_its_frame_before_the_plot_is_laid_out_and_on_a_new_view(qtbot):
    plot = TimePlot()
    qtbot.addWidget(plot)
    plot.set_curves(np.arange(100), ["a"], np.zeros(100))
    plot.set_cursor(33)  # not laid out: the line goes to its frame
    assert plot.cursor.value() == 33 and plot.cursor_frame == 33
    seconds = TimePlot()
    qtbot.addWidget(seconds)
    seconds.set_x_unit("seconds", 0.01)
    seconds.set_cursor(1)
    assert seconds.cursor.value() == pytest.approx(0.01)
    plot.resize(600, 240)
    plot.show()
    qtbot.waitExposed(plot)
    plot.view_box.setXRange(0, 1000, padding=0)  # about half a pixel a frame
    QApplication.processEvents()
    plot.set_cursor(34)  # within half a pixel: the line may stay
    plot.view_box.setXRange(0, 50, padding=0)  # a new range: the line exactly at its frame
    assert plot.cursor.value() == 34


def test_setting_the_cursor_sends_no_signal_of_the_line(qtbot):
    plot = make_plot(qtbot)
    moved = signals(plot.cursor.sigPositionChanged)
    asked = signals(plot.frame_requested)
    plot.set_cursor(120)
    plot.view_box.setXRange(0, 150, padding=0)
    assert moved == [] and asked == [] and plot.cursor.value() == 120


def test_on_a_long_take_the_cursor_is_drawn_within_half_a_pixel_of_its_frame_on_whole_frames(qtbot):
    plot = long_plot(qtbot)
    per_frame = device_x(plot, 1) - device_x(plot, 0)
    assert 0.1 < per_frame < 0.3  # several frames a pixel
    plot.set_cursor(100)
    places = set()
    for frame in range(101, 131):
        plot.set_cursor(frame)
        assert plot.cursor_frame == frame
        off = abs(device_x(plot, plot.cursor.value()) - device_x(plot, frame))
        assert off < 0.5, (frame, off)  # drawn within half a pixel of its frame
        assert float(plot.cursor.value()).is_integer()  # on a frame, never in between
        places.add(plot.cursor.value())
    assert len(places) > 2  # it moved along


def test_a_zoom_or_a_resize_puts_the_cursor_within_half_a_pixel_of_its_frame(qtbot):
    plot = long_plot(qtbot)
    plot.set_cursor(1000)
    plot.set_cursor(1002)  # within half a pixel: the line may stay on 1000
    plot.view_box.setXRange(990, 1010, padding=0)  # 30 pixels a frame
    QApplication.processEvents()
    assert plot.cursor.value() == pytest.approx(1002)  # exactly on its frame
    plot.set_cursor(1003)  # a frame is many pixels now: every frame moves it
    assert plot.cursor.value() == pytest.approx(1003)
    plot.view_box.setXRange(0, 1400, padding=0)  # about 0.4 pixels a frame
    QApplication.processEvents()
    plot.resize(1800, 240)  # wider: a frame is more than a pixel again
    QApplication.processEvents()
    assert device_x(plot, 1) - device_x(plot, 0) > 1.0
    for frame in (1004, 1005, 1006):
        plot.set_cursor(frame)
        assert abs(device_x(plot, plot.cursor.value()) - device_x(plot, frame)) < 0.5, frame


def test_a_frame_is_the_nearest_plotted_one(qtbot):
    plot = make_plot(qtbot)
    xs = (-3.0, 0.0, 0.49, 0.51, 10.5, 11.5, 198.6, 250.0)
    assert [plot.frame_at_x(x) for x in xs] == [0, 0, 0, 1, 10, 12, 199, 199]
    plot.set_curves(np.zeros(0, np.int64), [], np.zeros((0, 0)))
    assert plot.frame_at_x(5.0) == 0


def test_clicking_or_dragging_in_the_plot_asks_for_the_frame_under_the_pointer(qtbot):
    plot = make_plot(qtbot)
    asked = signals(plot.frame_requested)
    click(plot, 42.2)
    assert asked == [(42,)] and plot.cursor_frame == 42
    drag(plot, [10.0, 30.0, 77.8])
    assert asked[-1] == (78,) and plot.cursor_frame == 78
    plot.cursor.sigDragged.emit(plot.cursor)  # the cursor line dragged: seeks where it is
    assert asked[-1] == (78,)
    count = len(asked)
    click(plot, 10.0, RIGHT)
    assert len(asked) == count  # the right button is pyqtgraph's (its menu, off here): no seek


# ----------------------------------------------------------------------------- ranges
def test_a_range_is_shown_only_when_it_holds_a_frame_and_sends_nothing(qtbot):
    plot = make_plot(qtbot)
    sent = signals(plot.range_selected)
    plot.set_range(10, 20)
    assert plot.range == (10, 20) and plot.region.isVisible()
    assert plot.region.getRegion() == (9.5, 19.5)  # from half a frame before to half after
    plot.set_range(0, 1)
    assert plot.region.getRegion() == (-0.5, 0.5)
    for start, stop in ((-1, 5), (5, 5), (6, 5)):
        plot.set_range(start, stop)
        assert plot.range is None and not plot.region.isVisible()
    assert sent == []


def test_shift_dragging_selects_the_frames_between_both_ends_sent_when_done(qtbot):
    plot = make_plot(qtbot)
    sent = signals(plot.range_selected)
    asked = signals(plot.frame_requested)
    drag(plot, [60.1, 55.0, 45.0, 30.1], SHIFT, release=False)
    assert sent == [] and plot.range is not None and plot.region.isVisible()  # shown while dragging
    send(plot, QEvent.Type.MouseButtonRelease, 30.1, modifiers=SHIFT)
    assert sent == [(30, 61)] and plot.range == (30, 61) and plot.region.getRegion() == (29.5, 60.5)
    assert asked == []  # a range, not a seek
    other = make_plot(qtbot)
    sent = signals(other.range_selected)
    drag(other, [60.1, 65.0, 70.0], SHIFT)  # the other way: the same frames between both ends
    assert sent == [(60, 71)]


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
