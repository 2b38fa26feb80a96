"""BVH files (Biovision hierarchy): post-rotation motion.

Reading accepts any rotation order per joint (mixed in one file), 0 to 6 channels on any
joint (positions replace the OFFSET for that frame), several ROOTs, End Sites (they become
ordinary joints named ``<parent>_End``), CRLF/CR/LF endings, tabs, scientific notation and
names with ``.``, ``:``, ``-``. Errors are :class:`~core.errors.MotionFileError`.
"""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.formats.textmotion import (
    format_text_motion,
    motion_from_header,
    parse_text_file,
    read_text_motion,
)
from gmr_studio.core.model.channels import FileChannels
from gmr_studio.core.model.motion import Motion

__all__ = ["FileChannels", "bvh_text", "read_bvh", "read_bvh_with_channels", "write_bvh"]


def read_bvh(path: str | Path, data: bytes | None = None) -> Motion:
    """Read a BVH file into a post-rotation :class:`Motion` (``data``: the bytes, if in hand)."""
    return read_text_motion(path, "bvh", data)


def read_bvh_with_channels(path: str | Path, data: bytes | None = None) -> tuple[Motion, FileChannels]:
    """:func:`read_bvh`, and the file's rotation channel values as written
    (:class:`core.model.channels.FileChannels`, re-exported here)."""
    header, values, note = parse_text_file(path, "bvh", data)
    motion = motion_from_header(header, values, "bvh", str(path), note)
    values.flags.writeable = False
    orders, angles, column = {}, {}, 0
    for joint in header.joints:
        rotation_columns = [column + k for k, name in enumerate(joint.channels) if name.endswith("rotation")]
        if rotation_columns:
            orders[joint.name] = "".join(joint.channels[k - column][0] for k in rotation_columns)
            first, last = rotation_columns[0], rotation_columns[-1]
            contiguous = last - first + 1 == len(rotation_columns)  # as files have them: a view
            block = values[:, first : last + 1] if contiguous else values[:, rotation_columns]
            block.flags.writeable = False
            angles[joint.name] = block
        column += len(joint.channels)
    return motion, FileChannels(orders, angles, kind="bvh")


def write_bvh(motion: Motion, path: str | Path) -> None:
    """Write a post-rotation motion as BVH, atomically.

    Leaf joints without channels become End Sites; each joint keeps its rotation order;
    angles are written with 15 significant digits. A GMR motion must be converted first.
    BVH states no unit: a motion in metres that came from other units (a glTF export read
    back) is written in those units again (:func:`core.edits.world.in_source_unit`).
    """
    atomic_write_text(path, format_text_motion(motion, "bvh"))


def bvh_text(motion: Motion) -> str:
    """The BVH file as one string."""
    return "".join(format_text_motion(motion, "bvh"))
