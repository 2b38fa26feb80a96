"""``gmr markers`` and ``gmr info`` on marker files, end to end through files."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import load_gmr, read_motion, write_motion
from gmr_studio.core.formats.bvh_export import bvh_export
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import MarkerSet, load_marker_map, read_markers
from gmr_studio.core.markers.markermap import VirtualMarker, marker_map_text
from gmr_studio.core.markers.trc import trc_text
from gmr_studio.core.rotations.euler import rotation_angle
from tests.conftest import shared_path

CMU01 = "cmu/subject01/"
CMU02 = "cmu/subject02/"


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def joints_trc(tmp_path):
    """02_01's joint positions as a TRC labelled with the joint names (17 digits: exact)."""
    truth = load_gmr(shared_path(CMU02 + "02_01.amc"))
    markers = MarkerSet(labels=truth.names, positions=world_positions(truth), rate=120, units="mm")
    path = tmp_path / "joints.trc"
    path.write_text(trc_text(markers, digits=17))
    return path, truth


def test_exact_case_through_files_and_gmr_positions(capsys, tmp_path, joints_trc):
    trc, truth = joints_trc
    out_gmr, out_npz = tmp_path / "out.gmr", tmp_path / "out.npz"
    skeleton, amc = shared_path(CMU02 + "02.asf"), shared_path(CMU02 + "02_01.amc")
    code, out, _ = run(
        capsys, "markers", trc, "--skeleton", skeleton, "--map", "joints", "--reference", amc, "--truth", amc,
        "-o", out_gmr,
    )  # fmt: skip
    assert code == 0 and "343 frames x 31 joints at 120 Hz, roots root; map joints" in out
    assert "overall" in out and "lhumerus" in out
    assert run(capsys, "positions", out_gmr, "-o", out_npz)[0] == 0
    positions = np.load(out_npz)["positions"]
    assert np.abs(positions - world_positions(truth)).max() <= 1e-9 * truth.size
    written = read_motion(out_gmr)
    assert rotation_angle(np.swapaxes(written.rotations, -1, -2) @ truth.rotations).max() <= 1e-6


def test_json_table_roots_frames_and_bvh_output(capsys, tmp_path, joints_trc):
    trc, truth = joints_trc
    skeleton, amc = shared_path(CMU02 + "02.asf"), shared_path(CMU02 + "02_01.amc")
    code, out, _ = run(
        capsys, "markers", trc, "--skeleton", skeleton, "--truth", amc, "--roots", "lfemur,rfemur",
        "--frames", "100:200", "--json", "-o", tmp_path / "part.gmr",
    )  # fmt: skip
    table = json.loads(out)
    rows = {row["joint"]: row for row in table["joints"]}
    assert code == 0 and rows["lfemur"]["marker_max"] == pytest.approx(0.0, abs=1e-9)
    assert max(row["position_error"] for row in rows.values()) < 1e-9 * truth.size
    part = read_motion(tmp_path / "part.gmr")
    assert part.n_frames == 100 and sorted(part.names[r] for r in part.roots) == ["lfemur", "rfemur", "root"]
    assert run(capsys, "markers", trc, "--skeleton", skeleton, "-o", tmp_path / "out.bvh")[0] == 0
    bvh = read_motion(tmp_path / "out.bvh")
    order = [bvh.joint_index(name) for name in bvh_export(truth).names]  # leaves are End Sites there
    error = np.abs(world_positions(bvh)[:, order] - world_positions(truth)).max()
    assert error < 1e-6 * truth.size  # the BVH keeps the positions (to its printed digits)


def test_calibration_reproduces_the_shipped_cmu_map(capsys, tmp_path):
    """The command in docs/markers.md makes resources/markermaps/cmu.toml (calibrated on the
    samples the cameras measured: --drop-computed)."""
    template = tmp_path / "template.toml"
    shipped = load_marker_map("cmu")
    bare = shipped.replace(  # the same map before calibration
        virtual=tuple(VirtualMarker(v.name, v.kind, v.markers) for v in shipped.virtual),
        pelvis_home=None,
        calibration={},
    )
    template.write_text(marker_map_text(bare))
    saved = tmp_path / "cmu.toml"
    d = shared_path(CMU01 + "01_01.c3d").parent
    code, out, _ = run(
        capsys, "markers", d / "01_01.c3d", "--skeleton", d / "01.asf", "--map", template, "--reference",
        d / "01_01.amc", "--calibrate", "0:1100", "--save-map", saved, "--drop-computed", "-o", tmp_path / "cal.gmr",
    )  # fmt: skip
    assert code == 0 and "calibrated on frames 0:1100" in out
    again = load_marker_map(saved)
    for a, b in zip(again.virtual, shipped.virtual):
        np.testing.assert_allclose(a.offset, b.offset, atol=1e-9)
        np.testing.assert_allclose(a.template, b.template, atol=1e-9)
    np.testing.assert_allclose(again.pelvis_home, shipped.pelvis_home, atol=1e-12)


def test_cmu_markers_report_errors_against_the_amc(capsys, tmp_path):
    d = shared_path(CMU01 + "01_01.c3d").parent
    code, out, _ = run(
        capsys, "markers", d / "01_01.c3d", "--skeleton", d / "01.asf", "--map", "cmu", "--truth",
        d / "01_01.amc", "--frames", "1100:", "-o", tmp_path / "cmu.gmr",
    )  # fmt: skip
    assert code == 0
    overall = float(next(line for line in out.splitlines() if line.startswith("overall")).split()[-1])
    assert 5.0 < overall <= 14.0  # measured 13.1 mm (the bound was 30)
    code, paper, _ = run(
        capsys, "markers", d / "01_01.c3d", "--skeleton", d / "01.asf", "--map", "cmu", "--truth",
        d / "01_01.amc", "--frames", "1100:", "--root-at", "pelvis", "-o", tmp_path / "paper.gmr",
    )  # fmt: skip
    at_x1 = float(next(line for line in paper.splitlines() if line.startswith("overall")).split()[-1])
    assert code == 0 and 16.5 < at_x1 < 18.0  # the paper's root at X1: measured 17.2 mm
    # the pelvis fit follows the table: the real markers, not the rigid cluster's virtual ones
    assert "pelvis fit (mm, min / median / 95% / max over the frames):" in out
    assert "Procrustes on LFWT, RFWT, LBWT: " in out


def _truth_rows(capsys, tmp_path, skeleton, truth, *extra) -> tuple[dict, dict]:
    d = shared_path(CMU01 + "01_01.c3d").parent
    code, out, _ = run(
        capsys, "markers", d / "01_01.c3d", "--skeleton", d / skeleton, "--map", "cmu", "--truth", d / truth,
        "--frames", "1100:1700", "--json", "-o", tmp_path / "out.gmr", *extra,
    )  # fmt: skip
    assert code == 0
    report = json.loads(out)
    return report, {row["joint"]: row for row in report["joints"]}


def _mean_distances(written, truth, first_truth_frame: int) -> np.ndarray:
    """(J,) mean distance of each joint from the truth's, truth frames from first_truth_frame."""
    true = world_positions(truth)[first_truth_frame : first_truth_frame + written.n_frames]
    order = [truth.joint_index(name) for name in written.names]
    return np.linalg.norm(world_positions(written) - true[:, order], axis=-1).mean(axis=0)


def test_truth_amc_is_frame_for_frame(capsys, tmp_path):
    """The AMC has the C3D's 2,751 frames: offset 0, no note, errors against the same frames."""
    report, rows = _truth_rows(capsys, tmp_path, "01.asf", "01_01.amc")
    assert "truth" not in report  # the output is as it was before the comparison engine
    written = load_gmr(tmp_path / "out.gmr")
    mine = _mean_distances(written, read_motion(shared_path(CMU01 + "01_01.amc")), 1100)
    printed = np.array([rows[name]["position_error"] for name in written.names])
    factor = printed / mine  # millimetres per skeleton unit, the same for every joint
    assert np.ptp(factor) <= 1e-9 * factor.mean() and factor.mean() == pytest.approx(25.4 / 0.45, rel=1e-6)


def test_truth_bvh_is_put_on_the_markers_clock(capsys, tmp_path):
    """01_01.bvh has a T-pose frame more than the C3D: the offset +1 is found, MPJPE printed."""
    report, rows = _truth_rows(capsys, tmp_path, "01_01.bvh", "01_01.bvh")
    assert report["truth"].startswith("truth frame = marker frame +1 (found from the whole body); 38 joints")
    written = load_gmr(tmp_path / "out.gmr")
    truth = load_gmr(shared_path(CMU01 + "01_01.bvh"))  # as the command reads it
    printed = np.array([rows[name]["position_error"] for name in written.names])
    factor = printed / _mean_distances(written, truth, 1101)
    assert np.ptp(factor) <= 1e-9 * factor.mean()
    assert np.all(printed / _mean_distances(written, truth, 1100) != pytest.approx(factor.mean(), rel=1e-6))
    # the local angles are taken from the same truth frames
    true_local = truth.rotations[1101 : 1101 + written.n_frames]
    angle = np.degrees(rotation_angle(np.swapaxes(written.rotations, -1, -2) @ true_local)).mean(axis=0)
    for j, name in enumerate(written.names):
        if written.parents[j] >= 0:
            assert rows[name]["angle_error_deg"] == pytest.approx(angle[j], abs=1e-9)
    given, rows_given = _truth_rows(capsys, tmp_path, "01_01.bvh", "01_01.bvh", "--truth-offset", "1")
    assert given["truth"].startswith("truth frame = marker frame +1 (given)") and rows_given == rows


def test_truth_bvh_prints_an_mpjpe(capsys, tmp_path):
    d = shared_path(CMU01 + "01_01.c3d").parent
    code, out, _ = run(
        capsys, "markers", d / "01_01.c3d", "--skeleton", d / "01_01.bvh", "--map", "cmu", "--truth",
        d / "01_01.bvh", "--frames", "1100:1700", "-o", tmp_path / "out.gmr",
    )  # fmt: skip
    assert code == 0 and "  truth: truth frame = marker frame +1" in out
    overall = float(next(line for line in out.splitlines() if line.startswith("overall")).split()[-1])
    assert 5.0 < overall < 60.0


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--map", "nonesuch"], "no marker map of that name"),
        (["--axes", "xxy"], "name each axis once"),
        (["--axes", "x,y,-z"], "mirrors the markers"),
        (["--calibrate", "0:10"], "--calibrate needs --reference"),
        (["--truth", "TRUTH_SHORT"], "it must be the same trial"),
        (["--roots", "nose"], "unknown joint 'nose'"),
    ],
)
def test_errors_are_one_line_and_exit_2(capsys, tmp_path, joints_trc, argv, message):
    trc, truth = joints_trc
    if "TRUTH_SHORT" in argv:
        short = tmp_path / "short.gmr"
        write_motion(truth.frame_slice(slice(0, 10)), short)
        argv = [str(short) if a == "TRUTH_SHORT" else a for a in argv]
    code, _, err = run(
        capsys, "markers", trc, "--skeleton", shared_path(CMU02 + "02.asf"), *argv, "-o", tmp_path / "o.gmr"
    )
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1


def test_unknown_marker_format(capsys, tmp_path):
    path = tmp_path / "x.mkr"
    path.write_text("")
    code, _, err = run(capsys, "markers", path, "--skeleton", shared_path(CMU02 + "02.asf"), "-o", tmp_path / "o.gmr")
    assert code == 2 and "unknown marker format '.mkr'" in err


def test_info_lists_markers_rate_units_and_gaps(capsys):
    c3d = shared_path(CMU01 + "01_01.c3d")
    code, out, _ = run(capsys, "info", c3d)
    assert code == 0 and "C3D markers" in out and "2751 at 120 Hz" in out and "units:      mm" in out
    assert "markers:    42" in out and "LANK" in out and "gaps:       2.40% of all samples" in out
    code, out, _ = run(capsys, "info", c3d, "--json")
    info = json.loads(out)
    rows = {m["label"]: m for m in info["markers"]}
    assert info["frame_rate"] == 120 and rows["RBAC-1"]["missing"] == 2743 and rows["LTHI"]["missing"] == 0
    code, out, _ = run(capsys, "info", shared_path("c3d/ezc3d_Vicon.c3d"))
    assert "subjects:   " in out and "Daphnee" in out and "Daphnee:ASISr" in out
    code, out, _ = run(capsys, "info", shared_path("trc/opensim_gait2392_subject01_walk1.trc"))
    assert code == 0 and "TRC markers" in out and "at 60 Hz" in out


def gait_trial_with_its_pelvis_never_whole(tmp_path):
    """The Vicon gait trial (Plug-in Gait lower body) with its pelvis markers mostly hidden,
    as gap-filled samples dropped leave them: LASI missing in frames 0-49, RASI in 50-99,
    SACR from 100 on, so no frame sees all three. Written as a TRC."""
    markers = read_markers(shared_path("c3d/c3dorg_s03_gait-pig.c3d"))
    positions = markers.positions.copy()
    for label, frames in (("LASI", slice(0, 50)), ("RASI", slice(50, 100)), ("SACR", slice(100, None))):
        positions[frames, markers.index(label)] = np.nan
    path = tmp_path / "gait.trc"
    path.write_text(trc_text(markers.replace(positions=positions)))
    return path


def test_a_pelvis_never_seen_whole_is_one_line_naming_its_markers(capsys, tmp_path):
    code, out, err = run(capsys, "markers", gait_trial_with_its_pelvis_never_whole(tmp_path), "-o", tmp_path / "o.gmr")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "the pelvis is in no frame: its markers are never seen together (missing: LASI 55%, RASI 55%" in err
    assert "--fill-gaps N" in err and "--frames A:B" in err


def test_info_counts_the_computed_samples_and_drop_computed_makes_them_gaps(capsys):
    """CMU 01_01.c3d: the 859 samples of residual 0 (0.74%, the lab's gap filling) are kept
    and counted (STRN's 103, its longest filled run 93 frames); --drop-computed makes them
    gaps again (3.14% of the samples)."""
    c3d = shared_path(CMU01 + "01_01.c3d")
    code, out, _ = run(capsys, "info", c3d)
    assert code == 0 and "gaps:       2.40% of all samples" in out
    assert "computed:   0.74% of all samples (859, kept)" in out and "--drop-computed" in out
    code, out, _ = run(capsys, "info", c3d, "--json")
    info = json.loads(out)
    assert info["computed_fraction"] == pytest.approx(859 / (2751 * 42))
    assert {m["label"]: (m["missing"], m["computed"]) for m in info["markers"]}["STRN"] == (0, 103)
    code, out, _ = run(capsys, "info", c3d, "--json", "--drop-computed")
    info = json.loads(out)
    strn = {m["label"]: m for m in info["markers"]}["STRN"]
    assert info["missing_fraction"] == pytest.approx(0.0314, abs=1e-4) and info["computed_fraction"] == 0
    assert (strn["missing"], strn["longest"], strn["computed"]) == (103, 93, 0)


def test_plug_in_gait_joint_centres_are_named_as_computed_not_as_pelvis_markers(capsys, tmp_path):
    """The Vicon gait trial loses LASI and RASI at frames 114-141: the notes name the pelvis
    markers missing there and the joint centres computed from them (pelvis, LHJC...), never
    a 'pelvis marker LHJC'."""
    code, out, _ = run(capsys, "markers", shared_path("c3d/c3dorg_s03_gait-pig.c3d"), "-o", tmp_path / "o.gmr")
    assert code == 0 and "pelvis marker LHJC" not in out and "pelvis marker pelvis" not in out
    assert (
        "note: the pelvis markers are missing in frames 114-141 (LASI in 114-141; RASI in 114-141): the joint "
        "centres computed from them (pelvis, pelvis_front, LHJC, RHJC) are not placed there"
    ) in out
    assert "note: joint centre LHJC missing in frames 114-141" in out


def c3d_without_a_rate(path):
    """A C3D of 5 frames whose POINT:RATE (and the header's rate) is 0."""
    from tests.test_markers_c3d import write_c3d

    points = np.random.default_rng(0).normal(size=(5, 2, 3)) * 100
    write_c3d(path, ["A", "B"], points, np.ones((5, 2)), rate=123.25)
    data = path.read_bytes()
    path.write_bytes(data.replace(struct.pack("<f", 123.25), struct.pack("<f", 0.0)))
    return path


def test_a_c3d_without_a_rate_is_refused_with_rate_offered_and_read_with_it(capsys, tmp_path):
    path = c3d_without_a_rate(tmp_path / "phasespace.c3d")
    for command in (["info"], ["check"], ["markers", "-o", str(tmp_path / "o.gmr")]):
        code, _, err = run(capsys, *command, path)
        assert code == 2 and len(err.strip().splitlines()) == 1
        assert "the point rate is 0: the file does not say how many frames per second it holds; give the rate" in err
        assert "--rate HZ" in err
    code, out, _ = run(capsys, "info", path, "--rate", "480")
    assert code == 0 and "frames:     5 at 480 Hz" in out
    code, out, _ = run(capsys, "check", path, "--rate", "480")
    assert code == 0 and "5 frames at 480 Hz" in out
    with pytest.raises(SystemExit) as exit_:
        main(["info", str(path), "--rate", "0"])
    assert exit_.value.code == 2
    assert "--rate: expected a positive number of frames per second, not '0'" in capsys.readouterr().err


def test_labels_of_no_known_set_list_the_nearest_sets_and_the_map_option(capsys, tmp_path):
    """c3d.org's sample 02 (its own labels) and Xsens' virtual landmarks: the nearest sets
    with the labels matched and missing, and the way to map them (--skeleton with --map)."""
    for relative in ("c3d/c3dio_c3dorg-sample02_dec_real.c3d", "c3d/ezc3d_Vicon.c3d"):
        code, _, err = run(capsys, "markers", shared_path(relative), "-o", tmp_path / "o.gmr")
        assert code == 2 and len(err.strip().splitlines()) == 1
        assert "no known marker set fits these labels (nearest: " in err and "% (matched " in err
        assert "; missing LASI, RASI" in err or "; missing LFWT, RFWT" in err
        assert "--skeleton S.asf|S.bvh --map MAP.toml" in err
    assert "plug-in-gait-full 3% (matched T10; missing LASI, RASI, LPSI" in err  # ezc3d_Vicon: only T10 is named so


def test_a_known_set_whose_markers_are_never_seen_says_so(capsys, tmp_path):
    """walking5's first 400 frames: LASI, RASI and the condyle and malleolus markers are not
    seen once; the set is still named (not 'no known marker set')."""
    walk = shared_path("c3d/opensim-core_walking5.c3d")
    code, _, err = run(capsys, "markers", walk, "--frames", "0:400", "-o", tmp_path / "o.gmr")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert err.startswith(
        "gmr: error: this file's markers are set opensim-rajagopal, but LASI, RASI, LLFC, RLFC, LMFC, RMFC, LLMAL, "
        "RLMAL, LMMAL, RMMAL are missing in every frame of the 400 read"
    )
