"""Atomic writes: a failure midway leaves the old file whole and no temporary behind."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from gmr_studio.core.atomic import atomic_write_text
from gmr_studio.core.formats.gmr import read_gmr, write_gmr
from tests.conftest import random_motion


def test_failed_write_keeps_the_old_file(tmp_path):
    target = tmp_path / "motion.gmr"
    target.write_text("old content\n")

    def chunks():
        yield "new beginning\n"
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        atomic_write_text(target, chunks())
    assert target.read_text() == "old content\n"
    assert [p.name for p in tmp_path.iterdir()] == ["motion.gmr"]


def test_writer_failing_midway_keeps_the_previous_motion(tmp_path, rng, monkeypatch):
    target = tmp_path / "motion.gmr"
    first = random_motion(rng, [-1, 0, 1], n_frames=10)
    write_gmr(first, target)
    before = target.read_bytes()
    import gmr_studio.core.formats.textmotion as textmotion

    def broken(values, digits):
        raise MemoryError("simulated failure while formatting frames")

    monkeypatch.setattr(textmotion, "format_frames", broken)
    with pytest.raises(MemoryError):
        write_gmr(random_motion(rng, [-1, 0], n_frames=5), target)
    assert target.read_bytes() == before
    np.testing.assert_allclose(read_gmr(target).rotations, first.rotations, atol=1e-14)
    assert len(list(tmp_path.iterdir())) == 1


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o027])
def test_a_new_file_gets_the_permissions_the_umask_allows(tmp_path, umask):
    target = tmp_path / "fresh.gmr"
    previous = os.umask(umask)
    try:
        atomic_write_text(target, "x")
    finally:
        os.umask(previous)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~umask  # not mkstemp's 0o600


@pytest.mark.parametrize("mode", [0o640, 0o604, 0o755])
def test_a_rewritten_file_keeps_its_permissions(tmp_path, mode):
    target = tmp_path / "kept.gmr"
    target.write_text("old")
    target.chmod(mode)
    atomic_write_text(target, "new")
    assert target.read_text() == "new" and stat.S_IMODE(target.stat().st_mode) == mode
