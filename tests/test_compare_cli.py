"""``gmr compare``: table, JSON, CSV, plot, exit codes; and the MPJPE of ``gmr markers --truth``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from tests.conftest import shared_path

CMU01 = "cmu/subject01/"


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_bvh_against_amc_table_json_csv_plot(capsys, tmp_path):
    bvh, amc = shared_path(CMU01 + "01_01.bvh"), shared_path(CMU01 + "01_01.amc")
    out_json, out_csv, out_png = tmp_path / "c.json", tmp_path / "c.csv", tmp_path / "c.png"
    code, out, _ = run(
        capsys, "compare", bvh, amc, "--map", "cmu", "--offset", "auto",
        "--json", out_json, "--csv", out_csv, "--plot", out_png,
    )  # fmt: skip
    assert code == 0
    assert "LeftUpLeg ~ lhipjoint" in out and "unmatched in B: thorax, lwrist, rwrist" in out
    assert "B = A -1 frames" in out and "found" in out
    document = json.loads(out_json.read_text())
    for key in ("units", "frames", "mpjpe", "median", "p95", "max", "joints", "unmatched_a", "unmatched_b"):
        assert key in document
    assert set(document["alignment"]) >= {"kind", "rotation", "translation", "scale", "offset_frames"}
    assert document["max"]["joint"] in {"LFingers", "LFingers_End", "LThumb_End"}
    assert 1.0 < document["mpjpe"] < 1.1  # measured 1.0641: the dropped thorax and wrists (docs/compare.md)
    assert f"MPJPE:    {document['mpjpe']:.6g}" in out
    rows = {j["name"]: j for j in document["joints"]}
    assert rows["LeftLeg"]["match"] == "lfemur" and rows["LeftLeg"]["max"] < 1.5e-4
    # the CSV: one row per frame of A; its MPJPE column averages to the JSON's (frame 0 has no B)
    table = np.genfromtxt(out_csv, delimiter=",", skip_header=1)
    assert table.shape == (document["frames"], 3 + 2 * len(rows))
    assert np.isnan(table[0, 2]) and np.nanmean(table[:, 3 : 3 + len(rows)]) == pytest.approx(document["mpjpe"])
    # what was compared, and where the worst errors are, as the CSV has them (frame 0 has no B)
    errors = table[:, 3 : 3 + len(rows)]
    assert document["compared"] == int(np.isfinite(errors).sum()) == (document["frames"] - 1) * len(rows)
    worst_row, worst_joint = np.unravel_index(np.nanargmax(errors), errors.shape)
    assert (
        document["max"]["frame"] == int(table[worst_row, 0])
        and document["max"]["joint"] == document["joints"][worst_joint]["name"]
    )
    for j, joint in enumerate(document["joints"]):
        assert joint["max_frame"] == int(table[np.nanargmax(errors[:, j]), 0])
        assert joint["max"] == pytest.approx(np.nanmax(errors[:, j]), rel=1e-8)
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out_png.stat().st_size > 20_000


def test_frames_and_alignment_options(capsys, tmp_path):
    bvh = shared_path(CMU01 + "01_01.bvh")
    out_json = tmp_path / "c.json"
    code, _out, _ = run(capsys, "compare", bvh, bvh, "--frames", "100:200", "--align", "rigid", "--json", out_json)
    assert code == 0
    document = json.loads(out_json.read_text())
    assert document["frames"] == 100 and document["first_frame"] == 100 and document["last_frame"] == 199
    assert document["mpjpe"] < 1e-12 and document["alignment"]["kind"] == "rigid"
    np.testing.assert_allclose(document["alignment"]["rotation"], np.eye(3), atol=1e-12)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--frames", "1-2"], "--frames must be START:STOP"),
        (["--offset", "soon"], "--offset must be a number"),
        (["--map", "nonesuch"], "no joint map of that name"),
    ],
)
def test_refusals_exit_2(capsys, extra, message):
    bvh = shared_path(CMU01 + "01_01.bvh")
    code, _, err = run(capsys, "compare", bvh, bvh, *extra)
    assert code == 2 and message in err


def test_unreadable_input_exits_2(capsys, tmp_path):
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT\n")
    code, _, err = run(capsys, "compare", bad, shared_path(CMU01 + "01_01.bvh"))
    assert code == 2 and str(bad) in err and "Traceback" not in err
    code, _, err = run(capsys, "compare", shared_path(CMU01 + "01_01.bvh"), tmp_path / "missing.bvh")
    assert code == 2 and "cannot read" in err


def test_nothing_matched_exits_2(capsys):
    code, _, err = run(capsys, "compare", shared_path(CMU01 + "01_01.bvh"), shared_path(CMU01 + "01_01.amc"))
    assert code == 2 and "no joints matched" in err and "--map" in err


def test_markers_output_against_the_truth_gives_the_markers_mpjpe(capsys, tmp_path):
    """``gmr markers -o OUT.gmr`` then ``gmr compare OUT.gmr TRUTH.amc``: the MPJPE ``gmr markers
    --truth`` prints (the mean of its per-joint errors, in mm; the skeleton unit is 25.4/0.45 mm)."""
    d = shared_path(CMU01 + "01_01.c3d").parent
    output, compared = tmp_path / "cmu.gmr", tmp_path / "compare.json"
    code, out, _ = run(
        capsys, "markers", d / "01_01.c3d", "--skeleton", d / "01.asf", "--map", "cmu", "--truth",
        d / "01_01.amc", "--frames", "1100:1400", "-o", output, "--json",
    )  # fmt: skip
    assert code == 0
    rows = json.loads(out)["joints"]
    markers_mpjpe = np.mean([r["position_error"] for r in rows])
    code, _, _ = run(capsys, "compare", output, d / "01_01.amc", "--offset", "1100", "--json", compared)
    assert code == 0
    document = json.loads(compared.read_text())
    assert document["frames"] == 300 and not document["unmatched_a"] and not document["unmatched_b"]
    assert document["mpjpe"] * 25.4 / 0.45 == pytest.approx(markers_mpjpe, rel=1e-12)  # 17.05 mm (root fitted)
