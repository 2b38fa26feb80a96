"""Comparison layers: read-only motions and marker sets shown over the document.

A :class:`ComparisonLayer` is a motion snapshot (B), how it is drawn (colour, visible,
opacity), the alignment asked for (kind none|rigid|similarity, time offset auto or given)
and its :class:`~core.compare.Comparison` against the document (A), computed by
:func:`core.compare.compare_motions` (joints matched by name or a joint map, B on A's clock
and in A's space). A :class:`~app.marker_layers.MarkerLayer` is a marker set drawn as
spheres, aligned to the document as the marker overlay is. :class:`Layers` is the list the
Layers dock and the scene follow; it lives beside the state and recomputes every layer when
the document changes (an edit, undo, another file), so the errors always describe what is
shown. Layers are read-only: nothing here touches the document or its undo stack.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
from PyQt6.QtCore import QObject, pyqtSignal

from gmr_studio.app.model.marker_layers import MARKER_LAYER_OPACITY, MarkerLayer, realign_marker_layer
from gmr_studio.app.model.state import Snapshot, StudioState, marker_overlay_on
from gmr_studio.core.compare import ALIGN_KINDS, Comparison, compare_motions
from gmr_studio.core.compare.clock import DEFAULT_OFFSET, ghost_positions
from gmr_studio.core.jointmap import available_joint_maps, match_joints
from gmr_studio.core.markers import MarkerSet
from gmr_studio.core.markers.alignment import MarkerAlignment
from gmr_studio.core.rotations.euler import angle_axis_degrees

#: colours of successive layers (RGB in [0, 1]): none of them a tree colour of the document
LAYER_COLOURS = ((1.0, 0.45, 0.9), (0.55, 0.9, 1.0), (0.75, 1.0, 0.5), (1.0, 0.8, 0.45))
GHOST_OPACITY = 0.5


@dataclasses.dataclass(eq=False)
class ComparisonLayer:
    """One read-only motion over the document.

    snapshot : B and its kinematics. name : shown in the dock (the file's name).
    joint_map : the map its joints were matched through (None: by name).
    align : the alignment fitted after units and up axis: "none", "rigid" or "similarity".
    offset : B's time minus A's in A's frames, given or as found (``"auto"``) when the layer
        was added or its offset last set to auto, and then kept, so edits of the document do
        not move B in time. auto_offset : the offset was found, not given.
    comparison : B against the current document. ghost : (F_A, J_B, 3) every joint of B
        on A's frames and in A's space (NaN where B has no sample), what the scene draws.
    compared_with : the document's snapshot ``comparison`` and ``ghost`` were computed
        against (while an edit is being shown, the views may see the new document before the
        layers are compared with it: what is drawn of a comparison is drawn for this one).
    """

    snapshot: Snapshot
    name: str
    colour: tuple[float, float, float]
    joint_map: str | None = None
    align: str = "none"
    offset: float | str = DEFAULT_OFFSET
    auto_offset: bool = DEFAULT_OFFSET == "auto"
    visible: bool = True
    opacity: float = GHOST_OPACITY
    comparison: Comparison | None = None
    ghost: np.ndarray | None = None
    compared_with: Snapshot | None = None

    @property
    def alignment_text(self) -> str:
        """One line for the dock: offset, units, alignment kind and its RMS."""
        if self.comparison is None:
            return "not compared"
        a = self.comparison.alignment
        found = " (found)" if self.auto_offset else ""
        scale = f", x{a.space.scale:g} units" if a.space.scale != 1.0 else ""
        return f"offset {a.offset_frames:+g} frames{found}{scale}, align {a.kind}, RMS {a.rms_after:.3g}"

    @property
    def alignment_details(self) -> tuple[str, str]:
        """(detail lines, tooltip) of the alignment used: RMS before and after the fit, the
        fitted turn (angle about an axis), translation and scale; the tooltip adds the
        matrices, the offset in seconds and how units and up axis were decided."""
        if self.comparison is None:
            return "not compared", ""
        a = self.comparison.alignment
        units = self.comparison.units_text
        turn, axis = angle_axis_degrees(a.fit.rotation)
        line = (
            f"{a.kind}: RMS {a.rms_before:.4g} -> {a.rms_after:.4g} {units}\n"
            f"turn {turn:.3g} deg about ({_numbers(axis, '.3f')})\n"
            f"translation ({_numbers(a.fit.translation, '.4g')})\nscale {a.fit.scale:.6g}, "
            f"offset {a.offset_frames:+g} frames ({a.offset_seconds:+.4g} s), units x{a.space.scale:g}"
        )
        rows = "\n".join(f"  [{_numbers(row, '+.6f')}]" for row in a.fit.rotation)
        up = "\n".join(f"  [{_numbers(row, '+.0f')}]" for row in a.space.rotation)
        tooltip = (
            f"b' = scale * rotation @ (units x up) b + translation\nrotation:\n{rows}\n"
            f"translation: ({_numbers(a.fit.translation, '.6g')}) {units}\nscale: {a.fit.scale:.9g}\n"
            f"units scale: {a.space.scale:g}\nup rotation:\n{up}\n"
            f"offset: {a.offset_frames:+g} frames = {a.offset_seconds:+.6g} s"
            f"{' (found)' if self.auto_offset else ' (given)'}\n"
            f"RMS before {a.rms_before:.6g}, after {a.rms_after:.6g} {units}\n" + "\n".join(a.notes)
        )
        return line, tooltip


def _numbers(values, spec: str) -> str:
    return " ".join(format(float(v), spec) for v in values)


def compare_layer(document: Snapshot, layer: ComparisonLayer) -> tuple[Comparison, np.ndarray]:
    """The comparison of ``layer`` with ``document`` and its ghost (F_A, J_B, 3).

    Raises ValueError when no joint pairs up (give a joint map)."""
    comparison = compare_motions(
        document.motion,
        layer.snapshot.motion,
        joint_map=layer.joint_map,
        offset=layer.offset,
        align=layer.align,
        label_b=layer.name,
    )
    a, b = document.motion, layer.snapshot.motion
    ghost = ghost_positions(layer.snapshot.positions, a.n_frames, a.frame_rate, b.frame_rate, comparison.alignment)
    return comparison, ghost


def best_joint_map(document: Snapshot, other: Snapshot) -> str | None:
    """The shipped joint map that pairs the most joints of the two motions, or None when
    matching by name pairs at least as many (a file dropped without saying which map)."""
    names_a, names_b = document.motion.names, other.motion.names
    best, most = None, len(match_joints(names_a, names_b, None).pairs)
    for name in available_joint_maps():
        pairs = len(match_joints(names_a, names_b, name).pairs)
        if pairs > most:
            best, most = name, pairs
    return best


class Layers(QObject):
    """The comparison layers of a window (motions and marker sets, in the order added);
    signals: ``changed`` (added, removed, recomputed, re-aligned),
    ``appearance_changed(index)`` (colour, visibility, opacity)."""

    changed = pyqtSignal()
    appearance_changed = pyqtSignal(int)

    def __init__(self, state: StudioState, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.layers: list[ComparisonLayer | MarkerLayer] = []
        state.document_changed.connect(self._on_document_changed)
        state.motion_changed.connect(self.recompute)

    def __len__(self) -> int:
        return len(self.layers)

    def __getitem__(self, index: int) -> ComparisonLayer | MarkerLayer:
        return self.layers[index]

    @property
    def active(self) -> ComparisonLayer | None:
        """The layer the error view, inspector and error plot describe: the last visible one."""
        shown = [layer for layer in self.layers if layer.visible and layer.comparison is not None]
        return shown[-1] if shown else None

    def add(
        self,
        snapshot: Snapshot,
        path: str | Path,
        joint_map: str | None = None,
        *,
        align: str = "none",
        offset: float | str = DEFAULT_OFFSET,
    ) -> ComparisonLayer:
        """Compare ``snapshot`` with the document and show it as a new layer, B aligned by
        ``align`` (none, rigid, similarity) at ``offset`` (A's frames, or "auto": found;
        the default is the CLI's, :data:`core.compare.clock.DEFAULT_OFFSET`).

        Raises ValueError (nothing matched, no document, a bad option) and leaves the list
        as it was."""
        document = self.state.snapshot
        if document is None:
            raise ValueError("open a motion before comparing another with it")
        colour = self._next_colour()
        layer = ComparisonLayer(snapshot, Path(path).name, colour, joint_map or best_joint_map(document, snapshot))
        layer.align, layer.offset, layer.auto_offset = align, offset, offset == "auto"
        layer.comparison, layer.ghost = compare_layer(document, layer)
        layer.compared_with = document
        layer.offset = layer.comparison.alignment.offset_frames
        self.layers.append(layer)
        self.changed.emit()
        return layer

    def add_markers(
        self,
        markers: MarkerSet,
        path: str | Path,
        *,
        alignment: MarkerAlignment | None = None,
        document_bound: bool = False,
    ) -> MarkerLayer:
        """Show ``markers`` as a new layer, aligned to the document by ``alignment`` or
        automatically, as the marker overlay is; ``document_bound``: it goes when another
        document opens. Raises ValueError without a document."""
        document = self.state.snapshot
        if document is None:
            raise ValueError("open a motion before comparing markers with it")
        colour = self._next_colour()
        layer = MarkerLayer(
            markers, Path(path).name, colour, opacity=MARKER_LAYER_OPACITY, document_bound=document_bound
        )
        layer.overlay = marker_overlay_on(markers, document, alignment)  # None: the automatic one
        self.layers.append(layer)
        self.changed.emit()
        return layer

    def _next_colour(self) -> tuple[float, float, float]:
        return LAYER_COLOURS[len(self.layers) % len(LAYER_COLOURS)]

    def set_alignment(self, index: int, *, kind: str | None = None, offset: float | str | None = None) -> bool:
        """Compare layer ``index`` again with another alignment ``kind`` and/or time
        ``offset`` (A's frames, or "auto": found again, then kept). On a refusal (e.g. too
        few points for a fit) the layer stays as it was, with a message; returns False.
        The document and its undo stack are never touched."""
        layer = self.layers[index]
        document = self.state.snapshot
        if not isinstance(layer, ComparisonLayer) or document is None:
            return False
        if kind is not None and kind not in ALIGN_KINDS:
            raise ValueError(f"alignment must be one of {', '.join(ALIGN_KINDS)}, not {kind!r}")
        before = (layer.align, layer.offset, layer.auto_offset)
        if kind is not None:
            layer.align = kind
        if offset is not None:
            layer.offset, layer.auto_offset = offset, offset == "auto"
        try:
            layer.comparison, layer.ghost = compare_layer(document, layer)
            layer.compared_with = document
        except ValueError as exc:
            layer.align, layer.offset, layer.auto_offset = before
            self.state.show_message(f"Cannot align {layer.name} that way: {exc}")
            self.changed.emit()  # the dock shows what is kept
            return False
        layer.offset = layer.comparison.alignment.offset_frames
        self.changed.emit()
        return True

    def remove(self, index: int) -> None:
        del self.layers[index]
        self.changed.emit()

    def set_visible(self, index: int, visible: bool) -> None:
        self.layers[index].visible = bool(visible)
        self.appearance_changed.emit(index)

    def set_opacity(self, index: int, opacity: float) -> None:
        self.layers[index].opacity = float(min(max(opacity, 0.05), 1.0))
        self.appearance_changed.emit(index)

    def set_colour(self, index: int, colour: tuple[float, float, float]) -> None:
        self.layers[index].colour = tuple(float(c) for c in colour)
        self.appearance_changed.emit(index)

    def _on_document_changed(self) -> None:
        """Another document: each layer's offset (or marker alignment) is found again for it;
        the layers that came with the previous document go."""
        kept = [layer for layer in self.layers if not getattr(layer, "document_bound", False)]
        dropped, self.layers = len(kept) < len(self.layers), kept
        if dropped and not kept:
            self.changed.emit()
        for layer in self.layers:
            if isinstance(layer, ComparisonLayer):
                layer.offset, layer.auto_offset = "auto", True
            else:
                layer.overlay = None
        self.recompute()

    def recompute(self) -> None:
        """Compare every layer with the document as it now is; a layer that no longer
        matches any joint is dropped (with a message)."""
        document = self.state.snapshot
        if not self.layers:
            return
        kept = []
        for layer in self.layers:
            try:
                if document is None:
                    raise ValueError("no document")
                if isinstance(layer, MarkerLayer):
                    realign_marker_layer(layer, document, keep=layer.overlay is not None)
                else:
                    layer.comparison, layer.ghost = compare_layer(document, layer)
                    layer.compared_with = document
                    layer.offset = layer.comparison.alignment.offset_frames
            except ValueError as exc:
                self.state.show_message(f"Removed the comparison with {layer.name}: {exc}")
                continue
            kept.append(layer)
        self.layers = kept
        self.changed.emit()
