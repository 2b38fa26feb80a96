"""Recovery records are values (mutation survivor of app/reliability/recovery.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from gmr_studio.app.reliability import recovery


def test_a_record_is_frozen():
    record = recovery.RecoveryRecord(Path("/r/a.gmr"), None, "2026-11-26T10:00:00", 1, 5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        record.edits = 2


def test_listing_takes_include_live_by_name_only(tmp_path):
    with pytest.raises(TypeError):
        recovery.list_recoveries(tmp_path, True)


def test_the_folder_without_a_qt_location_is_under_the_home(monkeypatch, tmp_path):
    from PyQt6.QtCore import QStandardPaths

    monkeypatch.setattr(QStandardPaths, "writableLocation", lambda *_: "")
    monkeypatch.setattr(Path, "home", lambda: tmp_path)
    assert recovery.recovery_folder() == tmp_path / ".local" / "share" / "GMR Studio" / "recovery"


def test_a_copy_goes_into_folders_made_for_it_and_its_record_is_ascii(tmp_path):
    from gmr_studio.core.demo import MOTION_FILE, demo_folder
    from gmr_studio.core.formats import load_gmr

    walk = load_gmr(demo_folder() / MOTION_FILE)
    original = tmp_path / "café" / "walk.bvh"
    record = recovery.write_recovery(walk, tmp_path / "a" / "b" / "c" / "walk.gmr", original, 2)
    line = record.path.read_bytes().splitlines()[1]
    assert line.isascii() and b"caf\\u00e9" in line  # escaped: the file stays ASCII
    assert recovery.read_record(record.path).original == original.resolve()
    assert load_gmr(record.path).names == walk.names


def _record_ending_at(path: Path, end: int) -> None:
    """A recovery header whose record line's last byte (before its newline) is byte ``end``."""
    line = recovery.MARKER + '{"original": null, "saved_at": "2026-11-26T10:00:00", "edits": 1, "pid": 5}'
    padding = end - len("GMR 1\n") - len(line) - 1  # the comment line's newline
    path.write_text("GMR 1\n" + "#" * padding + "\n" + line + "\n")
    assert path.read_bytes().index(b"}\n") + 1 == end


def test_the_record_is_read_from_the_first_4096_bytes_only(tmp_path):
    _record_ending_at(tmp_path / "in.gmr", 4096)
    _record_ending_at(tmp_path / "out.gmr", 4097)
    assert recovery.read_record(tmp_path / "in.gmr").edits == 1
    assert recovery.read_record(tmp_path / "out.gmr") is None


def test_a_record_on_the_first_line_is_not_a_recovery_copy(tmp_path):
    line = recovery.MARKER + '{"original": null, "saved_at": "2026-11-26T10:00:00", "edits": 1, "pid": 5}'
    (tmp_path / "first.gmr").write_text(line + "\nGMR 1\n")
    assert recovery.read_record(tmp_path / "first.gmr") is None
