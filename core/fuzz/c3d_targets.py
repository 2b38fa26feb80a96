"""Fuzz target for C3D files: the real ones, cut and corrupted where their structure lives."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from gmr_studio.core.fuzz.targets import Target, _shared
from gmr_studio.core.markers.c3d import read_c3d


@cache
def c3d_seeds() -> list[tuple[str, bytes]]:
    return [(path.name, path.read_bytes()) for path in _shared("**/*.c3d")]


def c3d_structure(data: bytes) -> list[int]:
    """Cuts at the header, inside it, at each 512-byte block of the parameter section and
    the start of the data (the parameter section is at most a few dozen blocks)."""
    if len(data) < 512:
        return [0, len(data) // 2]
    parameter_block = max(data[0], 1)
    data_block = int.from_bytes(data[16:18], "little")  # header word 9: first block of data
    blocks = range(parameter_block - 1, min(data_block, parameter_block + 40))
    points = [0, 1, 2, 256, 511] + [512 * b for b in blocks] + [512 * b + 4 for b in blocks]
    if 0 < data_block * 512 < len(data):
        points += [512 * (data_block - 1), 512 * (data_block - 1) + 16, len(data) - 1]
    return sorted({p for p in points if 0 <= p < len(data)})


#: the reader gives ezc3d 10 s plus 1 s per MB; the fuzzer waits longer than that
C3D_TIMEOUT = 20.0


def _read_c3d(path: Path, data: bytes, seed: str):
    return read_c3d(path)


def targets(mutations, check_markers) -> dict[str, Target]:
    return {
        "c3d": Target(
            "c3d",
            ".c3d",
            c3d_seeds,
            _read_c3d,
            check_markers,
            mutations,
            needs_file=True,
            structure=c3d_structure,
            timeout=C3D_TIMEOUT,
        )
    }
