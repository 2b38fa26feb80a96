"""The curves dock, the plot widget and the contact bars, driven by real mouse events under Xvfb."""

from __future__ import annotations

import csv
import itertools

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPointF, Qt
from PyQt6.QtGui import QImage, QMouseEvent
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.docks.frame_follow import seen
from gmr_studio.app.docks.timeplot import CURSOR_COLOUR, TimePlot
from gmr_studio.app.media.video import image_pixels
from gmr_studio.core.analysis.contacts import foot_contacts
from gmr_studio.core.analysis.curves import joint_curves
from gmr_studio.core.cli import main as gmr
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

WALK = "cmu/subject02/02_01.amc"
LEFT = Qt.MouseButton.LeftButton
NONE = Qt.KeyboardModifier.NoModifier
SHIFT = Qt.KeyboardModifier.ShiftModifier


def send_mouse(widget, kind: QEvent.Type, point: QPointF, buttons, modifiers=NONE) -> None:
    """A mouse event sent to the widget itself (the X server is shared by test workers)."""
    button = LEFT if kind != QEvent.Type.MouseMove else Qt.MouseButton.NoButton
    event = QMouseEvent(kind, point, QPointF(widget.mapToGlobal(point.toPoint())), button, buttons, modifiers)
    QApplication.sendEvent(widget, event)


def drag(widget, points: list[QPointF], modifiers=NONE) -> None:
    send_mouse(widget, QEvent.Type.MouseButtonPress, points[0], LEFT, modifiers)
    for point in points[1:]:
        send_mouse(widget, QEvent.Type.MouseMove, point, LEFT, modifiers)
        QApplication.processEvents()
    send_mouse(widget, QEvent.Type.MouseButtonRelease, points[-1], Qt.MouseButton.NoButton, modifiers)
    QApplication.processEvents()


def pixel_of_frame(plot: TimePlot, frame: float, y: float = 0.5) -> QPointF:
    """The viewport point of ``frame`` at a height ``y`` (0 top, 1 bottom) of the plot area."""
    view_y = plot.view_box.viewRange()[1]
    scene = plot.view_box.mapViewToScene(QPointF(frame * plot.scale, view_y[1] - y * (view_y[1] - view_y[0])))
    return QPointF(plot.plot_widget.mapFromScene(scene))


def cursor_column(plot: TimePlot) -> int:
    """The x pixel of the plot image where the cursor's colour is most present."""
    pixels = image_pixels(plot.plot_widget.grab().toImage())
    height = pixels.shape[0]
    target = np.array([int(CURSOR_COLOUR[i : i + 2], 16) for i in (1, 3, 5)])
    match = (np.abs(pixels.astype(int) - target).max(axis=2) < 40).sum(axis=0)
    assert match.max() > height / 3, "no cursor line drawn"
    return int(np.argmax(match))


@pytest.fixture
def walk(qtbot, studio):
    studio.curves_dock.show()  # hidden in the default layout until asked for
    open_file(studio, shared_path(WALK))
    studio.state.select(studio.state.motion.joint_index("lfemur"))
    QApplication.processEvents()
    return studio


def test_the_dock_plots_the_selected_joints_quantity_and_pins(walk):
    dock, state = walk.curves, walk.state
    expected = joint_curves(state.motion, "lfemur", "channels", file_channels=state.file_channels)
    assert dock.plot.columns == expected.columns == ("lfemur.channels.rx", "lfemur.channels.ry", "lfemur.channels.rz")
    np.testing.assert_array_equal(dock.plot.values, expected.values)
    dock.pin_selected()
    state.select(state.motion.joint_index("rfemur"))
    dock.set_quantity("world")
    assert dock.plot.columns == tuple(f"{j}.world.{a}" for j in ("lfemur", "rfemur") for a in "xyz")
    np.testing.assert_array_equal(dock.plot.values[:, 3:], state.positions[:, state.motion.joint_index("rfemur")])
    assert dock.plot.colour_of(0) != dock.plot.colour_of(3)  # each joint its own colour
    low, high = dock.plot.view_box.viewRange()[1]
    assert low <= np.nanmin(dock.plot.values) and high >= np.nanmax(dock.plot.values)  # autoscaled
    dock.clear_pins()
    assert dock.plot.columns == ("rfemur.world.x", "rfemur.world.y", "rfemur.world.z")


def test_clicking_and_dragging_in_the_plot_moves_the_frame_and_the_cursor(walk):
    plot, state = walk.curves.plot, walk.state
    viewport = plot.plot_widget.viewport()
    point = pixel_of_frame(plot, 200)
    send_mouse(viewport, QEvent.Type.MouseButtonPress, point, LEFT)
    send_mouse(viewport, QEvent.Type.MouseButtonRelease, point, Qt.MouseButton.NoButton)
    QApplication.processEvents()
    assert abs(state.frame - 200) <= 1
    assert abs(cursor_column(plot) - point.x()) <= 2
    drag(viewport, [pixel_of_frame(plot, f) for f in (100, 90, 70, 50)])
    assert abs(state.frame - 50) <= 1
    assert abs(cursor_column(plot) - pixel_of_frame(plot, state.frame).x()) <= 2
    state.set_frame(300)  # the state moves the cursor too
    assert abs(cursor_column(plot) - pixel_of_frame(plot, 300).x()) <= 2


def test_seconds_on_the_x_axis(walk):
    dock, plot, state = walk.curves, walk.curves.plot, walk.state
    dock.x_unit_box.setCurrentIndex(dock.x_unit_box.findData("seconds"))
    assert plot.scale == state.motion.frame_time
    state.set_frame(240)
    assert plot.cursor.value() == pytest.approx(2.0, rel=1e-9)
    point = pixel_of_frame(plot, 120)
    send_mouse(plot.plot_widget.viewport(), QEvent.Type.MouseButtonPress, point, LEFT)
    send_mouse(plot.plot_widget.viewport(), QEvent.Type.MouseButtonRelease, point, Qt.MouseButton.NoButton)
    assert abs(state.frame - 120) <= 1


def test_shift_drag_selects_a_range_that_trims_as_an_undoable_edit(walk):
    dock, plot, state = walk.curves, walk.curves.plot, walk.state
    before = state.snapshot
    drag(plot.plot_widget.viewport(), [pixel_of_frame(plot, f) for f in (80, 120, 160, 200)], SHIFT)
    start, stop = state.frame_range
    assert abs(start - 80) <= 1 and abs(stop - 201) <= 1
    assert dock.trim_button.isEnabled() and "Range" in dock.range_label.text()
    dock.trim_button.click()
    assert state.motion.n_frames == stop - start and state.frame_range is None
    np.testing.assert_array_equal(state.positions, before.positions[start:stop])
    assert plot.values.shape[0] == stop - start
    state.undo_stack.undo()
    assert state.snapshot is before


def test_loop_range_plays_inside_the_range(qtbot, walk):
    state, player = walk.state, walk.player
    state.set_frame_range(100, 130)
    walk.curves.loop_range_button.click()
    seen = []
    state.frame_changed.connect(seen.append)
    wrapped = lambda: any(b < a for a, b in itertools.pairwise(seen))  # noqa: E731
    qtbot.waitUntil(wrapped, timeout=20000)  # looped back to the range's start (30 frames: 0.25 s)
    player.pause()
    assert min(seen) >= 100 and max(seen) <= 129
    state.set_frame(129)
    player.play_range(loop=False)
    qtbot.waitUntil(lambda: not player.playing, timeout=3000)
    assert state.frame == 129


def test_resample_and_mirror_are_undoable_edits(walk):
    dock, state = walk.curves, walk.state
    before = state.snapshot
    dock.rate_box.setValue(60.0)
    dock.resample_button.click()
    assert state.motion.frame_rate == pytest.approx(60.0) and state.motion.n_frames == 172
    np.testing.assert_array_equal(state.positions, before.positions[::2])
    state.undo_stack.undo()
    dock.mirror_button.click()
    j, partner = state.motion.joint_index("lfoot"), state.motion.joint_index("rfoot")
    mirrored = state.positions[:, j]
    np.testing.assert_allclose(mirrored[:, 1:], before.positions[:, partner, 1:], atol=1e-9 * state.motion.size)
    state.undo_stack.undo()
    assert state.snapshot is before


def test_export_csv_of_the_visible_range_and_png(walk, tmp_path):
    plot = walk.curves.plot
    plot.view_box.setXRange(50, 99, padding=0)
    plot.export_csv(tmp_path / "c.csv")
    with open(tmp_path / "c.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["frame", "time", *plot.columns]
    frames = np.array([int(r[0]) for r in rows[1:]])
    np.testing.assert_array_equal(frames, np.arange(50, 100))
    np.testing.assert_allclose(np.array(rows[1:], float)[:, 2:], plot.values[50:100], rtol=1e-9)
    plot.export_png(tmp_path / "c.png")
    image = QImage(str(tmp_path / "c.png"))
    assert image.width() == plot.plot_widget.width() and image.height() == plot.plot_widget.height()


def test_the_dock_exports_what_gmr_curves_writes(walk, tmp_path):
    """Export CSV of the whole take gives the same file as ``gmr curves`` for the same joints and quantity."""
    dock = walk.curves
    dock.pin_selected()
    walk.state.select(walk.state.motion.joint_index("rfemur"))
    dock.plot.autoscale()
    dock.export_csv(str(tmp_path / "dock.csv"))
    argv = ["curves", str(shared_path(WALK)), "--joints", "lfemur,rfemur", "--quantity", "channels"]
    assert gmr([*argv, "-o", str(tmp_path / "cli.csv")]) == 0
    written = (tmp_path / "dock.csv").read_text()
    assert written.startswith("frame,time,lfemur.channels.rx,")
    assert written.count("\n") == walk.state.motion.n_frames + 1
    assert written == (tmp_path / "cli.csv").read_text()


def test_contact_bars_show_the_core_contacts_and_seek(qtbot, walk):
    walk.contacts_dock.show()
    bars, state = walk.contact_bars, walk.state
    qtbot.waitUntil(lambda: bars.strip.contacts is not None)  # computed once the first frame is drawn
    QApplication.processEvents()
    expected = foot_contacts(state.motion, state.positions)
    assert bars.strip.contacts.names == expected.names
    np.testing.assert_array_equal(bars.strip.contacts.planted, expected.planted)
    image = bars.strip.grab().toImage()
    row = expected.names.index("lfoot")
    y = 1 + row * 14 + 7
    planted = expected.planted[:, row]
    for frame in (np.flatnonzero(planted)[len(np.flatnonzero(planted)) // 2], np.flatnonzero(~planted)[5]):
        colour = image.pixelColor(int(bars.strip.x_of_frame(frame + 0.5)) + 1, y)
        assert (colour.green() > 140 and colour.red() < 120) == bool(planted[frame])
    bars.height_box.setValue(0.5)
    assert bars.strip.contacts.planted.sum() < expected.planted.sum()
    x = bars.strip.x_of_frame(250.5)
    send_mouse(bars.strip, QEvent.Type.MouseButtonPress, QPointF(x, 5), LEFT)
    assert state.frame == 250
    drag(bars.strip, [QPointF(bars.strip.x_of_frame(f + 0.5), 5) for f in (200, 150, 120)], SHIFT)
    assert state.frame_range == (120, 201) and state.frame == 250
    assert walk.curves.plot.range == (120, 201)  # the plot shows the range chosen under the timeline


def test_the_selected_marker_is_plotted_with_its_gaps_shaded(qtbot, studio):
    from gmr_studio.core.analysis.curves import gap_spans

    open_file(studio, shared_path("cmu/subject01/01_01.bvh"), shared_path("cmu/subject01/01_01.c3d"))
    overlay = studio.state.marker_overlay
    missing = np.isnan(overlay.positions).any(axis=2)
    marker = int(np.argmax(missing.sum(axis=0)))  # the marker with the most missing frames
    assert missing[:, marker].any() and not missing[:, marker].all()
    studio.state.select_marker(marker)
    plot = studio.curves.plot
    label = overlay.markers.labels[marker]
    assert plot.columns[-3:] == (f"{label}.x", f"{label}.y", f"{label}.z")
    np.testing.assert_array_equal(plot.values[:, -3:], overlay.positions[:, marker])
    np.testing.assert_array_equal(plot.spans, gap_spans(overlay.positions[:, marker]))
    assert len(plot.spans) > 0


def test_a_hidden_dock_costs_nothing_and_catches_up_when_shown(walk):
    """Issue 26, item 4: frame changes reach the curves only while the dock is seen."""
    dock, plot, state = walk.curves, walk.curves.plot, walk.state
    follower = dock.frame_follower
    walk.curves_dock.hide()
    QApplication.processEvents()
    calls = follower.calls
    for frame in (10, 20, 30):
        state.set_frame(frame)
    assert follower.calls == calls and follower.stale  # nothing ran while hidden
    walk.curves_dock.show()
    QApplication.processEvents()
    assert follower.calls == calls + 1 and not follower.stale  # one update, to the frame shown
    assert plot.cursor.value() == pytest.approx(30 * plot.scale)
    state.set_frame(40)
    assert follower.calls == calls + 2 and plot.cursor.value() == pytest.approx(40 * plot.scale)


def test_a_dock_behind_another_tab_costs_nothing_and_catches_up_in_front(qtbot, walk):
    """Qt keeps a tabbed dock behind another visible (moved out of the window): it is not
    updated until its tab is brought to front, then once, to the frame shown."""
    state, curves, contacts = walk.state, walk.curves.frame_follower, walk.contact_bars.strip.frame_follower
    walk.contacts_dock.show()  # tabbed with the curves, in front (layout.tab_when_shown)
    qtbot.waitUntil(lambda: walk.contacts_dock in walk.tabifiedDockWidgets(walk.curves_dock))
    walk.curves_dock.raise_()
    qtbot.waitUntil(lambda: seen(walk.curves) and not seen(walk.contact_bars.strip))
    assert walk.contact_bars.strip.isVisible()
    before = curves.calls, contacts.calls
    for frame in (10, 20, 30):
        state.set_frame(frame)
    assert (curves.calls, contacts.calls) == (before[0] + 3, before[1]) and contacts.stale
    walk.contacts_dock.raise_()
    qtbot.waitUntil(lambda: seen(walk.contact_bars.strip))
    assert contacts.calls == before[1] + 1 and not contacts.stale and curves.calls == before[0] + 3
