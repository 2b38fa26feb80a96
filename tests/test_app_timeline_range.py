"""A frame range chosen on the timeline itself: Shift+drag on the slider, the I and O keys
(and buttons); the same state range the curves plot and the contact bars show, shaded on
the slider."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPointF, Qt
from PyQt6.QtGui import QKeySequence, QMouseEvent
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.docks.range_slider import RANGE_COLOUR, range_ending_at, range_starting_at
from gmr_studio.app.media.video import image_pixels
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

WALK = "cmu/subject02/02_01.amc"
LEFT = Qt.MouseButton.LeftButton
SHIFT = Qt.KeyboardModifier.ShiftModifier
NONE = Qt.KeyboardModifier.NoModifier


def send(widget, kind: QEvent.Type, x: float, buttons, modifiers) -> None:
    point = QPointF(x, widget.height() / 2)
    button = Qt.MouseButton.NoButton if kind == QEvent.Type.MouseMove else LEFT
    event = QMouseEvent(kind, point, QPointF(widget.mapToGlobal(point.toPoint())), button, buttons, modifiers)
    QApplication.sendEvent(widget, event)
    QApplication.processEvents()


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


def test_shift_drag_on_the_slider_selects_the_range_and_shades_it(studio):
    open_file(studio, shared_path(WALK))
    state, slider, plot = studio.state, studio.timeline.slider, studio.curves.plot
    state.set_frame(300)
    QApplication.processEvents()  # the layout settles (the time label's width) before the slider is measured
    xs = [slider.x_of_frame(f) for f in (120, 80, 60)]
    send(slider, QEvent.Type.MouseButtonPress, xs[0], LEFT, SHIFT)
    for x in xs[1:]:
        send(slider, QEvent.Type.MouseMove, x, LEFT, SHIFT)
    send(slider, QEvent.Type.MouseButtonRelease, xs[-1], Qt.MouseButton.NoButton, SHIFT)
    assert state.frame_range == (60, 121) and state.frame == 300  # the frame stays put
    assert plot.range == (60, 121) and slider.frame_range == (60, 121)
    assert studio.actions["trim_range"].isEnabled()
    # the band is drawn over the selected frames only
    pixels = image_pixels(slider.grab().toImage()).astype(int)
    tint = pixels[:, :, 0] - pixels[:, :, 2]  # the range colour is yellow: red well above blue
    inside = [int(slider.x_of_frame(f)) for f in (70, 90, 110)]
    outside = [int(slider.x_of_frame(f)) for f in (20, 200)]
    assert RANGE_COLOUR.red() - RANGE_COLOUR.blue() > 200
    assert all(np.median(tint[:, x]) > 25 for x in inside), [np.median(tint[:, x]) for x in inside]
    assert all(np.median(tint[:, x]) < 10 for x in outside), [np.median(tint[:, x]) for x in outside]
    # a plain drag still moves the frame and keeps the range
    send(slider, QEvent.Type.MouseButtonPress, slider.x_of_frame(300), LEFT, NONE)
    send(slider, QEvent.Type.MouseMove, slider.x_of_frame(250), LEFT, NONE)
    send(slider, QEvent.Type.MouseButtonRelease, slider.x_of_frame(250), Qt.MouseButton.NoButton, NONE)
    assert abs(state.frame - 250) <= 1 and state.frame_range == (60, 121)


def test_i_and_o_set_the_range_at_the_current_frame(studio):
    open_file(studio, shared_path(WALK))
    state, actions, timeline = studio.state, studio.actions, studio.timeline
    assert actions["range_start"].shortcut() == QKeySequence("I")
    assert actions["range_end"].shortcut() == QKeySequence("O")
    state.set_frame(100)
    actions["range_start"].trigger()
    assert state.frame_range == (100, state.n_frames)
    state.set_frame(180)
    timeline.range_buttons["range_end"].click()
    assert state.frame_range == (100, 181) and studio.curves.plot.range == (100, 181)
    state.set_frame(150)
    timeline.range_buttons["range_start"].click()
    assert state.frame_range == (150, 181)
    state.set_frame(20)
    actions["range_end"].trigger()  # before the start: the range runs from frame 0
    assert state.frame_range == (0, 21)
    actions["clear_range"].trigger()
    assert state.frame_range is None and slider_is_clear(studio)


def slider_is_clear(studio) -> bool:
    return studio.timeline.slider.frame_range is None and not studio.actions["clear_range"].isEnabled()
