"""Every surface says the same thing about every real file and every rig (issue 21).

For each motion file of the shared data (BVH, ASF/AMC) and each rig of :mod:`core.rigs`
(written as a BVH, so that it goes through the same readers):

- ``gmr info``'s duration is the core clock's, and the timeline's total;
- ``gmr curves`` (the CLI, from the file in its own convention), the core, the curves dock's
  model (the app's GMR snapshot with the file's channels) and the inspector's numbers
  (:func:`core.analysis.curves.values_at`) agree at sampled frames, for every quantity;
- the file compared with itself after each edit kind (shift root, split, join, split all,
  join all, remove dummies, mirror twice) is zero;
- mirror twice is the identity and keeps the joint count;
- ``gmr edit --frames a:b`` then ``gmr compare`` with the automatic offset finds ``-a``.

Frames are sampled and long takes cut, so that the whole module runs in well under a minute
per core.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.analysis.curves import QUANTITIES, joint_curves, values_at
from gmr_studio.core.cli import main
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.edits.dummies import find_dummies, remove_dummies
from gmr_studio.core.edits.mirror import mirror, side_partners
from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import read_motion_with_channels
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.rigs import RIGS, make_rig
from gmr_studio.core.timebase.clock import duration_of, frame_seconds
from tests.conftest import shared_files

FILES = shared_files("**/*.bvh") + shared_files("**/*.amc")
RIG_NAMES = list(RIGS)
#: rigs checked in memory only (writing and reading 100,000 frames as text takes half a minute)
IN_MEMORY = ("long_take",)
#: frames the curves are compared at (spread over the take), and the frames edits are checked on
SAMPLED_FRAMES = 7
EDIT_FRAMES = 400
#: positions and angles agree to this, relative to the motion's size (positions) or 1 degree
TOLERANCE = 1e-9


@pytest.fixture(scope="module")
def rig_files(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("rigs")
    paths = {}
    for name in RIG_NAMES:
        if name in IN_MEMORY:
            continue
        paths[name] = folder / f"{name}.bvh"
        write_bvh(make_rig(name), paths[name])
    return paths


def _path(case, rig_files) -> Path:
    return rig_files[case] if isinstance(case, str) else Path(case)


def _motion(case, rig_files):
    """(motion in its file's convention, its file channels or None)."""
    if case in IN_MEMORY:
        return make_rig(case), None
    return read_motion_with_channels(_path(case, rig_files))


#: the files and the rigs written as BVH; with the rigs checked in memory; those with frames to trim
CASES = [*FILES, *(pytest.param(name, id=f"rig:{name}") for name in RIG_NAMES if name not in IN_MEMORY)]
ALL_CASES = [*CASES, *(pytest.param(name, id=f"rig:{name}") for name in IN_MEMORY)]
MOVING_CASES = [case for case in CASES if case.values[0] != "t_pose"]  # one frame: nothing to trim


def run(capsys, *argv) -> str:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array([[float(v) if v else np.nan for v in r] for r in rows[1:]]).reshape(len(rows) - 1, -1)


def _joints(motion) -> list[str]:
    """A root, a joint in the middle of the first tree, and a leaf (an End Site in a BVH)."""
    leaves = [j for j in range(motion.n_joints) if not motion.children[j]]
    picks = [int(motion.roots[0]), motion.n_joints // 2, leaves[len(leaves) // 2]]
    return list(dict.fromkeys(motion.names[j] for j in picks))


@pytest.mark.parametrize("case", CASES)
def test_info_duration_is_the_clocks_and_the_timelines(case, rig_files, capsys):
    from gmr_studio.app.docks.timeline import time_text

    path = _path(case, rig_files)
    motion, _ = read_motion_with_channels(path)
    info = json.loads(run(capsys, "info", path, "--json"))
    assert info["duration"] == duration_of(motion) == motion.n_frames * motion.frame_time
    assert info["frames"] == motion.n_frames
    last = max(motion.n_frames - 1, 0)
    shown_time, shown_total = time_text(motion, last).split(" / ")
    assert float(shown_time.split()[0]) == pytest.approx(frame_seconds(last, motion.frame_time), abs=5e-4)
    assert float(shown_total.split()[0]) == pytest.approx(info["duration"], abs=5e-4)


@pytest.mark.parametrize("case", CASES)
def test_curves_agree_on_every_surface(case, rig_files, capsys, tmp_path):
    from gmr_studio.app.model.loading import load_snapshot

    path = _path(case, rig_files)
    motion, channels = read_motion_with_channels(path)
    snapshot = load_snapshot(path)  # what the app shows: GMR, its caches, the file's channels
    joints = _joints(motion)
    frames = np.unique(np.linspace(0, motion.n_frames - 1, SAMPLED_FRAMES).round().astype(int))
    for quantity in QUANTITIES:
        out = tmp_path / f"{quantity}.csv"
        run(capsys, "curves", path, "--joints", ",".join(joints), "--quantity", quantity, "-o", out)
        header, table = read_csv(out)
        cli = table[:, 2:]
        core = [joint_curves(motion, j, quantity, file_channels=channels) for j in joints]
        dock = [joint_curves(snapshot.motion, j, quantity, snapshot.positions, snapshot.file_channels) for j in joints]
        columns = tuple(c for block in core for c in block.columns)
        assert header[2:] == list(columns) == [c for block in dock for c in block.columns], quantity
        core_values = np.concatenate([b.values for b in core], axis=1)
        dock_values = np.concatenate([b.values for b in dock], axis=1)
        scale = max(1.0, float(np.nanmax(np.abs(core_values), initial=0.0)))
        if quantity in ("local-pre", "local-post", "world", "speed", "acceleration"):
            scale = max(scale, motion.size)
        tolerance = TOLERANCE * scale * (1e3 if quantity == "acceleration" else 1.0)  # d2/dt2 of rounding
        np.testing.assert_allclose(cli[frames], core_values[frames], rtol=1e-9, atol=tolerance, err_msg=quantity)
        np.testing.assert_allclose(dock_values[frames], core_values[frames], rtol=0, atol=tolerance, err_msg=quantity)
        for frame in frames[:3]:  # the inspector's numbers at a frame
            shown = [
                values_at(snapshot.motion, j, quantity, frame, snapshot.positions, snapshot.file_channels)
                for j in joints
            ]
            assert tuple(c for cols, _ in shown for c in cols) == columns
            np.testing.assert_array_equal(np.concatenate([v for _, v in shown]), dock_values[frame])


def _edited(motion) -> dict[str, object]:
    """Every edit kind that keeps the joints' positions, applied to a GMR motion."""
    inner = [j for j in range(motion.n_joints) if motion.parents[j] >= 0 and motion.children[j]]
    joint = inner[len(inner) // 2] if inner else None
    edits = {}
    if joint is not None:
        edits["shift root"] = lambda m: shift_root(m, joint)
        edits["split"] = lambda m: split(m, joint)
        edits["split then join"] = lambda m: join(split(m, joint), joint)
    edits["split all"] = split_all
    edits["split all then join all"] = lambda m: join_all(split_all(m))
    if find_dummies(motion):
        edits["remove dummies"] = lambda m: remove_dummies(m)[0]
    if side_partners(motion.names, motion.parents).pairs.size:
        edits["mirror twice"] = lambda m: mirror(mirror(m)[0])[0]
    return edits


@pytest.mark.parametrize("case", ALL_CASES)
def test_a_file_compared_with_itself_after_each_edit_is_zero(case, rig_files):
    motion = pre_from_post(_motion(case, rig_files)[0]).frame_slice(slice(0, EDIT_FRAMES))
    before = world_positions(motion)
    for kind, edit in _edited(motion).items():
        edited = edit(motion)
        result = compare_motions(motion, edited, offset=0)
        if kind != "remove dummies":  # the one edit that removes joints (and only those)
            assert edited.n_joints == motion.n_joints, kind
        assert result.n_pairs == edited.n_joints and not result.unmatched_b, kind
        assert np.nanmax(result.position_error) <= TOLERANCE * motion.size, kind
        if kind == "mirror twice":  # the identity: the same joints, positions and rotations
            assert edited.names == motion.names and np.array_equal(edited.parents, motion.parents)
            assert np.abs(world_positions(edited) - before).max() <= TOLERANCE * motion.size
            assert np.nanmax(result.rotation_error, initial=0.0) < 1e-7, kind


@pytest.mark.parametrize("case", ALL_CASES)
def test_mirror_keeps_the_joints_and_twice_is_the_identity(case, rig_files):
    motion = _motion(case, rig_files)[0].frame_slice(slice(0, EDIT_FRAMES))
    try:
        once, _ = mirror(motion)
    except OperationError as error:  # nothing to mirror: no left/right names
        assert "left/right" in str(error) and not side_partners(motion.names, motion.parents).pairs.size
        return
    assert once.n_joints == motion.n_joints and once.names == motion.names
    assert once.rotation_orders.count("") == motion.rotation_orders.count("")  # End Sites stay End Sites
    twice, _ = mirror(once)
    np.testing.assert_array_equal(twice.parents, motion.parents)
    np.testing.assert_array_equal(twice.rotations, motion.rotations)
    assert np.abs(world_positions(twice) - world_positions(motion)).max() <= TOLERANCE * motion.size


@pytest.mark.parametrize("case", MOVING_CASES)
def test_trimmed_then_compared_with_the_automatic_offset_finds_minus_the_start(case, rig_files, capsys, tmp_path):
    path = _path(case, rig_files)
    motion, _ = read_motion_with_channels(path)
    assert motion.n_frames >= 20
    # a start within half a stride: the rigs are exactly periodic, so -a and -a +- 200 frames
    # (3 strides) tie and the one nearest 0 is kept; a real take has one answer
    start = 7 if isinstance(case, str) else min(motion.n_frames // 4, 300)
    stop = start + max(10, (motion.n_frames - start) * 3 // 5)
    trimmed, report = tmp_path / "T.bvh", tmp_path / "c.json"
    run(capsys, "edit", path, "-o", trimmed, "--frames", f"{start}:{stop}")
    out = run(capsys, "compare", path, trimmed, "--json", report)
    document = json.loads(report.read_text())
    assert document["alignment"]["offset_frames"] == -start and document["alignment"]["offset_found"], out
    assert document["compared"] > 0 and document["mpjpe"] <= 1e-6 * document["size_a"]


def test_the_long_take_in_memory():
    """The 100,000-frame rig: info's duration is the clock's, and a trimmed copy is found at
    minus its start by the automatic offset (the whole-body search over 100,000 frames)."""
    from gmr_studio.core.cli.info import describe
    from gmr_studio.core.edits.clip import trim

    motion = make_rig("long_take")
    assert describe(motion, "long_take.bvh")["duration"] == duration_of(motion) == motion.n_frames / 60.0
    trimmed = trim(motion, 7, 60_007)
    result = compare_motions(motion, trimmed)
    assert result.alignment.offset_found and result.alignment.offset_frames == -7
    assert np.nanmax(result.position_error) <= TOLERANCE * motion.size
