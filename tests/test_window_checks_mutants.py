"""The quality checks wired into the window (issue 24, the mutants of app/window/checks.py):
the Problems dock hidden beside the Curves, a chosen finding framing its joint (joint 0 too)
or the figure, the marks following the findings and the level shown, and the status bar's
count, which opens the dock."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.model.state import Snapshot
from gmr_studio.core.checks import Finding
from tests import app_fixtures
from tests.test_problems_model_mutants import knocked_walk

studio = app_fixtures.studio
pytestmark = pytest.mark.gui


def test_the_dock_made_hidden_in_the_analysis_area(studio):
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
    centre = state.positions[5, ~state.motion.anchors].mean(axis=0)
    np.testing.assert_allclose(camera.GetFocalPoint(), centre, atol=1e-9)


def test_the_count_and_the_marks_follow_the_findings(studio):
    state, problems, count, marks = studio.state, studio.problems, studio.problems_count, studio.problem_marks
    state.open_document(Snapshot.of(knocked_walk(12)), None)
    assert count.text() == '<a href="problems">Problems: checking\u2026</a>'
    problems.wait()
    assert count.text() == '<a href="problems">Problems: 1 error, 1 warning</a>'
    assert marks.flags is problems.flags and marks.min_level == 1
    problems.set_min_level(3)
    assert marks.min_level == 3
    problems._publish([], None)
    assert count.text() == '<a href="problems">Problems: none</a>' and marks.flags is None
    info = Finding("pop", (0,), ("Hips",), 2, 2, "info", 1.0, "m")
    flags = np.zeros((state.n_frames, state.motion.n_joints), np.int8)
    flags[2, 0] = 1
    problems._publish([info], flags)
    assert count.text() == '<a href="problems">Problems: 1 info</a>' and marks.flags is flags


def test_a_click_on_the_count_opens_the_dock(studio):
    studio.state.open_document(Snapshot.of(knocked_walk(12)), None)
    studio.problems.wait()
    dock = studio.problems_dock
    assert dock.isHidden()
    studio.problems_count.linkActivated.emit("problems")
    QApplication.processEvents()
    assert dock.isVisible()
