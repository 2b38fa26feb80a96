"""The inspector dock: everything about the selected joint at the current frame.

Name, parent, soft-link parent, offset, channels both ways; the joint's two rotation
quantities, ``channels`` (labelled with what they are: the file's own values only while they
are, :mod:`app.model.channel_labels`) and ``gmr-euler``, named and computed as the curves
dock and ``gmr curves`` give them (:func:`core.analysis.curves.cached_curves`); the local transform both ways
(:mod:`app.joint_transforms`): under BVH the post-rotation ``[R, t]`` from the joint's own
BVH channels (for a motion read from a BVH, the file's channel values next to the matrix;
an End Site has none), under GMR the pre-rotation ``[R, R t]`` from its GMR channels (a
BVH's channels of its parent), each labelled with the joint its channels come from; the
world position and both world rotations; the selected marker; and the pelvis fit residual
when pelvis frames are shown. Numbers are rounded to the motion's precision
(:mod:`app.formatting`).
"""

from __future__ import annotations

import functools
import html
from pathlib import Path

import numpy as np
from PyQt6.QtGui import QFontDatabase
from PyQt6.QtWidgets import QScrollArea, QWidget

from gmr_studio.app.docks.rich_text import SLOT_OPEN, RichText, slot, slot_lines
from gmr_studio.app.model.channel_labels import channels_caption
from gmr_studio.app.model.formatting import format_angles, format_lengths, format_matrix, frame_of
from gmr_studio.app.model.joint_transforms import (
    LocalTransform,
    bvh_local,
    bvh_world_rotation,
    channel_names,
    gmr_local,
)
from gmr_studio.app.model.state import StudioState
from gmr_studio.core.analysis.curves import cached_curves
from gmr_studio.core.rotations.euler import complete_order, euler_from_matrix
from gmr_studio.core.timebase.clock import frame_seconds


class Inspector(QScrollArea):
    """Shows the selected joint; updated when the frame, selection or motion changes."""

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.label = RichText()
        self.setWidget(self.label)
        self.setWidgetResizable(True)
        self._mono = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont).family()
        self._frame: int | None = None
        for signal in (state.document_changed, state.motion_changed, state.markers_changed, state.pelvis_changed):
            signal.connect(self._on_changed)
        state.frame_changed.connect(self._on_frame_changed)
        state.selection_changed.connect(self._on_changed)
        state.marker_selection_changed.connect(self._on_changed)
        state.overlay_changed.connect(self._on_changed)
        state.modified_changed.connect(self._on_changed)  # "unchanged by the edits" (channels_caption)
        # every change is shown at once, during playback too (a throttled refresh lagged the
        # frame shown by several frames), and it is painted in the same pass as the timeline,
        # so the two never disagree; a hidden inspector only notes it is stale
        self._stale = False
        self.sections: list = []  # more sections: (frame, joint or None) -> list of HTML parts
        # each section's HTML and slot count when last built (see _on_frame_changed)
        self._built: list[tuple[str, int]] = []
        self.label.fill = self._html  # the stale slots' values, when they come into sight
        self._on_changed()

    def text(self) -> str:
        """The shown text without markup (for tests and copying)."""
        if self._stale:
            self._refresh()
        return self.label.plain_text()

    def shown_frame(self) -> int | None:
        """The frame the text describes (None without a motion)."""
        return self._frame

    def _on_changed(self, *_args) -> None:
        if self.isVisible():
            self._refresh()
        else:
            self._stale = True

    def _on_frame_changed(self, _frame: int) -> None:
        """A new frame: the sections with a number on screen are built again, the others keep
        their text of an earlier frame, marked stale (the label asks for the text as it is
        now, :meth:`_html`, when one of their lines comes into sight or the text is read).
        At the default layout fewer than half the sections are on screen."""
        if not self.isVisible():
            self._stale = True
            return
        builders = self._builders(self.state.frame)
        on_screen = self.label.slots_on_screen()
        if self._stale or len(builders) != len(self._built) or len(on_screen) != sum(n for _, n in self._built):
            self._refresh()
            return
        parts, stale, first = [], [], 0
        for k, (build, (text, count)) in enumerate(zip(builders, self._built, strict=True)):
            if count and not any(on_screen[first : first + count]):
                parts.append(text)
                stale += range(first, first + count)
            else:
                parts.append(self._build(k, build))
            first += count
        self._frame = self.state.frame
        self.label.setText("".join(parts), stale)

    def showEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        if self._stale:
            self._refresh()
        super().showEvent(event)

    def _refresh(self) -> None:
        self._stale = False
        self._frame = self.state.frame if self.state.motion is not None else None
        self.label.setText(self._html())

    def _build(self, k: int, build) -> str:
        """Section ``k``'s HTML from ``build``, noted with its slot count."""
        text = "".join(build())
        self._built[k] = (text, text.count(SLOT_OPEN))
        return text

    def _pre(self, text: str) -> str:
        return f"<pre style='font-family:\"{self._mono}\"; margin:0 0 6px 0'>{slot_lines(text)}</pre>"

    def _html(self) -> str:
        """The whole text at the state's frame, every section built (and noted)."""
        builders = self._builders(self.state.frame)
        self._built = [("", 0)] * len(builders)
        return "".join(self._build(k, build) for k, build in enumerate(builders))

    def _builders(self, f: int) -> list:
        """The text's sections at frame ``f``, in order: each a function giving its HTML parts.
        The joint's transforms are computed once for the sections that show them."""
        state = self.state
        motion = state.motion
        if motion is None:
            return [lambda: ["<i>No motion</i>"]]
        seconds = f"{frame_seconds(f, motion.frame_time):.3f}"
        place = frame_of(f"{slot(str(f))}</b>", motion.n_frames)
        builders = [lambda: [f"<b>Frame {place} &nbsp; ({slot(seconds)} s)"]]
        j = state.selected
        if j is None:
            builders.append(lambda: ["<p><i>Click a joint in the view or the forest to inspect it.</i></p>"])
        else:
            builders += self._joint_builders(j, f)
        builders.append(lambda: self._overlay_html(f))
        builders += [functools.partial(section, f, j) for section in self.sections]
        return builders

    def _joint_builders(self, j: int, f: int) -> list:
        """The selected joint's sections: its table, angles, both local transforms, world
        position and both world rotations (each transform computed once, when first shown)."""
        state = self.state
        motion = state.motion
        size = motion.size
        bvh = functools.cache(lambda: bvh_local(motion, f, j, state.file_channels))
        gmr = functools.cache(lambda: gmr_local(motion, f, j, state.file_channels))
        world = functools.cache(lambda: state.snapshot.rotations_at(f))  # (J, 3, 3)
        order = complete_order(motion.rotation_orders[j]) if motion.rotation_orders[j] else "ZYX"
        parent = int(motion.parents[j])
        note = " (a root: its translation is its world position)" if parent < 0 else ""

        def table() -> list[str]:
            name = html.escape(motion.names[j])
            link = int(motion.soft_parents[j])
            rows = [
                ("Joint", f"<b>{name}</b> (index {j})"),
                ("Parent", "none: a root" if parent < 0 else html.escape(motion.names[parent])),
                ("Soft link", html.escape(motion.names[link]) if link >= 0 else "none"),
                ("Offset", format_lengths(motion.offsets[j], size)),
                ("Channels (BVH)", channel_names(motion, j, bvh().channels_of is not None, bvh().order)),
                ("Channels (GMR)", channel_names(motion, j, True, order)),
            ]
            cells = "".join(f"<tr><td><b>{k}</b>&nbsp;</td><td>{v}</td></tr>" for k, v in rows)
            return [f"<table style='margin-top:6px'>{cells}</table>"]

        def world_position() -> list[str]:
            position = self._pre(format_matrix(state.positions[f, j][None], size, lengths=True))
            return ["<p style='margin-bottom:2px'><b>World position</b></p>", position]

        return [
            table,
            lambda: [self._angles_html(j, f)],
            lambda: self._transform_html("Local, post-rotation [R, t] (BVH)", bvh(), size, "t"),
            lambda: self._transform_html(f"Local, pre-rotation [R, R t] (GMR){note}", gmr(), size, "R t"),
            world_position,
            lambda: [
                self._world_html(
                    "BVH: the frame its children hang in", bvh_world_rotation(motion, world(), f, j), order
                )
            ],
            lambda: [self._world_html("GMR: the frame of the bone that ends at it", world()[j], order)],
        ]

    def _angles_html(self, j: int, f: int) -> str:
        """The joint's two rotation quantities at this frame, named and computed as the curves
        dock and ``gmr curves`` name and compute them (:func:`core.analysis.curves.cached_curves`), the
        channels labelled with what their numbers are (:func:`app.model.channel_labels.channels_caption`:
        the file's own only while they are). Each number is on a line of its own under its
        name (see :func:`_value_line`)."""
        state = self.state
        lines = []
        for quantity in ("channels", "gmr-euler"):
            curves = cached_curves(state.motion, j, quantity, state.positions, state.file_channels)
            if quantity == "channels":
                what = channels_caption(curves, state.path, state.modified)
            else:
                what = "the GMR rotation"
            labels = " ".join(c.rsplit(".", 1)[1] for c in curves.columns)
            name = f"<b>{quantity}</b> ({html.escape(what)}{': ' + labels if labels else ''}):"
            values = curves.values[f]
            if curves.columns and not np.isnan(values).all():
                shown = _value_line(f"{slot(format_angles(values))} deg")
            else:
                shown = _value_line("none")
            lines.append(f"<p style='margin:6px 0 0 0'>{name}</p>{shown}")
        return "".join(lines)

    def _transform_html(self, title: str, shown: LocalTransform, size: float, translation: str) -> list[str]:
        """A local transform's section. What may change from frame to frame is a slot, the
        note and where the angles come from included (an edit may leave the file's values
        making the rotation at some frames only): a section whose numbers are off screen is
        not rebuilt at a new frame, and a slot brings it up to date when it comes into sight."""
        out = [f"<p style='margin:6px 0 2px 0'><b>{html.escape(title)}</b><br/><i>{slot(shown.note)}</i></p>"]
        if shown.matrix is not None:  # R's rows, then the translation on a line of its own:
            # side by side, a rotation and a translation to seven digits are wider than the dock
            out.append(self._pre(format_matrix(shown.matrix[:, :3])))
            out.append(f"<p style='margin:0'>translation {translation}:</p>")
            translation_text = " ".join(format_matrix(shown.matrix[:, 3], size, lengths=True).split())
            out.append(_value_line(slot(translation_text), bottom=4))  # to the motion's precision, as the position
        if shown.angles is not None:
            where = "the file's channel values" if shown.from_file else "from the matrix"
            out.append(f"<p style='margin:0'>{slot(f'Euler {shown.order} ({where}):')}</p>")
            out.append(_value_line(f"{slot(format_angles(shown.angles))} deg"))
        return out

    def _world_html(self, title: str, rotation: np.ndarray, order: str) -> str:
        euler = slot(format_angles(np.degrees(euler_from_matrix(rotation, order))))
        return (
            f"<p style='margin:6px 0 0 0'><b>World rotation</b> ({html.escape(title)}), Euler {order}:</p>"
            + _value_line(f"{euler} deg", bottom=2)
            + self._pre(format_matrix(rotation))
        )

    def _overlay_html(self, f: int) -> list[str]:
        out = []
        overlay = self.state.marker_overlay
        if overlay is not None:
            markers = overlay.markers
            computed = markers.computed.mean() if markers.computed.size else 0.0
            share = f"; {100 * computed:.2g}% computed by the capture software" if computed else ""
            out.append(
                f"<p><b>Markers</b>: {markers.n_markers} from {html.escape(Path(markers.source).name or 'a file')}, "
                f"{markers.rate:g} Hz, {markers.units}{share}<br/>aligned: {html.escape(overlay.alignment.method)}</p>"
            )
            m = self.state.selected_marker
            if m is not None:
                point = overlay.positions[f, m]
                gap = not np.isfinite(point).all()
                where = "missing (a gap)" if gap else format_lengths(point, self.state.motion.size)
                if overlay.computed is not None and overlay.computed[f, m]:
                    where += " (computed by the capture software)"
                out.append(f"<p><b>Marker {html.escape(markers.labels[m])}</b>: {slot(where)}</p>")
        pelvis = self.state.pelvis
        if pelvis is not None and self.state.overlays["pelvis"]:
            residual = pelvis.residuals[f]
            text = f"{residual:.3g} {pelvis.source.units}" if np.isfinite(residual) else "not recovered at this frame"
            labels = html.escape(", ".join(pelvis.source.fit_labels or pelvis.source.labels)) or "X1, X2, X3"
            out.append(f"<p><b>Pelvis fit residual</b> (RMS of {labels}): {slot(text)}</p>")
            if np.isfinite(residual):
                out.append("<p style='margin-bottom:2px'><b>Pelvis rotation</b> (recovered, motion axes)</p>")
                out.append(self._pre(format_matrix(pelvis.rotations[f])))
        return out


def _value_line(text: str, bottom: int = 0) -> str:
    """A paragraph of its own for a number that changes every frame: its block is short,
    so writing it lays out one short line, not the wrapped sentence naming it."""
    return f"<p style='margin:0 0 {bottom}px 0'>{text}</p>"
