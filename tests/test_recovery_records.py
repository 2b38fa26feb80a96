"""Recovery files without a window (app.reliability.recovery): their names, the record they
carry and read back, which are offered (processes gone) and how they are listed."""

from __future__ import annotations

import datetime
import hashlib
import os
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.app.reliability import recovery
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions


@pytest.fixture(scope="module")
def walk():
    return load_gmr(demo_folder() / MOTION_FILE)


def test_a_copy_is_a_gmr_file_whose_second_line_is_its_record(tmp_path, walk):
    original = tmp_path / "takes" / "walk.bvh"
    before = datetime.datetime.now().replace(microsecond=0)
    record = recovery.write_recovery(walk, tmp_path / "r" / "walk.gmr", original, 7)
    after = datetime.datetime.now()
    assert record.path == tmp_path / "r" / "walk.gmr" and record.original == original.resolve()
    assert record.edits == 7 and record.pid == os.getpid()
    assert before <= datetime.datetime.fromisoformat(record.saved_at) <= after
    assert len(record.saved_at) == 19  # to the second
    lines = record.path.read_text().splitlines()
    assert lines[0] == "GMR 1" and lines[1].startswith(recovery.MARKER)
    assert recovery.read_record(record.path) == record
    back = load_gmr(record.path)  # any GMR reader opens it
    assert back.names == walk.names
    assert np.abs(world_positions(back) - world_positions(walk)).max() <= 1e-9 * walk.size
    untitled = recovery.write_recovery(walk, tmp_path / "u.gmr", None, 1)
    assert untitled.original is None and recovery.read_record(untitled.path) == untitled


def test_names_are_the_stem_and_a_hash_of_the_full_path(tmp_path, monkeypatch):
    folder = tmp_path / "recovery"
    assert recovery.recovery_path(None, folder) == folder / "untitled.gmr"
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    digest = hashlib.sha256(str((tmp_path / "a" / "walk.bvh").resolve()).encode()).hexdigest()[:8]
    assert recovery.recovery_path(tmp_path / "a" / "walk.bvh", folder) == folder / f"walk.{digest}.gmr"
    assert recovery.recovery_path(tmp_path / "b" / "walk.bvh", folder) != folder / f"walk.{digest}.gmr"
    monkeypatch.chdir(tmp_path)
    assert recovery.recovery_path("a/walk.bvh", folder) == folder / f"walk.{digest}.gmr"  # relative: the same file


def test_the_folder_follows_xdg_data_home(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    assert recovery.recovery_folder() == tmp_path / "data" / "GMR Studio" / "recovery"
    assert recovery.recovery_path(None) == tmp_path / "data" / "GMR Studio" / "recovery" / "untitled.gmr"


def test_the_line_a_record_is_described_by():
    record = recovery.RecoveryRecord(
        recovery.Path("/r/walk.1.gmr"), recovery.Path("/m/walk.bvh"), "2026-11-26T10:00:05", 1, 5
    )
    assert record.display_name == "walk.bvh"
    assert record.describe() == "/m/walk.bvh  saved 2026-11-26 10:00:05  1 edit  (/r/walk.1.gmr)"
    three = recovery.RecoveryRecord(recovery.Path("/r/u.gmr"), None, "2026-11-26T10:00:05", 3, 5)
    assert three.display_name == "untitled motion"
    assert three.describe() == "untitled motion (no file)  saved 2026-11-26 10:00:05  3 edits  (/r/u.gmr)"


def test_files_that_are_not_recovery_copies_have_no_record(tmp_path, walk):
    record = recovery.write_recovery(walk, tmp_path / "good.gmr", None, 2)
    text = record.path.read_text()
    lines = text.splitlines(keepends=True)
    cases = {
        "plain.gmr": "GMR 1\n# a comment\n",
        "third-line.gmr": lines[0] + "# another comment\n" + "".join(lines[1:]),  # still read on line 3
        "fourth-line.gmr": lines[0] + "# one\n# two\n" + "".join(lines[1:]),  # too far down
        "bad-json.gmr": "GMR 1\n" + recovery.MARKER + "{not json\n",
        "no-edits.gmr": "GMR 1\n" + recovery.MARKER + '{"original": null, "saved_at": "x", "pid": 1}\n',
        "edits-not-a-number.gmr": "GMR 1\n"
        + recovery.MARKER
        + '{"original": null, "saved_at": "x", "edits": "many", "pid": 1}\n',
        "far-down.gmr": "GMR 1\n" + "#" * 5000 + "\n" + lines[1],
    }
    for name, content in cases.items():
        (tmp_path / name).write_text(content)
    found = {name: recovery.read_record(tmp_path / name) for name in cases}
    assert found.pop("third-line.gmr").edits == 2
    assert found == dict.fromkeys(found)
    assert recovery.read_record(tmp_path / "absent.gmr") is None
    assert recovery.read_record(tmp_path) is None  # a folder: unreadable


def test_a_process_holds_its_copies_while_it_runs(tmp_path):
    assert recovery.process_alive(os.getpid())
    marked = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)", "gmr-studio"])
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        assert recovery.process_alive(marked.pid)  # a GMR Studio process is running
        assert not recovery.process_alive(other.pid)  # a reused pid of another program
    finally:
        for process in (marked, other):
            process.kill()
            process.wait()
    assert not recovery.process_alive(marked.pid)  # gone


def test_listing_leaves_out_copies_in_use_and_other_files(tmp_path, walk):
    folder = tmp_path / "recovery"
    assert recovery.list_recoveries(folder) == [] and recovery.list_recoveries(folder, include_live=True) == []
    ours = recovery.write_recovery(walk, folder / "ours.gmr", None, 1)
    left = recovery.write_recovery(walk, folder / "left.gmr", tmp_path / "x.bvh", 4)
    text = left.path.read_text().replace(f'"pid": {os.getpid()}', '"pid": 999999999')  # a process long gone
    left.path.write_text(text)
    (folder / "notes.txt").write_text("GMR 1\n" + ours.path.read_text().splitlines()[1] + "\n")
    (folder / "plain.gmr").write_text("GMR 1\n")
    offered = recovery.list_recoveries(folder)
    assert [r.path for r in offered] == [left.path] and offered[0].pid == 999999999
    assert {r.path for r in recovery.list_recoveries(folder, include_live=True)} == {left.path, ours.path}
    recovery.discard(offered[0])
    assert not left.path.exists()
    recovery.discard(offered[0])  # gone already: fine


def test_the_recover_option_prints_every_copy(tmp_path, walk, capsys):
    folder = tmp_path / "recovery"
    assert recovery.print_recoveries(folder) == 0
    assert capsys.readouterr().out == f"no recovery files in {folder}\n"
    ours = recovery.write_recovery(walk, folder / "ours.gmr", tmp_path / "walk.bvh", 3)
    assert recovery.print_recoveries(folder) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines == [
        "1 recovery file(s); start gmr-studio to restore or discard them:",
        ours.describe() + "  [in use by a running GMR Studio]",
    ]
