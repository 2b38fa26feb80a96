"""The timeline's frame slider on its own (app/docks/range_slider.py): the I/O keys' ranges,
the frame <-> pixel mapping against the style's own handle, the checks' flags as pixel spans
and their tooltip, the range's and the flags' pixels, Shift+drag selecting a range, and the
repaint only when the handle moves. A bare widget: no window, no take."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPoint, QPointF, Qt
from PyQt6.QtGui import QColor, QHelpEvent, QImage, QMouseEvent, QPainter
from PyQt6.QtWidgets import QApplication, QStyle, QToolTip

from gmr_studio.app.docks.range_slider import (
    FLAG_COLOURS,
    FLAG_HEIGHT,
    FLAG_MIN_WIDTH,
    RANGE_COLOUR,
    RANGE_EDGE,
    RangeSlider,
    range_ending_at,
    range_starting_at,
)
from gmr_studio.app.docks.timeplot import CURSOR_COLOUR, RANGE_BRUSH
from gmr_studio.app.media.video import image_pixels

pytestmark = pytest.mark.gui
SHIFT = Qt.KeyboardModifier.ShiftModifier
NONE = Qt.KeyboardModifier.NoModifier
LEFT = Qt.MouseButton.LeftButton


def make_slider(qtbot, minimum: int = 0, maximum: int = 1999, width: int = 600) -> RangeSlider:
    slider = RangeSlider()
    qtbot.addWidget(slider)
    slider.setRange(minimum, maximum)
    slider.resize(width, 24)
    slider.show()
    qtbot.waitExposed(slider)
    return slider


def handle_centre(slider: RangeSlider, value: int) -> float:
    """The x of the style's own handle centre with the slider at ``value``."""
    slider.setValue(value)
    rect = slider._handle()  # the style's own rectangle for the handle there
    return rect.x() + rect.width() / 2


def send_mouse(widget, kind: QEvent.Type, x: float, modifiers=NONE) -> None:
    point = QPointF(x, widget.height() / 2)
    button = LEFT if kind != QEvent.Type.MouseMove else Qt.MouseButton.NoButton
    buttons = Qt.MouseButton.NoButton if kind == QEvent.Type.MouseButtonRelease else LEFT
    event = QMouseEvent(kind, point, QPointF(widget.mapToGlobal(point.toPoint())), button, buttons, modifiers)
    QApplication.sendEvent(widget, event)


# ----------------------------------------------------------------- the I/O keys' ranges
def test_a_range_starting_at_a_frame_keeps_a_stop_after_it_else_runs_to_the_end():
    assert range_starting_at(None, 5, 100) == (5, 100)
    assert range_starting_at((2, 10), 5, 100) == (5, 10)
    assert range_starting_at((2, 6), 5, 100) == (5, 6)  # the stop just after the frame: kept
    assert range_starting_at((2, 5), 5, 100) == (5, 100)  # the stop at the frame: to the end
    assert range_starting_at((2, 3), 5, 100) == (5, 100)


def test_a_range_ending_at_a_frame_includes_it_and_keeps_a_start_not_after_it():
    assert range_ending_at(None, 5) == (0, 6)
    assert range_ending_at((3, 10), 5) == (3, 6)
    assert range_ending_at((5, 10), 5) == (5, 6)  # the start at the frame: kept
    assert range_ending_at((6, 10), 5) == (0, 6)  # the start after it: from frame 0


# ----------------------------------------------------------------------- state setters
def test_a_frame_range_is_shown_only_when_it_holds_a_frame(qtbot):
    slider = make_slider(qtbot)
    slider.set_frame_range(0, 1)
    assert slider.frame_range == (0, 1)
    slider.set_frame_range(3.0, 7.0)
    assert slider.frame_range == (3, 7) and all(isinstance(v, int) for v in slider.frame_range)
    for start, stop in ((-1, 5), (5, 5), (6, 5)):
        slider.set_frame_range(start, stop)
        assert slider.frame_range is None


def test_levels_without_a_flag_are_no_levels(qtbot):
    slider = make_slider(qtbot)
    slider.set_levels(np.zeros(2000, np.int8))
    assert slider.levels is None and slider.flag_spans() == []
    levels = np.zeros(2000, np.int64)
    levels[7] = 2
    slider.set_levels(levels)
    assert slider.levels.dtype == np.int8 and slider.levels[7] == 2
    slider.set_levels(None)
    assert slider.levels is None and slider.flag_spans() == []


# ------------------------------------------------------------------ frames and pixels
@pytest.mark.parametrize(("minimum", "maximum"), [(0, 1999), (10, 110), (0, 7)])
def test_frames_sit_where_the_style_puts_the_handle(qtbot, minimum, maximum):
    slider = make_slider(qtbot, minimum, maximum)
    for value in (minimum, (minimum + maximum) // 2, maximum):
        assert abs(slider.x_of_frame(value) - handle_centre(slider, value)) <= 1.0
    left, length = slider._span()
    assert slider.x_of_frame(minimum) == pytest.approx(left)
    assert slider.x_of_frame(maximum) == pytest.approx(left + length)
    assert slider.x_of_frame(minimum + 0.5) == pytest.approx(left + 0.5 * length / (maximum - minimum))
    for value in range(minimum, maximum + 1, max((maximum - minimum) // 37, 1)):
        assert slider.frame_at(slider.x_of_frame(value)) == value
    assert slider.frame_at(-50) == minimum and slider.frame_at(slider.width() + 50) == maximum


def test_a_slider_of_one_frame_maps_without_dividing_by_zero(qtbot):
    slider = make_slider(qtbot, 4, 4)
    left, length = slider._span()
    assert slider.x_of_frame(4) == pytest.approx(left)
    assert slider.x_of_frame(5) == pytest.approx(left + length)  # one frame counted as one step
    assert slider.frame_at(left) == 4 and slider.frame_at(left + length) == 4


# ----------------------------------------------------------------------------- flags
def expected_span(slider: RangeSlider, first: int, last: int) -> tuple[int, int]:
    """[x0, x1) of frames ``first``..``last`` flagged alone, from x_of_frame."""
    count = max(slider.maximum() - slider.minimum(), 1)
    half = max(slider._span()[1] / count, FLAG_MIN_WIDTH) / 2
    x0 = min(max(math.floor(slider.x_of_frame(first) - half), 0), slider.width())
    x1 = min(max(math.ceil(slider.x_of_frame(last) + half), 0), slider.width())
    return x0, x1


def test_flags_are_pixel_spans_at_least_a_few_pixels_wide_mildest_first(qtbot):
    slider = make_slider(qtbot)  # 2000 frames on about 580 pixels: several frames a pixel
    levels = np.zeros(2000, np.int8)
    levels[1000] = 3  # one frame: FLAG_MIN_WIDTH pixels around it
    levels[100:301] = 1  # a run: one span
    levels[1500] = 2
    levels[1502] = 2  # two frames a pixel apart: one span
    slider.set_levels(levels)
    spans = slider.flag_spans()
    assert spans == [
        (*expected_span(slider, 100, 300), 1),
        (*expected_span(slider, 1500, 1502), 2),
        (*expected_span(slider, 1000, 1000), 3),
    ]
    x0, x1, _ = spans[2]
    assert FLAG_MIN_WIDTH <= x1 - x0 <= FLAG_MIN_WIDTH + 1
    assert x0 < slider.x_of_frame(1000) < x1


def test_flags_far_apart_are_spans_of_their_own_and_stay_inside_the_widget(qtbot):
    slider = make_slider(qtbot, 0, 99, width=300)  # about 3 pixels a frame
    levels = np.zeros(100, np.int8)
    levels[[0, 50, 99]] = 2
    slider.set_levels(levels)
    spans = slider.flag_spans()
    assert [level for *_, level in spans] == [2, 2, 2]
    assert spans == [(*expected_span(slider, f, f), 2) for f in (0, 50, 99)]
    assert spans[0][0] >= 0 and spans[-1][1] <= slider.width()


def test_flags_at_the_very_edges_are_clipped_to_the_widget(qtbot):
    slider = make_slider(qtbot, 0, 2, width=200)  # half a frame is wider than the handle's margin
    slider.set_levels(np.array([3, 0, 3], np.int8))
    spans = slider.flag_spans()
    assert spans[0][0] == 0 and spans[-1][1] == slider.width()
    assert slider.x_of_frame(0) - slider._span()[1] / 4 < 0  # clipped, not merely close
    assert spans == [(*expected_span(slider, f, f), 3) for f in (0, 2)]


def test_flag_spans_are_measured_once_per_geometry(qtbot):
    slider = make_slider(qtbot)
    levels = np.zeros(2000, np.int8)
    levels[1000] = 3
    slider.set_levels(levels)
    spans = slider.flag_spans()
    assert slider.flag_spans() is spans  # painted at every frame: kept
    slider.resize(300, 24)
    QApplication.processEvents()
    resized = slider.flag_spans()
    assert resized is not spans and resized == [(*expected_span(slider, 1000, 1000), 3)]
    slider.setRange(0, 999)
    assert slider.flag_spans() == [(*expected_span(slider, 1000, 1000), 3)]
    slider.setRange(500, 1999)
    assert slider.flag_spans() == [(*expected_span(slider, 1000, 1000), 3)]
    levels[1000] = 1
    slider.set_levels(levels)  # new levels: measured again
    assert [level for *_, level in slider.flag_spans()] == [1]


def test_the_tooltip_over_a_flag_names_the_frames_around_it(qtbot, monkeypatch):
    slider = make_slider(qtbot)
    levels = np.zeros(2000, np.int8)
    levels[1000] = 2
    slider.set_levels(levels)
    x = slider.x_of_frame(1000)
    assert slider.flag_text_at(x) == ""  # no text given: nothing to say
    asked = []
    slider.flag_text = lambda first, last: asked.append((first, last)) or f"frames {first}-{last}"
    half = FLAG_MIN_WIDTH / 2 + 0.5
    assert slider.flag_text_at(x) == f"frames {slider.frame_at(x - half)}-{slider.frame_at(x + half)}"
    assert asked == [(slider.frame_at(x - 2.0), slider.frame_at(x + 2.0))]
    x0, x1, _ = slider.flag_spans()[0]
    assert slider.flag_text_at(x0) != "" and slider.flag_text_at(x1 - 1) != ""
    assert slider.flag_text_at(x0 - 1) == "" and slider.flag_text_at(x1) == ""
    slider.set_levels(None)
    assert slider.flag_text_at(x) == ""

    shown = []
    monkeypatch.setattr(QToolTip, "showText", lambda *args: shown.append(args[1]))
    slider.set_levels(levels)
    over = QHelpEvent(QEvent.Type.ToolTip, QPoint(round(x), 5), slider.mapToGlobal(QPoint(round(x), 5)))
    assert slider.event(over) is True and shown == [slider.flag_text_at(round(x))]
    away = QHelpEvent(QEvent.Type.ToolTip, QPoint(20, 5), slider.mapToGlobal(QPoint(20, 5)))
    slider.event(away)
    assert len(shown) == 1  # elsewhere: the slider's own tooltip, not a flag's


# ---------------------------------------------------------------------------- pixels
def test_the_flags_are_painted_in_their_colours_in_a_band_at_the_bottom(qtbot):
    slider = make_slider(qtbot)
    slider.setValue(0)
    levels = np.zeros(2000, np.int8)
    levels[1000] = 3
    levels[1400:1600] = 1
    slider.set_levels(levels)
    slider.repaint()
    pixels = image_pixels(slider.grab().toImage()).astype(int)
    top = slider.height() - FLAG_HEIGHT - 1
    for x0, x1, level in slider.flag_spans():
        colour = FLAG_COLOURS[level]
        want = np.array([colour.red(), colour.green(), colour.blue()])
        band = pixels[top : top + FLAG_HEIGHT, x0:x1, :3]
        assert np.abs(band - want).max() <= 1, level
        assert np.abs(pixels[top - 1, x0:x1, :3] - want).max(axis=-1).min() > 1  # the band's top
        assert np.abs(pixels[top + FLAG_HEIGHT, x0:x1, :3] - want).max(axis=-1).min() > 1  # and bottom
    x0, x1, _ = slider.flag_spans()[-1]
    assert np.abs(pixels[top : top + FLAG_HEIGHT, x1 + 2, :3] - want).max() > 1  # nothing beside it


def test_the_range_is_shaded_between_its_edges(qtbot):
    slider = make_slider(qtbot, 0, 99, width=500)
    slider.setValue(99)
    plain = image_pixels(slider.grab().toImage()).astype(int)
    slider.set_frame_range(20, 40)
    slider.repaint()
    pixels = image_pixels(slider.grab().toImage()).astype(int)
    left, right = slider.x_of_frame(19.5), slider.x_of_frame(39.5)
    changed = np.flatnonzero(np.abs(pixels - plain)[1:-1, :, :3].max(axis=(0, 2)) > 2)
    assert abs(changed.min() - left) <= 1 and abs(changed.max() - right) <= 1
    edge = np.array([RANGE_EDGE.red(), RANGE_EDGE.green(), RANGE_EDGE.blue()])
    assert np.abs(pixels[2:-2, int(left), :3] - edge).max() <= 1  # the edges' lines
    row = slider.height() // 2 - 6
    inside = pixels[row, int(left) + 3 : int(right) - 2, :3]
    assert (inside[:, 2] < plain[row, int(left) + 3 : int(right) - 2, 2]).all()  # tinted yellow
    slider.set_frame_range(50, 51)  # one frame: still at least 2 pixels wide
    slider.repaint()
    one = image_pixels(slider.grab().toImage()).astype(int)
    changed = np.flatnonzero(np.abs(one - plain)[1:-1, :, :3].max(axis=(0, 2)) > 2)
    assert 2 <= changed.max() - changed.min() + 1 <= 7


# ----------------------------------------------------------------------------- mouse
def test_shift_dragging_selects_the_frames_under_the_pointer(qtbot):
    slider = make_slider(qtbot, 0, 99, width=500)
    slider.setValue(10)
    selected = []
    slider.range_selected.connect(lambda start, stop: selected.append((start, stop)))
    send_mouse(slider, QEvent.Type.MouseButtonPress, slider.x_of_frame(60), SHIFT)
    assert selected == [(60, 61)] and slider.value() == 10
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(70), SHIFT)
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(40), SHIFT)
    assert selected[1:] == [(60, 71), (40, 61)]
    send_mouse(slider, QEvent.Type.MouseButtonRelease, slider.x_of_frame(40), SHIFT)
    assert slider._anchor is None and slider.value() == 10
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(80), NONE)
    assert len(selected) == 3  # released: a move selects nothing


def test_a_plain_click_moves_the_frame_and_selects_nothing(qtbot):
    slider = make_slider(qtbot, 0, 99, width=500)
    slider.setValue(10)
    selected = []
    slider.range_selected.connect(lambda start, stop: selected.append((start, stop)))
    send_mouse(slider, QEvent.Type.MouseButtonPress, slider.x_of_frame(10), NONE)  # on the handle
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(30), NONE)
    send_mouse(slider, QEvent.Type.MouseButtonRelease, slider.x_of_frame(30), NONE)
    assert selected == [] and slider._anchor is None
    assert abs(slider.value() - 30) <= 1  # the handle dragged as in any slider


# ---------------------------------------------------------------------------- repaints
def test_a_new_range_or_levels_repaint_even_when_the_handle_stays(qtbot):
    slider = make_slider(qtbot)
    QApplication.processEvents()
    paints = []
    paint = slider.paintEvent

    def noted(event) -> None:
        paints.append(1)
        paint(event)

    slider.paintEvent = noted

    def painted(count: int) -> None:
        # Qt may hold an update back while the window's last flush is pending (a loaded
        # machine): wait for the paint, then make sure no second one follows
        qtbot.waitUntil(lambda: len(paints) >= count, timeout=3000)
        QApplication.processEvents()
        assert len(paints) == count

    slider.set_frame_range(10, 20)
    painted(1)
    levels = np.zeros(2000, np.int8)
    levels[5] = 1
    slider.set_levels(levels)
    painted(2)
    slider.setRange(0, 999)  # not a value change: repainted
    painted(3)


def test_a_new_frame_repaints_the_slider_only_when_its_handle_moves(qtbot):
    """2752 frames on a 600-pixel slider: several frames share the handle's place, and only
    a frame that moves the handle repaints it; what is painted shows the handle at the
    frame's place, as a fresh paint does."""
    slider = RangeSlider()
    qtbot.addWidget(slider)
    slider.setRange(0, 2751)
    slider.resize(600, 24)
    slider.show()
    qtbot.waitExposed(slider)
    slider.setValue(999)
    QApplication.processEvents()
    start = slider._handle().x()
    paints = []
    paint = slider.paintEvent

    def noted(event) -> None:
        paints.append(slider.value())
        paint(event)

    slider.paintEvent = noted
    places = set()
    for frame in range(1000, 1040):
        slider.setValue(frame)
        QApplication.processEvents()
        places.add(slider._handle().x())
        assert slider._painted_handle == slider._handle()  # drawn where the style puts it
    moved = places - {start}
    assert 2 <= len(moved) < 40
    assert len(paints) == len(moved)  # one paint each time the handle moved, none else
    drawn = image_pixels(slider.grab().toImage())
    slider.paintEvent = paint
    slider.repaint()
    assert np.array_equal(drawn, image_pixels(slider.grab().toImage()))


# ----------------------------------------------------------- what the first run let through
def test_the_range_is_the_plots_yellow_its_band_blended_over_the_slider(qtbot):
    """The timeline's range is the yellow of the time plots' cursor and range, its edges
    opaque and its band that yellow at alpha 90 over what the slider draws: every pixel
    inside it is the plain slider's pixel blended by Qt with (255, 212, 0, 90)."""
    assert RANGE_EDGE.getRgb()[:3] == QColor(CURSOR_COLOUR).getRgb()[:3] == RANGE_BRUSH[:3]
    assert RANGE_COLOUR.getRgb()[:3] == RANGE_BRUSH[:3]  # the band too, only more opaque
    slider = make_slider(qtbot, 0, 99, width=500)
    slider.setValue(99)
    plain_image = slider.grab().toImage().convertToFormat(QImage.Format.Format_ARGB32_Premultiplied)
    slider.set_frame_range(20, 40)
    slider.repaint()
    pixels = image_pixels(slider.grab().toImage()).astype(int)
    left, right = int(slider.x_of_frame(19.5)), int(slider.x_of_frame(39.5))
    painter = QPainter(plain_image)
    painter.fillRect(left + 1, 1, right - left - 1, slider.height() - 2, QColor(255, 212, 0, 90))
    painter.end()
    expected = image_pixels(plain_image).astype(int)
    inside = np.s_[1 : slider.height() - 1, left + 1 : right]
    np.testing.assert_array_equal(pixels[inside][..., :3], expected[inside][..., :3])
    assert (pixels[1 : slider.height(), left, :3] == RANGE_EDGE.getRgb()[:3]).all()  # the edge, opaque


def test_a_one_frame_range_is_a_band_two_pixels_wide_between_its_edges(qtbot):
    """2000 frames on 600 pixels: one frame is a third of a pixel, and its band is drawn 2
    pixels wide: an edge, one pixel of band, an edge; the band from row 1 to the row above
    the last, the edges one row lower."""
    slider = make_slider(qtbot)
    slider.setValue(0)
    plain = image_pixels(slider.grab().toImage()).astype(int)
    slider.set_frame_range(1000, 1001)
    slider.repaint()
    pixels = image_pixels(slider.grab().toImage()).astype(int)
    height = slider.height()
    changed = np.abs(pixels - plain)[:, :, :3].max(axis=2) > 0
    x = int(np.floor(slider.x_of_frame(999.5)))
    np.testing.assert_array_equal(np.flatnonzero(changed.any(axis=0)), [x, x + 1, x + 2])
    edge = RANGE_EDGE.getRgb()[:3]
    assert (pixels[1:height, x, :3] == edge).all() and (pixels[1:height, x + 2, :3] == edge).all()
    np.testing.assert_array_equal(np.flatnonzero(changed[:, x + 1]), np.arange(1, height - 1))
    np.testing.assert_array_equal(np.flatnonzero(changed[:, x]), np.arange(1, height))


def test_the_flags_band_is_five_pixels_high_one_above_the_bottom(qtbot):
    slider = make_slider(qtbot)
    slider.setValue(0)
    plain = image_pixels(slider.grab().toImage()).astype(int)
    levels = np.zeros(2000, np.int8)
    levels[1200:1400] = 3
    slider.set_levels(levels)
    slider.repaint()
    pixels = image_pixels(slider.grab().toImage()).astype(int)
    x0, x1, _ = slider.flag_spans()[0]
    changed = np.abs(pixels - plain)[:, (x0 + x1) // 2, :3].max(axis=1) > 0
    height = slider.height()
    np.testing.assert_array_equal(np.flatnonzero(changed), np.arange(height - 6, height - 1))


def test_a_slider_of_two_frames_maps_half_way_between_them(qtbot):
    slider = make_slider(qtbot, 0, 1, width=300)
    left, length = slider._span()
    assert slider.frame_at(left + 0.3 * length) == 0 and slider.frame_at(left + 0.7 * length) == 1
    assert slider.x_of_frame(1) == pytest.approx(left + length)
    slider.set_levels(np.array([0, 2], np.int8))
    assert slider.flag_spans() == [(*expected_span(slider, 1, 1), 2)]
    assert slider.flag_spans()[0][0] >= slider.x_of_frame(0.5)  # about the second frame only


def test_a_flag_on_a_slider_of_one_frame_is_at_the_handle(qtbot):
    slider = make_slider(qtbot, 4, 4, width=200)
    slider.set_levels(np.array([0, 0, 0, 0, 3], np.int8))  # levels by frame number: frame 4 flagged
    ((x0, x1, level),) = slider.flag_spans()
    left, length = slider._span()
    assert level == 3 and (x0, x1) == (max(math.floor(left - length / 2), 0), math.ceil(left + length / 2))
    assert x1 < slider.width()  # one frame counted as one step: half the groove each side


def test_a_slider_narrower_than_its_handle_maps_frames_over_one_pixel(qtbot):
    slider = make_slider(qtbot, 0, 99, width=10)
    option = slider._option()
    style = slider.style()
    groove = style.subControlRect(QStyle.ComplexControl.CC_Slider, option, QStyle.SubControl.SC_SliderGroove, slider)
    handle = style.subControlRect(QStyle.ComplexControl.CC_Slider, option, QStyle.SubControl.SC_SliderHandle, slider)
    assert groove.width() - handle.width() < 1  # no room to slide
    left, length = slider._span()
    assert length == 1 and slider.x_of_frame(99) == pytest.approx(left + 1)
    assert slider.frame_at(left + 1) == 99 and slider.frame_at(left) == 0


def test_only_a_tooltip_over_a_flag_shows_the_flags_findings(qtbot, monkeypatch):
    """A "What's this?" help event is a QHelpEvent too: it is the slider's own, not a flag's."""
    slider = make_slider(qtbot)
    levels = np.zeros(2000, np.int8)
    levels[1000] = 2
    slider.set_levels(levels)
    slider.flag_text = lambda first, last: "a flag"
    shown = []
    monkeypatch.setattr(QToolTip, "showText", lambda *args: shown.append(args[1]))
    x = round(slider.x_of_frame(1000))
    slider.event(QHelpEvent(QEvent.Type.WhatsThis, QPoint(x, 5), slider.mapToGlobal(QPoint(x, 5))))
    assert shown == []
    slider.event(QHelpEvent(QEvent.Type.ToolTip, QPoint(x, 5), slider.mapToGlobal(QPoint(x, 5))))
    assert shown == ["a flag"]
