"""The Teach dock: why a pre-rotation local transform lets any joint be a root.

For the selected joint at the current frame: its chain from the root, each link's local
transform as GMR ``[R_j, R_j t_j]`` and as BVH ``[R_j, t_j]``, both products and the world
transform FK gives (they agree to rounding, and the dock says by how much); a slider that
scales the joint's rotation from the identity to its value at this frame while the view
draws the bone it turns both ways (:mod:`app.teach_overlay`); after a Shift root, which links
were reversed and how far any joint moved (rounding); and the paper's trade-off live: a
roots slider that splits that many joints, deepest first, and measures FK per frame in a
worker thread.
"""

from __future__ import annotations

import html

import numpy as np
from PyQt6.QtCore import QObject, QRunnable, Qt, QThreadPool, QTimer, pyqtSignal
from PyQt6.QtGui import QFontDatabase
from PyQt6.QtWidgets import QGroupBox, QLabel, QSlider, QTextBrowser, QVBoxLayout, QWidget

from gmr_studio.app.docks.frame_follow import follow_frame
from gmr_studio.app.model.commands import SHIFT_ROOT_TEXT, MotionEdit
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.analysis.classroom import (
    JointChain,
    TradeoffPoint,
    explain_shift_root,
    joint_chain,
    roots_tradeoff,
)

REFRESH_MS = 60
MEASURE_DELAY_MS = 250


def format_transform(matrix: np.ndarray) -> list[str]:
    """The top three rows of a (4, 4) transform as text, a bar before the translation."""
    return [" ".join(f"{v:7.3f}" for v in row[:3]) + " |" + f"{row[3]:8.3f}" for row in matrix[:3]]


def _side_by_side(left: np.ndarray, right: np.ndarray | None) -> list[str]:
    right_rows = format_transform(right) if right is not None else [""] * 3
    return [f"{a}   {b}" for a, b in zip(format_transform(left), right_rows, strict=True)]


def chain_text(chain: JointChain) -> str:
    """The chain as monospaced text: per link its two locals side by side, then the products
    and the world transform FK gives."""
    width = len(format_transform(np.eye(4))[0])
    header = f"{'GMR [R_j, R_j t_j]':<{width}}   BVH [R_j, t_j]"
    lines = []
    for k, link in enumerate(chain.links):
        kind = "root" if k == 0 else f"link {k}"
        lines += [f"{link.name} ({kind}; BVH R = {link.bvh_rotation_from})", "  " + header]
        lines += ["  " + row for row in _side_by_side(link.gmr_local, link.bvh_local)]
        lines.append("")
    lines += ["Product of the links", "  " + header]
    lines += ["  " + row for row in _side_by_side(chain.gmr_product, chain.bvh_product)]
    lines += ["", "World transform (FK)"] + ["  " + row for row in format_transform(chain.world)]
    return "\n".join(lines)


def chain_html(chain: JointChain, size: float) -> str:
    """:func:`chain_text` in a <pre>, then what the numbers say."""
    relative = chain.position_gap / size if size > 0 else 0.0
    out = [
        f"<pre>{html.escape(chain_text(chain))}</pre>",
        f"<p>Both products put the joint at its FK position: largest difference {chain.position_gap:.2g} "
        f"({relative:.2g} of the skeleton's size); GMR rotation vs FK {chain.rotation_gap:.2g}: rounding. "
        "The GMR product's rotation is the frame of the bone ending at the joint; the BVH product's, "
        "of the bones leaving it.</p>",
    ]
    if chain.children_differ:
        out.append("<p>This joint's children carry different rotations: BVH needs a dummy joint per child.</p>")
    return "".join(out)


MATRIX_LINES = 12  # lines of the chain view always visible


class _Signals(QObject):
    done = pyqtSignal(object, object)  # (Snapshot measured, TradeoffPoint)
    failed = pyqtSignal(str)


class _Measure(QRunnable):
    def __init__(self, snapshot: Snapshot, roots: int) -> None:
        super().__init__()
        self.snapshot, self.roots, self.signals = snapshot, roots, _Signals()

    def run(self) -> None:
        try:
            point = roots_tradeoff(self.snapshot.motion, self.roots, reference=self.snapshot.positions)
        except Exception as exc:  # shown in the dock; the document is not touched
            self.signals.failed.emit(f"{type(exc).__name__}: {exc}")
            return
        self.signals.done.emit(self.snapshot, point)


class TeachDock(QWidget):
    """The classroom. ``amount_changed(float)`` tells the overlay the slider's value (0 to 1)."""

    amount_changed = pyqtSignal(float)
    measured = pyqtSignal(object)  # TradeoffPoint

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.pool = QThreadPool(self)
        self.pool.setMaxThreadCount(1)
        self.points: dict[int, TradeoffPoint] = {}
        self.chain: JointChain | None = None
        self.title = QLabel("Select a joint to see its chain.")
        self.title.setWordWrap(True)
        self.chain_view = QTextBrowser()
        self.chain_view.setFont(QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont))
        # a matrix and its neighbours readable at once: at least MATRIX_LINES lines tall (the
        # dock opens wide enough for a matrix's rows; narrower, they scroll sideways)
        self.chain_view.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAsNeeded)
        self.chain_view.setMinimumHeight(MATRIX_LINES * self.chain_view.fontMetrics().lineSpacing() + 12)
        self.amount = QSlider(Qt.Orientation.Horizontal)
        self.amount.setRange(0, 100)
        self.amount.setValue(100)
        self.amount_label = QLabel()
        self.amount_label.setWordWrap(True)
        self.shift_text = QLabel("Shift the root to a joint to see which links reverse.")
        self.shift_text.setWordWrap(True)
        self.roots = QSlider(Qt.Orientation.Horizontal)
        self.roots.setRange(1, 1)
        self.roots_label = QLabel()
        self.roots_label.setWordWrap(True)
        self.measured_text = QLabel()
        self.measured_text.setWordWrap(True)
        layout = QVBoxLayout(self)
        layout.setSizeConstraint(QVBoxLayout.SizeConstraint.SetMinimumSize)  # in a scroll area: never squeezed
        layout.addWidget(self.title)
        layout.addWidget(self.chain_view, 1)
        layout.addWidget(self.amount_label)
        layout.addWidget(self.amount)
        for title, widgets in (
            ("Shift root", [self.shift_text]),
            ("Roots and FK time (paper, Fig. 4)", [self.roots, self.roots_label, self.measured_text]),
        ):
            box = QGroupBox(title)
            inner = QVBoxLayout(box)
            for widget in widgets:
                inner.addWidget(widget)
            layout.addWidget(box)
        self._refresh_timer = QTimer(self, singleShot=True, interval=REFRESH_MS, timeout=self.refresh)
        self._measure_timer = QTimer(self, singleShot=True, interval=MEASURE_DELAY_MS, timeout=self.measure)
        self.amount.valueChanged.connect(self._on_amount)
        self.roots.valueChanged.connect(lambda _: self._measure_timer.start())
        state.selection_changed.connect(lambda _: self.schedule())
        self.frame_follower = follow_frame(self, state, lambda _: self.schedule())  # only while shown
        state.document_changed.connect(self._on_new_motion)
        state.motion_changed.connect(self._on_new_motion)
        state.undo_stack.indexChanged.connect(self._on_history)
        self._on_amount(self.amount.value())
        self._on_new_motion()

    @property
    def amount_value(self) -> float:
        return self.amount.value() / 100.0

    def schedule(self) -> None:
        # hidden (by default a tab behind the inspector) it is refreshed when shown
        if self.isVisible() and not self._refresh_timer.isActive():
            self._refresh_timer.start()

    def settle(self) -> None:
        """Refresh now if a refresh is pending (a screenshot cannot wait for the timer)."""
        if self._refresh_timer.isActive():
            self._refresh_timer.stop()
            self.refresh()

    def showEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        self._refresh_timer.start()
        super().showEvent(event)

    def _on_amount(self, value: int) -> None:
        joint = self.state.selected
        name = self.state.motion.names[joint] if self.state.motion is not None and joint is not None else "the joint"
        self.amount_label.setText(
            f"Rotation of {name}: {value}% of its value at this frame "
            "(pink: the bone GMR's R turns; cyan: the bones BVH's R turns)"
        )
        self.amount_changed.emit(value / 100.0)

    def _on_new_motion(self) -> None:
        self.points.clear()
        motion = self.state.motion
        n = motion.n_joints if motion is not None else 1
        self.roots.blockSignals(True)
        self.roots.setRange(1, max(1, n))
        self.roots.setValue(int((motion.parents < 0).sum()) if motion is not None else 1)
        self.roots.blockSignals(False)
        self.roots_label.setText(f"{self.roots.value()} root(s): move the slider to split more joints (deepest first).")
        self.measured_text.setText("")
        self.schedule()

    def refresh(self) -> None:
        snapshot, joint = self.state.snapshot, self.state.selected
        self._on_amount(self.amount.value())
        if snapshot is None or joint is None or snapshot.motion.n_frames == 0:
            self.chain = None
            self.title.setText("Select a joint to see its chain.")
            self.chain_view.setHtml("")
            return
        frame = min(self.state.frame, snapshot.motion.n_frames - 1)
        world = (snapshot.positions[frame : frame + 1], snapshot.rotations_at(frame)[None])
        self.chain = joint_chain(snapshot.motion.frame_slice(slice(frame, frame + 1)), joint, 0, world)
        names = " \u2192 ".join(link.name for link in self.chain.links)
        self.title.setText(f"<b>{html.escape(snapshot.motion.names[joint])}</b> at frame {frame}: {html.escape(names)}")
        self.chain_view.setHtml(chain_html(self.chain, snapshot.motion.size))

    def _on_history(self, index: int) -> None:
        command = self.state.undo_stack.command(index - 1) if index > 0 else None
        if not isinstance(command, MotionEdit) or not command.text().startswith(SHIFT_ROOT_TEXT):
            return
        before, after = command.before, command.after
        became = np.flatnonzero((after.motion.parents < 0) & (before.motion.parents >= 0))
        if len(became) != 1:
            return
        explanation = explain_shift_root(
            before.motion, after.motion, int(became[0]), (before.positions, after.positions)
        )
        self.shift_text.setText("<br>".join(html.escape(line) for line in explanation.lines()))

    def measure(self) -> None:
        snapshot = self.state.snapshot
        if snapshot is None:
            return
        roots = self.roots.value()
        self.roots_label.setText(f"{roots} root(s): measuring FK in the background...")
        job = _Measure(snapshot, roots)
        job.signals.done.connect(self._on_measured)
        job.signals.failed.connect(lambda text: self.roots_label.setText(f"Measuring failed: {text}"))
        self.pool.start(job)

    def _on_measured(self, snapshot: Snapshot, point: TradeoffPoint) -> None:
        if snapshot is not self.state.snapshot:
            return  # the document changed meanwhile
        self.points[point.roots] = point
        size = snapshot.motion.size
        self.roots_label.setText(
            f"{point.roots} root(s): FK {point.fk_us_per_frame:.2f} \u00b5s per frame, "
            f"{point.stored_per_frame} numbers ({8 * point.stored_per_frame} bytes) stored per frame, "
            "same positions (largest change "
            f"{point.largest_change:.2g}, {point.largest_change / size if size else 0:.2g} of the size)."
        )
        rows = "".join(
            f"<tr><td>{p.roots}</td><td>{p.fk_us_per_frame:.2f}</td><td>{p.stored_per_frame}</td></tr>"
            for p in sorted(self.points.values(), key=lambda p: p.roots)
        )
        self.measured_text.setText(
            f"<table><tr><th>roots</th><th>\u00b5s/frame</th><th>numbers/frame</th></tr>{rows}</table>"
        )
        self.measured.emit(point)
