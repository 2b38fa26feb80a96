"""The comparison's clock (issue 21, items 1-3): the offset found from the whole body, with
how sure it is; one default offset for the CLI and the app, printed; clocks that share no
time refused in one line."""

from __future__ import annotations

import inspect
import json

import numpy as np
import pytest

from gmr_studio.core.benchmark.compare_speed import perturbed
from gmr_studio.core.cli import main
from gmr_studio.core.compare import compare_motions, compare_tracks, track_of_motion
from gmr_studio.core.compare.clock import DEFAULT_OFFSET, ghost_positions
from gmr_studio.core.compare.offset import search_offset
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.jointmap import match_joints
from gmr_studio.core.rigs import make_rig
from gmr_studio.core.timebase.sampling import interpolate as resample
from tests.conftest import shared_path


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_root_pinned_at_the_origin_trimmed_is_found_at_minus_the_start(capsys, tmp_path):
    """Item 1: the Bandai-style rig (Root at the origin, the hips carry the walk): `gmr edit
    --frames 50:100` then compare with the automatic offset gives -50 and no error (the root
    trajectories alone said -169)."""
    walk = tmp_path / "W.bvh"
    write_bvh(make_rig("origin_root"), walk)
    trimmed = tmp_path / "T.bvh"
    assert run(capsys, "edit", walk, "-o", trimmed, "--frames", "50:100")[0] == 0
    code, out, _ = run(capsys, "compare", walk, trimmed, "--offset", "auto", "--json", tmp_path / "c.json")
    assert code == 0 and "B = A -50 frames" in out
    document = json.loads((tmp_path / "c.json").read_text())
    assert document["mpjpe"] < 1e-9 * document["size_a"] and document["compared"] == 50 * 28
    search = document["alignment"]["offset_search"]
    assert search["lag"] == -50 and search["mismatch"] < 1e-9
    # how sure: the next best offset is a quarter of a second away or more, with a clear mismatch
    assert abs(search["runner_up"] + 50) >= 15 and search["runner_up_mismatch"] > 1e-3
    assert "next best" in out


def test_whole_body_search_survives_per_frame_noise_and_agrees_with_a_direct_sum():
    """B is A from frame 20 on with every joint turned by ~2 degrees per frame (noise): the
    search finds -20; its mismatch at every lag equals the plain sum over frames."""
    a = read_motion(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 600))
    b = perturbed(a.frame_slice(slice(20, 600)), seed=3)
    result = compare_tracks(track_of_motion(a), track_of_motion(b), match_joints(a.names, b.names), offset="auto")
    assert result.alignment.offset_frames == -20
    found = result.alignment.offset_search
    assert found.mismatch < found.runner_up_mismatch
    rng = np.random.default_rng(0)
    fa, fb = rng.normal(size=(40, 3)), rng.normal(size=(30, 3))
    fb[5:9, 1] = np.nan
    fb[:25] = fa[7:32] + rng.normal(scale=1e-3, size=(25, 3))
    search = search_offset(fa, fb, 10.0, min_overlap=0.5)
    assert search.lag == -7
    a_rows = np.arange(40)
    b_rows = a_rows - 7
    inside = (b_rows >= 0) & (b_rows < 30)
    difference = fa[a_rows[inside]] - fb[b_rows[inside]]
    assert search.mismatch == pytest.approx(np.sqrt(np.nanmean(difference**2)), rel=1e-9)


def test_one_default_offset_printed_by_compare_and_used_by_the_app(capsys):
    """Item 2: CMU 01_01's BVH against its AMC with no --offset: the default (auto) finds the
    one-frame shift, says so, and the rotation error is that of rounding, not 174.8 degrees."""
    from gmr_studio.app.model.layers import ComparisonLayer, Layers

    assert DEFAULT_OFFSET == "auto"
    assert inspect.signature(Layers.add).parameters["offset"].default == DEFAULT_OFFSET
    assert ComparisonLayer.__dataclass_fields__["offset"].default == DEFAULT_OFFSET
    assert inspect.signature(compare_tracks).parameters["offset"].default == DEFAULT_OFFSET
    bvh, amc = shared_path("cmu/subject01/01_01.bvh"), shared_path("cmu/subject01/01_01.amc")
    code, out, _ = run(capsys, "compare", bvh, amc, "--map", "cmu")
    assert code == 0
    offset_line = next(line for line in out.splitlines() if line.startswith("offset:"))
    assert "B = A -1 frames" in offset_line and "(the default)" in offset_line
    rotation_line = next(line for line in out.splitlines() if line.startswith("rotation:"))
    assert float(rotation_line.split()[2]) < 0.01  # degrees: measured 8.8e-05
    given = run(capsys, "compare", bvh, amc, "--map", "cmu", "--offset", "-1")[1]
    assert "given" in next(line for line in given.splitlines() if line.startswith("offset:"))


def test_clocks_that_share_no_time_are_one_line_errors(capsys, tmp_path):
    """Item 3: an offset that puts every frame of A outside B's time range."""
    walk = tmp_path / "W.bvh"
    write_bvh(make_rig("metres").frame_slice(slice(0, 100)), walk)
    code, out, err = run(capsys, "compare", walk, walk, "--offset", "250")
    assert code == 2 and not out and len(err.strip().splitlines()) == 1
    assert "share no time" in err and "+250 frames" in err and "nan" not in err.lower()


def test_the_ghost_is_the_comparisons_b_on_as_clock():
    """The app's ghost comes from core.compare: for the matched joints it is the compared B."""
    a = make_rig("metres")
    b = a.frame_slice(slice(7, 200)).replace(frame_time=a.frame_time * (1 + 3e-6))  # one rate, printed apart
    result = compare_motions(a, b, offset=-7)
    from gmr_studio.core.kinematics.fk import world_positions

    ghost = ghost_positions(world_positions(b), a.n_frames, a.frame_rate, b.frame_rate, result.alignment)
    np.testing.assert_array_equal(ghost[:, result.index_b], result.positions_b)
    assert np.isnan(ghost[:7]).all() and np.isfinite(ghost[7:200]).all()
    assert resample(world_positions(b), np.array([0.0]))[0, 0, 0] == ghost[7, 0, 0]
