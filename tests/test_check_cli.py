"""``gmr check``: the table, the JSON document, --only, --strict, and --batch with its table."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from gmr_studio.core.checks import KINDS
from gmr_studio.core.cli import main
from gmr_studio.core.formats import write_motion
from gmr_studio.core.kinematics.convention import pre_from_post
from tests.checks_walk import clean_walk, reference_frame_crouch
from tests.conftest import shared_path


def held_walk():
    """The clean walk (cm) with frame 250 shown three times (two duplicates) and frames
    400-440 frozen (then the root jumps: a teleport)."""
    motion = clean_walk(120.0, unit=0.01)
    index = np.concatenate([np.arange(251), [250, 250], np.arange(251, motion.n_frames)])
    index[400:441] = index[400]
    return motion.frame_slice(index)


@pytest.fixture
def files(tmp_path):
    folder = tmp_path / "takes"
    (folder / "a").mkdir(parents=True)
    write_motion(pre_from_post(clean_walk(120.0, unit=0.01)), folder / "a" / "clean.gmr")
    write_motion(pre_from_post(held_walk()), folder / "held.gmr")
    return folder


def test_table_and_json(files, tmp_path, capsys):
    out = tmp_path / "held.json"
    assert main(["check", str(files / "held.gmr"), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "3 findings (2 warning, 1 info)" in text
    assert "duplicate    warning      251-252  (whole pose)" in text
    document = json.loads(out.read_text())
    assert list(document) == ["file", "frames", "frame_rate", "units", "findings", "skipped"]
    assert document["skipped"] == []  # no rest pose: every check saw every frame
    assert (document["frames"], document["frame_rate"], document["units"]) == (602, 120.0, "file units")
    kinds = [(f["kind"], f["start"], f["end"], f["severity"]) for f in document["findings"]]
    assert kinds == [
        ("duplicate", 251, 252, "warning"),
        ("frozen", 400, 440, "info"),
        ("teleport", 440, 441, "warning"),
    ]
    finding = document["findings"][2]
    assert list(finding) == ["kind", "joints", "start", "end", "severity", "value", "units"]
    assert finding["joints"] == ["Hips"] and finding["units"] == "file units"
    assert document["findings"][0]["joints"] == [] and document["findings"][0]["value"] == 2


def test_only_strict_and_fail_on(files, capsys):
    held = str(files / "held.gmr")
    assert main(["check", held, "--only", "frozen", "--strict"]) == 0  # 0.34 s held: info
    assert main(["check", held, "--only", "frozen", "--strict", "--fail-on", "info"]) == 1
    assert main(["check", held, "--strict"]) == 1  # the duplicates and the teleport are warnings
    assert main(["check", held, "--strict", "--fail-on", "error"]) == 0
    assert main(["check", str(files / "a" / "clean.gmr"), "--strict", "--fail-on", "info"]) == 0
    assert "0 findings" in capsys.readouterr().out
    assert main(["check", held, "--only", "pops"]) == 2
    assert "gmr: error: unknown check 'pops'" in capsys.readouterr().err


def test_json_to_stdout_only(files, capsys):
    assert main(["check", str(files / "held.gmr"), "--json", "-", "--only", "teleport"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert [f["kind"] for f in document["findings"]] == ["teleport"]


def test_settings_file(files, tmp_path, capsys):
    settings = tmp_path / "s.json"
    settings.write_text(json.dumps({"frozen_limits": [1.0, 2.0, 3.0], "kinds": ["frozen"]}))
    assert main(["check", str(files / "held.gmr"), "--settings", str(settings)]) == 0
    assert "0 findings" in capsys.readouterr().out  # 0.34 s held is under the 1 s asked for
    settings.write_text("[1, 2]")
    assert main(["check", str(files / "held.gmr"), "--settings", str(settings)]) == 2


def test_bad_file_is_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n")
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(str(bad)) and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_batch_rows_and_table(files, tmp_path, capsys, suffix):
    (files / "broken.bvh").write_text("HIERARCHY\nROOT Hips\n{\n")
    table = tmp_path / f"summary{suffix}"
    code = main(
        ["check", "--batch", str(files), "--table", str(table), "--jobs", "2", "--json", str(tmp_path / "all.json")]
    )
    assert code == 1  # a file could not be read
    out = capsys.readouterr().out.splitlines()
    assert out[0] == f"{files / 'a' / 'clean.gmr'}: 600 frames, 0 findings"
    assert out[1].startswith(str(files / "broken.bvh") + ":")
    assert (
        out[2] == f"{files / 'held.gmr'}: 602 frames, 3 findings (2 warning, 1 info): 1 frozen, 1 duplicate, 1 teleport"
    )
    if suffix == ".csv":
        with table.open() as handle:
            rows = list(csv.DictReader(handle))
    else:
        pyarrow = pytest.importorskip("pyarrow.parquet")
        rows = [{k: str(v) for k, v in row.items()} for row in pyarrow.read_table(table).to_pylist()]
    assert [r["file"] for r in rows] == [
        str(files / "a" / "clean.gmr"),
        str(files / "broken.bvh"),
        str(files / "held.gmr"),
    ]
    assert list(rows[0])[:10] == [
        "file",
        "status",
        "frames",
        "frame_rate",
        "units",
        "findings",
        "info",
        "warning",
        "error",
        "worst",
    ]
    assert list(rows[0])[10:] == list(KINDS)
    held = rows[2]
    assert (held["status"], held["findings"], held["error"], held["worst"], held["teleport"]) == (
        "ok",
        "3",
        "0",
        "warning",
        "1",
    )
    assert rows[1]["status"].startswith(str(files / "broken.bvh"))
    documents = json.loads((tmp_path / "all.json").read_text())["files"]
    assert [d["file"] for d in documents] == [str(files / "a" / "clean.gmr"), str(files / "held.gmr")]


def test_batch_strict(files):
    assert main(["check", "--batch", str(files), "--jobs", "1"]) == 0
    assert main(["check", "--batch", str(files), "--jobs", "1", "--strict"]) == 1
    assert main(["check", "--batch", str(files), "--jobs", "1", "--only", "pop", "--strict"]) == 0


def test_real_files_say_what_the_docs_say(capsys):
    """docs/checks.md: CMU 01_01.bvh's T-pose frame and its right foot sliding at 2018-2123."""
    path = shared_path("cmu/subject01/01_01.bvh")
    assert main(["check", str(path), "--json", "-"]) == 0
    findings = json.loads(capsys.readouterr().out)["findings"]
    assert findings[0] == {
        "kind": "rest-pose",
        "joints": [],
        "start": 0,
        "end": 0,
        "severity": "warning",
        "value": 1.0,
        "units": "frames",
    }
    warnings = [(f["kind"], f["start"], f["end"], f["joints"]) for f in findings if f["severity"] != "info"]
    assert ("foot-skate", 2018, 2123, ["RightFoot", "RightToeBase"]) in warnings
    assert not [f for f in findings if f["severity"] == "error"]


def test_batch_on_a_dask_cluster(files, capsys):
    pytest.importorskip("distributed")
    assert main(["check", "--batch", str(files), "--scheduler", "local:1"]) == 0
    captured = capsys.readouterr()
    assert captured.out.splitlines()[1].endswith("3 findings (2 warning, 1 info): 1 frozen, 1 duplicate, 1 teleport")
    assert "(Dask local:1)" in captured.err


def test_a_z_up_bvh_is_checked_along_the_axis_its_figure_stands_on(tmp_path, capsys):
    """A BVH states no up axis: a Z-up one written by ``gmr edit --up z`` is checked along Z,
    as the view draws it, with no flag; ``--up y --from-up z`` gives the same."""
    from gmr_studio.core.edits.world import change_up_axis
    from gmr_studio.core.formats.bvh import write_bvh
    from tests.test_checks import with_translation

    def slide(f):
        shift = np.zeros((f.size, 3))
        shift[:, 0] = 2.0 * np.clip((f - 100) / 20, 0.0, 1.0)
        return shift

    motion = with_translation(clean_walk(120.0, unit=0.01), "RightFoot", slide)
    path = tmp_path / "z_up.bvh"
    write_bvh(change_up_axis(motion, "z"), path)
    assert main(["check", str(path), "--only", "foot-skate", "--json", "-", "--up", "y", "--from-up", "z"]) == 0
    (finding,) = json.loads(capsys.readouterr().out)["findings"]
    assert (finding["start"], finding["end"], finding["joints"][0]) == (100, 120, "RightFoot")
    assert finding["value"] == pytest.approx(2.0, rel=0.1)
    assert main(["check", str(path), "--only", "foot-skate", "--json", "-"]) == 0  # the figure says Z up
    (same,) = json.loads(capsys.readouterr().out)["findings"]
    assert (same["start"], same["end"], same["joints"][0]) == (100, 120, "RightFoot")
    told_wrong = ["--up", "y", "--from-up", "y"]  # the user says it is Y up: measured along Y
    assert main(["check", str(path), "--only", "foot-skate", "--json", "-", *told_wrong]) == 0
    assert [(f["start"], f["end"]) for f in json.loads(capsys.readouterr().out)["findings"]] != [(100, 120)]


def test_the_frames_left_out_are_reported_and_the_foot_skate_found_with_only(tmp_path, capsys):
    """A Second Life take (frame 0 the reference T-pose, frames 1-60 a crouch whose face and
    fingers sit at zero, the right foot sliding over frames 1-11): the rest pose is frame 0
    alone, the text and the JSON say the other checks left it out, and ``--only
    foot-skate`` still finds the slide (and says frame 0 was left out of it)."""
    take = tmp_path / "crouch.bvh"
    write_motion(reference_frame_crouch("t-pose"), take)
    out = tmp_path / "crouch.json"
    assert main(["check", str(take), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "skipped: frame 0 (the rest pose at the start) is left out of every check but rest-pose" in text
    document = json.loads(out.read_text())
    assert [(f["kind"], f["start"], f["end"]) for f in document["findings"]] == [
        ("rest-pose", 0, 0),
        ("foot-skate", 1, 11),
    ]
    assert document["skipped"] == [
        {"start": 0, "end": 0, "kinds": [k for k in KINDS if k != "rest-pose"], "reason": "the rest pose at the start"}
    ]
    assert main(["check", str(take), "--only", "foot-skate,pop", "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert [(f["kind"], f["start"], f["end"]) for f in document["findings"]] == [("foot-skate", 1, 11)]
    assert document["skipped"][0]["kinds"] == ["foot-skate", "pop"]
    assert main(["check", str(take), "--only", "foot-skate"]) == 0
    assert "skipped: frame 0 (the rest pose at the start) is left out of foot-skate\n" in capsys.readouterr().out


def test_cmu_frame_0_is_reported_as_the_rest_pose_and_left_out(capsys):
    """cgspeed's CMU 01_01.bvh: frame 0 is the T-pose the converter adds (its fingers, too,
    change only between frames 0 and 1): still the rest pose, and said to be left out."""
    assert main(["check", str(shared_path("cmu/subject01/01_01.bvh")), "--only", "rest-pose,pop", "--json", "-"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert [(f["kind"], f["start"], f["end"]) for f in document["findings"] if f["kind"] == "rest-pose"] == [
        ("rest-pose", 0, 0)
    ]
    assert document["skipped"] == [{"start": 0, "end": 0, "kinds": ["pop"], "reason": "the rest pose at the start"}]


def test_marker_files_are_checked_with_their_computed_samples_unless_dropped(capsys):
    """CMU 01_01.c3d: the lab's filled samples are checked with the rest (STRN's noise beside
    its filled stretch, 1296-1322, is found); --drop-computed checks the measured ones only."""
    c3d = str(shared_path("cmu/subject01/01_01.c3d"))
    assert main(["check", c3d, "--only", "jitter,pop", "--json", "-"]) == 0
    kept = json.loads(capsys.readouterr().out)["findings"]
    assert ("jitter", 1296, 1322, ["STRN"]) in [(f["kind"], f["start"], f["end"], f["joints"]) for f in kept]
    assert main(["check", c3d, "--only", "jitter,pop", "--json", "-", "--drop-computed"]) == 0
    dropped = json.loads(capsys.readouterr().out)["findings"]
    assert len(dropped) == 10 and len(kept) == 14 and not any(f["joints"] == ["STRN"] for f in dropped)
