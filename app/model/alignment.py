"""Marker alignment: its home is :mod:`core.markers.alignment` (pure numpy); this module
re-exports it for the app (the up-axis rule is :func:`core.space.up_axis.detect_up_axis`)."""

from __future__ import annotations

from gmr_studio.core.markers.alignment import (
    MAX_FRAME_OFFSET,
    PELVIS_NAMES,
    SNAP_TOLERANCE,
    MarkerAlignment,
    auto_alignment,
    candidate_frame_offsets,
    figure_centre_joint,
    marker_joint_pairs,
    markers_on_motion_frames,
    similarity_fit,
    turned_about,
)
from gmr_studio.core.space.up_axis import detect_up_axis

__all__ = [
    "MAX_FRAME_OFFSET",
    "PELVIS_NAMES",
    "SNAP_TOLERANCE",
    "MarkerAlignment",
    "auto_alignment",
    "candidate_frame_offsets",
    "detect_up_axis",
    "figure_centre_joint",
    "marker_joint_pairs",
    "markers_on_motion_frames",
    "similarity_fit",
    "turned_about",
]
