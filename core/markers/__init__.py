"""Marker data: reading C3D and TRC files, and turning markers into GMR motion.

``read_markers(path)`` picks the reader by suffix and returns a :class:`MarkerSet`.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from core.errors import MotionFileError
from core.markers.c3d import read_c3d
from core.markers.markerset import MarkerSet
from core.markers.trc import read_trc

MARKER_READERS: dict[str, Callable[..., MarkerSet]] = {".trc": read_trc, ".c3d": read_c3d}


def read_markers(path: str | Path, **options) -> MarkerSet:
    """Read a marker file (by suffix); MotionFileError for unknown formats and bad files."""
    reader = MARKER_READERS.get(Path(path).suffix.lower())
    if reader is None:
        known = ", ".join(sorted(MARKER_READERS))
        raise MotionFileError(path, f"unknown marker format '{Path(path).suffix}': expected one of {known}")
    return reader(path, **options)


__all__ = ["MARKER_READERS", "MarkerSet", "read_markers"]
