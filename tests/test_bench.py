"""``gmr bench`` and its machinery, on tiny inputs (no timing is asserted)."""

from __future__ import annotations

import importlib.metadata
import json
import shutil
import sys

import numpy as np
import pytest

from gmr_studio.core.benchmark import peers as peers_module
from gmr_studio.core.benchmark.configs import random_root_sets, with_roots
from gmr_studio.core.benchmark.data import build_benchmark_data, find_bvh_files
from gmr_studio.core.benchmark.peers import PEERS, run_peers
from gmr_studio.core.benchmark.startup import report_lines, startup_seconds
from gmr_studio.core.benchmark.timing import Timing, peak_memory, time_call
from gmr_studio.core.cli import main
from gmr_studio.core.edits.operations import shift_root, split
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.fk import reference_forward_kinematics, world_positions
from tests.conftest import random_motion, shared_path
from tests.test_bvh_reader import SMALL

#: a second skeleton (three joints in a chain, different channels) for the grouping test
OTHER = SMALL.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 3 Xrotation Yrotation Zrotation")


def test_with_roots_is_shift_root_then_split(rng):
    motion = random_motion(rng, [-1, 0, 1, 2, 1, 4, 0, 6], n_frames=5)
    roots = np.array([5, 0, 3])
    built = with_roots(motion, roots)
    expected = split(split(motion, 5), 3)  # 0 is the root already: no shift needed
    assert sorted(built.roots) == [0, 3, 5]
    np.testing.assert_array_equal(built.parents, expected.parents)
    np.testing.assert_allclose(built.rotations, expected.rotations, atol=1e-12)
    np.testing.assert_allclose(built.translations, expected.translations, atol=1e-12)
    np.testing.assert_allclose(world_positions(built), reference_forward_kinematics(motion)[0], atol=1e-12)
    shifted = with_roots(motion, np.array([7, 2]))
    reference = split(shift_root(motion, 7), 2)
    assert sorted(shifted.roots) == [2, 7]
    np.testing.assert_array_equal(shifted.parents, reference.parents)
    np.testing.assert_allclose(world_positions(shifted), world_positions(motion), atol=1e-12)
    everything = with_roots(motion, np.arange(8)[::-1])
    assert len(everything.roots) == 8
    np.testing.assert_allclose(everything.translations, world_positions(motion), atol=1e-12)


def test_random_root_sets_are_seeded_and_distinct():
    first = random_root_sets(38, 5, 10, np.random.default_rng(6))
    again = random_root_sets(38, 5, 10, np.random.default_rng(6))
    assert len(first) == 10 and all(np.array_equal(a, b) for a, b in zip(first, again))
    assert all(len(set(s.tolist())) == 5 and s.max() < 38 for s in first)


def test_files_are_grouped_by_skeleton_and_tiled(tmp_path):
    folder = tmp_path / "data"
    (folder / "sub").mkdir(parents=True)
    (folder / "a.bvh").write_text(SMALL)
    (folder / "sub" / "b.BVH").write_text(SMALL.replace("Hips", "Pelvis").replace("4 5 6 90", "7 8 9 45"))
    (folder / "c.bvh").write_text(OTHER)
    (folder / "notes.txt").write_text("not a motion")
    assert [p.name for p in find_bvh_files([folder])] == ["a.bvh", "c.bvh", "b.BVH"]
    data = build_benchmark_data([folder], 7, tmp_path)
    included = {s.path.name: s.included for s in data.sources}
    assert included == {"a.bvh": True, "b.BVH": True, "c.bvh": False}
    assert data.post.n_frames == 7 and data.gmr.convention == "pre"
    assert data.post.frame_rate == pytest.approx(120.0, rel=1e-6)
    # a, b, a, b... frame lines under a's header: a1 a2 b1 b2 a1 a2 b1
    roots = data.post.translations[:, 0]
    np.testing.assert_array_equal(roots[:, 0], [1, 4, 1, 7, 1, 4, 1])
    assert data.block_bytes == len(data.block) and data.file_bytes == data.path.stat().st_size
    assert read_bvh(data.path).n_frames == 7


def test_a_peer_is_compared_on_the_joints_it_shares_by_name(monkeypatch, tmp_path):
    """A peer's joints are matched to ours by name (its others left out); the error is the
    largest distance between matched joints. The peer stands in for numpy, installed."""
    ours = np.zeros((2, 3, 3))
    theirs = np.zeros((2, 2, 3))
    theirs[1, 0] = (0, 3, 4)

    def peer(path, repeat, frames):
        return [("peer", "as is", 2, 1e-3, theirs, ["c", "zzz"])]

    monkeypatch.setattr(peers_module, "PEERS", (("numpy", peer, True),))
    (result,) = run_peers(tmp_path / "a.bvh", tmp_path / "b.bvh", ours, ("a", "b", "c"), 10.0, 1, 2, print)
    assert (result.max_error, result.joints_compared, result.relative_error) == (5.0, 1, 0.5)


def test_timing_and_memory_helpers():
    timing = Timing((0.2, 0.1, 0.3))
    assert timing.best == 0.1 and timing.median == 0.2 and timing.noise == pytest.approx(1.0)
    assert timing.us_per_frame(1000) == pytest.approx(100.0)
    assert len(time_call(lambda: None, 3).runs) == 3
    assert peak_memory(lambda: np.ones(1_000_000)) >= 8_000_000


def installed_peers() -> list[str]:
    """The peer distributions installed here (the ``bench`` extra installs all of them)."""
    found = []
    for distribution, _, _ in PEERS:
        try:
            importlib.metadata.version(distribution)
        except importlib.metadata.PackageNotFoundError:
            continue
        found.append(distribution)
    return found


#: rows each peer gives: upc-pymotion is timed from its cached quaternions and from Euler
PEER_ROWS = {"pybvh": 1, "upc-pymotion": 2, "bvhio": 1}
#: each peer's position error over the skeleton's size, near what it measures: pybvh 6.3e-16
#: (float64), upc-pymotion 1.6e-8 (float32 quaternions), bvhio 2.8e-7 (float32 GLM)
PEER_TOLERANCE = {"pybvh": 1e-14, "upc-pymotion": 1e-7, "bvhio": 1e-6}


def test_startup_figures_are_whole_processes_side_by_side():
    sleep = "import time; time.sleep(0.05)"
    commands = {"bare": [sys.executable, "-c", "pass"], "sleeps": [sys.executable, "-c", sleep]}
    seconds = startup_seconds(2, commands)
    assert [len(runs) for runs in seconds.values()] == [2, 2]
    assert min(seconds["sleeps"]) >= 0.05
    bare, sleeps = report_lines({"bare": [0.2, 0.1, 0.4], "sleeps": [0.3, 0.15, 0.9]})
    assert bare.startswith("bare") and "min   100.0 ms" in bare and "median   200.0 ms" in bare
    assert "ratio  1.00" in bare
    assert "min   150.0 ms" in sleeps and "ratio  1.50" in sleeps


def test_a_peer_that_fails_is_reported_and_each_row_is_checked_on_its_own_output(monkeypatch, tmp_path):
    ours = np.arange(2 * 3 * 3, dtype=float).reshape(2, 3, 3)
    names = ("a", "b", "c")

    def good(path, repeat, frames):
        shifted = ours.copy()
        shifted[:, 1] += (0.0, 0.0, 2.0)  # this row's own output is off by 2 at joint b
        return [
            ("good", "as is", 2, 1e-3, ours.copy(), list(names)),
            ("good", "shifted", 2, 2e-3, shifted, list(names)),
        ]

    def broken(path, repeat, frames):
        raise RuntimeError("simulated peer bug")

    # the peers stand in for two distributions installed here, numpy and scipy
    monkeypatch.setattr(peers_module, "PEERS", (("numpy", good, True), ("scipy", broken, True)))
    lines: list[str] = []
    results = run_peers(tmp_path / "a.bvh", tmp_path / "b.bvh", ours, names, 10.0, 1, 2, lines.append)
    assert [(r.name, r.starts_from) for r in results] == [
        ("good", "as is"),
        ("good", "shifted"),
        ("scipy", "(failed)"),
    ]
    assert results[0].max_error == 0.0 and results[0].agrees() and results[0].us_per_frame == pytest.approx(500.0)
    assert results[1].max_error == 2.0 and results[1].relative_error == 0.2 and not results[1].agrees()
    assert results[2].failure == "RuntimeError: simulated peer bug" and not results[2].agrees()
    assert lines == [f"  scipy {importlib.metadata.version('scipy')}: FAILED: RuntimeError: simulated peer bug"]


def test_pymotion_times_and_checks_each_of_its_rows(tmp_path):
    if "upc-pymotion" not in installed_peers():
        pytest.fail("upc-pymotion is not installed: install the bench extra (pip install '.[bench]')")
    path = tmp_path / "small.bvh"
    path.write_text(SMALL)
    pymotion = {distribution: runner for distribution, runner, _ in PEERS}["upc-pymotion"]
    rows = pymotion(path, 2, 10)
    assert [row[1] for row in rows] == ["quaternions cached at load", "Euler angles as stored (get_data + fk)"]
    assert rows[0][4] is not rows[1][4]  # each row's own timed output
    motion = read_bvh(path)
    expected = world_positions(motion)
    for row in rows:
        shared = [name for name in row[5] if name in motion.names]
        assert len(shared) == 2  # no end sites in pymotion
        ours = expected[:, [motion.names.index(n) for n in shared]]
        theirs = row[4][:, [row[5].index(n) for n in shared]]
        assert np.linalg.norm(ours - theirs, axis=-1).max() <= 1e-7  # float32: 2.8e-8 measured


def test_bench_command_on_a_tiny_input(capsys, tmp_path):
    cmu = shared_path("cmu/subject01/01_01.bvh")
    extra = tmp_path / "extra"
    extra.mkdir()
    shutil.copy(cmu, extra / "same_skeleton.bvh")  # joins the benchmark group
    (extra / "other.bvh").write_text(OTHER)  # a different skeleton: listed, left out
    out, plot, tables = tmp_path / "bench.json", tmp_path / "bench.png", tmp_path / "bench.md"
    options = ["--frames", "2000", "--instances", "1", "--repeat", "1", "--peer-frames", "20", "--data", str(extra)]
    code = main(["bench", *options, "--json", str(out), "--plot", str(plot), "--markdown", str(tables)])
    printed = capsys.readouterr().out
    assert code == 0
    result = json.loads(out.read_text())
    sources = {s["path"]: s for s in result["sources"]}
    assert sources[str(extra / "same_skeleton.bvh")]["included"] is True
    assert sources[str(extra / "other.bvh")] == {
        "path": str(extra / "other.bvh"),
        "frames": 2,
        "joints": 3,
        "included": False,
        "note": "different skeleton from the benchmark group",
    }
    assert f"{extra / 'other.bvh'} (2 frames, 3 joints, 2 fps): left out" in printed
    assert result["frames"] == 2000 and result["joints"] == 38
    assert [c["k"] for c in result["configs"]] == list(range(1, 39))
    for config in result["configs"]:
        assert config["us_per_frame"] > 0 and config["ratio_to_bvh"] > 0
        assert config["max_position_error"] <= 1e-15 * result["size"]  # measured 4.3e-17 of the size
    assert result["engine_vs_reference_error"] <= 5e-15  # measured 8.0e-16
    assert {"shift_root", "split", "join"} == set(result["operations"])
    assert all(0 < op["seconds"] < 60 for op in result["operations"].values())
    memory = result["memory"]
    assert memory["rotations_array_mb"] == 2000 * 38 * 9 * 8 / 1e6
    positions_mb = 2000 * 38 * 3 * 8 / 1e6
    both_mb = positions_mb + memory["rotations_array_mb"]
    # the outputs and little else (measured 1.833 of 1.824 MB; 7.302 of 7.296 MB)
    assert positions_mb <= memory["positions_peak_mb"] <= 1.1 * positions_mb
    assert positions_mb <= memory["positions_from_euler_peak_mb"] <= 1.1 * positions_mb
    assert both_mb <= memory["positions_and_rotations_peak_mb"] <= 1.1 * both_mb
    rows = [(p["name"], p["starts_from"]) for p in result["peers"]]
    expected = {name: PEER_ROWS[name] for name in installed_peers()}
    assert {name: sum(1 for n, _ in rows if n == name) for name in expected} == expected, rows
    for peer in result["peers"]:
        assert not peer["failure"] and peer["agrees"] and peer["joints_compared"] >= 31, peer
        assert peer["name"] != "pybvh" or peer["joints_compared"] == 38, peer  # its end sites matched by name
        assert peer["relative_error"] <= PEER_TOLERANCE[peer["name"]], peer
        assert peer["frames"] == (20 if peer["name"] == "bvhio" else 2000)
    for label in ("C_1 ", "C_38", "faster than BVH", "targets:", "MB/s", "operations on 2000 frames"):
        assert label in printed
    assert "FAILED" not in printed
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    markdown = tables.read_text()
    assert "| 38 |" in markdown and "Parsing:" in markdown and "x faster than BVH" in markdown
