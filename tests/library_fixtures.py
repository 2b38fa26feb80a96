"""Fixtures for the library's tests: a folder of real takes (copied from the shared data at
test time, trimmed to what the tests need), bad files beside them, a PNG reader, and records
of made-up files for libraries of thousands of rows.

Import them into a test module (``from tests.library_fixtures import takes``).
"""

from __future__ import annotations

import shutil
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.library.reading import FileRecord
from gmr_studio.core.library.skeletons import Skeleton
from tests.conftest import shared_path

#: the real files of the folder: (shared path, path in the folder)
REAL = (
    ("bvh/cmu_cgspeed_npybvh_example_75f.bvh", "cmu/clip_75f.bvh"),
    ("bvh/bvh-python_test_mocapbank.bvh", "mocapbank.bvh"),
    ("cmu/subject02/02.asf", "cmu/02/02.asf"),
    ("cmu/subject02/02_01.amc", "cmu/02/02_01.amc"),
    ("gltf/lab0_CesiumMan.glb", "gltf/CesiumMan.glb"),
    ("trc/opensim-core_markers_walk.trc", "markers/walk.trc"),
)
#: files that cannot be read (path in the folder)
BAD = ("broken/truncated.bvh", "broken/not_a.c3d", "broken/walk_poses.npz")


def make_takes(folder: Path) -> Path:
    """Copy the real files into ``folder`` and write the bad ones beside them."""
    for shared, relative in REAL:
        target = folder / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(shared_path(shared), target)
    broken = folder / "broken"
    broken.mkdir(parents=True, exist_ok=True)
    text = shared_path("bvh/bvh-python_test_mocapbank.bvh").read_bytes()
    (broken / "truncated.bvh").write_bytes(text[: len(text) // 2])  # cut in the middle of a frame
    (broken / "not_a.c3d").write_bytes(b"\x02\x50" + bytes(600))
    np.savez(broken / "walk_poses.npz", poses=np.zeros((3, 156)), trans=np.zeros((3, 3)))  # AMASS: no body model
    return folder


@pytest.fixture
def takes(tmp_path) -> Path:
    """A folder of real takes and bad files (module docstring)."""
    return make_takes(tmp_path / "takes")


def read_png(data: bytes) -> np.ndarray:
    """(H, W, 3) uint8 of an 8-bit RGB PNG whose rows are unfiltered (what the library
    writes), read chunk by chunk with its CRCs checked."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    offset, chunks = 8, {}
    while offset < len(data):
        (length,) = struct.unpack(">I", data[offset : offset + 4])
        kind = data[offset + 4 : offset + 8]
        body = data[offset + 8 : offset + 8 + length]
        (crc,) = struct.unpack(">I", data[offset + 8 + length : offset + 12 + length])
        assert zlib.crc32(kind + body) & 0xFFFFFFFF == crc
        chunks[kind] = chunks.get(kind, b"") + body
        offset += 12 + length
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", chunks[b"IHDR"])
    assert (depth, colour, interlace) == (8, 2, 0) and b"IEND" in chunks
    rows = np.frombuffer(zlib.decompress(chunks[b"IDAT"]), np.uint8).reshape(height, 1 + 3 * width)
    assert (rows[:, 0] == 0).all()
    return rows[:, 1:].reshape(height, width, 3)


FORMATS = ("bvh", "c3d", "amc", "glb")
RIGS = (
    Skeleton(("hips", "spine", "head"), (-1, 0, 1)),
    Skeleton(("root", "lfemur", "rfemur", "lowerback"), (-1, 0, 0, 0)),
    Skeleton(("a", "b"), (-1, 0)),
)


def made_up_records(n: int, seed: int = 3) -> list[FileRecord]:
    """``n`` records of made-up files: ties in every field, some failed, some with problems."""
    rng = np.random.default_rng(seed)
    made = []
    for k in range(n):
        fmt = FORMATS[int(rng.integers(len(FORMATS)))]
        name = f"{'Take' if k % 3 else 'take'}{int(rng.integers(400)):04d}.{fmt}"  # names repeat, cases differ
        path = f"/lib/{'ab'[k % 2]}/{k:05d}/{name}"
        record = FileRecord(path, 100 + k % 7, 10**18 + k % 11, "", f"{k:032x}", "", fmt, "motion")
        if k % 17 == 0:
            record.status, record.message = "failed", f"{path}:1:1: not a motion"
        else:
            rig = RIGS[int(rng.integers(len(RIGS)))]
            record.frames = int(rng.integers(1, 40)) * 30
            record.frame_rate = float(rng.choice([30.0, 60.0, 120.0]))
            record.duration = record.frames / record.frame_rate
            record.joints, record.roots, record.skeleton = rig.n_joints, 1, rig
            levels = rng.integers(0, 4, size=3)  # a count of info, warning, error findings
            kinds = [("pop", 1, int(levels[0])), ("jitter", 2, int(levels[1])), ("foot-skate", 3, int(levels[2]))]
            record.problems = tuple(p for p in kinds if p[2])
            record.infos, record.warnings, record.errors = (int(v) for v in levels)
            record.findings = int(levels.sum())
            record.worst_level = max((level for _, level, _ in record.problems), default=0)
            record.worst = (None, "info", "warning", "error")[record.worst_level]
        made.append(record)
    return made


def write_records(library, records: list) -> None:
    """Write ``records`` into ``library`` in batches, group their skeletons and gather the
    query planner's statistics, as indexing does."""
    for start in range(0, len(records), 500):
        library.write([(r, r.path.rsplit("/", 2)[0]) for r in records[start : start + 500]])
    library.regroup()
    library.connection.execute("ANALYZE")
