"""A marker file (C3D, TRC) opened alone: the skeleton built from its markers is the document.

:func:`load_marker_document` (run in the loading worker) reads the markers, recognises the
marker set from the labels, builds the skeleton and its motion with the core
(:func:`core.markers.built_motion.markers_to_built_motion`: joint centres by the published methods,
the paper's closed form, optionally the least-squares refinement) and computes the motion's
kinematics. :func:`show_marker_document` makes it the document and shows the markers over it
(the file's own space: the motion is in millimetres in the file's axes, so the markers are
only scaled to millimetres), the recovered pelvis frames (the Procrustes frames the motion's
root was solved from) and, when the file stores the lab model's joint centres (Plug-in Gait,
pyCGM2: ``LHJC``, ``LKJC``, ``PELO``...), those as a marker-set comparison layer.

:class:`BuildSkeletonEdit` does the same from the markers shown over another motion
(Markers > Build skeleton), as one undoable edit: redo shows the built motion with the
markers in the file's space, undo the previous motion with the alignment it had.
"""

from __future__ import annotations

import dataclasses
import html
from pathlib import Path

import numpy as np
from PyQt6.QtGui import QUndoCommand

from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers import MarkerSet, read_markers
from gmr_studio.core.markers.alignment import MarkerAlignment
from gmr_studio.core.markers.built_motion import BuiltMotion, markers_to_built_motion
from gmr_studio.core.markers.file_model import FILE_POINTS
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.space.units import UNITS, unit_factor, unit_named
from gmr_studio.core.timebase.clock import rate_text

#: how the markers are placed over a skeleton built from them (shown in the alignment dialog)
FILE_SPACE = "the file's own space (the skeleton was built from these markers)"


@dataclasses.dataclass(frozen=True, eq=False)
class MarkerDocument:
    """A skeleton built from a marker file, ready to be shown.

    snapshot : the built motion (mm, the file's axes, the markers' rate) and its kinematics.
    markers : the markers drawn over it (the lab model's points taken out).
    model_points : the lab model's joint centres stored in the file (``LHJC``... as markers),
        or None when the file has none.
    built : the core's result (skeleton, bone lengths and spread, pelvis frames, refinement).
    """

    snapshot: Snapshot
    markers: MarkerSet
    model_points: MarkerSet | None
    built: BuiltMotion

    def summary(self) -> str:
        """One line for the status bar: the set, the skeleton, the fit."""
        built, motion = self.built, self.snapshot.motion
        spread = built.built.spread[np.isfinite(built.built.spread)]
        text = (
            f"skeleton built from marker set {built.built.set_match.definition.name}: {motion.n_joints} joints, "
            f"{motion.n_frames} frames at {rate_text(motion.frame_time)} Hz (mm); bone length spread median "
            f"{np.median(spread) if spread.size else float('nan'):.2g} mm"
        )
        if built.refinement is not None:
            residual = built.refinement.residuals
            median = np.nanmedian(residual[np.isfinite(residual).any(axis=1)], axis=0) if residual.size else residual
            text += f"; refined: marker residual median {np.nanmedian(median):.3g} mm"
        else:
            text += "; closed form (Markers > Refine the fit for least squares)"
        if self.model_points is not None:
            text += f"; the lab model's {', '.join(self.model_points.labels)} shown as a layer"
        return text


def model_point_labels(markers: MarkerSet) -> list[str]:
    """The lab model's joint centres and segment origins among the file's points
    (:data:`core.markers.file_model.FILE_POINTS`), in file order."""
    known = {label for points in FILE_POINTS.values() for label in points}
    return [label for label in markers.labels if label in known]


def segment_frame_labels(labels) -> set[str]:
    """Plug-in Gait's segment-frame points among ``labels``: for each segment code (``PEL``,
    ``LFE``, ``RTI``...) its origin, proximal, anterior and lateral points ``PELO``, ``PELP``,
    ``PELA``, ``PELL``, counted only when all four are there (a marker named ``LTOE``... is
    not one)."""
    present = set(labels)
    codes = {label[:-1] for label in present if len(label) in (4, 5) and label[-1] == "O"}
    return {code + end for code in codes if all(code + e in present for e in "OPAL") for end in "OPAL"}


def build_document(markers: MarkerSet, *, refine: bool = False) -> MarkerDocument:
    """The skeleton and motion built from ``markers`` (see the module docstring).

    Raises OperationError naming what is missing when no known set fits the labels or the set
    lacks markers the skeleton needs."""
    model = model_point_labels(markers)
    computed = set(model) | segment_frame_labels(markers.labels)
    own = markers.select([label for label in markers.labels if label not in computed]) if computed else markers
    built = markers_to_built_motion(own, refine=refine)
    snapshot = Snapshot.of(built.result.motion)
    return MarkerDocument(snapshot, own, markers.select(model) if model else None, built)


def load_marker_document(path: str | Path, *, refine: bool = False) -> MarkerDocument:
    """Read a marker file and build its document (for the loading worker).

    Raises MotionFileError for a file that cannot be read, and OperationError for one whose
    markers make no skeleton (no known marker set, markers missing), naming what is missing."""
    markers = read_markers(path)
    try:
        return build_document(markers, refine=refine)
    except OperationError as exc:
        raise OperationError(
            f"Cannot open {Path(path).name} as a motion: {exc}. The app shows markers over a motion only: "
            "open a motion (a skeleton) and add these markers with Markers > Add markers"
        ) from None


def file_alignment(markers: MarkerSet) -> MarkerAlignment:
    """Markers over a skeleton built from them: the file's axes, scaled to millimetres."""
    scale = unit_factor(unit_named(markers.units), UNITS["mm"])
    return MarkerAlignment(transform=Similarity(scale=scale), method=FILE_SPACE, units=markers.units)


def show_overlays(state: StudioState, document: MarkerDocument) -> None:
    """The markers in the file's space and the pelvis frames the root was solved from."""
    state.set_markers(document.markers, file_alignment(document.markers))
    pelvis = document.built.result.pelvis  # in skeleton units: the built skeleton's are mm
    state.set_pelvis(dataclasses.replace(pelvis, units="mm"))


def show_marker_document(state: StudioState, document: MarkerDocument, path: str | Path, layers=None) -> str:
    """Make ``document`` the state's document (history afresh), show its markers and pelvis
    frames, and the lab model's points as a layer of ``layers`` (app.model.layers.Layers)
    when the file has them. Returns the message to show."""
    state.open_document(document.snapshot, path)
    show_overlays(state, document)
    add_model_layer(document, path, layers)
    text = f"Opened {Path(path).name}: {document.summary()}"
    valid = document.built.result.frame_valid
    first = int(np.argmax(valid)) if valid.any() else 0
    if first:  # before it the markers give no pelvis: the motion holds that first pose
        state.set_frame(first)
        text += f"; shown from frame {first}, the first where the markers give the pelvis"
    return text


def add_model_layer(document: MarkerDocument, path: str | Path, layers) -> None:
    """The lab model's points of ``document`` as a layer of ``layers`` (replacing one of the
    same file), in the file's space; it goes when another document opens."""
    if layers is not None and document.model_points is not None:
        name = f"{Path(path).name}: lab model"
        for index in reversed(range(len(layers))):
            if layers[index].name == name:
                layers.remove(index)
        alignment = file_alignment(document.model_points)
        layers.add_markers(document.model_points, name, alignment=alignment, document_bound=True)


class BuildSkeletonEdit(QUndoCommand):
    """Markers > Build skeleton: the document replaced by the skeleton built from the markers
    shown; undo gives back the motion and the markers' alignment of before."""

    def __init__(self, state: StudioState, document: MarkerDocument) -> None:
        super().__init__(f"Build skeleton ({document.built.built.set_match.definition.name})")
        self.state = state
        self.document = document
        self.before = state.snapshot
        overlay = state.marker_overlay
        self.before_markers = None if overlay is None else (overlay.markers, overlay.alignment)
        self.before_pelvis = None if state.pelvis is None else state.pelvis.source

    def redo(self) -> None:
        self.state.apply_snapshot(self.document.snapshot)
        show_overlays(self.state, self.document)

    def undo(self) -> None:
        self.state.apply_snapshot(self.before)
        if self.before_markers is None:
            self.state.set_markers(None)
            return
        self.state.set_markers(*self.before_markers)
        if self.before_pelvis is not None:
            self.state.set_pelvis(self.before_pelvis)


def build_from_markers(markers: MarkerSet, *, refine: bool = False) -> MarkerDocument:
    """The document built from markers already read (for the worker): Markers > Build skeleton.

    Raises OperationError naming what is missing."""
    try:
        return build_document(markers, refine=refine)
    except OperationError as exc:
        raise OperationError(f"Build skeleton from {Path(markers.source or '').name or 'the markers'}: {exc}") from None


def push_build_skeleton(state: StudioState, document: MarkerDocument) -> bool:
    """Replace the document by ``document`` as one undoable edit."""
    if state.snapshot is None:
        state.show_message("Build skeleton: no motion is open")
        return False
    state.undo_stack.push(BuildSkeletonEdit(state, document))
    state.show_message(f"Built the skeleton: {document.summary()}")
    return True


def joint_section(document: MarkerDocument | None, state: StudioState, frame: int, joint: int | None) -> list[str]:
    """The inspector's part (HTML) for a joint of a skeleton built from markers: how its
    centre was placed (formula, citation), its bone's fitted length with the spread of the
    measured lengths, and after a refinement the residual of the markers its bone carries at
    ``frame``. Nothing when the document is not ``document``'s skeleton (another file, or
    the motion of before a Build skeleton, after an undo)."""
    motion = state.motion
    if document is None or motion is None or joint is None:
        return []
    built, name = document.built.built, motion.names[joint]
    if set(motion.names) != set(built.skeleton.names):
        return []
    j = built.skeleton.names.index(name)
    lines = [f"placed by {html.escape(built.methods.get(name, '?'))}"]
    if np.isfinite(built.lengths[j]):
        low, high = built.span[j]
        lines.append(
            f"bone {built.lengths[j]:.1f} mm (the median over the frames; RMS spread {built.spread[j]:.1f} mm, "
            f"5-95% {low:.1f}-{high:.1f} mm)"
        )
    refinement = document.built.refinement
    if refinement is not None and frame < refinement.residuals.shape[0]:
        carried = np.flatnonzero(document.built.bones == j)
        residual = refinement.residuals[frame, carried]
        seen = [f"{document.built.labels[m]} {r:.1f}" for m, r in zip(carried, residual) if np.isfinite(r)]
        if seen:
            lines.append(f"marker residuals (mm): {', '.join(seen)}")
    set_name = html.escape(built.set_match.definition.name)
    return [f"<p><b>Built from markers</b> (set {set_name}): " + "<br/>".join(lines) + "</p>"]
