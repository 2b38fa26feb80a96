"""Acclaim ASF/AMC motion capture: the skeleton (ASF) and its motion (AMC), read into GMR.

The public names live here; the ASF parser is :mod:`core.formats.asf`, the AMC reader and
the conversion to pre-rotation :mod:`core.formats.amc`. See ``docs/formats.md`` for the
conventions (which Acclaim rotation order means what, units, the root).
"""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.acclaim_skeleton import (
    ROOT_NAME,
    AcclaimBone,
    AcclaimSkeleton,
    AcclaimUnits,
    axis_rotation,
)
from gmr_studio.core.formats.amc import (
    DEFAULT_FRAME_RATE,
    parse_amc_frames,
    read_amc,
    read_amc_with_channels,
    skeleton_motion,
)
from gmr_studio.core.formats.asf import read_asf
from gmr_studio.core.model.channels import FileChannels
from gmr_studio.core.model.motion import Motion

__all__ = [
    "DEFAULT_FRAME_RATE",
    "ROOT_NAME",
    "AcclaimBone",
    "AcclaimSkeleton",
    "AcclaimUnits",
    "asf_beside",
    "axis_rotation",
    "parse_amc_frames",
    "read_amc",
    "read_amc_file",
    "read_amc_file_with_channels",
    "read_asf",
    "read_asf_file",
    "skeleton_motion",
]


def asf_beside(amc_path: str | Path) -> Path:
    """The skeleton of an AMC file when none is named: the single ``.asf`` in its folder;
    with several, the one named like the AMC (``walk.asf`` for ``walk.amc``) or like its
    subject (``01.asf`` for CMU's ``01_01.amc``). MotionFileError if none can be chosen."""
    amc = Path(amc_path)
    folder = amc.parent
    candidates = sorted(p for p in folder.glob("*") if p.suffix.lower() == ".asf" and p.is_file())
    if len(candidates) == 1:
        return candidates[0]
    for stem in (amc.stem, amc.stem.split("_")[0]):
        named = [p for p in candidates if p.stem == stem]
        if len(named) == 1:
            return named[0]
    if not candidates:
        raise MotionFileError(amc_path, f"no .asf skeleton beside this AMC in {folder or '.'}: name one with --asf")
    listed = ", ".join(p.name for p in candidates)
    raise MotionFileError(amc_path, f"several .asf skeletons beside this AMC ({listed}): name one with --asf")


def read_amc_file(
    path: str | Path,
    asf: str | Path | AcclaimSkeleton | None = None,
    frame_rate: float = DEFAULT_FRAME_RATE,
    data: bytes | None = None,
) -> Motion:
    """``read_motion``'s AMC reader: ``asf`` defaults to the skeleton beside the file."""
    return read_amc(path, asf if asf is not None else asf_beside(path), frame_rate=frame_rate, data=data)


def read_amc_file_with_channels(
    path: str | Path,
    asf: str | Path | AcclaimSkeleton | None = None,
    frame_rate: float = DEFAULT_FRAME_RATE,
    data: bytes | None = None,
) -> tuple[Motion, FileChannels]:
    """:func:`read_amc_file` and the file's rotation dofs as written."""
    skeleton = asf if asf is not None else asf_beside(path)
    return read_amc_with_channels(path, skeleton, frame_rate=frame_rate, data=data)


def read_asf_file(path: str | Path, data: bytes | None = None, **_ignored) -> Motion:
    """``read_motion``'s ASF reader: the skeleton's rest pose as a one-frame GMR motion."""
    return skeleton_motion(read_asf(path, data))
