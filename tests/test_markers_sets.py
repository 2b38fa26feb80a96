"""Marker sets recognised on the shared files, `gmr info` and `gmr markers` without a skeleton,
and the comparison with the lab model's points (issue 22)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.build import build_skeleton
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.file_model import compare_with_file_model
from gmr_studio.core.markers.sets import identify_marker_set
from tests.conftest import shared_path
from tests.test_markers_build import generated_markers

SETS = {
    "c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d": "plug-in-gait-full",
    "c3d/c3dorg_s03_gait-pig.c3d": "plug-in-gait-lower",
    "c3d/opensim-core_walking5.c3d": "opensim-rajagopal",
    "trc/opensim-core_dataWithBlanksForMissingMarkers.trc": "opensim-rajagopal",
    "c3d/ezc3d_Qualisys.c3d": "qualisys-sports",
    "c3d/c3dio_c3dorg-sample11_evart.c3d": "helen-hayes",
    "cmu/subject01/01_01.c3d": "cmu",
    "trc/opensim_gait2392_subject01_walk1.trc": "opensim-gait2392",
    "c3d/ezc3d_Vicon.c3d": None,  # an upper-limb protocol: no known set
}


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("relative", sorted(SETS))
def test_shared_files_sets(relative):
    match = identify_marker_set(read_markers(shared_path(relative)))
    expected = SETS[relative]
    assert (match.definition.name if match else None) == expected
    if match is not None:
        assert match.complete


def test_subject_prefixes_are_stripped():
    markers = read_markers(shared_path("c3d/c3dorg_s03_gait-pig.c3d"))
    assert set(markers.subjects) == {"A22"} and "RKNE" in markers.labels
    assert identify_marker_set(markers).definition.name == "plug-in-gait-lower"


def test_info_names_the_set(capsys):
    code, out, _ = run(capsys, "info", shared_path("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d"))
    assert code == 0 and "set:        plug-in-gait-full (Plug-in Gait full body (Vicon))" in out
    code, out, _ = run(capsys, "info", shared_path("c3d/ezc3d_Vicon.c3d"), "--json")
    info = json.loads(out)
    assert info["marker_set"]["name"] is None and "ASIS" in info["marker_set"]["note"]


def test_another_sets_map_says_so(capsys, tmp_path):
    code, _, err = run(
        capsys, "markers", shared_path("c3d/c3dorg_s03_gait-pig.c3d"), "--skeleton",
        shared_path("cmu/subject01/01.asf"), "--map", "cmu", "-o", tmp_path / "x.gmr",
    )  # fmt: skip
    assert code != 0
    assert "this file's markers are set plug-in-gait-lower, not map cmu (missing: LFWT, RFWT" in err
    assert "frames 0-141" not in err


def test_markers_without_skeleton(capsys, tmp_path):
    out_json = tmp_path / "model.json"
    code, out, _ = run(
        capsys, "markers", shared_path("c3d/c3dorg_s03_gait-pig.c3d"), "--refine", "--against-file-model",
        "--json", out_json, "-o", tmp_path / "s03.gmr",
    )  # fmt: skip
    assert code == 0, out
    assert "skeleton built from set plug-in-gait-lower" in out and "Harrington et al. 2007" in out
    assert "overall RMS after" in out
    report = json.loads(out_json.read_text())
    assert {row["name"] for row in report["joints"]} >= {"pelvis", "LHJC", "RKJC", "LAJC"}
    row = report["joints"][0]
    assert set(row) == {"name", "file_point", "frames", "mean_mm", "median_mm", "max_mm"}
    assert set(report["pelvis"]) >= {"file_segment", "median_deg", "max_deg"}
    assert report["pelvis"]["median_deg"] < 2.0  # the pelvis frames agree to a degree or two
    motion = load_gmr(tmp_path / "s03.gmr")
    assert motion.n_frames == 142 and motion.names[0] == "pelvis"
    code, out, _ = run(capsys, "info", tmp_path / "s03.gmr")
    assert code == 0


def test_every_shared_file_of_a_buildable_set_becomes_motion():
    for relative, name in SETS.items():
        if name is None:
            continue
        built = markers_to_built_motion(read_markers(shared_path(relative)), refine=True, iterations=2)
        positions = world_positions(built.result.motion)
        assert np.isfinite(positions).all(), relative


def test_file_model_comparison_exact():
    markers, joints = generated_markers("plug-in-gait-lower")
    built = markers_to_built_motion(markers)
    motion = built.result.motion
    positions = world_positions(motion)
    points = {"PELO": joints["pelvis"], "LFEP": joints["LHJC"], "RFEO": joints["RKJC"], "LTIO": joints["LAJC"]}
    # the lab's pelvis frame: our pelvis turned by a constant rotation (another axis convention)
    root = motion.rotations[:, 0]
    turn = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    axes = root @ turn
    for key, column in zip("ALP", range(3)):
        points["PEL" + key] = joints["pelvis"] + 100.0 * axes[:, :, column]
    with_model = markers.replace(
        labels=[*markers.labels, *points],
        subjects=(),
        positions=np.concatenate([markers.positions, np.stack(list(points.values()), 1)], 1),
    )
    report = compare_with_file_model(with_model, motion, positions)
    assert {r["file_point"] for r in report["joints"]} == {"PELO", "LFEP", "RFEO", "LTIO"}
    assert max(r["max_mm"] for r in report["joints"]) < 1e-9
    assert report["pelvis"]["max_deg"] < 1e-6


def test_marker_weights(capsys, tmp_path):
    markers = read_markers(shared_path("c3d/c3dorg_s03_gait-pig.c3d"))
    plain = markers_to_built_motion(markers, refine=True)
    heavy = markers_to_built_motion(markers, refine=True, weights={"LTHI": 100.0})
    column = plain.labels.index("LTHI")
    before, after = (np.nanmedian(b.refinement.residuals[:, column]) for b in (plain, heavy))
    assert after < 0.5 * before
    code, _, err = run(
        capsys, "markers", shared_path("c3d/c3dorg_s03_gait-pig.c3d"), "--refine", "--weights", "LTHI=2,NOPE=1",
        "-o", tmp_path / "w.gmr",
    )  # fmt: skip
    assert code != 0 and "--weights names markers the file does not have: NOPE" in err


def test_subject_widths_come_from_the_processing_group(tmp_path):
    # Vicon Nexus stores the subject's measurements in the PROCESSING group: read as
    # MarkerSet.parameters, they set the chord's widths (no "assumed" note then)
    ezc3d = pytest.importorskip("ezc3d")
    source = read_markers(shared_path("c3d/c3dorg_s03_gait-pig.c3d"))
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [source.rate]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = list(source.labels)
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    data = np.ones((4, source.n_markers, source.n_frames))
    data[:3] = np.nan_to_num(source.positions).transpose(2, 1, 0)
    c3d["data"]["points"] = data
    c3d["data"]["meta_points"]["residuals"] = np.where(source.present, 1.0, -1.0).T[None]
    c3d.add_parameter("PROCESSING", "KneeWidth", [105.0])
    c3d.add_parameter("PROCESSING", "AnkleWidth", [72.0])
    c3d.add_parameter("PROCESSING", "MarkerDiameter", [16.0])
    c3d.write(str(tmp_path / "widths.c3d"))
    markers = read_markers(tmp_path / "widths.c3d")
    assert markers.parameters == {"KneeWidth": 105.0, "AnkleWidth": 72.0, "MarkerDiameter": 16.0}
    built = build_skeleton(markers)
    assert not [n for n in built.notes if "assumed" in n]
    knee, lateral = built.centres[:, built.skeleton.joint_index("LKJC")], markers.positions[:, markers.index("LKNE")]
    distance = np.linalg.norm(knee - lateral, axis=1)
    assert np.allclose(distance[np.isfinite(distance)], 105.0 / 2 + 8.0)
