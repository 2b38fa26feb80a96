"""Huge motions: the memory estimate, and a refusal before the caches are allocated."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.app.model import loading, memory
from gmr_studio.app.model.state import Snapshot
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import load_gmr


def test_the_cache_estimate_is_what_a_snapshot_allocates():
    motion = load_gmr(demo_folder() / MOTION_FILE)
    snapshot = Snapshot.of(motion)
    measured = snapshot.positions.nbytes + snapshot.rotations.nbytes
    assert memory.cache_bytes(motion.n_frames, motion.n_joints) == measured
    assert memory.needed_bytes(motion.n_frames, motion.n_joints) == int(measured * 1.5)


def test_a_million_frames_of_38_joints():
    assert memory.cache_bytes(1_000_000, 38) == 1_000_000 * 38 * 12 * 8  # 3.40 GiB
    text = memory.too_large(1_000_000, 38, available=2 * memory.GIB)
    assert text is not None and "need 5.1 GiB" in text and "2.0 GiB of memory is available" in text
    assert "1,000,000 frames of 38 joints" in text
    assert memory.too_large(1_000_000, 38, available=6 * memory.GIB) is None


def test_available_memory_is_read_from_meminfo(tmp_path):
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   1048576 kB\n")
    assert memory.available_bytes(meminfo) == memory.GIB
    # this machine's own figure is its /proc/meminfo's, read here independently (it moves
    # between reads: within the range of a read before and one after, with 256 MiB of slack)
    before = _mem_available_kib()
    got = memory.available_bytes()
    after = _mem_available_kib()
    slack = 256 * 1024**2
    assert min(before, after) * 1024 - slack <= got <= max(before, after) * 1024 + slack
    # a meminfo without MemAvailable (old kernels): the free physical pages instead
    meminfo.write_text("MemTotal:       24000000 kB\nMemFree:  100 kB\n")
    pages = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    assert abs(memory.available_bytes(meminfo) - pages) <= 2 * slack
    assert memory.available_bytes(tmp_path / "absent") is not None  # the same fallback


def _mem_available_kib() -> int:
    """MemAvailable of /proc/meminfo in KiB (the tests run on Linux, as CI does)."""
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemAvailable:"):
            return int(line.split()[1])
    raise AssertionError("no MemAvailable in /proc/meminfo")


def test_opening_is_refused_before_the_caches_are_allocated(monkeypatch):
    def no_fk(motion):
        raise AssertionError("the caches were computed")

    monkeypatch.setattr(memory, "available_bytes", lambda: 1_000_000)
    monkeypatch.setattr(loading.Snapshot, "of", staticmethod(no_fk))
    with pytest.raises(MotionFileError) as caught:
        loading.load_snapshot(demo_folder() / MOTION_FILE)
    assert "0.0 GiB of memory is available" in str(caught.value) and "walk.gmr" in str(caught.value)
    assert np.isclose(memory.needed_bytes(480, 31), 480 * 31 * 96 * 1.5)
