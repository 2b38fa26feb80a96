"""``gmr audit``: every round trip of every BVH and AMC in the shared data stays within tolerance;
the auditor's rules on small motions: the tolerance inclusive and scaled by the size, dummies
measured against the ancestor kept, renamed BVH joints matched back, one-frame results against
the rest pose, a skeleton without frames audited through its rest pose, the root shifted to
every fifth joint by default."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.compare import audit
from gmr_studio.core.compare.audit import (
    BVH_FILE_TOLERANCE,
    GLTF_FILE_TOLERANCE,
    OPERATION_TOLERANCE,
    AuditPath,
    audit_motion,
    round_trips,
    through_gltf,
)
from gmr_studio.core.edits.world import scale_lengths
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rigs import make_rig
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


def still(names: tuple[str, ...], parents: tuple[int, ...], offsets, n_frames: int = 2) -> Motion:
    """A motion standing still (identity rotations): its world positions are sums of the
    offsets, exact in binary for the small dyadic numbers used here."""
    offsets = np.array(offsets, dtype=np.float64)
    n = len(names)
    return Motion(
        names=names,
        parents=np.array(parents),
        offsets=offsets,
        rotation_orders=("XYZ",) * n,
        has_translation=np.array(parents) < 0,
        rotations=np.broadcast_to(np.eye(3), (n_frames, n, 3, 3)).copy(),
        translations=np.broadcast_to(offsets, (n_frames, n, 3)).copy(),
        frame_time=0.1,
    )


def moved(motion: Motion, joint: int, dx: float) -> Motion:
    """The motion with one joint's offset (and translations) moved by ``dx`` along x."""
    translations = motion.translations.copy()
    translations[:, joint, 0] += dx
    offsets = motion.offsets.copy()
    offsets[joint, 0] += dx
    return motion.replace(translations=translations, offsets=offsets)


def only(monkeypatch, *trips) -> None:
    """round_trips replaced by the given (name, tolerance, trip)."""
    monkeypatch.setattr(audit, "round_trips", lambda motion, source=None, every=5: list(trips))


def walk(n_frames: int = 10) -> Motion:
    return make_rig("metres").frame_slice(slice(0, n_frames))


def test_the_tolerance_is_inclusive_and_scaled_by_the_size(monkeypatch):
    # a at (1, 1, 1), b at (5, 1, 1), c at (5, 3, 1): size 4, so 1/8 of it is 0.5
    chain = still(("a", "b", "c"), (-1, 0, 1), [[1, 1, 1], [4, 0, 0], [0, 2, 0]])
    assert chain.size == 4.0
    at_tolerance = moved(chain, 1, 0.5)  # b and c move by exactly 1/8 of the size
    beyond = moved(at_tolerance, 2, 0.5)  # c by 1/4
    only(monkeypatch, ("at", 0.125, lambda m: at_tolerance), ("beyond", 0.125, lambda m: beyond))
    at, past = audit_motion(chain)
    assert at.max_error == 0.5 and at.relative_error == 0.125 and at.ok and at.failing_joints == ()
    assert past.max_error == 1.0 and past.relative_error == 0.25 and not past.ok
    assert past.failing_joints == ("c",) and (past.worst_joint, past.worst_frame) == ("c", 0)
    assert AuditPath("p", 1.0, 1e-9, 1e-9, "Hips", 0).ok  # exactly at the tolerance passes


def test_a_removed_dummy_is_measured_against_the_ancestor_that_stayed(monkeypatch):
    # "dummy" sits on the root (index 0); the trip folds it and moves everything by 1/4 of the size
    with_dummy = still(("a", "dummy", "c"), (-1, 0, 1), [[1, 1, 1], [0, 0, 0], [0, 2, 0]])
    folded = moved(still(("a", "c"), (-1, 0), [[1, 1, 1], [0, 2, 0]]), 0, 0.5)
    assert with_dummy.size == 2.0
    only(monkeypatch, ("fold", 0.125, lambda m: (folded, ["dummy"])))
    (path,) = audit_motion(with_dummy)
    assert path.lost_joints == () and path.failing_joints == ("a", "dummy", "c")
    assert path.max_error == 0.5 and not path.ok
    # a removed root has no ancestor: it is not measured (nor lost)
    under_world = still(("world", "a", "c"), (-1, 0, 1), [[0, 0, 0], [1, 1, 1], [0, 2, 0]])
    rooted = still(("a", "c"), (-1, 0), [[1, 1, 1], [0, 2, 0]])
    only(monkeypatch, ("unroot", 1e-9, lambda m: (rooted, ["world"])))
    (path,) = audit_motion(under_world)
    assert path.ok and path.max_error == 0.0 and path.lost_joints == () and path.failing_joints == ()


def test_renamed_bvh_joints_are_matched_back():
    # BVH names are single words: "Left Hand" is written Left_Hand and read back under the source's name
    source = walk()
    spaced = source.replace(names=tuple(n.replace("Left", "Left ") for n in source.names))
    assert sum(" " in n for n in spaced.names) > 3
    for path in audit_motion(spaced, every=100):
        if path.name in ("BVH written and read", "forest export after split all"):
            assert path.ok and path.lost_joints == () and path.relative_error < 1e-12, path


def test_a_one_frame_result_is_measured_against_the_rest_pose_unless_the_motion_has_one_frame(monkeypatch):
    only(monkeypatch, ("rest", 1e-9, lambda m: m.rest_pose()))
    two = walk(2)
    (path,) = audit_motion(two)
    assert path.ok and path.max_error == 0.0
    one = walk(1)
    (path,) = audit_motion(one)  # its one frame is not the rest pose: the trip lost it
    assert not path.ok and path.relative_error > 0.01


def test_a_skeleton_without_frames_is_audited_through_its_rest_pose(monkeypatch):
    """A skeleton-only BVH (``Frames: 0``): every path passes, measured on the rest pose."""
    skeleton = walk(0)
    paths = audit_motion(skeleton)
    assert len(paths) == 15 and all(p.ok and not p.error for p in paths), [p for p in paths if not p.ok]
    assert max(p.relative_error for p in paths if "glTF" not in p.name) < 1e-12
    # a trip that changes the skeleton is still caught
    only(monkeypatch, ("longer bones", 1e-9, lambda m: scale_lengths(m, 1 + 1e-6)))
    (path,) = audit_motion(skeleton)
    assert not path.ok and path.relative_error > 1e-7
    # and the rest pose stands in only for a skeleton: a trip that loses a motion's frames fails
    only(monkeypatch, ("no frames", 1e-9, lambda m: m.frame_slice(slice(0, 0))))
    (path,) = audit_motion(walk())
    assert not path.ok and path.error


def test_through_gltf_keeps_the_frames_and_gives_a_frameless_motion_its_rest_pose():
    source = walk()
    tolerance = 2e-7 * source.size
    for motion, expected in (
        (source, world_positions(source)),
        (source.frame_slice(slice(3, 4)), world_positions(source)[3:4]),
        (source.frame_slice(slice(0, 0)), world_positions(source.rest_pose())),
    ):
        back = through_gltf(motion)
        assert back.n_frames == expected.shape[0]
        positions = world_positions(back)[:, [back.names.index(n) for n in motion.names]]
        np.testing.assert_allclose(positions, expected, atol=tolerance, rtol=0)
    # the one frame is not the rest pose: keeping it is not giving the rest pose
    assert np.abs(world_positions(source)[3] - world_positions(source.rest_pose())[0]).max() > 0.01


def test_the_root_goes_to_every_fifth_joint_by_default_and_to_every_joint_with_0():
    motion = walk()
    every_fifth = [f"shift root to {motion.names[j]}" for j in range(0, motion.n_joints, 5)]
    assert [n for n, _, _ in round_trips(motion) if n.startswith("shift")] == every_fifth
    assert [p.name for p in audit_motion(motion) if p.name.startswith("shift")] == every_fifth
    every_joint = [f"shift root to {n}" for n in motion.names]
    assert [n for n, _, _ in round_trips(motion, every=0) if n.startswith("shift")] == every_joint


def test_a_path_that_raises_has_no_joint_nor_frame(monkeypatch):
    def broken(m):
        raise RuntimeError("no such writer")

    only(monkeypatch, ("broken", 1e-6, broken))
    (path,) = audit_motion(walk())
    assert (path.worst_joint, path.worst_frame, path.max_error, path.relative_error) == ("", -1, np.inf, np.inf)
    assert path.to_json()["worst_frame"] == -1 and path.to_json()["error"] == "RuntimeError: no such writer"


def test_audit_path_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        AuditPath("p", 0.0, 0.0, 1e-9, "Hips", 0).max_error = 1.0  # type: ignore[misc]
