"""Comparison layers: read-only motions shown over the document, each compared with it.

A :class:`ComparisonLayer` is a motion snapshot (B), how it is drawn (colour, visible,
opacity) and its :class:`~core.compare.Comparison` against the document (A), computed by
:func:`core.compare.compare_motions` (joints matched by name or a joint map, B on A's clock
and in A's space). :class:`Layers` is the list the Layers dock and the scene follow; it lives
beside the state and recomputes every comparison when the document changes (an edit, undo,
another file), so the errors always describe what is shown.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
from PyQt6.QtCore import QObject, pyqtSignal

from gmr_studio.app.state import Snapshot, StudioState
from gmr_studio.core.compare import Comparison, compare_motions
from gmr_studio.core.compare.clock import resample
from gmr_studio.core.jointmap import available_joint_maps, match_joints

#: colours of successive layers (RGB in [0, 1]): none of them a tree colour of the document
LAYER_COLOURS = ((1.0, 0.45, 0.9), (0.55, 0.9, 1.0), (0.75, 1.0, 0.5), (1.0, 0.8, 0.45))
GHOST_OPACITY = 0.5


@dataclasses.dataclass(eq=False)
class ComparisonLayer:
    """One read-only motion over the document.

    snapshot : B and its kinematics. name : shown in the dock (the file's name).
    joint_map : the map its joints were matched through (None: by name).
    offset : B's time minus A's in A's frames, as found (``"auto"``) when the layer was
        added and then kept, so edits of the document do not move B in time.
    comparison : B against the current document. ghost : (F_A, J_B, 3) every joint of B
        on A's frames and in A's space (NaN where B has no sample), what the scene draws.
    """

    snapshot: Snapshot
    name: str
    colour: tuple[float, float, float]
    joint_map: str | None = None
    offset: float | str = "auto"
    visible: bool = True
    opacity: float = GHOST_OPACITY
    comparison: Comparison | None = None
    ghost: np.ndarray | None = None

    @property
    def alignment_text(self) -> str:
        """One line for the dock: offset, units, alignment kind and its RMS."""
        if self.comparison is None:
            return "not compared"
        a = self.comparison.alignment
        found = " (found)" if a.offset_found else ""
        scale = f", x{a.units_scale:g} units" if a.units_scale != 1.0 else ""
        return f"offset {a.offset_frames:+g} frames{found}{scale}, align {a.kind}, RMS {a.rms_after:.3g}"


def compare_layer(document: Snapshot, layer: ComparisonLayer) -> tuple[Comparison, np.ndarray]:
    """The comparison of ``layer`` with ``document`` and its ghost (F_A, J_B, 3).

    Raises ValueError when no joint pairs up (give a joint map)."""
    comparison = compare_motions(
        document.motion,
        layer.snapshot.motion,
        joint_map=layer.joint_map,
        offset=layer.offset,
        label_b=layer.name,
    )
    a = comparison.alignment
    rate_a, rate_b = document.motion.frame_rate, layer.snapshot.motion.frame_rate
    if abs(rate_b / rate_a - 1.0) < 1e-5:  # one rate, as the engine takes it
        rate_b = rate_a
    at = (np.arange(document.motion.n_frames) / rate_a + a.offset_seconds) * rate_b
    ghost = a.apply(resample(layer.snapshot.positions, at))
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
    """The comparison layers of a window; signals: ``changed`` (added, removed, recomputed),
    ``appearance_changed(index)`` (colour, visibility, opacity)."""

    changed = pyqtSignal()
    appearance_changed = pyqtSignal(int)

    def __init__(self, state: StudioState, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.layers: list[ComparisonLayer] = []
        state.document_changed.connect(self._on_document_changed)
        state.motion_changed.connect(self.recompute)

    def __len__(self) -> int:
        return len(self.layers)

    def __getitem__(self, index: int) -> ComparisonLayer:
        return self.layers[index]

    @property
    def active(self) -> ComparisonLayer | None:
        """The layer the error view, inspector and error plot describe: the last visible one."""
        shown = [layer for layer in self.layers if layer.visible and layer.comparison is not None]
        return shown[-1] if shown else None

    def add(self, snapshot: Snapshot, path: str | Path, joint_map: str | None = None) -> ComparisonLayer:
        """Compare ``snapshot`` with the document and show it as a new layer.

        Raises ValueError (nothing matched, no document) and leaves the list as it was."""
        document = self.state.snapshot
        if document is None:
            raise ValueError("open a motion before comparing another with it")
        colour = LAYER_COLOURS[len(self.layers) % len(LAYER_COLOURS)]
        layer = ComparisonLayer(snapshot, Path(path).name, colour, joint_map or best_joint_map(document, snapshot))
        layer.comparison, layer.ghost = compare_layer(document, layer)
        layer.offset = layer.comparison.alignment.offset_frames
        self.layers.append(layer)
        self.changed.emit()
        return layer

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
        """Another document: each layer's offset is found again for it."""
        for layer in self.layers:
            layer.offset = "auto"
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
                layer.comparison, layer.ghost = compare_layer(document, layer)
            except ValueError as exc:
                self.state.show_message(f"Removed the comparison with {layer.name}: {exc}")
                continue
            kept.append(layer)
        self.layers = kept
        self.changed.emit()
