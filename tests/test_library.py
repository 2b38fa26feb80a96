"""The library's index of a folder of real takes: one row per file with what it holds, its
skeleton and its quality; bad files as rows with their reader's line; incremental runs."""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest

from gmr_studio.core.checks import run_checks
from gmr_studio.core.checks.markers import run_marker_checks
from gmr_studio.core.checks.report import check_document, summary_row
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import read_motion, write_motion
from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import Query, count, row_of_path, select_rows
from gmr_studio.core.markers import read_markers
from gmr_studio.core.timebase.clock import duration_of
from tests import library_fixtures
from tests.library_fixtures import BAD, REAL, make_takes, read_png

takes = library_fixtures.takes


@pytest.fixture(scope="module")
def indexed(tmp_path_factory):
    """(folder, library) of the takes and a copy of the CMU clip, indexed once for the
    tests that only read the rows."""
    folder = make_takes(tmp_path_factory.mktemp("indexed") / "takes")
    shutil.copyfile(folder / "cmu/clip_75f.bvh", folder / "cmu/clip_again.bvh")
    db = folder.parent / "library.sqlite"
    index(folder, db)
    return folder, db


def index(folder, db, **options):
    with Library(db) as library:
        return library.index([folder], jobs=1, **options)


def rows_by_name(db) -> dict[str, dict]:
    with Library(db) as library:
        return {row["path"]: row for row in select_rows(library.connection)}


def test_every_file_is_a_row_with_what_its_reader_and_the_checks_say(indexed):
    folder, db = indexed
    rows = rows_by_name(db)
    expected = (*(r for _, r in REAL), *BAD, "cmu/clip_again.bvh")
    assert sorted(rows) == sorted(str(folder / relative) for relative in expected)
    for path, row in rows.items():
        if row["format"] == "trc":
            markers = read_markers(path)
            motion, findings = run_marker_checks(markers)
            assert (row["frames"], row["markers"], row["units"]) == (markers.n_frames, markers.n_markers, "mm")
            assert row["joints"] is None and row["skeleton"] is None
        elif row["status"] == "ok":
            motion = read_motion(path)
            findings = run_checks(motion)
            assert (row["joints"], row["roots"]) == (motion.n_joints, len(motion.roots))
            assert row["duration"] == pytest.approx(duration_of(motion), rel=1e-12)
        else:
            continue
        assert (row["frames"], row["frame_rate"]) == (motion.n_frames, pytest.approx(motion.frame_rate))
        # the quality summary counts what gmr check --batch counts, kind by kind
        expected = summary_row(check_document(path, motion, findings), path)
        quality = row["quality"]
        assert (quality["findings"], quality["info"], quality["warning"], quality["error"]) == tuple(
            expected[k] for k in ("findings", "info", "warning", "error")
        )
        assert {k: sum(v.values()) for k, v in quality["kinds"].items()} == {k: expected[k] for k in quality["kinds"]}
        assert quality["worst"] == (expected["worst"] or None)
        assert row["thumbnail"]


def test_a_file_that_cannot_be_read_is_a_row_with_its_readers_one_line(indexed):
    folder, db = indexed
    rows = rows_by_name(db)
    for relative in BAD:
        path = str(folder / relative)
        row = rows[path]
        with pytest.raises(MotionFileError) as raised:
            read_markers(path) if path.endswith(".c3d") else read_motion(path)
        assert row["status"] == "failed" and row["message"] == str(raised.value)
        assert "\n" not in row["message"] and row["quality"] is None and not row["thumbnail"]
    assert "need the body model" in rows[str(folder / "broken/walk_poses.npz")]["message"]
    with Library(db) as library:
        failed = select_rows(library.connection, Query(failed=True))
    assert sorted(r["path"] for r in failed) == sorted(str(folder / b) for b in BAD)


def test_takes_of_one_rig_share_a_skeleton_group_through_the_joint_maps(indexed):
    _folder, db = indexed
    rows = {os.path.basename(p): r for p, r in rows_by_name(db).items()}
    clip, again, amc, asf = (rows[n]["skeleton"] for n in ("clip_75f.bvh", "clip_again.bvh", "02_01.amc", "02.asf"))
    assert clip["signature"] == again["signature"] and amc["signature"] == asf["signature"]
    assert clip["signature"] != amc["signature"]
    # CMU's BVH and ASF name their joints differently; the shipped CMU map pairs them
    assert clip["group"] == amc["group"]
    assert rows["CesiumMan.glb"]["skeleton"]["group"] != clip["group"]


def test_indexing_again_reads_only_new_and_changed_files_and_drops_removed_ones(takes, tmp_path):
    db = tmp_path / "library.sqlite"
    index(takes, db)
    before = rows_by_name(db)
    again = index(takes, db)
    assert (again.read, again.unchanged, again.removed) == (0, 9, 0)
    assert rows_by_name(db) == before
    # a file changed between runs: read again, its row says what it holds now
    clip = takes / "cmu/clip_75f.bvh"
    write_motion(read_motion(clip).frame_slice(slice(0, 40)), clip)
    # a file touched (new time, same content): not read, its stamp updated
    asf_row = before[str(takes / "cmu/02/02.asf")]
    os.utime(takes / "mocapbank.bvh", ns=(asf_row["mtime_ns"], asf_row["mtime_ns"] + 10**9))
    # a file removed, one added
    (takes / "markers/walk.trc").unlink()
    shutil.copyfile(shared_trc := takes / "gltf/CesiumMan.glb", takes / "gltf/copy.glb")
    third = index(takes, db)
    assert (third.new, third.changed, third.removed, third.touched, third.read) == (1, 2, 1, 1, 2)
    rows = rows_by_name(db)
    assert rows[str(clip)]["frames"] == 40 and before[str(clip)]["frames"] == 75
    assert rows[str(clip)]["hash"] != before[str(clip)]["hash"]
    assert str(takes / "markers/walk.trc") not in rows
    touched = rows[str(takes / "mocapbank.bvh")]
    assert touched["hash"] == before[str(takes / "mocapbank.bvh")]["hash"]
    assert touched["mtime_ns"] == asf_row["mtime_ns"] + 10**9
    assert rows[str(takes / "gltf/copy.glb")]["hash"] == rows[str(shared_trc)]["hash"]


def test_an_amc_is_read_again_when_its_asf_changes(takes, tmp_path):
    db = tmp_path / "library.sqlite"
    index(takes, db)
    asf = takes / "cmu/02/02.asf"
    asf.write_bytes(asf.read_bytes().replace(b"0.45", b"0.9", 1))  # another length unit
    again = index(takes, db)
    assert again.changed == 2 and again.read == 2  # the ASF itself and the AMC that reads it


def test_a_query_filters_and_sorts_as_asked(indexed):
    folder, db = indexed
    with Library(db) as library:
        connection = library.connection
        everything = select_rows(connection)
        assert count(connection) == len(everything) == 10
        ok = [r for r in everything if r["status"] == "ok"]
        by_duration = select_rows(connection, Query(sort="duration", descending=True))
        durations = [r["duration"] for r in by_duration if r["duration"] is not None]
        assert durations == sorted(durations, reverse=True) and by_duration[-1]["duration"] is None
        bvh = select_rows(connection, Query(formats=("bvh",)))
        assert {r["name"] for r in bvh} == {"clip_75f.bvh", "clip_again.bvh", "mocapbank.bvh", "truncated.bvh"}
        middle = select_rows(connection, Query(min_duration=1.0, max_duration=3.0))
        assert {r["name"] for r in middle} == {r["name"] for r in ok if 1.0 <= r["duration"] <= 3.0}
        assert {r["name"] for r in select_rows(connection, Query(joints=31))} == {"02.asf", "02_01.amc"}
        assert {r["name"] for r in select_rows(connection, Query(name="*.A?C"))} == {"02_01.amc"}
        assert {r["name"] for r in select_rows(connection, Query(words=("cesium",)))} == {"CesiumMan.glb"}
        with_warnings = select_rows(connection, Query(has=(("any", 2),)))
        assert {r["name"] for r in with_warnings} == {
            r["name"] for r in ok if r["quality"]["warning"] + r["quality"]["error"] > 0
        }
        assert row_of_path(connection, str(folder / "nowhere.bvh")) is None


def test_rows_hold_the_same_numbers_with_two_worker_processes(takes, tmp_path):
    one, two = tmp_path / "one.sqlite", tmp_path / "two.sqlite"
    index(takes, one)
    with Library(two) as library:
        summary = library.index([takes], jobs=2)
    assert summary.workers == "2 processes"
    assert comparable(rows_by_name(one)) == comparable(rows_by_name(two))


def comparable(rows: dict[str, dict]) -> dict[str, dict]:
    """Rows without what depends on when and in which order they were written."""
    return {path: {k: v for k, v in row.items() if k != "id"} for path, row in rows.items()}


def test_thumbnails_are_png_pictures_of_the_take(indexed):
    folder, db = indexed
    with Library(db) as library:
        row = row_of_path(library.connection, str(folder / "mocapbank.bvh"))
        picture = read_png(library.thumbnail(row["id"]))
    assert picture.shape == (64, 160, 3)
    blue = np.array([31, 119, 180])  # the first tree's colour in the view
    figure = np.abs(picture.astype(int) - blue).max(axis=-1) < 40
    assert figure.sum() > 150
    columns = np.flatnonzero(figure.any(axis=0))
    gaps = np.flatnonzero(np.diff(columns) > 3)
    assert len(gaps) == 3  # four poses side by side
