"""Features whose core parts come from other branches, found when they are installed.

- Remove dummy joints: ``core.dummies.remove_dummies_edit(motion) -> (Edited, names)`` (formats branch).
- Pelvis frames: ``core.markers.pelvis.recover_pelvis(markers, marker_map) -> PelvisFrames``
  (markers branch); a shipped map made for the markers shown that cannot apply to the
  skeleton (no joint-name map pairs them) is said, even when the recovery is quiet.
- ASF/AMC and C3D: whatever suffixes ``core.formats.READERS`` and
  ``core.markers.MARKER_READERS`` list are offered by the dialogs and accepted by drops.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

import numpy as np

from gmr_studio.app.model.commands import run_edit
from gmr_studio.app.model.state import StudioState
from gmr_studio.core.formats import READERS
from gmr_studio.core.markers import MARKER_READERS


def _find(module: str, name: str) -> Callable | None:
    try:
        return getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        return None


def motion_suffixes() -> set[str]:
    return set(READERS)


def marker_suffixes() -> set[str]:
    return set(MARKER_READERS)


def remove_dummies_available(motion=None) -> bool:
    """The core can remove dummy joints (and, given a motion, it has some)."""
    find = _find("gmr_studio.core.dummies", "find_dummies")
    if find is None or _find("gmr_studio.core.dummies", "remove_dummies_edit") is None:
        return False
    return motion is None or bool(find(motion))


def remove_dummy_joints(state: StudioState) -> bool:
    """Fold zero-offset dummy joints into their children, as an undoable edit (the
    remaining joints keep their cached world transforms: :meth:`Snapshot.of_edit`)."""
    remove = _find("gmr_studio.core.dummies", "remove_dummies_edit")
    if remove is None:
        state.show_message("Remove dummy joints needs core.dummies (not installed in this build)")
        return False
    removed: list[str] = []

    def operation(motion):
        result, names = remove(motion, threads=None)
        removed.extend(names)
        return result

    if not run_edit(state, "Remove dummy joints", operation):
        return False
    state.show_message(f"Removed {len(removed)} dummy joints: {', '.join(removed)}")
    return True


def pelvis_recovery_available() -> bool:
    return _find("gmr_studio.core.markers.pelvis", "recover_pelvis") is not None


def candidate_marker_maps(state: StudioState) -> list:
    """Marker maps to try for the pelvis, best first: the markers named like joints (with
    the app's alignment, so the skeleton's rest pose gives the home pelvis), then every map
    shipped in ``resources/markermaps``."""
    from gmr_studio.core.markers.markermap import MAPS_DIR, Alignment, joints_map

    alignment = state.marker_overlay.alignment
    joints = joints_map(()).replace(
        alignment=Alignment(rotation=alignment.rotation, scale=alignment.scale, offset=alignment.offset)
    )
    return [joints, *sorted(p.stem for p in MAPS_DIR.glob("*.toml"))]


def recover_pelvis_frames(state: StudioState, *, quiet: bool = False) -> bool:
    """Recover the pelvis frames from the shown markers (the first marker map that fits)
    and show them; ``quiet``: say nothing when no map fits."""
    recover = _find("gmr_studio.core.markers.pelvis", "recover_pelvis")
    overlay = state.marker_overlay
    if recover is None or overlay is None:
        if not quiet:
            state.show_message("Pelvis recovery needs markers and core.markers.pelvis.recover_pelvis")
        return False
    from gmr_studio.core.errors import MotionFileError, OperationError

    problems, relevant = [], []
    for marker_map in candidate_marker_maps(state):
        name = getattr(marker_map, "name", marker_map)
        try:
            pelvis = recover(overlay.markers, marker_map, skeleton=state.motion)
        except (OperationError, MotionFileError, ValueError, KeyError) as exc:
            problems.append(f"{name}: {exc}")
            if map_fits_markers(marker_map, overlay.markers):
                relevant.append(f"marker map '{name}' fits these markers but cannot apply to this skeleton: {exc}")
            continue
        if pelvis.valid.any():
            state.set_pelvis(pelvis)
            valid = state.pelvis.residuals[np.isfinite(state.pelvis.residuals)]
            fitted = f" (fitted on {', '.join(pelvis.fit_labels)})" if pelvis.fit_labels != pelvis.labels else ""
            state.show_message(
                f"Pelvis frames from marker map '{name}' ({', '.join(pelvis.labels)}){fitted} on "
                f"{int(pelvis.valid.sum())} of {pelvis.n_frames} frames; median residual "
                f"{np.median(valid) if valid.size else float('nan'):.3g} {pelvis.units}"
            )
            return True
        problems.append(f"{name}: {'; '.join(pelvis.reasons)}")
        if map_fits_markers(marker_map, overlay.markers):
            relevant.append(f"marker map '{name}' fits these markers but gives no pelvis: {'; '.join(pelvis.reasons)}")
    if relevant:  # said even when quiet: a map for these markers that cannot apply is news
        state.show_message(" | ".join(relevant))
    elif not quiet:
        state.show_message("No marker map gives pelvis frames: " + " | ".join(problems[:3]))
    return False


def map_fits_markers(marker_map, markers, share: float = 0.8) -> bool:
    """The map reads real markers, and the marker set has at least ``share`` of them: it was
    made for markers like these (the built-in ``joints`` map never counts)."""
    from gmr_studio.core.errors import MotionFileError
    from gmr_studio.core.markers.markermap import load_marker_map

    try:
        loaded = load_marker_map(marker_map)
    except MotionFileError:
        return False
    labels = set(loaded.labels())
    return bool(labels) and not loaded.joints and len(labels & set(markers.labels)) >= share * len(labels)
