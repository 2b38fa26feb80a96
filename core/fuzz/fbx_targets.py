"""Fuzz target for FBX files: the real ones (binary and ASCII), cut and corrupted.

The reader parses in a child process (core/formats/fbx_in), so a file that crashes ufbx
still has to come back as a :class:`~core.errors.MotionFileError`, never take the caller down.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from gmr_studio.core.formats.fbx_in import read_fbx
from gmr_studio.core.fuzz.mutations import flip_bytes, flip_bytes_in_header, truncate_anywhere
from gmr_studio.core.fuzz.targets import Target, _shared, text_structure

#: the binary FBX header: 21 bytes of magic, 2 bytes, the version (4 bytes)
BINARY_MAGIC = b"Kaydara FBX Binary  \x00"
#: a case reads through a child process: the fuzzer waits this long at least
FBX_TIMEOUT = 90.0
#: bytes between cut points in the body of a binary file
BINARY_STEP = 4096


@cache
def fbx_seeds() -> list[tuple[str, bytes]]:
    return [(path.name, path.read_bytes()) for path in _shared("fbx/*.fbx")]


def fbx_structure(data: bytes) -> list[int]:
    """Cuts in the header and every few KB of a binary file (its node records nest too
    deeply to list cheaply); the line starts of an ASCII file's first lines."""
    if not data.startswith(BINARY_MAGIC):
        return text_structure(data)
    return sorted({0, 1, 20, 23, 27, *range(27, len(data), BINARY_STEP), max(len(data) - 1, 0)})


def _read_fbx(path: Path, data: bytes, seed: str):
    return read_fbx(path, data=data)


MUTATIONS = {
    "truncate anywhere": truncate_anywhere,
    "flip bytes": flip_bytes,
    "flip header bytes": flip_bytes_in_header,
}


def targets(check_motion) -> dict[str, Target]:
    return {
        "fbx": Target(
            "fbx", ".fbx", fbx_seeds, _read_fbx, check_motion, MUTATIONS, structure=fbx_structure, timeout=FBX_TIMEOUT
        )
    }
