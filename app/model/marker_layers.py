"""Marker sets as read-only comparison layers (a TRC or C3D file shown over the document).

A :class:`MarkerLayer` is drawn as small spheres in its colour at the document's current
frame. It is put on the document's clock and in its space exactly as the marker overlay is
(:func:`app.state.marker_overlay_on`: resampled to the document's rate, so frames match by
time; units, up axis and heading by :func:`app.alignment.auto_alignment`), without touching
the document, its undo stack or the single "Add markers" overlay of the state.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.app.model.state import MarkerOverlay, Snapshot, marker_overlay_on
from gmr_studio.core.markers import MarkerSet

MARKER_LAYER_OPACITY = 0.9  # small spheres: nearly opaque, so their colour shows
MARKER_LAYER_RADIUS = 0.011  # of the document's size; the overlay's markers are 0.009


@dataclasses.dataclass(eq=False)
class MarkerLayer:
    """One read-only marker set over the document.

    markers : the set as read (file units and axes, its own rate). name : the file's name.
    overlay : the markers on the document's frames and in its space (its ``positions`` are
    (F_A, M, 3), NaN for gaps and outside the recording) with the alignment used.
    comparison : always None (a marker set is drawn, not compared joint by joint).
    document_bound : the layer came with the document (the lab model's points of the marker
        file it was built from) and goes when another document opens.
    """

    markers: MarkerSet
    name: str
    colour: tuple[float, float, float]
    visible: bool = True
    opacity: float = MARKER_LAYER_OPACITY
    overlay: MarkerOverlay | None = None
    comparison: None = None
    document_bound: bool = False

    @property
    def positions(self) -> np.ndarray:
        """(F_A, M, 3) the markers at the document's frames, in its space (NaN: gap)."""
        return self.overlay.positions

    @property
    def alignment_text(self) -> str:
        """One line for the dock: how many markers and how they were aligned."""
        if self.overlay is None:
            return "not aligned"
        a = self.overlay.alignment
        shift = f", frame offset {a.frame_offset:+d}" if a.frame_offset else ""
        return f"{self.markers.n_markers} markers, x{a.transform.scale:.4g}{shift}: {a.method}"

    @property
    def alignment_details(self) -> tuple[str, str]:
        """(detail lines, tooltip): the marker alignment, as the marker overlay shows it."""
        if self.overlay is None:
            return "not aligned", ""
        a = self.overlay.alignment
        m = self.markers
        line = (
            f"aligned as the marker overlay: scale {a.transform.scale:.6g} ({m.units} -> document)\n"
            f"translation ({' '.join(f'{v:.4g}' for v in a.transform.translation)})\n"
            f"frame offset {a.frame_offset:+d}, {m.rate:g} Hz resampled to the document's rate"
        )
        rows = "\n".join("  [" + " ".join(f"{v:+.4f}" for v in row) + "]" for row in a.transform.rotation)
        return line, f"p_document = scale * rotation @ p_marker + translation\nrotation:\n{rows}\n{a.method}"


def realign_marker_layer(layer: MarkerLayer, document: Snapshot, *, keep: bool) -> None:
    """Put ``layer`` on ``document``'s frames and in its space: with the alignment it has
    (``keep``, after an edit of the same document) or a new automatic one."""
    keep = keep and layer.overlay is not None and same_space(layer.overlay.positions, document)
    alignment = layer.overlay.alignment if keep else None
    layer.overlay = marker_overlay_on(layer.markers, document, alignment)


def same_space(aligned: np.ndarray, document: Snapshot) -> bool:
    """Markers aligned for an earlier version of the document (``aligned`` (F, M, 3)) still
    fit it: their extent in a frame (median over the frames) is within a factor five of the
    document's size. An edit that moves
    the document into another space (Markers > Build skeleton: inches and Y up to millimetres
    and Z up; its undo) needs a new alignment."""
    finite = np.isfinite(aligned).all(axis=-1)  # (F, M)
    rows = finite.sum(axis=1) >= 2
    if not rows.any():
        return True
    seen, points = finite[rows][..., None], aligned[rows]
    spans = np.where(seen, points, -np.inf).max(axis=1) - np.where(seen, points, np.inf).min(axis=1)
    extent = float(np.median(spans.max(axis=1)))  # the markers' extent in a frame, as Motion.size
    return 0.2 < extent / document.motion.size < 5.0
