"""Features whose core parts come from other branches, found when they are installed.

- Remove dummy joints: ``core.dummies.remove_dummies(motion) -> Motion`` (formats branch).
- Pelvis frames: ``core.markers.pelvis.recover_pelvis(markers, marker_map) -> PelvisFrames``
  (markers branch).
- ASF/AMC and C3D: whatever suffixes ``core.formats.READERS`` and
  ``core.markers.MARKER_READERS`` list are offered by the dialogs and accepted by drops.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

from app.commands import run_edit
from app.state import StudioState
from core.formats import READERS
from core.markers import MARKER_READERS


def _find(module: str, name: str) -> Callable | None:
    try:
        return getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        return None


def motion_suffixes() -> set[str]:
    return set(READERS)


def marker_suffixes() -> set[str]:
    return set(MARKER_READERS)


def remove_dummies_available() -> bool:
    return _find("core.dummies", "remove_dummies") is not None


def remove_dummy_joints(state: StudioState) -> bool:
    """Fold zero-offset dummy joints into their children, as an undoable edit."""
    remove = _find("core.dummies", "remove_dummies")
    if remove is None:
        state.show_message("Remove dummy joints needs core.dummies (not installed in this build)")
        return False
    return run_edit(state, "Remove dummy joints", remove)


def pelvis_recovery_available() -> bool:
    return _find("core.markers.pelvis", "recover_pelvis") is not None


def recover_pelvis_frames(state: StudioState) -> bool:
    """Recover the pelvis frames from the shown markers and show them."""
    recover = _find("core.markers.pelvis", "recover_pelvis")
    overlay = state.marker_overlay
    if recover is None or overlay is None:
        state.show_message("Pelvis recovery needs markers and core.markers.pelvis.recover_pelvis")
        return False
    try:
        pelvis = recover(overlay.markers, None)
    except (ValueError, KeyError) as exc:
        state.show_message(f"Cannot recover the pelvis frames: {exc}")
        return False
    state.set_pelvis(pelvis)
    valid = int(pelvis.valid.sum())
    state.show_message(f"Pelvis frames recovered on {valid} of {pelvis.n_frames} frames")
    return True
