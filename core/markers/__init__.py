"""Marker data: reading C3D and TRC files, and turning markers into GMR motion.

- ``read_markers(path)`` picks the reader by suffix (``.c3d`` through ezc3d, ``.trc``) and
  returns a :class:`MarkerSet` (positions (F, M, 3), gaps NaN, computed (F, M): samples the
  capture software computed, rate, units, subjects).
- ``load_marker_map(name_or_path)``: a :class:`MarkerMap` (``"joints"``, ``"cmu"`` or a
  TOML file), which says how each virtual marker (joint centre) comes from real markers;
  ``compute_virtual_markers`` evaluates it, ``calibrate_marker_map`` fits its clusters.
- ``recover_pelvis(markers, marker_map)``: the pelvis frames by Procrustes
  (:class:`PelvisFrames`, what the app draws over the markers).
- ``markers_to_motion(markers, skeleton, marker_map, reference=...)``: a GMR motion
  (:class:`MarkerMotion`), what ``gmr markers`` runs.

See ``docs/markers.md``.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers.c3d import read_c3d
from gmr_studio.core.markers.markermap import MarkerMap, load_marker_map, save_marker_map
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.pelvis import PelvisFrames, recover_pelvis
from gmr_studio.core.markers.solve import MarkerMotion, markers_to_motion
from gmr_studio.core.markers.trc import read_trc
from gmr_studio.core.markers.virtual import VirtualMarkers, calibrate_marker_map, compute_virtual_markers

MARKER_READERS: dict[str, Callable[..., MarkerSet]] = {".trc": read_trc, ".c3d": read_c3d}


def read_markers(path: str | Path, *, computed: str = "keep", rate: float | None = None, **options) -> MarkerSet:
    """Read a marker file (by suffix); MotionFileError for unknown formats and bad files.

    ``computed``: ``"keep"`` the samples the capture software computed (marked in
    ``MarkerSet.computed``) or ``"drop"`` them (gaps); ``rate``: frames per second for a
    file that states none (None: the file's); ``options`` go to the reader (``data``: a
    TRC's bytes in hand, ``isolate`` for a C3D)."""
    suffix = Path(path).suffix.lower()
    if suffix not in MARKER_READERS:
        known = ", ".join(sorted(MARKER_READERS))
        raise MotionFileError(path, f"unknown marker format '{Path(path).suffix}': expected one of {known}")
    if suffix == ".c3d":
        return read_c3d(path, computed=computed, rate=rate, **options)
    markers = MARKER_READERS[suffix](path, rate=rate, **options)
    return markers.without_computed() if computed == "drop" else markers


__all__ = [
    "MARKER_READERS",
    "MarkerMap",
    "MarkerMotion",
    "MarkerSet",
    "PelvisFrames",
    "VirtualMarkers",
    "calibrate_marker_map",
    "compute_virtual_markers",
    "load_marker_map",
    "markers_to_motion",
    "read_c3d",
    "read_markers",
    "read_trc",
    "recover_pelvis",
    "save_marker_map",
]
