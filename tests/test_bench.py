"""``gmr bench`` and its machinery, on tiny inputs (no timing is asserted)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.benchmark.configs import random_root_sets, with_roots
from gmr_studio.core.benchmark.data import build_benchmark_data, find_bvh_files
from gmr_studio.core.benchmark.peers import _compare, _pybvh_name
from gmr_studio.core.benchmark.timing import Timing, peak_memory, time_call
from gmr_studio.core.cli import main
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics import reference_forward_kinematics, world_positions
from gmr_studio.core.operations import shift_root, split
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


def test_peer_helpers():
    assert _pybvh_name("EndSiteLeftToeBase") == "LeftToeBase_End" and _pybvh_name("Hips") == "Hips"
    ours = np.zeros((2, 3, 3))
    theirs = np.zeros((2, 2, 3))
    theirs[1, 0] = (0, 3, 4)
    error, compared = _compare(ours, ("a", "b", "c"), theirs, ["c", "zzz"])
    assert (error, compared) == (5.0, 1)


def test_timing_and_memory_helpers():
    timing = Timing((0.2, 0.1, 0.3))
    assert timing.best == 0.1 and timing.median == 0.2 and timing.noise == pytest.approx(1.0)
    assert timing.us_per_frame(1000) == pytest.approx(100.0)
    assert len(time_call(lambda: None, 3).runs) == 3
    assert peak_memory(lambda: np.ones(1_000_000)) >= 8_000_000


def test_bench_command_on_a_tiny_input(capsys, tmp_path):
    shared_path("cmu/subject01/01_01.bvh")
    out, plot, tables = tmp_path / "bench.json", tmp_path / "bench.png", tmp_path / "bench.md"
    options = ["--frames", "2000", "--instances", "1", "--repeat", "1", "--peer-frames", "20"]
    code = main(["bench", *options, "--json", str(out), "--plot", str(plot), "--markdown", str(tables)])
    printed = capsys.readouterr().out
    assert code == 0
    result = json.loads(out.read_text())
    for key in ("frames", "joints", "bvh_us_per_frame", "yardstick_us_per_frame", "configs", "parse_mb_per_s"):
        assert key in result
    assert "numpy_parse_mb_per_s" in result and "peers" in result
    assert result["frames"] == 2000 and result["joints"] == 38
    assert [c["k"] for c in result["configs"]] == list(range(1, 39))
    for config in result["configs"]:
        assert {"k", "us_per_frame", "ratio_to_bvh"} <= set(config) and config["us_per_frame"] > 0
        assert config["max_position_error"] <= 1e-9  # every configuration keeps every position
    assert result["engine_vs_reference_error"] <= 1e-12
    assert {"shift_root", "split", "join"} <= set(result["operations"])
    assert result["memory"]["positions_peak_mb"] > 0
    for peer in result["peers"]:
        assert {"name", "version", "us_per_frame"} <= set(peer)
        assert peer["agrees"], peer  # every installed peer computes the same positions
    for label in ("C_1 ", "C_38", "faster than BVH", "targets:", "MB/s", "operations on 2000 frames"):
        assert label in printed
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    markdown = tables.read_text()
    assert "| 38 |" in markdown and "Parsing:" in markdown and "x faster than BVH" in markdown
