"""``gmr audit``: every round trip of every BVH and AMC in the shared data stays within tolerance."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.compare import audit
from gmr_studio.core.compare.audit import BVH_FILE_TOLERANCE, GLTF_FILE_TOLERANCE, OPERATION_TOLERANCE, audit_motion
from gmr_studio.core.edits.world import scale_lengths
from gmr_studio.core.formats import read_motion
from tests.conftest import shared_files, shared_path

EXPECTED_PATHS = {
    "to GMR in memory",
    "GMR file written and read",
    "BVH written and read",
    "forest export after split all",
    "dummy removal",
    "dummy removal and back",
    "split all / join all",
    "glTF written and read",
    "forest glTF after split all",
}
GLTF_PATHS = {"glTF written and read", "forest glTF after split all"}


@pytest.mark.parametrize("path", shared_files("**/*.bvh") + shared_files("**/*.amc") + shared_files("gltf/**/*.gl*"))
def test_every_shared_file_passes(capsys, tmp_path, path):
    out_json = tmp_path / "audit.json"
    code = main(["audit", str(path), "--json", str(out_json)])
    out = capsys.readouterr().out
    document = json.loads(out_json.read_text())
    paths = {p["name"]: p for p in document["paths"]}
    assert code == 0, out
    assert set(paths) >= EXPECTED_PATHS
    assert sum(name.startswith("shift root to ") for name in paths) == len(range(0, read_motion(path).n_joints, 5))
    if path.suffix == ".amc":
        assert "ASF rest pose against the AMC's" in paths
    for p in document["paths"]:
        assert p["ok"] and p["relative_error"] <= p["tolerance"] and not p["lost_joints"]
        assert p["max_error"] == pytest.approx(p["relative_error"] * document["size"], rel=1e-12)
        if p["name"] in GLTF_PATHS:  # float32: measured at most 1.0e-7 (01_01.bvh)
            assert p["tolerance"] == GLTF_FILE_TOLERANCE and p["relative_error"] < 1.5e-7
        else:
            assert p["relative_error"] < 1e-13  # measured at most 2.1e-14 (split all / join all)
    assert f"{len(paths)} of {len(paths)} paths within tolerance" in out


def test_a_path_that_moves_joints_fails_and_names_them(capsys, monkeypatch):
    path = shared_path("cmu/subject01/01_01.bvh")
    original = audit.round_trips

    def with_a_bad_path(motion, source=None, every=5):
        bad = ("lengths off by 1e-6", OPERATION_TOLERANCE, lambda m: scale_lengths(m, 1 + 1e-6))
        return [*original(motion, source, every), bad]

    monkeypatch.setattr(audit, "round_trips", with_a_bad_path)
    motion = read_motion(path)
    result = {p.name: p for p in audit_motion(motion, path)}["lengths off by 1e-6"]
    assert not result.ok and result.relative_error > OPERATION_TOLERANCE
    # every point moves by 1e-6 of its distance from the origin: all joints fail
    assert result.worst_joint in result.failing_joints and len(result.failing_joints) == motion.n_joints
    assert result.relative_error == pytest.approx(
        1e-6 * np.abs(audit.forward_kinematics(motion)[0]).max() / motion.size, rel=0.8
    )
    code = main(["audit", str(path)])
    out = capsys.readouterr().out
    assert code == 1 and "FAIL" in out and "lengths off by 1e-6" in out


def test_a_path_that_raises_is_reported(monkeypatch):
    path = shared_path("cmu/subject01/01_01.bvh")

    def broken(m):
        raise RuntimeError("no such writer")

    monkeypatch.setattr(
        audit, "round_trips", lambda motion, source=None, every=5: [("broken", BVH_FILE_TOLERANCE, broken)]
    )
    (result,) = audit_motion(read_motion(path), path)
    assert not result.ok and result.error == "RuntimeError: no such writer"
    assert result.to_json()["ok"] is False


def test_unreadable_file_exits_2(capsys, tmp_path):
    bad = tmp_path / "bad.amc"
    bad.write_text(":FULLY-SPECIFIED\n1\nroot 1 2\n")
    code = main(["audit", str(bad)])
    assert code == 2 and "Traceback" not in capsys.readouterr().err
