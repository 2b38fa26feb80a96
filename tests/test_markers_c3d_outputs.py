"""C3D analysis outputs (POINT:ANGLES, FORCES, MOMENTS, POWERS, SCALARS, TYPE_GROUPS) are kept
out of the marker set: available apart, listed by ``gmr info``, never drawn nor aligned."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.markers.c3d import read_c3d
from tests.conftest import shared_path

#: group parameter -> (the labels it lists, their unit); COFM is named only by TYPE_GROUPS
OUTPUTS = {
    "ANGLES": (["LHipAngles", "RKneeAngles", "Sam:LPelvisAngles"], "deg"),
    "FORCES": (["LHipForce"], "N"),
    "MOMENTS": (["RHipMoment_CGM_2.4", "LKneeMoment"], "Nmm"),
    "POWERS": (["LAnklePower"], "W"),
    "SCALARS": (["LStepLength"], "mm"),
    "COFM": (["CentreOfMass"], ""),
}
N_FRAMES = 120


def write_with_outputs(path) -> tuple:
    """CMU 01_01's first frames and markers (positive residuals), with analysis outputs
    interleaved among them (residual 0, as Vicon writes computed points; wild values)."""
    ezc3d = pytest.importorskip("ezc3d")
    cmu = read_c3d(shared_path("cmu/subject01/01_01.c3d")).frame_slice(slice(0, N_FRAMES))
    rng = np.random.default_rng(14)
    output_labels = [label for labels, _ in OUTPUTS.values() for label in labels]
    outputs = rng.uniform(-5000, 5000, (N_FRAMES, len(output_labels), 3)).round(1)
    labels, points, residuals, where = [], [], [], []
    markers = [f"{s}:{m}" if s else m for s, m in zip(cmu.subjects, cmu.labels)]
    for m, label in enumerate(markers):  # an output after every fourth marker
        labels.append(label)
        points.append(np.nan_to_num(cmu.positions[:, m]))
        residuals.append(np.where(cmu.present[:, m], 1.0, -1.0))
        if m % 4 == 3 and len(where) < len(output_labels):
            where.append(len(labels))
            labels.append(output_labels[len(where) - 1])
            points.append(outputs[:, len(where) - 1])
            residuals.append(np.zeros(N_FRAMES))
    assert len(where) == len(output_labels)
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [120.0]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = labels
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    data = np.ones((4, len(labels), N_FRAMES))
    data[:3] = np.stack(points, axis=1).transpose(2, 1, 0)
    c3d["data"]["points"] = data
    c3d["data"]["meta_points"]["residuals"] = np.stack(residuals, axis=1).T[None]
    for group, (members, unit) in OUTPUTS.items():
        c3d.add_parameter("POINT", group, members)
        if unit and group != "COFM":
            c3d.add_parameter("POINT", f"{group.removesuffix('S')}_UNITS", [unit])
    c3d.add_parameter("POINT", "TYPE_GROUPS", ["Angles", "ANGLES", "Moments", "MOMENTS", "CentreOfMass", "COFM"])
    c3d.write(str(path))
    return cmu, output_labels, outputs


def test_outputs_are_kept_apart_from_the_markers(tmp_path):
    cmu, output_labels, outputs = write_with_outputs(tmp_path / "gait.c3d")
    markers = read_c3d(tmp_path / "gait.c3d")
    assert markers.labels == cmu.labels and markers.subjects == cmu.subjects  # 42 markers, none of the outputs
    np.testing.assert_allclose(markers.positions, cmu.positions, rtol=1e-6, atol=1e-4)  # float32 in the file
    found = markers.outputs
    assert [f"{s}:{m}" if s else m for s, m in zip(found.subjects, found.labels)] == output_labels
    assert found.kinds == ("angles",) * 3 + ("forces", "moments", "moments", "powers", "scalars", "cofm")
    # residual 0 does not make outputs gaps: they are computed, the rule is the markers'
    np.testing.assert_allclose(found.values, outputs, rtol=1e-6, atol=1e-3)
    assert found.units["angles"] == "deg" and found.units["moments"] == "Nmm" and found.units["cofm"] == ""
    assert "9 analysis outputs (3 angles, 1 forces, 2 moments, 1 powers, 1 scalars, 1 cofm)" in " ".join(markers.notes)
    sliced = markers.frame_slice(slice(10, 20))
    np.testing.assert_array_equal(sliced.outputs.values, found.values[10:20])
    assert markers.resampled(60.0).outputs is None  # the app's copy at the motion's rate has none


def test_gmr_info_lists_the_outputs(tmp_path, capsys):
    write_with_outputs(tmp_path / "gait.c3d")
    assert main(["info", str(tmp_path / "gait.c3d")]) == 0
    text = capsys.readouterr().out
    assert "markers:    42" in text
    assert "output:     3 angles (deg): LHipAngles, RKneeAngles, Sam:LPelvisAngles" in text
    assert "output:     2 moments (Nmm): RHipMoment_CGM_2.4, LKneeMoment" in text
    assert "LHipAngles" not in text.split("\nmarker ", 1)[1]  # not in the per-marker gap table
    assert main(["info", str(tmp_path / "gait.c3d"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert len(info["markers"]) == 42 and info["outputs"]["forces"] == {"units": "N", "labels": ["LHipForce"]}
