"""Every edit of the document is a :class:`QUndoCommand` that swaps immutable snapshots.

The core operations never change their input, so a command keeps the snapshot before and
the one after (motion plus its cached kinematics) and its redo and undo just hand one or
the other to the state: undo restores the very same arrays. An edit that the core refuses
(:class:`~core.errors.OperationError`, e.g. joining the last root) is never pushed; its
message goes to the status bar and nothing changes. Neither is an edit that fails
unexpectedly (a bug, out of memory): it is logged to the crash log and reported, and the
document and history stay as they were.
"""

from __future__ import annotations

from collections.abc import Callable

from PyQt6.QtGui import QUndoCommand

from gmr_studio.app.crash import report_unexpected
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.edits.clip import resample_edit, trim_edit
from gmr_studio.core.edits.dummies import find_dummies, remove_dummies_edit
from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.edits.mirror import mirror_edit, mirror_pairs, pairs_text
from gmr_studio.core.edits.operations import (
    join_all_edit,
    join_edit,
    shift_root_edit,
    split_all_edit,
    split_edit,
)
from gmr_studio.core.edits.world import change_up_axis_edit, scale_lengths_edit
from gmr_studio.core.errors import OperationError
from gmr_studio.core.model.motion import Motion

#: left/right pairs the status bar names after a mirror (the rest counted: one line at 1280 px)
MIRROR_PAIRS_SHOWN = 4


class MotionEdit(QUndoCommand):
    """One edit: redo shows ``after``, undo shows ``before``."""

    def __init__(self, state: StudioState, text: str, before: Snapshot, after: Snapshot) -> None:
        super().__init__(text)
        self.state = state
        self.before = before
        self.after = after

    def redo(self) -> None:
        self.state.apply_snapshot(self.after)

    def undo(self) -> None:
        self.state.apply_snapshot(self.before)


def run_edit(state: StudioState, text: str, operation: Callable[[Motion], Motion | Edited]) -> bool:
    """Apply ``operation`` to the document as an undoable edit named ``text``.

    An operation that returns an :class:`~core.edits.edited.Edited` hands the new snapshot
    the document's kinematics (:meth:`Snapshot.of_edit`); one that returns a motion gets
    its forward kinematics computed. Returns True if the edit was pushed. A refused
    operation (OperationError) or one that changes nothing is reported in the status bar
    and leaves the document and history as they were.
    """
    before = state.snapshot
    if before is None:
        state.show_message(f"{text}: no motion is open")
        return False
    try:
        result = operation(before.motion)
        motion = result.motion if isinstance(result, Edited) else result
        if motion is before.motion:
            after = None
        elif isinstance(result, Edited):
            after = Snapshot.of_edit(before, result)
        else:
            after = Snapshot.of(motion)
    except OperationError as exc:
        state.show_message(f"{text} refused: {exc}")
        return False
    except Exception as exc:
        report_unexpected(text, exc, state.show_message)
        return False
    if after is None:
        state.show_message(f"{text}: nothing to change")
        return False
    state.undo_stack.push(MotionEdit(state, text, before, after))
    state.show_message(text)
    return True


def _name(state: StudioState, joint: int) -> str:
    return state.motion.names[joint] if state.motion is not None else str(joint)


#: how a shift root's edit is named in the history: ``Shift root to 'LeftHand'``
SHIFT_ROOT_TEXT = "Shift root to"
#: the operations edit blocks of frames on every core, as the cache is computed
THREADS = None


def shift_root_to(state: StudioState, joint: int) -> bool:
    """Shift the root of the joint's tree to the joint (:func:`core.edits.operations.shift_root`)."""
    return run_edit(
        state, f"{SHIFT_ROOT_TEXT} '{_name(state, joint)}'", lambda m: shift_root_edit(m, joint, threads=THREADS)
    )


def split_here(state: StudioState, joint: int) -> bool:
    """Split the tree at the joint (it becomes a root with a soft link to its parent)."""
    return run_edit(state, f"Split at '{_name(state, joint)}'", lambda m: split_edit(m, joint, threads=THREADS))


def join_to_parent(state: StudioState, joint: int) -> bool:
    """Join the split root back under its soft-link parent."""
    return run_edit(
        state, f"Join '{_name(state, joint)}' to its parent", lambda m: join_edit(m, joint, threads=THREADS)
    )


def split_everything(state: StudioState) -> bool:
    """Every joint a root: the document's world positions and rotations become the motion's
    translations and rotations (the same arrays; the rotations computed first when no view
    has asked for them yet)."""
    snapshot = state.snapshot
    kinematics = None if snapshot is None else (snapshot.positions, snapshot.rotations)
    return run_edit(state, "Split all", lambda m: split_all_edit(m, kinematics=kinematics))


def join_everything(state: StudioState) -> bool:
    return run_edit(state, "Join all", lambda m: join_all_edit(m, threads=THREADS))


def can_join(motion: Motion | None, joint: int | None) -> bool:
    """Join to parent applies: the joint is a split root (a root holding a soft link)."""
    return motion is not None and joint is not None and motion.parents[joint] < 0 and motion.soft_parents[joint] >= 0


def can_remove_dummies(motion: Motion | None) -> bool:
    """Remove dummy joints applies: the motion has zero-offset dummy joints
    (:func:`core.edits.dummies.find_dummies`)."""
    return motion is not None and bool(find_dummies(motion))


def remove_dummy_joints(state: StudioState) -> bool:
    """Fold zero-offset dummy joints into their children (:func:`core.edits.dummies.remove_dummies`);
    the remaining joints keep their cached world transforms (:meth:`Snapshot.of_edit`), and
    the status bar names the joints removed."""
    removed: list[str] = []

    def operation(motion: Motion) -> Edited:
        result, names = remove_dummies_edit(motion, threads=THREADS)
        removed.extend(names)
        return result

    if not run_edit(state, "Remove dummy joints", operation):
        return False
    state.show_message(f"Removed {len(removed)} dummy joints: {', '.join(removed)}")
    return True


def trim_to_range(state: StudioState, start: int, stop: int) -> bool:
    """Keep frames ``[start, stop)`` (:func:`core.edits.clip.trim`); the cache keeps the
    document's rows of those frames."""
    return run_edit(state, f"Trim to frames {start}-{stop - 1}", lambda m: trim_edit(m, start, stop))


def resample_to(state: StudioState, rate: float) -> bool:
    """Resample to ``rate`` frames per second (:func:`core.edits.clip.resample`); the cache
    keeps the document's rows of every n-th frame when the rate divides its own."""
    return run_edit(state, f"Resample to {rate:g} Hz", lambda m: resample_edit(m, rate))


def mirror_left_right(state: StudioState) -> bool:
    """Swap left and right (:func:`core.edits.mirror.mirror`; the cache is the document's,
    reflected and swapped: :meth:`Snapshot.of_edit`); the status bar says the pairs
    swapped (the first :data:`MIRROR_PAIRS_SHOWN` by name) and the names without a partner."""
    said: list[str] = []

    def operation(motion: Motion) -> Edited:
        result, unmatched = mirror_edit(motion, threads=THREADS)
        said.append(f"swapped {pairs_text(motion.names, mirror_pairs(motion).pairs, MIRROR_PAIRS_SHOWN)}")
        if unmatched:
            said.append(f"no partner for {', '.join(unmatched)} (left as they are)")
        return result

    done = run_edit(state, "Mirror left/right", operation)
    if done:
        state.show_message("Mirror left/right: " + "; ".join(said))
    return done


def up_axis_to(state: StudioState, axis: str) -> bool:
    """Turn the world so that ``axis`` ('y' or 'z') is up (:func:`core.edits.world.change_up_axis`);
    the cache is the document's, turned (:meth:`Snapshot.of_edit`)."""
    return run_edit(state, f"{axis.upper()} up", lambda m: change_up_axis_edit(m, axis, threads=THREADS))


def scale_by(state: StudioState, factor: float) -> bool:
    """Every length times ``factor`` (:func:`core.edits.world.scale_lengths`); the cache's
    positions are the document's scaled, its rotations the document's."""
    return run_edit(state, f"Scale by {factor:g}", lambda m: scale_lengths_edit(m, factor))
