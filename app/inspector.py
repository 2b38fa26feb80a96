"""The inspector dock: everything about the selected joint at the current frame.

Name, parent, soft-link parent, offset, channels; the local transform both ways, as GMR's
pre-rotation ``[R, R t]`` and as BVH's post-rotation ``[R, t]`` (for a root both are
``[R, G]``: its translation is its world position); the world position and rotation (with
the rotation's Euler angles in the joint's order); the selected marker; and the pelvis
fit residual when pelvis frames are shown.
"""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np
from PyQt6.QtCore import QElapsedTimer, Qt, QTimer
from PyQt6.QtGui import QFontDatabase
from PyQt6.QtWidgets import QLabel, QScrollArea, QWidget

from gmr_studio.app.state import StudioState
from gmr_studio.core.rotations import complete_order, euler_from_matrix

REFRESH_MS = 100


def format_matrix(matrix: np.ndarray, digits: int = 4) -> str:
    """Rows of a matrix as aligned text, with a bar before the last column of a 3x4."""
    rows = []
    width = digits + 6
    for row in np.atleast_2d(matrix):
        cells = [f"{v:{width}.{digits}f}" for v in row]
        if len(cells) == 4:
            cells.insert(3, " |")
        rows.append(" ".join(cells))
    return "\n".join(rows)


def local_transforms(rotation: np.ndarray, translation: np.ndarray, is_root: bool) -> tuple[np.ndarray, np.ndarray]:
    """(3, 4) pre-rotation ``[R, R t]`` and post-rotation ``[R, t]`` of a local transform
    (a root's is ``[R, G]`` both ways)."""
    pre_translation = translation if is_root else rotation @ translation
    return np.column_stack([rotation, pre_translation]), np.column_stack([rotation, translation])


def channel_names(has_translation: bool, order: str) -> str:
    names = ["Xposition", "Yposition", "Zposition"] if has_translation else []
    return " ".join(names + [f"{axis}rotation" for axis in order]) or "none"


class Inspector(QScrollArea):
    """Shows the selected joint; updated when the frame, selection or motion changes."""

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.label = QLabel()
        self.label.setTextFormat(Qt.TextFormat.RichText)
        self.label.setAlignment(Qt.AlignmentFlag.AlignTop | Qt.AlignmentFlag.AlignLeft)
        self.label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.label.setMargin(6)
        self.label.setWordWrap(True)
        self.setWidget(self.label)
        self.setWidgetResizable(True)
        self._mono = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont).family()
        for signal in (state.document_changed, state.motion_changed, state.markers_changed, state.pelvis_changed):
            signal.connect(self._on_changed)
        state.frame_changed.connect(self._on_frame_changed)
        state.selection_changed.connect(self._on_changed)
        state.marker_selection_changed.connect(self._on_changed)
        state.overlay_changed.connect(self._on_changed)
        # during playback the text is laid out at most every REFRESH_MS (it costs more than
        # moving the skeleton); the last frame is always shown
        self._clock = QElapsedTimer()
        self._pending = QTimer(self, singleShot=True, interval=REFRESH_MS)
        self._pending.timeout.connect(self._on_changed)
        self._on_changed()

    def _on_frame_changed(self, _frame: int) -> None:
        if self._clock.isValid() and self._clock.elapsed() < REFRESH_MS:
            if not self._pending.isActive():
                self._pending.start()
        else:
            self._on_changed()

    def text(self) -> str:
        """The shown text without markup (for tests and copying)."""
        from PyQt6.QtGui import QTextDocument

        if self._pending.isActive():
            self._pending.stop()
            self._on_changed()
        document = QTextDocument()
        document.setHtml(self.label.text())
        return document.toPlainText()

    def _on_changed(self, *_args) -> None:
        self._pending.stop()
        self._clock.start()
        self.label.setText(self._html())

    def _pre(self, text: str) -> str:
        return f"<pre style='font-family:\"{self._mono}\"; margin:0 0 6px 0'>{html.escape(text)}</pre>"

    def _html(self) -> str:
        state = self.state
        motion = state.motion
        if motion is None:
            return "<i>No motion</i>"
        f = state.frame
        parts = [f"<b>Frame {f}</b> of {motion.n_frames} &nbsp; ({f * motion.frame_time:.3f} s)"]
        j = state.selected
        if j is None:
            parts.append("<p><i>Click a joint in the view or the forest to inspect it.</i></p>")
        else:
            parts += self._joint_html(j, f)
        parts += self._overlay_html(f)
        return "".join(parts)

    def _joint_html(self, j: int, f: int) -> list[str]:
        motion = self.state.motion
        name = html.escape(motion.names[j])
        parent = int(motion.parents[j])
        link = int(motion.soft_parents[j])
        is_root = parent < 0
        rotation = motion.rotations[f, j]
        translation = motion.translations[f, j]
        pre, post = local_transforms(rotation, translation, is_root)
        world_rotation = self.state.rotations[f, j]
        world_position = self.state.positions[f, j]
        order = complete_order(motion.rotation_orders[j]) if motion.rotation_orders[j] else "ZYX"
        euler = np.degrees(euler_from_matrix(world_rotation, order))
        rows = [
            ("Joint", f"<b>{name}</b> (index {j})"),
            ("Parent", "none: a root" if is_root else html.escape(motion.names[parent])),
            ("Soft link", html.escape(motion.names[link]) if link >= 0 else "none"),
            ("Offset", " ".join(f"{v:.4g}" for v in motion.offsets[j])),
            ("Channels", channel_names(bool(motion.has_translation[j]), motion.rotation_orders[j])),
        ]
        table = "".join(f"<tr><td><b>{k}</b>&nbsp;</td><td>{v}</td></tr>" for k, v in rows)
        note = " (a root: its translation is its world position)" if is_root else ""
        return [
            f"<table style='margin-top:6px'>{table}</table>",
            f"<p style='margin-bottom:2px'><b>Local, pre-rotation</b> [R, R t] (GMR){note}</p>",
            self._pre(format_matrix(pre)),
            "<p style='margin-bottom:2px'><b>Local, post-rotation</b> [R, t] (BVH)</p>",
            self._pre(format_matrix(post)),
            "<p style='margin-bottom:2px'><b>World position</b></p>",
            self._pre(format_matrix(world_position[None])),
            f"<p style='margin-bottom:2px'><b>World rotation</b> (Euler {order}: "
            + ", ".join(f"{v:.2f}" for v in euler)
            + " deg)</p>",
            self._pre(format_matrix(world_rotation)),
        ]

    def _overlay_html(self, f: int) -> list[str]:
        out = []
        overlay = self.state.marker_overlay
        if overlay is not None:
            markers = overlay.markers
            out.append(
                f"<p><b>Markers</b>: {markers.n_markers} from {html.escape(Path(markers.source).name or 'a file')}, "
                f"{markers.rate:g} Hz, {markers.units}<br/>aligned: {html.escape(overlay.alignment.method)}</p>"
            )
            m = self.state.selected_marker
            if m is not None:
                point = overlay.positions[f, m]
                where = "missing (a gap)" if not np.isfinite(point).all() else " ".join(f"{v:.4g}" for v in point)
                out.append(f"<p><b>Marker {html.escape(markers.labels[m])}</b>: {where}</p>")
        pelvis = self.state.pelvis
        if pelvis is not None and self.state.overlays["pelvis"]:
            residual = pelvis.residuals[f]
            units = html.escape(pelvis.source.units)
            text = f"{residual:.3g} {units}" if np.isfinite(residual) else "not recovered at this frame"
            labels = html.escape(", ".join(pelvis.source.fit_labels or pelvis.source.labels)) or "X1, X2, X3"
            out.append(f"<p><b>Pelvis fit residual</b> (RMS of {labels}): {text}</p>")
            if np.isfinite(residual):
                out.append("<p style='margin-bottom:2px'><b>Pelvis rotation</b> (recovered, motion axes)</p>")
                out.append(self._pre(format_matrix(pelvis.rotations[f])))
        return out
