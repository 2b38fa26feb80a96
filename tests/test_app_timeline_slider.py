"""The timeline's frame slider on its own (app/docks/range_slider.py), a bare widget: frames
sit where the style draws the handle, the checks' flags cover their frames in their level's
colour along the bottom, the selected range is a yellow band between two edges, Shift+drag
selects frames while a plain drag moves the frame, a flag's tooltip names its findings,
and what is on screen follows every change without anything else asking for a repaint."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPoint, QPointF, Qt
from PyQt6.QtGui import QColor, QHelpEvent, QMouseEvent
from PyQt6.QtWidgets import QApplication, QStyle, QStyleOptionSlider, QToolTip

from gmr_studio.app.docks.range_slider import (
    FLAG_COLOURS,
    FLAG_MIN_WIDTH,
    RANGE_COLOUR,
    RANGE_EDGE,
    RangeSlider,
)
from gmr_studio.app.docks.timeplot import CURSOR_COLOUR, RANGE_BRUSH
from gmr_studio.app.media.video import image_pixels

pytestmark = pytest.mark.gui
SHIFT = Qt.KeyboardModifier.ShiftModifier
NONE = Qt.KeyboardModifier.NoModifier
LEFT = Qt.MouseButton.LeftButton
#: how far a colour may be from the expected one, per channel (Qt's blending rounds)
TOLERANCE = 3


def make_slider(qtbot, minimum: int = 0, maximum: int = 1999, width: int = 600) -> RangeSlider:
    slider = RangeSlider()
    qtbot.addWidget(slider)
    slider.setRange(minimum, maximum)
    slider.resize(width, 24)
    slider.show()
    qtbot.waitExposed(slider)
    return slider


def style_rect(slider: RangeSlider, control: QStyle.SubControl):
    """The style's own rectangle of ``control`` (the handle or the groove) as it is now."""
    option = QStyleOptionSlider()
    slider.initStyleOption(option)
    return slider.style().subControlRect(QStyle.ComplexControl.CC_Slider, option, control, slider)


def handle_centre(slider: RangeSlider, value: int) -> float:
    """The x of the handle's centre as the style draws it with the slider at ``value``."""
    slider.setValue(value)
    rect = style_rect(slider, QStyle.SubControl.SC_SliderHandle)
    return rect.x() + rect.width() / 2


def drawn(slider: RangeSlider) -> np.ndarray:
    """(H, W, 3) int: the slider painted afresh."""
    return image_pixels(slider.grab().toImage()).astype(int)


def on_screen(slider: RangeSlider) -> np.ndarray:
    """(H, W, 3) int: what the screen shows of the slider now (its last paint)."""
    return image_pixels(slider.screen().grabWindow(slider.winId()).toImage()).astype(int)


def rgb(colour: QColor) -> np.ndarray:
    return np.array([colour.red(), colour.green(), colour.blue()])


def send_mouse(widget, kind: QEvent.Type, x: float, modifiers=NONE) -> None:
    point = QPointF(x, widget.height() / 2)
    button = LEFT if kind != QEvent.Type.MouseMove else Qt.MouseButton.NoButton
    buttons = Qt.MouseButton.NoButton if kind == QEvent.Type.MouseButtonRelease else LEFT
    event = QMouseEvent(kind, point, QPointF(widget.mapToGlobal(point.toPoint())), button, buttons, modifiers)
    QApplication.sendEvent(widget, event)


# ------------------------------------------------------------------------ what it holds
def test_a_frame_range_is_kept_only_when_it_holds_a_frame(qtbot):
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


# ------------------------------------------------------------------- frames and pixels
@pytest.mark.parametrize(("minimum", "maximum"), [(0, 1999), (10, 110), (0, 7), (0, 1)])
def test_frames_sit_where_the_style_draws_the_handle(qtbot, minimum, maximum):
    slider = make_slider(qtbot, minimum, maximum)
    for value in sorted({minimum, (minimum + maximum) // 2, maximum}):
        assert abs(slider.x_of_frame(value) - handle_centre(slider, value)) <= 1.0
    step = (slider.x_of_frame(maximum) - slider.x_of_frame(minimum)) / (maximum - minimum)
    assert slider.x_of_frame(minimum + 0.5) == pytest.approx(slider.x_of_frame(minimum) + step / 2)
    for value in range(minimum, maximum + 1, max((maximum - minimum) // 37, 1)):
        assert slider.frame_at(slider.x_of_frame(value)) == value
        assert slider.frame_at(slider.x_of_frame(value) + 0.4 * step) == value  # the nearest frame
    assert slider.frame_at(-50) == minimum and slider.frame_at(slider.width() + 50) == maximum


def test_a_slider_of_one_frame_maps_every_pixel_to_it(qtbot):
    slider = make_slider(qtbot, 4, 4)
    assert abs(slider.x_of_frame(4) - handle_centre(slider, 4)) <= 1.0
    assert np.isfinite(slider.x_of_frame(5)) and slider.x_of_frame(5) > slider.x_of_frame(4)
    assert {slider.frame_at(x) for x in range(-5, slider.width() + 5)} == {4}


def test_a_slider_narrower_than_its_handle_still_maps_frames_in_order(qtbot):
    slider = make_slider(qtbot, 0, 99, width=10)
    groove = style_rect(slider, QStyle.SubControl.SC_SliderGroove)
    handle = style_rect(slider, QStyle.SubControl.SC_SliderHandle)
    assert groove.width() - handle.width() < 1  # no room to slide
    first, last = slider.x_of_frame(0), slider.x_of_frame(99)
    assert np.isfinite([first, last]).all() and last > first
    assert slider.frame_at(first) == 0 and slider.frame_at(last) == 99


# ----------------------------------------------------------------------------- flags
def pixels_per_frame(slider: RangeSlider) -> float:
    count = max(slider.maximum() - slider.minimum(), 1)
    return (slider.x_of_frame(slider.maximum()) - slider.x_of_frame(slider.minimum())) / count


def assert_flags_cover_their_frames(slider: RangeSlider, levels: np.ndarray) -> list:
    """The flags as the module promises them: each flagged frame's pixel covered by a span of
    its level, at least FLAG_MIN_WIDTH wide; no column covered more than half a frame (or half
    the least width) and a pixel away from a frame of that level; a level's spans apart from
    each other, inside the widget, mildest level first (worse levels painted over them)."""
    spans = slider.flag_spans()
    width = slider.width()
    reach = max(pixels_per_frame(slider), FLAG_MIN_WIDTH) / 2 + 1
    assert [level for *_, level in spans] == sorted(level for *_, level in spans)
    for level in (1, 2, 3):
        own = [(x0, x1) for x0, x1, lvl in spans if lvl == level]
        frames = np.flatnonzero(levels == level)
        assert bool(own) == bool(frames.size), level
        for (_, end), (start, _) in itertools.pairwise(own):
            assert end < start, level  # touching spans would be one
        for x0, x1 in own:
            assert 0 <= x0 < x1 <= width
            assert x1 - x0 >= FLAG_MIN_WIDTH or x0 == 0 or x1 == width
            centres = np.array([slider.x_of_frame(f) for f in frames])
            columns = np.arange(x0, x1) + 0.5
            assert (np.abs(columns[:, None] - centres[None, :]).min(axis=1) <= reach).all(), (level, x0, x1)
        for frame in frames:
            x = slider.x_of_frame(frame)
            if 0 <= x < width:
                assert any(x0 <= x < x1 for x0, x1 in own), (level, frame)
    return spans


def test_flags_cover_their_frames_a_single_frame_a_few_pixels_wide(qtbot):
    slider = make_slider(qtbot)  # 2000 frames on about 580 pixels: several frames a pixel
    levels = np.zeros(2000, np.int8)
    levels[1000] = 3  # one frame: a few pixels around it
    levels[100:301] = 1  # a run: one span
    levels[[1500, 1502]] = 2  # two frames a pixel apart: one span
    slider.set_levels(levels)
    spans = assert_flags_cover_their_frames(slider, levels)
    assert [level for *_, level in spans] == [1, 2, 3]
    x0, x1, _ = spans[2]
    assert FLAG_MIN_WIDTH <= x1 - x0 <= FLAG_MIN_WIDTH + 2


def test_flags_far_apart_are_spans_of_their_own_and_stay_inside_the_widget(qtbot):
    slider = make_slider(qtbot, 0, 99, width=300)  # about 3 pixels a frame
    levels = np.zeros(100, np.int8)
    levels[[0, 50, 99]] = 2
    slider.set_levels(levels)
    spans = assert_flags_cover_their_frames(slider, levels)
    assert [level for *_, level in spans] == [2, 2, 2]


def test_a_run_of_flagged_frames_is_one_band_from_half_a_frame_before_to_half_after(qtbot):
    slider = make_slider(qtbot, 0, 99, width=500)  # about 5 pixels a frame: wider than a flag's least
    assert pixels_per_frame(slider) > FLAG_MIN_WIDTH
    levels = np.zeros(100, np.int8)
    levels[20:30] = 2
    slider.set_levels(levels)
    ((x0, x1, level),) = assert_flags_cover_their_frames(slider, levels)
    assert level == 2
    assert abs(x0 - slider.x_of_frame(19.5)) <= 1 and abs(x1 - slider.x_of_frame(29.5)) <= 1


def test_flags_at_the_very_edges_are_clipped_to_the_widget(qtbot):
    slider = make_slider(qtbot, 0, 2, width=200)  # half a frame is wider than the handle's margin
    levels = np.array([3, 0, 3], np.int8)
    slider.set_levels(levels)
    spans = assert_flags_cover_their_frames(slider, levels)
    assert spans[0][0] == 0 and spans[-1][1] == slider.width()
    assert len(spans) == 2 and spans[0][1] < slider.x_of_frame(1) < spans[1][0]  # the frame between: clear


def test_a_flag_on_a_slider_of_two_frames_covers_its_frame_only(qtbot):
    slider = make_slider(qtbot, 0, 1, width=300)
    levels = np.array([0, 2], np.int8)
    slider.set_levels(levels)
    ((x0, x1, level),) = assert_flags_cover_their_frames(slider, levels)
    assert level == 2 and x0 >= slider.x_of_frame(0.5) - 1 and x1 == slider.width()


def test_a_flag_on_a_slider_of_one_frame_is_at_the_handle(qtbot):
    slider = make_slider(qtbot, 4, 4, width=200)
    slider.set_levels(np.array([0, 0, 0, 0, 3], np.int8))  # levels by frame number: frame 4 flagged
    ((x0, x1, level),) = slider.flag_spans()
    assert level == 3 and x0 <= handle_centre(slider, 4) < x1 < slider.width()


def test_flags_follow_the_sliders_size_range_and_levels(qtbot):
    slider = make_slider(qtbot)
    levels = np.zeros(2000, np.int8)
    levels[1000] = 3
    slider.set_levels(levels)
    assert_flags_cover_their_frames(slider, levels)
    slider.resize(300, 24)
    QApplication.processEvents()
    assert_flags_cover_their_frames(slider, levels)
    slider.setRange(0, 999)  # frame 1000 one past the last: beyond the handle's last place
    assert_flags_cover_their_frames(slider, levels)
    assert slider.flag_spans()[0][1] > slider.x_of_frame(999) + 1
    slider.setRange(500, 1999)
    assert_flags_cover_their_frames(slider, levels)
    levels = np.zeros(2000, np.int8)
    levels[600] = 1
    slider.set_levels(levels)
    assert_flags_cover_their_frames(slider, levels)


def test_the_flags_are_a_band_along_the_bottom_in_the_worst_levels_colour(qtbot):
    slider = make_slider(qtbot)
    slider.setValue(0)
    plain = drawn(slider)
    levels = np.zeros(2000, np.int8)
    levels[1200:1400] = 1
    levels[1300] = 3  # an error inside the info run: red over the blue
    slider.set_levels(levels)
    pixels = drawn(slider)
    height = slider.height()
    changed = np.abs(pixels - plain).max(axis=2) > TOLERANCE
    rows = np.flatnonzero(changed.any(axis=1))
    assert rows.max() >= height - 3 and rows.min() > height // 2  # a thin band at the bottom
    assert np.array_equal(rows, np.arange(rows.min(), rows.max() + 1))  # one band, no gap
    band = pixels[rows.min() : rows.max() + 1]
    spans = slider.flag_spans()
    (red,) = [(x0, x1) for x0, x1, level in spans if level == 3]
    (blue,) = [(x0, x1) for x0, x1, level in spans if level == 1]
    assert (np.abs(band[:, red[0] : red[1]] - rgb(FLAG_COLOURS[3])).max(axis=2) <= TOLERANCE).all()
    outside_red = np.r_[blue[0] : red[0], red[1] : blue[1]]
    assert (np.abs(band[:, outside_red] - rgb(FLAG_COLOURS[1])).max(axis=2) <= TOLERANCE).all()
    assert not changed[:, : blue[0]].any() and not changed[:, blue[1] :].any()  # nothing beside it


# ----------------------------------------------------------------------------- range
def test_the_range_is_the_plots_yellow(qtbot):
    """The timeline's range is the yellow of the time plots' cursor and range."""
    assert rgb(RANGE_EDGE).tolist() == rgb(QColor(CURSOR_COLOUR)).tolist() == list(RANGE_BRUSH[:3])
    assert rgb(RANGE_COLOUR).tolist() == list(RANGE_BRUSH[:3]) and 0 < RANGE_COLOUR.alpha() < 255


def test_the_range_is_a_yellow_band_between_two_edges_over_its_frames(qtbot):
    slider = make_slider(qtbot, 0, 99, width=500)
    slider.setValue(99)
    plain = drawn(slider)
    slider.set_frame_range(20, 40)
    pixels = drawn(slider)
    height = slider.height()
    changed = np.flatnonzero(np.abs(pixels - plain).max(axis=(0, 2)) > TOLERANCE)
    left, right = slider.x_of_frame(19.5), slider.x_of_frame(39.5)  # half a frame before and after
    assert abs(changed.min() - left) <= 1 and abs(changed.max() - right) <= 1
    edge = (np.abs(pixels - rgb(RANGE_EDGE)).max(axis=2) <= TOLERANCE)[1:-1]
    assert edge[:, changed.min()].all() and edge[:, changed.max()].all()  # the edges' lines, opaque
    inside = np.s_[1 : height - 1, changed.min() + 1 : changed.max()]
    alpha = RANGE_COLOUR.alphaF()
    blended = plain[inside] + (rgb(RANGE_COLOUR) - plain[inside]) * alpha  # the slider seen through the band
    assert np.abs(pixels[inside] - blended).max() <= TOLERANCE
    between = np.s_[changed.min() + 1 : changed.max()]
    for row in (0, height - 1):  # a pixel left clear above and below the band
        assert (np.abs(pixels[row, between] - plain[row, between]) <= TOLERANCE).all(), row


def test_a_one_frame_range_is_still_a_visible_band(qtbot):
    """2000 frames on 600 pixels: one frame is a third of a pixel, its band still shows."""
    slider = make_slider(qtbot)
    slider.setValue(0)
    plain = drawn(slider)
    slider.set_frame_range(1000, 1001)
    pixels = drawn(slider)
    changed = np.flatnonzero(np.abs(pixels - plain).max(axis=(0, 2)) > TOLERANCE)
    assert 2 <= changed.max() - changed.min() + 1 <= 5
    assert changed.min() - 1 <= slider.x_of_frame(1000) <= changed.max() + 1
    assert np.array_equal(changed, np.arange(changed.min(), changed.max() + 1))


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
    assert slider.value() == 10
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(80), NONE)
    assert len(selected) == 3  # released: a move selects nothing
    send_mouse(slider, QEvent.Type.MouseButtonPress, slider.x_of_frame(10), NONE)  # then a plain drag
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(30), NONE)
    send_mouse(slider, QEvent.Type.MouseButtonRelease, slider.x_of_frame(30), NONE)
    assert len(selected) == 3 and abs(slider.value() - 30) <= 1


def test_a_plain_drag_moves_the_frame_and_selects_nothing(qtbot):
    slider = make_slider(qtbot, 0, 99, width=500)
    slider.setValue(10)
    selected = []
    slider.range_selected.connect(lambda start, stop: selected.append((start, stop)))
    send_mouse(slider, QEvent.Type.MouseButtonPress, slider.x_of_frame(10), NONE)  # on the handle
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(30), NONE)
    send_mouse(slider, QEvent.Type.MouseButtonRelease, slider.x_of_frame(30), NONE)
    assert selected == [] and abs(slider.value() - 30) <= 1  # the handle dragged as in any slider
    send_mouse(slider, QEvent.Type.MouseMove, slider.x_of_frame(50), SHIFT)  # no button held: nothing
    assert selected == []


# --------------------------------------------------------------------------- tooltip
def test_the_tooltip_over_a_flag_names_the_frames_under_it(qtbot, monkeypatch):
    slider = make_slider(qtbot)
    levels = np.zeros(2000, np.int8)
    levels[1000] = 2
    slider.set_levels(levels)
    x = slider.x_of_frame(1000)
    assert slider.flag_text_at(x) == ""  # no text given: nothing to say
    asked = []
    slider.flag_text = lambda first, last: asked.append((first, last)) or f"frames {first}-{last}"
    text = slider.flag_text_at(x)
    ((first, last),) = asked
    assert text == f"frames {first}-{last}"
    assert first <= 1000 <= last and (last - first) * pixels_per_frame(slider) <= FLAG_MIN_WIDTH + 2
    x0, x1, _ = slider.flag_spans()[0]
    for column in (x0, x1 - 1):  # anywhere over the flag names the flagged frame
        asked.clear()
        assert slider.flag_text_at(column) != ""
        assert asked[0][0] <= 1000 <= asked[0][1]
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
    whats_this = QHelpEvent(QEvent.Type.WhatsThis, QPoint(round(x), 5), slider.mapToGlobal(QPoint(round(x), 5)))
    slider.event(whats_this)  # a help event too, but not a tooltip: the slider's own
    assert len(shown) == 1


# ------------------------------------------------------------------------ on screen
def assert_shows(qtbot, slider: RangeSlider) -> None:
    """The screen comes to show the slider as a fresh paint draws it, with no repaint asked."""
    expected = drawn(slider)
    qtbot.waitUntil(lambda: np.abs(on_screen(slider) - expected).max() <= TOLERANCE, timeout=3000)


def test_a_new_range_levels_or_slider_range_show_on_screen(qtbot):
    slider = make_slider(qtbot)
    assert_shows(qtbot, slider)
    before = on_screen(slider)
    slider.set_frame_range(1000, 1200)
    assert_shows(qtbot, slider)
    levels = np.zeros(2000, np.int8)
    levels[1500:1600] = 3
    slider.set_levels(levels)
    assert_shows(qtbot, slider)
    slider.setRange(0, 2999)  # the same frame, the band and flags narrower
    assert_shows(qtbot, slider)
    assert np.abs(on_screen(slider) - before).max() > TOLERANCE


def test_the_handle_on_screen_follows_the_frame_on_a_long_take(qtbot):
    """2752 frames on a 600-pixel slider: several frames share the handle's place, and the
    screen shows the handle where the style puts it for every frame."""
    slider = make_slider(qtbot, 0, 2751, width=600)
    slider.setValue(999)
    assert_shows(qtbot, slider)
    places = set()
    for frame in range(1000, 1040, 3):
        slider.setValue(frame)
        places.add(style_rect(slider, QStyle.SubControl.SC_SliderHandle).x())
        assert_shows(qtbot, slider)
    assert len(places) >= 2  # the handle moved, and was seen moving
