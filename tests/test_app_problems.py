"""The quality checks in the app (issue 23, item 3): the Problems dock lists the findings of
a motion with planted defects, a click seeks, selects and frames the joint, the timeline
shows severity flags, the flagged joint is drawn in the warning colour, edits update the
list, and the settings are remembered across windows."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPoint, QSettings, Qt
from PyQt6.QtGui import QHelpEvent
from PyQt6.QtTest import QTest
from PyQt6.QtWidgets import QApplication, QToolTip

from gmr_studio.app.docks.range_slider import FLAG_HEIGHT
from gmr_studio.app.media.video import image_pixels
from gmr_studio.app.model import commands
from gmr_studio.app.model import problems as problems_module
from gmr_studio.app.model.problems import LEVEL_COLOURS, Problems, shown_limits
from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.window.main_window import MainWindow
from gmr_studio.core.checks import CheckSettings, Finding
from gmr_studio.core.kinematics.convention import pre_from_post
from tests import app_fixtures
from tests.app_fixtures import screen_image
from tests.checks_walk import clean_walk
from tests.conftest import shared_path
from tests.test_app_cli import read_png
from tests.test_app_problems_model import knocked_walk
from tests.test_checks import with_translation

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

POP_FRAME = 300
REST_FRAMES = 10
#: (kind, start, end, joints) of the planted walk: the rest pose planted at frames 0-9, the
#: left hand knocked 5 cm at frame 300 (which stretches its bone that frame too)
PLANTED = [
    ("rest-pose", 0, REST_FRAMES - 1, ()),
    ("pop", POP_FRAME, POP_FRAME, ("LeftHand",)),
    ("bone-length", POP_FRAME, POP_FRAME, ("LeftHand",)),
]


def planted_walk():
    """The clean synthetic walk (120 Hz, centimetres, 4 s) with its defects planted, in the
    GMR form the app holds."""
    motion = clean_walk(120.0, seconds=4.0, unit=0.01)

    def knock(frames):
        shift = np.zeros((frames.size, 3))
        shift[frames == POP_FRAME] = [0.0, 5.0, 0.0]
        return shift

    motion = with_translation(motion, "LeftHand", knock)
    rotations = motion.rotations.copy()
    rotations[:REST_FRAMES] = np.eye(3)
    return pre_from_post(motion.replace(rotations=rotations))


def listed(problems: Problems) -> list[tuple]:
    return [(f.kind, f.start, f.end, f.names) for f in problems.findings]


def open_planted(window: MainWindow) -> None:
    window.state.open_document(Snapshot.of(planted_walk()), None)
    window.problems.wait()


def table_rows(window: MainWindow) -> list[tuple[str, ...]]:
    table = window.problems_panel.table
    return [tuple(table.item(r, c).text() for c in range(table.columnCount())) for r in range(table.rowCount())]


def click_row(table, row: int) -> None:
    QTest.mouseClick(table.viewport(), Qt.MouseButton.LeftButton, pos=table.visualItemRect(table.item(row, 3)).center())


def colour_pixels(image: np.ndarray, level: int, tolerance: int = 8) -> np.ndarray:
    """(H, W) bool: pixels of the severity colour ``level`` (marks are drawn unlit: flat)."""
    target = np.rint(np.asarray(LEVEL_COLOURS[level]) * 255)
    return (np.abs(image[..., :3].astype(np.int16) - target) <= tolerance).all(axis=-1)


def test_the_planted_defects_are_listed(studio):
    open_planted(studio)
    assert listed(studio.problems) == PLANTED
    rows = table_rows(studio)
    assert [r[:4] for r in rows] == [
        ("rest-pose", "warning", "0-9", "(whole pose)"),
        ("pop", "warning", "300", "LeftHand"),
        ("bone-length", "error", "300", "LeftHand"),
    ]
    assert rows[1][4].endswith("file units") and float(rows[1][4].split()[0]) == pytest.approx(5.0, rel=0.1)
    assert "3 findings: 1 error, 2 warnings" in studio.problems_panel.summary.text()
    skipped = studio.problems_panel.skipped_label  # no check leaves frames out silently
    assert skipped.text() == "Frames 0-9 (the rest pose at the start) are left out of every check but rest-pose"
    assert skipped.isVisibleTo(studio.problems_panel)
    assert ">Problems: 1 error, 2 warnings<" in studio.problems_count.text()
    studio.problems_panel.filter_box.setCurrentIndex(2)  # errors only
    assert [r[0] for r in table_rows(studio)] == ["bone-length"]


def test_a_click_seeks_selects_and_frames_the_joint(studio, qtbot):
    open_planted(studio)
    studio.problems_dock.show()
    studio.problems_dock.raise_()
    qtbot.waitExposed(studio.problems_panel.table)
    table = studio.problems_panel.table
    row = next(r for r in range(table.rowCount()) if table.item(r, 0).text() == "pop")
    click_row(table, row)
    state, scene = studio.state, studio.view.scene
    hand = state.motion.names.index("LeftHand")
    assert (state.frame, state.selected) == (POP_FRAME, hand)
    camera = scene.plotter.camera
    np.testing.assert_allclose(camera.GetFocalPoint(), state.positions[POP_FRAME, hand], atol=1e-9)
    x, y, _depth = scene.joint_screen_positions()[hand]
    width, height = scene.viewport()
    assert abs(x - width / 2) < 2 and abs(y - height / 2) < 2  # the hand in the middle of the view
    distance = np.linalg.norm(np.subtract(camera.GetPosition(), camera.GetFocalPoint()))
    half_view = distance * np.tan(np.radians(camera.GetViewAngle()) / 2)
    assert 2 * half_view == pytest.approx(0.5 * state.motion.size, rel=1e-6)  # half the figure fills the view
    rest = next(r for r in range(table.rowCount()) if table.item(r, 0).text() == "rest-pose")
    click_row(table, rest)
    assert (state.frame, state.selected) == (0, hand)  # the whole pose: no joint to select
    pose = state.positions[0]  # ... and the camera on the middle of the figure's box
    np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (pose.min(0) + pose.max(0)) / 2, atol=1e-9)
    panel = studio.problems_panel
    panel.step_buttons[1].click()  # next: the pop at 300 (the first finding after frame 0)
    assert (state.frame, state.selected, panel.table.item(panel.table.currentRow(), 0).text()) == (300, hand, "pop")
    panel.step_buttons[1].click()  # the bone-length finding starts at 300 too: not after; round to the first
    assert state.frame == 0
    panel.step_buttons[-1].click()  # previous from frame 0: round to the last (bone-length at 300)
    assert (state.frame, panel.table.item(panel.table.currentRow(), 0).text()) == (300, "bone-length")


def test_the_timeline_shows_the_flags(studio):
    open_planted(studio)
    studio.state.set_frame(150)  # the handle away from the flags
    slider = studio.timeline.slider
    QApplication.processEvents()
    image = image_pixels(slider.grab().toImage())
    row = slider.height() - 1 - FLAG_HEIGHT // 2
    pop_x = round(slider.x_of_frame(POP_FRAME))
    assert colour_pixels(image[row : row + 1, pop_x - 1 : pop_x + 2], 3).all()  # error: red
    rest_x = round(slider.x_of_frame(REST_FRAMES / 2))
    assert colour_pixels(image[row : row + 1, rest_x : rest_x + 1], 2).all()  # warning: orange
    between = round(slider.x_of_frame(200))
    assert not any(colour_pixels(image[row : row + 1, between : between + 1], level).any() for level in (1, 2, 3))
    assert [level for *_, level in slider.flag_spans()] == [2, 3]
    tip = slider.flag_text_at(pop_x)  # hovering a flag names its findings
    assert tip.startswith("pop (warning) 300: LeftHand, 4.99") and "bone-length (error) 300: LeftHand" in tip
    assert slider.flag_text_at(between) == ""
    point = QPoint(pop_x, row)
    QApplication.sendEvent(slider, QHelpEvent(QEvent.Type.ToolTip, point, slider.mapToGlobal(point)))
    assert QToolTip.isVisible() and QToolTip.text() == tip
    QToolTip.hideText()
    studio.problems.set_min_level(3)  # errors only: the rest pose's warning not flagged
    assert [level for *_, level in slider.flag_spans()] == [3]


def test_the_flagged_joint_is_drawn_in_the_warning_colour(studio):
    open_planted(studio)
    state, scene = studio.state, studio.view.scene
    hand = state.motion.names.index("LeftHand")
    state.set_frame(POP_FRAME)
    scene.render(now=True)
    image = screen_image(studio)
    x, y, _depth = scene.joint_screen_positions()[hand]
    red = colour_pixels(image, 3)
    row, column = round(y), round(x)
    assert red[row - 1 : row + 2, column - 1 : column + 2].all()
    assert not colour_pixels(image, 2).any()
    assert not scene.front_renderer.GetDraw()  # the marks are drawn in front in the main renderer: no second pass
    state.set_frame(POP_FRAME + 20)  # no finding there: nothing flagged
    scene.render(now=True)
    image = screen_image(studio)
    assert not colour_pixels(image, 3).any() and not colour_pixels(image, 2).any()
    assert not scene.front_renderer.GetDraw()
    state.set_frame(3)  # the rest pose: every joint orange
    scene.render(now=True)
    image = screen_image(studio)
    orange = colour_pixels(image, 2)
    points = scene.joint_screen_positions()
    inside = [orange[round(py), round(px)] for px, py, _ in points]
    assert np.mean(inside) > 0.9  # every joint's centre (a few hidden behind others)
    studio.problems_panel.filter_box.setCurrentIndex(2)  # errors only: the warning not drawn
    assert studio.problems.min_level == 3
    scene.render(now=True)
    assert not colour_pixels(screen_image(studio), 2).any()


def test_edits_that_fix_a_problem_update_the_list(studio):
    open_planted(studio)
    state = studio.state
    assert commands.trim_to_range(state, REST_FRAMES, state.n_frames)
    assert studio.problems.running  # emptied at once, filled by the worker
    studio.problems.wait()
    assert listed(studio.problems) == [
        ("pop", POP_FRAME - REST_FRAMES, POP_FRAME - REST_FRAMES, ("LeftHand",)),
        ("bone-length", POP_FRAME - REST_FRAMES, POP_FRAME - REST_FRAMES, ("LeftHand",)),
    ]
    assert [r[0] for r in table_rows(studio)] == ["pop", "bone-length"]
    assert not studio.problems_panel.skipped_label.isVisibleTo(studio.problems_panel)  # no frame left out now
    assert studio.problems.flags.shape == (state.n_frames, state.motion.n_joints)
    state.undo_stack.undo()  # the earlier findings, at once (kept with their snapshot)
    assert not studio.problems.running and listed(studio.problems) == PLANTED
    assert studio.problems_panel.skipped_label.text().startswith("Frames 0-9 (the rest pose at the start)")
    assert commands.resample_to(state, 60.0)
    studio.problems.wait()
    assert [(k, s) for k, s, _e, _n in listed(studio.problems)] == [
        ("rest-pose", 0),
        ("pop", POP_FRAME // 2),
        ("bone-length", POP_FRAME // 2),
    ]


def test_settings_are_remembered_across_windows(studio, qtbot, tmp_path):
    open_planted(studio)
    panel = studio.problems_panel
    limits = panel.limits_table
    pop_row = [limits.item(r, 0).text() for r in range(limits.rowCount())].index("pop")
    limits.item(pop_row, 0).setCheckState(Qt.CheckState.Unchecked)  # as a click on the box does
    studio.problems.wait()
    assert "pop" not in studio.problems.settings.kinds
    assert [k for k, *_ in listed(studio.problems)] == ["rest-pose", "bone-length"]
    flip_row = [limits.item(r, 0).text() for r in range(limits.rowCount())].index("flip")
    limits.item(flip_row, 3).setText("170")  # the error limit, in degrees
    assert studio.problems.settings.flip_limits == (45.0, 90.0, 170.0)
    limits.item(flip_row, 1).setText("200")  # above the warning limit: refused, the old value back
    assert studio.problems.settings.flip_limits == (45.0, 90.0, 170.0)
    assert limits.item(flip_row, 1).text() == "45"
    assert "flip limits" in studio.status.text()
    panel.filter_box.setCurrentIndex(1)  # warnings and errors

    second = MainWindow(settings=QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat))
    try:
        kinds = [k for k in CheckSettings().kinds if k != "pop"]
        assert second.problems.settings == CheckSettings(kinds=kinds, flip_limits=(45, 90, 170))
        table = second.problems_panel.limits_table
        assert table.item(pop_row, 0).checkState() == Qt.CheckState.Unchecked
        assert table.item(flip_row, 3).text() == "170"
        assert shown_limits(second.problems.settings, "pop") == pytest.approx((0.5, 1.0, 3.0))
        assert second.problems.min_level == 2 and second.problems_panel.filter_box.currentIndex() == 1
    finally:
        second.close()
        second.deleteLater()
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)


def test_a_window_screenshot_with_a_finding_chosen(tmp_path):
    """``--dock problems --finding N`` shows the dock and clicks its finding N: the 75-frame
    cgspeed clip's RightFoot pop at frame 2, drawn orange; a dock it has not is refused."""
    clip = str(shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh"))
    out = tmp_path / "problems.png"
    studio_command = [sys.executable, "-m", "gmr_studio.app.main", clip, "--screenshot", str(out), "--window"]
    args = ["--dock", "problems", "--finding", "1", "--size", "1000x700"]
    result = subprocess.run([*studio_command, *args], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "frame 2)" in result.stdout
    image = read_png(out)
    orange = np.rint(np.asarray(LEVEL_COLOURS[2]) * 255)
    assert (np.abs(image.astype(int) - orange).max(axis=2) <= 8).sum() > 100  # the foot's disc, the table's cells
    bad = subprocess.run([*studio_command, "--dock", "nope"], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and bad.stderr.strip().count("\n") == 0 and "no dock 'nope'" in bad.stderr


def figure_pixels(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixels of the figure's blue (its bones and joints, tree colour), not
    the dark ground nor the grey grid."""
    r, g, b = (image[..., k].astype(int) for k in range(3))
    return (b > 120) & (b > r + 60) & (b > g + 20)


def test_a_whole_pose_finding_fits_the_figure_to_the_view_the_docks_leave(studio, qtbot):
    """Issue 40.8f: with the Problems dock open (the view about half as tall), choosing a
    finding of the whole pose frames the figure in the view it has: on a rig whose joints
    crowd the head (185 face points), its silhouette, feet included, lies inside the view,
    clear of every edge."""
    from gmr_studio.core.rigs import make_rig

    studio.state.open_document(Snapshot.of(pre_from_post(make_rig("fingers_and_face"))), "fingers_and_face.bvh")
    studio.problems_dock.show()
    studio.problems_dock.raise_()
    qtbot.waitExposed(studio.problems_panel.table)
    QApplication.processEvents()
    assert studio.view.scene.viewport()[1] < 0.6 * studio.height()  # the dock took its share
    for frame in (0, 60):
        studio.state.set_frame(frame)
        studio.problems_panel.joint_framed.emit(-1)  # what choosing a whole-pose finding asks
        figure = figure_pixels(screen_image(studio))
        rows, columns = np.nonzero(figure)
        assert figure.sum() > 500
        margin = 3
        assert rows.min() >= margin and rows.max() < figure.shape[0] - margin  # head and feet inside
        assert columns.min() >= margin and columns.max() < figure.shape[1] - margin
        assert rows.max() - rows.min() > 0.5 * figure.shape[0]  # and large: fitted, not lost in the view


# --------------------------------------------------------- the window's wiring on a small walk
def test_the_dock_is_made_hidden_in_the_analysis_area(studio):
    dock = studio.problems_dock
    assert dock.widget() is studio.problems_panel and dock.objectName() == "problems"
    assert dock.isHidden() and studio.dockWidgetArea(dock) == Qt.DockWidgetArea.BottomDockWidgetArea
    assert studio.problem_marks in studio.view.scene.drawables
    assert studio.problems_count.textFormat() == Qt.TextFormat.RichText
    assert studio.problems_count.text() == ""  # no motion: no count


def test_a_chosen_finding_frames_its_joint_or_the_figure(studio):
    state, scene = studio.state, studio.view.scene
    state.open_document(Snapshot.of(knocked_walk()), None)
    studio.problems.wait()
    state.set_frame(5)
    camera = scene.plotter.camera
    for joint in (0, 10):
        studio.problems_panel.joint_framed.emit(joint)
        np.testing.assert_allclose(camera.GetFocalPoint(), state.positions[5, joint], atol=1e-9)
    studio.problems_panel.joint_framed.emit(-1)
    pose = state.positions[5, ~state.motion.anchors]  # the whole figure: the middle of its box
    np.testing.assert_allclose(camera.GetFocalPoint(), (pose.min(axis=0) + pose.max(axis=0)) / 2, atol=1e-9)


def test_the_count_and_the_marks_follow_the_findings(studio, monkeypatch):
    state, problems, count, marks = studio.state, studio.problems, studio.problems_count, studio.problem_marks
    state.open_document(Snapshot.of(knocked_walk(12)), None)
    assert count.text() == '<a href="problems">Problems: checking\u2026</a>'
    problems.wait()
    assert count.text() == '<a href="problems">Problems: 1 error, 1 warning</a>'
    assert marks.flags is problems.flags and marks.min_level == 1
    problems.set_min_level(3)
    assert marks.min_level == 3
    found = []
    monkeypatch.setattr(problems_module, "run_checks", lambda *args, **kwargs: list(found))
    state.open_document(Snapshot.of(knocked_walk(12)), None)  # the checks (stood in for) find nothing
    problems.wait()
    assert count.text() == '<a href="problems">Problems: none</a>' and not marks.flags.any()
    found.append(Finding("pop", (0,), ("Hips",), 2, 2, "info", 1.0, "m"))
    state.open_document(Snapshot.of(knocked_walk(12)), None)
    problems.wait()
    assert count.text() == '<a href="problems">Problems: 1 info</a>' and marks.flags is problems.flags
    assert marks.flags[2, 0] == 1 and marks.flags.sum() == 1


def test_a_click_on_the_count_opens_the_dock(studio):
    studio.state.open_document(Snapshot.of(knocked_walk(12)), None)
    studio.problems.wait()
    dock = studio.problems_dock
    assert dock.isHidden()
    studio.problems_count.linkActivated.emit("problems")
    QApplication.processEvents()
    assert dock.isVisible()
