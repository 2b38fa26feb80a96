"""Will a motion's caches fit in memory? Decided before they are allocated.

The app keeps, for every frame, every joint's world position (F, J, 3) and, once a view
shows joint frames, rotation (F, J, 3, 3) in float64 (:class:`app.state.Snapshot`), next to the motion's own rotations
(F, J, 3, 3) and translations (F, J, 3). Opening a motion whose caches do not fit in the
memory the system has available is refused with a message saying how much it would need
and how much there is, instead of the process being killed for running out of memory.
"""

from __future__ import annotations

import os
from pathlib import Path

#: float64 numbers per frame and joint in the caches: position 3 + rotation 9
CACHE_NUMBERS = 3 + 9
#: the caches' working memory on top of themselves, as a fraction of their size (forward
#: kinematics' temporaries, the undo history's next snapshot)
HEADROOM = 0.5
GIB = 1024**3


def cache_bytes(n_frames: int, n_joints: int) -> int:
    """Bytes of the positions (F, J, 3) and rotations (F, J, 3, 3) caches, float64."""
    return int(n_frames) * int(n_joints) * CACHE_NUMBERS * 8


def needed_bytes(n_frames: int, n_joints: int) -> int:
    """Bytes the app must still allocate to show a motion it has read: caches and headroom."""
    return int(cache_bytes(n_frames, n_joints) * (1 + HEADROOM))


def available_bytes(meminfo: Path = Path("/proc/meminfo")) -> int | None:
    """Memory the system can give without swapping (Linux ``MemAvailable``), or None when
    unknown (then nothing is refused)."""
    try:
        for line in meminfo.read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def too_large(n_frames: int, n_joints: int, available: int | None = None) -> str | None:
    """Why a motion of this size cannot be shown (``needs X GiB, Y GiB available``), or None."""
    available = available_bytes() if available is None else available
    needed = needed_bytes(n_frames, n_joints)
    if available is None or needed <= available:
        return None
    return (
        f"{n_frames:,} frames of {n_joints} joints are too large to show: their positions and rotations "
        f"for every frame need {needed / GIB:.1f} GiB, and {available / GIB:.1f} GiB of memory is available"
    )
