"""Reading documents and marker files, off the GUI thread.

:func:`load_snapshot` reads any motion file the core knows (BVH, GMR, and ASF/AMC once the
formats branch adds them) as GMR and computes its kinematics for every frame.
:class:`LoadJob` runs a reading function in a worker thread and hands the result (or the
error) back to the GUI thread through a signal, so a long load leaves the window responsive.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from PyQt6.QtCore import QThread, pyqtSignal

from gmr_studio.app.model import memory
from gmr_studio.app.model.state import Snapshot
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import READERS, read_motion_with_channels
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.markers import MARKER_READERS, MarkerSet, read_markers


def motion_suffixes() -> list[str]:
    """Suffixes the core can open as motions, e.g. ['.bvh', '.gmr']."""
    return sorted(READERS)


def marker_suffixes() -> list[str]:
    return sorted(MARKER_READERS)


def file_filter(suffixes: list[str], what: str) -> str:
    """A Qt file-dialog filter such as ``Motion files (*.bvh *.gmr);;All files (*)``."""
    patterns = " ".join(f"*{s}" for s in suffixes)
    return f"{what} ({patterns});;All files (*)"


def load_snapshot(path: str | Path, **options) -> Snapshot:
    """Read a motion file as GMR and compute its forward kinematics for every frame
    (``options`` go to the reader, e.g. ``body_model`` for AMASS ``.npz``).

    Raises MotionFileError for a bad or unknown file, and for a motion whose caches would
    not fit in the memory available (:mod:`app.memory`), before allocating them.
    """
    motion, channels = read_motion_with_channels(path, **options)  # the file's own channels, as written
    motion = pre_from_post(motion)
    refusal = memory.too_large(motion.n_frames, motion.n_joints)
    if refusal is not None:  # before the caches are allocated
        raise MotionFileError(path, refusal)
    return Snapshot.of(motion, file_channels=channels)


def load_markers(path: str | Path) -> MarkerSet:
    return read_markers(path)


class LoadJob(QThread):
    """Runs ``function(path)`` in a worker thread; emits ``loaded(job, result)`` or
    ``failed(job, error)`` (connect them to methods of a QObject of the GUI thread, so they
    are delivered there)."""

    loaded = pyqtSignal(object, object)
    failed = pyqtSignal(object, object)

    def __init__(self, function: Callable[[str], object], path: str | Path, parent=None) -> None:
        super().__init__(parent)
        self.function = function
        self.path = str(path)

    def run(self) -> None:
        try:
            result = self.function(self.path)
        except Exception as exc:
            self.failed.emit(self, exc)
        else:
            self.loaded.emit(self, result)
