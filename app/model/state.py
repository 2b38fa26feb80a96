"""The one state object of the app: the document, its cached kinematics, what is shown.

Widgets read the state and subscribe to its signals (handlers named ``_on_<thing>_changed``);
they change it only through its methods, and the document's motion only through the undo
stack (:mod:`app.commands`). Widgets never call each other.

The document is a :class:`Snapshot`: an immutable GMR :class:`~core.model.motion.Motion` with
the world positions (F, J, 3) of every joint for every frame, computed once with the
vectorised forward kinematics, and their world rotations (F, J, 3, 3), computed once for
every frame when a view first shows joint frames (axes, the teaching overlay, the
inspector). The views index these arrays; an edit swaps in another snapshot, and undo swaps
the previous one back (the same objects, so undo restores positions and structure exactly
and recomputes nothing but the world rotations, which only the document shown holds: the
snapshots the history keeps let theirs go, so that it keeps more steps). An edit whose
result's world positions follow from the document's (shift root, split, join, split all,
join all, remove dummy joints, trim, mirror, up axis, scale:
:class:`core.edits.edited.Edited`) hands the new snapshot the old one's array, or makes it
from that in one pass, instead of running forward kinematics again
(:meth:`Snapshot.of_edit`).
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path

import numpy as np
from PyQt6.QtCore import QObject, pyqtSignal
from PyQt6.QtGui import QUndoStack

from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.formats.bvh import FileChannels
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.markers import MarkerSet
from gmr_studio.core.markers.alignment import MarkerAlignment, auto_alignment, markers_on_motion_frames
from gmr_studio.core.markers.pelvis import PelvisFrames
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.timebase.clock import frame_seconds

#: overlay name -> shown at start
OVERLAYS: dict[str, bool] = {
    "ground": True,
    "soft_links": True,
    "axes": False,
    "trails": False,
    "labels": False,
    "markers": True,
    "marker_labels": True,
    "pelvis": True,
    "follow": True,  # the camera moves along with the figure
}
#: memory the undo history may hold (snapshots of motion + caches), bytes
UNDO_MEMORY_BUDGET = 2 * 1024**3


def _readonly(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


@dataclasses.dataclass(frozen=True, eq=False)
class Snapshot:
    """A motion and its forward kinematics for every frame.

    Attributes
    ----------
    motion : the GMR (pre-rotation) motion.
    positions : (F, J, 3) float64 world positions, read-only.
    rotations : (F, J, 3, 3) float64 world rotations, read-only: those given at
        construction, else computed for every frame on first use (the views that show
        joint frames ask for them; drawing the figure needs only the positions).
    file_channels : the rotation channel values of the BVH file the motion was read from
        (as written, for the inspector), or None.
    """

    motion: Motion
    positions: np.ndarray
    known_rotations: dataclasses.InitVar[np.ndarray | None] = None
    file_channels: FileChannels | None = None

    def __post_init__(self, known_rotations: np.ndarray | None) -> None:
        if known_rotations is not None:
            self.__dict__["rotations"] = known_rotations  # the cached value of ``rotations``

    @functools.cached_property
    def rotations(self) -> np.ndarray:
        """(F, J, 3, 3) world rotations of every joint (see the class docstring)."""
        return _readonly(forward_kinematics(self.motion, threads=None)[1])  # all cores

    def rotations_at(self, frame: int) -> np.ndarray:
        """(J, 3, 3) world rotations at one frame: read from ``rotations`` when they are at
        hand, else computed for that frame alone (what shows one frame, such as the
        inspector, does not make every frame's)."""
        if self.holds_rotations:
            return self.rotations[frame]
        return forward_kinematics(self.motion.frame_slice(slice(frame, frame + 1)))[1][0]

    @property
    def holds_rotations(self) -> bool:
        """The world rotations are at hand (given, or computed since)."""
        return "rotations" in self.__dict__

    def let_go_of_rotations(self) -> None:
        """Free the world rotations (computed again on next use): a snapshot the history
        keeps while another is shown holds only its motion and positions."""
        self.__dict__.pop("rotations", None)

    @classmethod
    def of(cls, motion: Motion, file_channels: FileChannels | None = None) -> Snapshot:
        positions = forward_kinematics(motion, with_rotations=False, threads=None)[0]  # all cores
        return cls(motion, _readonly(positions), None, file_channels)

    @classmethod
    def of_edit(cls, before: Snapshot, edited: Edited) -> Snapshot:
        """The snapshot of an operation's result on ``before``'s motion: its world positions
        follow from ``before``'s (the same array where every joint keeps its own, else
        gathered, sliced, turned or scaled in one pass;
        :meth:`core.edits.edited.Edited.world_positions`), which equal the result's forward
        kinematics to rounding, and so do its world rotations when they are ``before``'s
        very array; computed afresh when the result's frames are not the input's."""
        if edited.frames is None:
            return cls.of(edited.motion)
        positions = _readonly(edited.world_positions(before.positions, threads=None))
        kept = before.holds_rotations and edited.keeps_rotations(before.rotations)
        return cls(edited.motion, positions, before.rotations if kept else None)

    @property
    def nbytes(self) -> int:
        """Memory held by the arrays this snapshot does not share with others (at most)."""
        m = self.motion
        held = m.rotations.nbytes + m.translations.nbytes + self.positions.nbytes
        return int(held + (self.rotations.nbytes if self.holds_rotations else 0))


@dataclasses.dataclass(frozen=True, eq=False)
class MarkerOverlay:
    """Markers as drawn over the motion.

    Attributes
    ----------
    markers : the marker set as read (file units and axes, its own rate).
    alignment : how they map onto the motion.
    positions : (F, M, 3) float64 on the motion's frames and axes, NaN for gaps.
    computed : (F, M) bool on the motion's frames: samples the capture software computed
        (``MarkerSet.computed``), or None when not given (none).
    """

    markers: MarkerSet
    alignment: MarkerAlignment
    positions: np.ndarray
    computed: np.ndarray | None = None


@dataclasses.dataclass(frozen=True, eq=False)
class PelvisOverlay:
    """Recovered pelvis frames on the motion's frames and axes.

    Attributes
    ----------
    rotations : (F, 3, 3) world rotations (identity where not valid).
    origins : (F, 3) positions, NaN where not valid.
    residuals : (F,) fit residuals, NaN where not valid.
    source : the recovered frames as computed (marker axes and rate).
    """

    rotations: np.ndarray
    origins: np.ndarray
    residuals: np.ndarray
    source: PelvisFrames


class StudioState(QObject):
    """Document, cache, current frame, selection, overlays and markers; emits what changes."""

    document_changed = pyqtSignal()  # another document: views rebuild and reset the camera
    document_shown = pyqtSignal()  # its first frame is drawn: work that frame does not need starts
    motion_changed = pyqtSignal()  # the same document was edited (or undone): views rebuild in place
    frame_changed = pyqtSignal(int)
    selection_changed = pyqtSignal(int)  # joint index, -1 for none
    overlay_changed = pyqtSignal(str, bool)
    markers_changed = pyqtSignal()
    marker_selection_changed = pyqtSignal(int)  # marker index, -1 for none
    pelvis_changed = pyqtSignal()
    path_changed = pyqtSignal(str)
    modified_changed = pyqtSignal(bool)
    message = pyqtSignal(str)  # for the status bar
    range_changed = pyqtSignal(int, int)  # frame range [start, stop) for range actions; (-1, -1): none

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.undo_stack = QUndoStack(self)
        self.undo_stack.cleanChanged.connect(self._on_clean_changed)
        self.snapshot: Snapshot | None = None
        #: the channel values of the file the document was read from (kept through edits)
        self.file_channels: FileChannels | None = None
        self.path: Path | None = None
        self.frame = 0
        self.selected: int | None = None
        self.overlays = dict(OVERLAYS)
        self.marker_overlay: MarkerOverlay | None = None
        self.selected_marker: int | None = None
        self.pelvis: PelvisOverlay | None = None
        self.frame_range: tuple[int, int] | None = None
        #: a view draws the document and says when its first frame is drawn (see first_frame_drawn)
        self.drawn_by_view = False
        self.shown = True  # the document's first frame is drawn (False from open_document until then)

    # ------------------------------------------------------------------ the document
    @property
    def motion(self) -> Motion | None:
        return None if self.snapshot is None else self.snapshot.motion

    @property
    def positions(self) -> np.ndarray | None:
        """(F, J, 3) world positions of the document, or None."""
        return None if self.snapshot is None else self.snapshot.positions

    @property
    def rotations(self) -> np.ndarray | None:
        """(F, J, 3, 3) world rotations of the document, or None."""
        return None if self.snapshot is None else self.snapshot.rotations

    @property
    def modified(self) -> bool:
        return not self.undo_stack.isClean()

    def open_document(self, snapshot: Snapshot, path: str | Path | None) -> None:
        """Show another document: history, selection, markers and pelvis frames start afresh.

        ``document_changed`` builds what its first frame needs; ``document_shown`` follows once
        that frame is drawn (:meth:`first_frame_drawn`; at once when no view draws it), and the
        analyses the frame does not need (the checks, the foot contacts) start then."""
        self.shown = False
        self.undo_stack.clear()
        self.undo_stack.setUndoLimit(undo_limit_for(snapshot))
        self.snapshot = snapshot
        self.file_channels = snapshot.file_channels
        self.path = Path(path) if path is not None else None
        self.frame = 0
        self.selected = None
        self.marker_overlay = None
        self.selected_marker = None
        self.pelvis = None
        self.set_frame_range(-1, -1)
        self.document_changed.emit()
        self.path_changed.emit(str(self.path or ""))
        self.frame_changed.emit(0)
        self.selection_changed.emit(-1)
        self.markers_changed.emit()
        self.pelvis_changed.emit()
        self.modified_changed.emit(False)
        if not self.drawn_by_view:
            self.first_frame_drawn()

    def first_frame_drawn(self) -> None:
        """The document's first frame is drawn (the view says so, or a caller that needs the
        analyses now, e.g. a screenshot): emit ``document_shown``, once per document."""
        if not self.shown and self.snapshot is not None:
            self.shown = True
            self.document_shown.emit()

    def apply_snapshot(self, snapshot: Snapshot) -> None:
        """Replace the document's motion (commands call this from redo and undo).

        The selection follows the joint, by name, whatever its index in the new motion; a
        joint the new motion does not have is deselected. Stale status messages are cleared.
        """
        if self.snapshot is not None and snapshot.motion.n_frames != self.snapshot.motion.n_frames:
            self.frame = min(self.frame, max(snapshot.motion.n_frames - 1, 0))
            self.set_frame_range(-1, -1)
        followed = self.follow_joint(self.selected, snapshot.motion)
        moved = followed != self.selected
        if moved and self.selected is not None:  # views drop the old index before they rebuild
            self.selected = None
            self.selection_changed.emit(-1)
        if self.snapshot is not None and self.snapshot is not snapshot:
            self.snapshot.let_go_of_rotations()  # only the document shown holds them
        self.snapshot = snapshot
        self.message.emit("")
        self.motion_changed.emit()
        if moved and followed is not None:
            self.selected = followed
            self.selection_changed.emit(followed)

    def follow_joint(self, joint: int | None, motion: Motion) -> int | None:
        """The index in ``motion`` of the current motion's joint ``joint`` (by name), or None."""
        if joint is None or self.motion is None or joint >= self.motion.n_joints:
            return None
        name = self.motion.names[joint]
        return motion.names.index(name) if name in motion.names else None

    def mark_saved(self, path: str | Path) -> None:
        """The document was written to ``path``: it is now the document's file, unmodified."""
        self.path = Path(path)
        self.undo_stack.setClean()
        self.path_changed.emit(str(self.path))

    def _on_clean_changed(self, clean: bool) -> None:
        self.modified_changed.emit(not clean)

    # -------------------------------------------------------------- frame, selection
    @property
    def n_frames(self) -> int:
        return 0 if self.snapshot is None else self.snapshot.motion.n_frames

    def set_frame(self, frame: int) -> None:
        frame = int(min(max(frame, 0), max(self.n_frames - 1, 0)))
        if frame != self.frame:
            self.frame = frame
            self.frame_changed.emit(frame)

    def step(self, frames: int) -> None:
        self.set_frame(self.frame + frames)

    def select(self, joint: int | None) -> None:
        """Select a joint by index (None or -1 clears the selection)."""
        if joint is not None and (joint < 0 or self.motion is None or joint >= self.motion.n_joints):
            joint = None
        if joint != self.selected:
            self.selected = joint
            self.selection_changed.emit(-1 if joint is None else joint)

    def set_frame_range(self, start: int, stop: int) -> None:
        """Select frames ``[start, stop)`` for range actions (play, loop, trim); clamped to the
        motion; an empty range (e.g. ``-1, -1``) clears it."""
        start, stop = max(int(start), 0), min(int(stop), self.n_frames)
        selected = (start, stop) if start < stop else None
        if selected != self.frame_range:
            self.frame_range = selected
            self.range_changed.emit(*(selected or (-1, -1)))

    def set_overlay(self, name: str, shown: bool) -> None:
        if name not in self.overlays:
            raise KeyError(f"no overlay {name!r}: expected one of {', '.join(self.overlays)}")
        if self.overlays[name] != bool(shown):
            self.overlays[name] = bool(shown)
            self.overlay_changed.emit(name, bool(shown))

    def show_message(self, text: str) -> None:
        self.message.emit(text)

    # ---------------------------------------------------------------------- markers
    def set_markers(self, markers: MarkerSet | None, alignment: MarkerAlignment | None = None) -> None:
        """Show a marker set over the motion (None removes it); without an alignment, the
        automatic one (:func:`app.alignment.auto_alignment`)."""
        self.pelvis = None
        self.selected_marker = None
        if markers is None or self.snapshot is None:
            self.marker_overlay = None
        else:
            self.marker_overlay = marker_overlay_on(markers, self.snapshot, alignment)
        self.markers_changed.emit()
        self.marker_selection_changed.emit(-1)
        self.pelvis_changed.emit()

    def set_alignment(self, alignment: MarkerAlignment) -> None:
        """Re-align the markers shown (and the pelvis frames recovered from them)."""
        if self.marker_overlay is None:
            return
        self.marker_overlay = marker_overlay_on(self.marker_overlay.markers, self.snapshot, alignment)
        self.markers_changed.emit()
        if self.pelvis is not None:
            self.set_pelvis(self.pelvis.source)

    def select_marker(self, marker: int | None) -> None:
        if marker is not None and (
            self.marker_overlay is None or not 0 <= marker < self.marker_overlay.markers.n_markers
        ):
            marker = None
        if marker != self.selected_marker:
            self.selected_marker = marker
            self.marker_selection_changed.emit(-1 if marker is None else marker)

    def set_pelvis(self, pelvis: PelvisFrames | None) -> None:
        """Show pelvis frames recovered from the current markers (marker axes and rate)."""
        if pelvis is None or self.marker_overlay is None:
            self.pelvis = None
        else:
            overlay = self.marker_overlay
            self.pelvis = pelvis_on_motion(pelvis, overlay.markers.rate, overlay.alignment, self.motion)
        self.pelvis_changed.emit()


def marker_overlay_on(
    markers: MarkerSet, snapshot: Snapshot, alignment: MarkerAlignment | None = None
) -> MarkerOverlay:
    """``markers`` on the frames and in the space of ``snapshot``'s motion: resampled to its
    rate (same clock, by time), shifted by the alignment's frame offset and aligned; without
    an alignment, the automatic one (:func:`app.alignment.auto_alignment`). The marker
    overlay and the marker-set comparison layers (:mod:`app.marker_layers`) both use it."""
    resampled = markers.resampled(snapshot.motion.frame_rate)
    if alignment is None:
        alignment = auto_alignment(
            resampled.positions, resampled.labels, snapshot.positions, snapshot.motion.names, markers.units
        )
    alignment = alignment.replace(units=markers.units)
    on_frames = markers_on_motion_frames(resampled.positions, snapshot.motion.n_frames, alignment.frame_offset)
    flags = np.repeat(resampled.computed[..., None].astype(np.float64), 3, axis=2)  # as points: the same frames
    computed = markers_on_motion_frames(flags, snapshot.motion.n_frames, alignment.frame_offset)[..., 0] == 1.0
    return MarkerOverlay(markers, alignment, _readonly(alignment.apply(on_frames)), _readonly(computed))


def pelvis_on_motion(pelvis: PelvisFrames, rate: float, alignment: MarkerAlignment, motion: Motion) -> PelvisOverlay:
    """Pelvis frames sampled at the motion's frames (nearest marker frame, after the
    alignment's frame offset) and turned into the motion's axes and units.

    ``pelvis.rotations`` act in the marker file's axes, so in the motion's they are
    ``A R A^T`` (``A`` the alignment's rotation); origins in the pelvis' units are taken to
    the marker file's (the alignment's scale is per marker-file unit) and then aligned.
    """
    times = frame_seconds(np.arange(motion.n_frames) + alignment.frame_offset, motion.frame_time)
    source = np.rint(times * rate).astype(np.int64)
    inside = (source >= 0) & (source < pelvis.n_frames)
    index = np.clip(source, 0, max(pelvis.n_frames - 1, 0))
    valid = inside & pelvis.valid[index] if pelvis.n_frames else np.zeros(motion.n_frames, bool)
    rotations = np.broadcast_to(np.eye(3), (motion.n_frames, 3, 3)).copy()
    origins = np.full((motion.n_frames, 3), np.nan)
    residuals = np.full(motion.n_frames, np.nan)
    if valid.any():
        rotations[valid] = alignment.transform.change_frames(pelvis.rotations[index[valid]])
        origins[valid] = alignment.apply(pelvis.origins[index[valid]] * alignment.unit_factor(pelvis.units))
        residuals[valid] = pelvis.residuals[index[valid]]
    return PelvisOverlay(_readonly(rotations), _readonly(origins), _readonly(residuals), pelvis)


def undo_limit_for(snapshot: Snapshot) -> int:
    """How many edits the history keeps for a motion this big (at least 1, at most 100):
    as many as fit in :data:`UNDO_MEMORY_BUDGET` beside the document shown (its motion,
    positions and world rotations) when every edit holds a whole new motion and positions
    as big (the most an edit holds: trim, resample, mirror; shift root, split, join and
    the others share arrays with the snapshot before and hold less, :func:`history_bytes`).
    The snapshots the history keeps hold no world rotations (:meth:`Snapshot.let_go_of_rotations`)."""
    motion = snapshot.motion
    size = max(motion.rotations.nbytes + motion.translations.nbytes + snapshot.positions.nbytes, 1)
    shown = size + motion.rotations.nbytes  # world rotations are as big as the local ones
    return int(min(100, max(1, (UNDO_MEMORY_BUDGET - shown) // size)))


def array_buffer(array: np.ndarray) -> np.ndarray:
    """The array that owns ``array``'s memory (itself, or the base of a view)."""
    while isinstance(array.base, np.ndarray):
        array = array.base
    return array


def history_bytes(state: StudioState) -> int:
    """Bytes held by the document's snapshot and every snapshot its undo history keeps,
    each buffer counted once however many snapshots share it."""
    snapshots = [state.snapshot] if state.snapshot is not None else []
    for index in range(state.undo_stack.count()):
        command = state.undo_stack.command(index)
        snapshots += [getattr(command, "before", None), getattr(command, "after", None)]
    buffers = {}
    for snapshot in filter(None, snapshots):
        motion = snapshot.motion
        held = (snapshot.rotations,) if snapshot.holds_rotations else ()
        for array in (motion.rotations, motion.translations, snapshot.positions, *held):
            owner = array_buffer(array)
            buffers[id(owner)] = owner.nbytes
    return sum(buffers.values())
