"""GMR files: the General Motion Representation as text (pre-rotation, skeleton forests).

The format is BVH's, with these differences (the full description is docs/gmr-format.md):

- the first line is ``GMR 1`` (format and version); lines starting with ``#`` are comments;
- local transforms are pre-rotation, ``L_j = [R_j, R_j t_j]``;
- HIERARCHY may hold several ROOT blocks (a forest); a ROOT's OFFSET is its static world
  position, its position channels its per-frame world position;
- every joint has rotation channels (their order is the composition order); end sites are
  ordinary JOINTs;
- ``SOFTLINK <name>`` in a joint block records the joint it was split from.
"""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.formats.textmotion import format_text_motion, read_text_motion
from gmr_studio.core.model.motion import Motion


def read_gmr(path: str | Path, data: bytes | None = None) -> Motion:
    """Read a GMR file into a pre-rotation :class:`Motion`."""
    return read_text_motion(path, "gmr", data)


def write_gmr(motion: Motion, path: str | Path) -> None:
    """Write a pre-rotation motion as a GMR file, atomically."""
    atomic_write_text(path, format_text_motion(motion, "gmr"))


def gmr_text(motion: Motion) -> str:
    """The GMR file as one string."""
    return "".join(format_text_motion(motion, "gmr"))
