"""BVH files (Biovision hierarchy): post-rotation motion.

Reading accepts any rotation order per joint (mixed in one file), 0 to 6 channels on any
joint (positions replace the OFFSET for that frame), several ROOTs, End Sites (they become
ordinary joints named ``<parent>_End``), CRLF/CR/LF endings, tabs, scientific notation and
names with ``.``, ``:``, ``-``. Errors are :class:`~core.errors.MotionFileError`.
"""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.formats.textmotion import format_text_motion, read_text_motion
from gmr_studio.core.motion import Motion


def read_bvh(path: str | Path, data: bytes | None = None) -> Motion:
    """Read a BVH file into a post-rotation :class:`Motion` (``data``: the bytes, if in hand)."""
    return read_text_motion(path, "bvh", data)


def write_bvh(motion: Motion, path: str | Path) -> None:
    """Write a post-rotation motion as BVH, atomically.

    Leaf joints without channels become End Sites; each joint keeps its rotation order;
    angles are written with 15 significant digits. A GMR motion must be converted first.
    """
    atomic_write_text(path, format_text_motion(motion, "bvh"))


def bvh_text(motion: Motion) -> str:
    """The BVH file as one string."""
    return "".join(format_text_motion(motion, "bvh"))
