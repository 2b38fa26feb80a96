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
