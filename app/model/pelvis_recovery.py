"""Pelvis frames recovered from the shown markers (:func:`core.markers.pelvis.recover_pelvis`),
trying the marker maps that could describe them, best first.

A shipped map made for the markers shown that cannot apply to the skeleton (no joint-name map
pairs them) is said, even when the recovery is quiet.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.app.model.state import StudioState
from gmr_studio.core.errors import MotionFileError, OperationError
from gmr_studio.core.markers.markermap import MAPS_DIR, joints_map, load_marker_map
from gmr_studio.core.markers.pelvis import recover_pelvis


def candidate_marker_maps(state: StudioState) -> list:
    """Marker maps to try for the pelvis, best first: the markers named like joints (with
    the app's alignment, so the skeleton's rest pose gives the home pelvis), then every map
    shipped in ``resources/markermaps``."""
    alignment = state.marker_overlay.alignment
    joints = joints_map(()).replace(alignment=alignment.transform)
    return [joints, *sorted(p.stem for p in MAPS_DIR.glob("*.toml"))]


def recover_pelvis_frames(state: StudioState, *, quiet: bool = False) -> bool:
    """Recover the pelvis frames from the shown markers (the first marker map that fits)
    and show them; ``quiet``: say nothing when no map fits."""
    overlay = state.marker_overlay
    if overlay is None:
        if not quiet:
            state.show_message("Pelvis recovery needs markers: add a marker file first")
        return False
    problems, relevant = [], []
    for marker_map in candidate_marker_maps(state):
        name = getattr(marker_map, "name", marker_map)
        try:
            pelvis = recover_pelvis(overlay.markers, marker_map, skeleton=state.motion)
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
    try:
        loaded = load_marker_map(marker_map)
    except MotionFileError:
        return False
    labels = set(loaded.labels())
    return bool(labels) and not loaded.joints and len(labels & set(markers.labels)) >= share * len(labels)
