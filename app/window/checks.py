"""The quality checks wired into the window: the Problems dock, the joints' warning colours
in the view, the count in the status bar.

:func:`install_problems` takes the window's :class:`~app.model.problems.Problems` (made
before the timeline, which paints its flags) and adds the Problems dock to the analysis
tabs (hidden until asked: View > Problems, or a click on the count in the status bar), the
:class:`~app.scene.problem_marks.ProblemMarks` drawable to the scene, and the camera framing
of a chosen finding.
"""

from __future__ import annotations

from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QDockWidget, QLabel

from gmr_studio.app.docks.problems_dock import ProblemsDock
from gmr_studio.app.model.problems import Problems, count_text
from gmr_studio.app.scene.problem_marks import ProblemMarks


def install_problems(window, problems: Problems, scene) -> QDockWidget:
    """The Problems dock (returned, hidden, beside the Curves dock), the marks in ``scene``
    and the status bar's count; the window lists the dock with its analysis docks."""
    panel = ProblemsDock(problems)
    window.problems_panel = panel
    dock = window._dock("Problems", panel, Qt.DockWidgetArea.BottomDockWidgetArea)
    window.splitDockWidget(window.curves_dock, dock, Qt.Orientation.Horizontal)  # the analysis area
    dock.hide()
    panel.joint_framed.connect(lambda joint: scene.frame_joint(None if joint < 0 else joint))

    marks = ProblemMarks()
    window.problem_marks = marks
    scene.add_drawable(marks)

    count = QLabel()  # a label, as tall as the status text: a button's changing size moved the view
    count.setTextFormat(Qt.TextFormat.RichText)
    count.setToolTip("The quality checks' findings: click to list them (View > Problems)")
    count.linkActivated.connect(lambda _link: (dock.show(), dock.raise_()))
    window.statusBar().addPermanentWidget(count)
    window.problems_count = count

    def on_problems_changed() -> None:
        marks.flags, marks.min_level = problems.flags, problems.min_level
        scene.redraw(marks)
        if problems.state.motion is None:
            text = ""
        elif problems.running:
            text = "checking\u2026"
        else:
            text = count_text(problems.findings)
        count.setText(f'<a href="problems">Problems: {text}</a>' if text else "")

    problems.changed.connect(on_problems_changed)
    on_problems_changed()
    return dock
