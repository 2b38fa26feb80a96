"""``gmr library``: index with a summary, list and query with every filter as JSON and CSV,
show one file, write the thumbnails; bad requests end in one line."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import shutil

import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import read_motion
from tests.library_fixtures import BAD, make_takes, read_png

#: every field a JSON row carries (docs/library.md)
FIELDS = {
    "id", "path", "name", "folder", "size", "modified", "mtime_ns", "hash", "format", "kind", "status", "message",
    "frames", "frame_rate", "duration", "joints", "roots", "markers", "units", "up_axis", "skeleton", "quality",
    "thumbnail",
}  # fmt: skip


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """(folder, db, the index command's stderr) of the takes indexed by the command line."""
    root = tmp_path_factory.mktemp("cli")
    folder = make_takes(root / "takes")
    shutil.copyfile(folder / "cmu/clip_75f.bvh", folder / "cmu/clip_again.bvh")
    db = root / "library.sqlite"
    stream = io.StringIO()
    with contextlib.redirect_stderr(stream):
        assert main(["library", "index", str(folder), "--db", str(db), "--workers", "1"]) == 0
    return folder, db, stream.getvalue()


def listed(capsys, db, *flags) -> list[dict]:
    assert main(["library", "list", "--db", str(db), "--json", *flags]) == 0
    return json.loads(capsys.readouterr().out)


def names(rows) -> set[str]:
    return {r["name"] for r in rows}


def test_index_says_what_it_read_and_which_files_failed(library):
    folder, db, err = library
    lines = err.strip().splitlines()
    assert lines[-1].startswith("10 files in 1 folder: 10 read (10 new, 0 changed), 0 unchanged, 0 removed, 3 failed")
    assert lines[-1].endswith(f"into {db}")
    for bad in BAD:  # one line each, the reader's
        assert any(line.startswith(f"{folder / bad}") for line in lines)


def test_the_json_rows_carry_every_field(library, capsys):
    folder, db, _ = library
    rows = listed(capsys, db)
    assert len(rows) == 10 and all(set(r) == FIELDS for r in rows)
    clip = next(r for r in rows if r["name"] == "clip_75f.bvh")
    motion = read_motion(folder / "cmu/clip_75f.bvh")
    assert (clip["frames"], clip["joints"], clip["roots"], clip["format"], clip["up_axis"]) == (75, 38, 1, "bvh", "y")
    assert clip["frame_rate"] == pytest.approx(motion.frame_rate) and clip["size"] > 0 and len(clip["hash"]) == 32
    assert set(clip["skeleton"]) == {"group", "signature", "topology", "group_match"}
    assert set(clip["quality"]) == {"findings", "info", "warning", "error", "worst", "worst_frame", "kinds"}
    markers = next(r for r in rows if r["format"] == "trc")
    assert markers["markers"] == 41 and markers["joints"] is None and markers["units"] == "mm"


def test_every_filter_of_list_and_query(library, capsys):
    folder, db, _ = library
    everything = listed(capsys, db)
    ok = [r for r in everything if r["status"] == "ok"]
    assert names(listed(capsys, db, "--format", "bvh", "--format", "amc")) == {
        "clip_75f.bvh", "clip_again.bvh", "mocapbank.bvh", "truncated.bvh", "02_01.amc"
    }  # fmt: skip
    assert names(listed(capsys, db, "--name", "clip_*")) == {"clip_75f.bvh", "clip_again.bvh"}
    assert names(listed(capsys, db, "--name", "*/cmu/02/*")) == {"02.asf", "02_01.amc"}
    assert names(listed(capsys, db, "--min-duration", "2", "--max-duration", "3")) == {
        r["name"] for r in ok if 2 <= r["duration"] <= 3
    }
    assert names(listed(capsys, db, "--joints", "38")) == {"clip_75f.bvh", "clip_again.bvh"}
    same = listed(capsys, db, "--same-skeleton-as", str(folder / "cmu/02/02_01.amc"))
    assert names(same) == {"clip_75f.bvh", "clip_again.bvh", "02.asf", "02_01.amc"}  # the CMU rig, BVH and ASF
    warned = listed(capsys, db, "--has", "any:warning")
    assert names(warned) == {r["name"] for r in ok if r["quality"]["warning"] + r["quality"]["error"]}
    for kind in {k for r in ok for k in r["quality"]["kinds"]}:
        assert names(listed(capsys, db, "--has", kind)) == {r["name"] for r in ok if kind in r["quality"]["kinds"]}
    assert names(listed(capsys, db, "--failed")) == {b.rsplit("/", 1)[1] for b in BAD}
    longest = listed(capsys, db, "--sort=-duration", "--limit", "2")
    assert [r["duration"] for r in longest] == sorted((r["duration"] for r in ok), reverse=True)[:2]
    assert main(["library", "query", "--db", str(db), "--json", "--format", "glb"]) == 0
    assert names(json.loads(capsys.readouterr().out)) == {"CesiumMan.glb"}


def test_csv_rows_hold_what_the_json_rows_hold(library, capsys):
    _folder, db, _ = library
    rows = listed(capsys, db)
    assert main(["library", "list", "--db", str(db), "--csv"]) == 0
    table = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [t["path"] for t in table] == [r["path"] for r in rows]
    for line, row in zip(table, rows):
        assert line["frames"] == ("" if row["frames"] is None else str(row["frames"]))
        assert line["status"] == row["status"] and line["message"] == (row["message"] or "")
        if row["quality"]:
            assert int(line["findings"]) == row["quality"]["findings"]


def test_show_prints_one_files_row_with_its_joints(library, capsys):
    folder, db, _ = library
    assert main(["library", "show", str(folder / "cmu/02/02_01.amc"), "--db", str(db), "--json"]) == 0
    row = json.loads(capsys.readouterr().out)
    assert row["name"] == "02_01.amc"
    assert row["skeleton"]["names"] == list(read_motion(folder / "cmu/02/02_01.amc").names)
    assert main(["library", "show", str(folder / "mocapbank.bvh"), "--db", str(db)]) == 0
    text = capsys.readouterr().out
    assert "frames       455" in text and "problems" in text


def test_thumbnails_are_written_as_png_files(library, tmp_path, capsys):
    _folder, db, _ = library
    out = tmp_path / "pictures"
    assert main(["library", "thumbnails", "--out", str(out), "--db", str(db), "--format", "bvh"]) == 0
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*.png"))
    assert written == ["takes/cmu/clip_75f.bvh.png", "takes/cmu/clip_again.bvh.png", "takes/mocapbank.bvh.png"]
    assert read_png((out / written[0]).read_bytes()).shape == (64, 160, 3)
    assert "wrote 3 thumbnails (of 4 files)" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("arguments", "words"),
    [
        (["list", "--has", "wobble"], "the kind is any or one of"),
        (["list", "--has", "pop:awful"], "the severity is one of info, warning, error"),
        (["list", "--sort", "colour"], "cannot sort by 'colour'"),
        (["show", "nowhere.bvh"], "is not in the library"),
    ],
)
def test_bad_requests_end_in_one_line(library, capsys, arguments, words):
    _folder, db, _ = library
    assert main(["library", *arguments, "--db", str(db)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("gmr: error:") and words in err and "\n" not in err


def test_listing_a_library_that_is_not_there(tmp_path, capsys):
    assert main(["library", "list", "--db", str(tmp_path / "none.sqlite")]) == 2
    assert "index a folder into it first" in capsys.readouterr().err
    assert not (tmp_path / "none.sqlite").exists()


def test_indexing_a_file_instead_of_a_folder(tmp_path, capsys):
    (tmp_path / "one.bvh").write_text("HIERARCHY")
    assert main(["library", "index", str(tmp_path / "one.bvh"), "--db", str(tmp_path / "l.sqlite")]) == 2
    assert "is not a folder" in capsys.readouterr().err
