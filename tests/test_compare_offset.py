"""The offset between two takes (core/compare/offset.py): the offset found from the whole body,
with how sure it is; one default offset for the CLI and the app, printed; clocks that share no
time refused in one line. Against plain loops: the scores of every lag, the overlap rule, the
features of one side, the centroid's travel, B at A's rate, ties, the runner-up, the sizes, and
what a search prints."""

from __future__ import annotations

import dataclasses
import inspect
import json

import numpy as np
import pytest

from gmr_studio.core.benchmark.compare_speed import perturbed
from gmr_studio.core.cli import main
from gmr_studio.core.compare import compare_motions, compare_tracks
from gmr_studio.core.compare.clock import DEFAULT_OFFSET, ghost_positions
from gmr_studio.core.compare.offset import (
    CHANNEL_BLOCK,
    FEATURE_BLOCK,
    PROJECTED_CHANNELS,
    OffsetSearch,
    at_rate,
    direct_mismatch,
    find_offset,
    find_offset_of_tracks,
    lag_scores,
    pose_features,
    search_offset,
    travel,
)
from gmr_studio.core.compare.tracks import track_of_motion, track_of_points
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


def scores_by_loops(fa: np.ndarray, fb: np.ndarray, min_overlap: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """lag_scores written as loops over lags, frames and features."""
    na, nb = len(fa), len(fb)
    lags = np.arange(-(na - 1), nb)
    scores, overlaps = [], []
    for lag in lags:
        rows = [i for i in range(na) if 0 <= i + lag < nb]
        pairs = [(fa[i, k], fb[i + lag, k]) for i in rows for k in range(fa.shape[1])]
        pairs = [(x, y) for x, y in pairs if np.isfinite(x) and np.isfinite(y)]
        overlaps.append(len(rows))
        enough = len(rows) >= max(2.0, min_overlap * min(na, nb)) and pairs
        scores.append(np.mean([(x - y) ** 2 for x, y in pairs]) if enough else np.inf)
    return lags, np.array(scores), np.array(overlaps)


def features(rng, n: int, complete: int, gappy: int) -> np.ndarray:
    values = rng.normal(size=(n, complete + gappy))
    values[:, complete:][rng.random((n, gappy)) < 0.3] = np.nan
    return values


@pytest.mark.parametrize(
    ("na", "nb", "complete", "gappy", "min_overlap"),
    [
        (23, 17, 2 * CHANNEL_BLOCK + 3, CHANNEL_BLOCK + 2, 0.5),  # blocks of both kinds, a partial last one
        (9, 30, 3, 0, 0.0),  # every lag of 2 frames or more counts
        (12, 12, 0, 5, 0.9),
        (1, 8, 2, 1, 0.0),  # one frame of A: never 2 frames overlap
        (8, 1, 2, 0, 0.0),
        (2, 2, 1, 1, 0.0),
    ],
)
def test_lag_scores_are_the_plain_mean_squares(na, nb, complete, gappy, min_overlap):
    rng = np.random.default_rng(na * 100 + nb)
    fa, fb = features(rng, na, complete, gappy), features(rng, nb, complete, gappy)
    lags, scores, overlap = lag_scores(fa, fb, min_overlap=min_overlap)
    if min_overlap == 0.5:  # the default
        np.testing.assert_array_equal(lag_scores(fa, fb)[1], scores)
    expected_lags, expected, expected_overlap = scores_by_loops(fa, fb, min_overlap)
    np.testing.assert_array_equal(lags, expected_lags)
    np.testing.assert_array_equal(overlap, expected_overlap)
    np.testing.assert_array_equal(np.isinf(scores), np.isinf(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(scores[finite], expected[finite], rtol=1e-9, atol=1e-12)


def test_a_lag_with_one_value_present_on_both_sides_scores_it():
    fa = np.array([[np.nan], [1.0], [2.0], [3.0]])
    fb = np.array([[0.0], [0.0], [5.0], [7.0]])
    lags, scores, overlap = lag_scores(fa, fb, min_overlap=0.0)
    at = int(np.flatnonzero(lags == 2)[0])  # A's 0 and 1 with B's 2 and 3: one pair present
    assert overlap[at] == 2 and scores[at] == pytest.approx(36.0)
    assert np.isinf(scores[lags == 3]).all()  # one frame overlapping
    # frames overlapping but no value present on both sides: nothing to score
    fa, fb = np.array([[1.0], [2.0], [np.nan], [np.nan]]), np.array([[np.nan], [np.nan], [3.0], [4.0]])
    lags, scores, overlap = lag_scores(fa, fb, min_overlap=0.0)
    assert overlap[lags == 0][0] == 4 and np.isinf(scores[lags == 0]).all()
    assert scores[lags == 2][0] == pytest.approx(((1 - 3) ** 2 + (2 - 4) ** 2) / 2)


def test_nothing_to_compare_scores_inf_at_every_lag():
    rng = np.random.default_rng(1)
    for fa, fb in (
        (rng.normal(size=(0, 2)), rng.normal(size=(5, 2))),
        (rng.normal(size=(5, 2)), rng.normal(size=(0, 2))),
        (rng.normal(size=(5, 0)), rng.normal(size=(6, 0))),
    ):
        lags, scores, _ = lag_scores(fa, fb)
        assert len(lags) == len(fa) + len(fb) - 1 == len(scores) and np.isinf(scores).all()
    alone = rng.normal(size=(6, 2))
    only_0 = search_offset(alone, alone, 10.0, min_overlap=1.0)  # no other lag overlaps every frame
    assert (only_0.lag, only_0.runner_up, only_0.overlap) == (0, None, 6) and np.isnan(only_0.runner_up_mismatch)
    # B's features a billion times A's: the least mismatch still ties with itself
    assert search_offset(alone, 1e9 * rng.normal(size=(6, 2)), 10.0, min_overlap=0.0).overlap >= 2
    found = search_offset(rng.normal(size=(5, 2)), rng.normal(size=(0, 2)), 10.0)
    assert (found.lag, found.runner_up, found.overlap, found.rate) == (0, None, 0, 10.0)
    assert np.isnan(found.mismatch) and np.isnan(found.runner_up_mismatch)


def test_direct_mismatch_is_the_rms_of_the_pairs_present():
    rng = np.random.default_rng(2)
    fa, fb = features(rng, 15, 2, 2), features(rng, 11, 2, 2)
    for lag in (-14, -3, 0, 4, 10):
        rows = [i for i in range(15) if 0 <= i + lag < 11]
        pairs = np.array([fa[i] - fb[i + lag] for i in rows])
        assert direct_mismatch(fa, fb, lag) == pytest.approx(np.sqrt(np.nanmean(pairs**2)), rel=1e-12)
    assert np.isnan(direct_mismatch(fa, fb, 40))


def test_pose_features_by_loops_over_frames_and_points():
    rng = np.random.default_rng(3)
    n, joints, size = FEATURE_BLOCK + 5, 4, 2.5
    positions = rng.normal(size=(n, joints, 3))
    positions[3, 1] = np.nan
    positions[FEATURE_BLOCK + 2, 0] = np.nan
    rotations = np.linalg.qr(rng.normal(size=(n, joints, 3, 3)))[0]
    columns, oriented = np.array([0, 1, 3]), np.array([1, 2, 3])
    found, centroid = pose_features(positions, rotations, columns, oriented, size)
    assert found.shape == (n, 6) and centroid.shape == (n, 3)
    for f in (0, 3, FEATURE_BLOCK - 1, FEATURE_BLOCK, FEATURE_BLOCK + 2, n - 1):
        points = positions[f, columns]
        present = np.isfinite(points).all(axis=1)
        middle = points[present].mean(axis=0)
        np.testing.assert_allclose(centroid[f], middle, rtol=1e-12, atol=1e-15)
        distances = np.linalg.norm(points - middle, axis=1) / size
        np.testing.assert_allclose(found[f, :3], distances, rtol=1e-12)
        chords = [np.linalg.norm(rotations[f, j] - rotations[f, oriented[0]]) for j in oriented]
        np.testing.assert_allclose(found[f, 3:], chords, rtol=1e-12, atol=1e-15)
    assert np.isnan(found[3, 1]) and np.isnan(found[FEATURE_BLOCK + 2, 0])
    # every point in order, no rotations
    every, middle = pose_features(positions, None, np.arange(joints), None, size)
    assert every.shape == (n, joints)
    np.testing.assert_allclose(every[0], np.linalg.norm(positions[0] - positions[0].mean(0), axis=1) / size)
    assert pose_features(positions, rotations, columns, np.array([], int), size)[0].shape == (n, 3)
    assert pose_features(positions, rotations, columns, None, size)[0].shape == (n, 3)
    # three frames, the first three of four points (as many points as frames)
    first, _ = pose_features(positions[:3], None, np.arange(3), None, size)
    points = positions[:3, :3]
    expected = np.linalg.norm(points - points.mean(axis=1, keepdims=True), axis=-1) / size
    np.testing.assert_allclose(first, expected, rtol=1e-12)
    # every point, in another order
    cycled = np.array([1, 2, 3, 0])
    found, centroid = pose_features(positions, None, cycled, None, size)
    np.testing.assert_allclose(found, every[:, cycled], rtol=1e-12)


@pytest.mark.parametrize(("rate", "step"), [(100.0, 10), (30.0, 3), (4.0, 1)])
def test_travel_is_the_centroids_speed_at_the_middle_of_the_window(rate, step):
    rng = np.random.default_rng(4)
    centroid = rng.normal(size=(25, 3))
    speed = travel(centroid, rate, 2.0)
    assert speed.shape == (25, 1)
    for f in range(25):
        start = f - step // 2
        if 0 <= start and start + step < 25:
            expected = np.linalg.norm(centroid[start + step] - centroid[start]) * rate / step / 2.0
            assert speed[f, 0] == pytest.approx(expected, rel=1e-12)
        else:
            assert np.isnan(speed[f, 0])
    assert np.isnan(travel(centroid[:step], rate, 2.0)).all()


def test_b_at_as_rate_covers_bs_duration_linearly():
    values = np.arange(11.0)[:, None] * np.array([[1.0, -2.0]])  # 11 frames at 50 Hz: 0.2 s
    at_100 = at_rate(values, 50.0, 100.0)
    np.testing.assert_allclose(at_100, np.arange(21.0)[:, None] / 2 * np.array([[1.0, -2.0]]), atol=1e-12)
    at_20 = at_rate(values, 50.0, 20.0)  # 0, 2.5, 5, 7.5, 10 of B's frames
    np.testing.assert_allclose(at_20[:, 0], [0.0, 2.5, 5.0, 7.5, 10.0], atol=1e-12)
    assert at_rate(values, 50.0, 50.0) is values and at_rate(values[:1], 50.0, 100.0).shape == (1, 2)
    np.testing.assert_allclose(at_rate(values[:2], 10.0, 20.0), [[0.0, 0.0], [0.5, -1.0], [1.0, -2.0]], atol=1e-12)


def test_ties_go_to_the_tie_break_then_to_the_lag_nearest_0():
    flat_a, flat_b = np.zeros((40, 2)), np.zeros((40, 2))  # every lag matches

    def ramps():  # B is A five frames later; one frame away misses by 1 a frame
        t = np.arange(40.0)[:, None]
        return t, t - 5.0

    assert search_offset(flat_a, flat_b, 10.0).lag == 0
    # equal to rounding is equal: a periodic motion against itself scores 3e-16 at lag 0 and
    # 0 at other periods (the transforms' rounding): still lag 0
    t = np.arange(100)
    periodic = np.stack([np.sin(2 * np.pi * t / 10), 0.5 * np.cos(2 * np.pi * t / 10) + 0.3], axis=1)
    lags, scores, _ = lag_scores(periodic, periodic, min_overlap=0.3)
    assert scores[lags == 0][0] < 1e-14 and scores.min() >= 0.0  # 3e-16 and 0 with numpy 2's pocketfft
    assert search_offset(periodic, periodic, 10.0, min_overlap=0.3).lag == 0
    found = search_offset(flat_a, flat_b, 10.0, tie_break=ramps)
    assert found.lag == 5 and found.mismatch == 0.0
    noise = np.random.default_rng(11).normal(scale=0.1, size=(40, 1))
    assert search_offset(flat_a, flat_b, 10.0, tie_break=lambda: (ramps()[0] + noise, ramps()[1])).lag == 5

    # two tied lags only (-3 and 7 of a 10-frame period, half overlapping): the tie-break decides
    wave = np.sin(2 * np.pi * np.arange(30.0) / 10)[:, None]
    shifted = lambda: (np.arange(20.0)[:, None], np.arange(20.0)[:, None] - 7)  # noqa: E731
    assert search_offset(wave[:20], wave[3:23], 10.0, tie_break=shifted).lag == 7
    # the tie-break's own ties are within 1e-9: a lag missing by 1 + 2.25 is not one missing by 2.25
    swing = 1.5 * np.where(np.arange(40) % 2, 1.0, -1.0)[:, None]
    assert search_offset(flat_a, flat_b, 10.0, tie_break=lambda: (ramps()[0] + swing, ramps()[1])).lag == 5

    def never():
        raise AssertionError("the tie-break is computed only for a tie")

    rng = np.random.default_rng(12)
    fa = rng.normal(size=(50, 2))
    assert search_offset(fa, fa[8:], 10.0, tie_break=never).lag == -8
    # a periodic motion (10 frames) and its cut 3 frames in: -3, 7, -13... tie, -3 is nearest 0
    wave = np.sin(2 * np.pi * np.arange(60.0) / 10)[:, None] * np.array([[1.0, 0.5]])
    assert search_offset(wave, wave[3:], 10.0, min_overlap=0.3).lag == -3
    assert search_offset(wave[3:], wave, 10.0, min_overlap=0.3).lag == 3


def test_the_runner_up_is_the_best_lag_a_quarter_second_away():
    rng = np.random.default_rng(5)
    fa = np.cumsum(rng.normal(size=(200, 3)), axis=0) / 10  # smooth: the nearest lags allowed miss least
    fb = fa[30:150] + rng.normal(scale=0.01, size=(120, 3))
    lags, scores, overlap = scores_by_loops(fa, fb, 0.5)
    for rate, away in ((40.0, 10), (1.0, 1)):  # a quarter second; at 1 Hz, less than a frame: one
        found = search_offset(fa, fb, rate, min_overlap=0.5)
        assert found.lag == -30 and found.overlap == overlap[lags == -30][0] == 120
        far = np.abs(lags + 30) >= away
        runner = int(lags[far][np.argmin(scores[far])])
        assert found.runner_up == runner
        assert found.runner_up_mismatch == pytest.approx(np.sqrt(scores[lags == runner][0]), rel=1e-9)
        assert found.mismatch == pytest.approx(np.sqrt(scores[lags == -30][0]), rel=1e-9)
    assert abs(search_offset(fa, fb, 40.0).runner_up + 30) == 10
    assert abs(search_offset(fa, fb, 1.0).runner_up + 30) == 1


def test_many_channels_are_projected_but_the_mismatch_is_on_every_channel():
    rng = np.random.default_rng(6)
    k = 3 * PROJECTED_CHANNELS
    fa = rng.normal(size=(120, k))
    fb = fa[12:100] + rng.normal(scale=0.05, size=(88, k))
    fb[:, 0] = np.nan  # a channel with gaps stays as it is
    found = search_offset(fa, fb, 50.0)
    assert found.lag == -12
    assert found.mismatch == direct_mismatch(fa, fb, -12)
    assert found.runner_up_mismatch == direct_mismatch(fa, fb, found.runner_up)
    assert 0.04 < found.mismatch < 0.06 < 1.0 < found.runner_up_mismatch
    short = search_offset(fa[:10], fa[:10] + 0.01, 50.0)  # fewer frames than channels
    assert short.lag == 0 and short.mismatch == direct_mismatch(fa[:10], fa[:10] + 0.01, 0)


def test_the_mismatch_is_in_as_sizes():
    motion = make_rig("metres").frame_slice(slice(0, 120))
    a, b = track_of_motion(motion), track_of_motion(motion.frame_slice(slice(10, 120)))
    noisy = dataclasses.replace(
        b, positions=b.positions + np.random.default_rng(7).normal(scale=0.01, size=b.positions.shape)
    )
    joints = np.arange(a.positions.shape[1])
    results = {}
    for size in (0.5, 2.0, 0.0):
        found = find_offset_of_tracks(dataclasses.replace(a, size=size), noisy, joints, joints, b.frame_rate, 1.0)
        assert found.lag == -10
        results[size] = found
    assert results[0.5].mismatch == pytest.approx(4 * results[2.0].mismatch, rel=0.2)
    assert results[0.0].mismatch == pytest.approx(2 * results[2.0].mismatch, rel=0.2)  # no size: 1


def test_a_search_says_what_it_found():
    sure = OffsetSearch(-50, 1e-10, -35, 0.0123, 100, 120.0)
    assert sure.text() == "whole-body mismatch 1e-10 against 0.0123 at the next best, -35 frames (-0.2917 s)"
    assert sure.to_json() == {
        "lag": -50,
        "mismatch": 1e-10,
        "runner_up": -35,
        "runner_up_mismatch": 0.0123,
        "overlap": 100,
    }
    alone = OffsetSearch(0, float("nan"), None, float("nan"), 0, 30.0)
    assert alone.text() == "whole-body mismatch nan (no other offset overlaps enough to compare)"
    assert alone.to_json() == {"lag": 0, "mismatch": None, "runner_up": None, "runner_up_mismatch": None, "overlap": 0}
    with pytest.raises(dataclasses.FrozenInstanceError):
        sure.lag = 1  # type: ignore[misc]


def test_tracks_without_rotations_compare_positions_only():
    motion = make_rig("metres").frame_slice(slice(0, 90))
    a = track_of_motion(motion)
    b = dataclasses.replace(track_of_motion(motion.frame_slice(slice(5, 90))), rotations=None)
    joints = np.arange(a.positions.shape[1])
    found = find_offset_of_tracks(a, b, joints, joints, b.frame_rate, 1.0)
    assert found.lag == -5 and found.mismatch < 1e-9


def test_find_offset_of_several_points():
    motion = make_rig("metres").frame_slice(slice(0, 150))
    positions = track_of_motion(motion).positions[:, :5]
    lag, mismatch = find_offset(positions[:100], positions[17:], motion.frame_rate, motion.frame_rate)
    assert lag == -17 and mismatch < 1e-9


def test_the_channels_with_gaps_are_searched_beside_the_projected_ones():
    rng = np.random.default_rng(14)
    fa = np.full((80, 2 * PROJECTED_CHANNELS), 0.5)  # complete channels that cannot tell a lag
    fa = np.concatenate([fa, np.cumsum(rng.normal(size=(80, 1)), axis=0)], axis=1)
    fb = fa[12:70].copy()
    fa[40, -1] = np.nan  # the one telling channel has a gap
    assert search_offset(fa, fb, 10.0).lag == -12


def test_a_tie_is_broken_by_the_positions_in_as_units():
    """A point going straight at constant speed: its features are the same at every lag; B
    is A from frame 7, in centimetres (A in metres, 2.97 m long): the positions, in A's
    units and sizes, say -7 (and a circling point too)."""
    t = np.arange(100.0)
    line = np.stack([1 + 0.03 * t, np.full(100, 0.5), np.zeros(100)], axis=1)[:, None]
    angle = t * 2 * np.pi / 400
    circle = np.stack([np.cos(angle), np.zeros(100), np.sin(angle)], axis=1)[:, None]
    joint = np.array([0])
    for path in (line, circle):
        a = track_of_points(["p"], path, 30.0)
        b = track_of_points(["p"], 100 * path[7:], 30.0)
        assert find_offset_of_tracks(a, b, joint, joint, 30.0, 0.01).lag == -7


def test_the_options_are_keyword_only():
    for function in (lag_scores, search_offset, find_offset_of_tracks, find_offset):
        parameters = inspect.signature(function).parameters
        assert parameters["min_overlap"].kind is inspect.Parameter.KEYWORD_ONLY
        assert parameters["min_overlap"].default == 0.5  # half of the shorter side
    assert inspect.signature(find_offset_of_tracks).parameters["up_rotation"].kind is inspect.Parameter.KEYWORD_ONLY


def test_up_to_12_complete_channels_are_searched_as_they_are():
    """12 channels, not projected: the mismatch of the transforms is the plain one."""
    fa = np.random.default_rng(18).normal(size=(60, 12))
    found = search_offset(fa, fa[5:] + 0.1, 10.0)
    assert found.lag == -5 and found.mismatch == pytest.approx(0.1, rel=1e-9)


def test_complete_and_gappy_channels_weigh_in_the_search_as_in_the_mismatch():
    """13 complete channels (projected for the search) agree at lag -10, 4 channels with gaps
    (searched as they are) at lag -20, three times larger: the search picks the lag whose
    mismatch over every channel is least, -20, as if no channel were projected."""
    rng = np.random.default_rng(3)
    complete = np.cumsum(rng.normal(size=(140, 13)), axis=0)
    gappy = 3.0 * np.cumsum(rng.normal(size=(140, 4)), axis=0)
    fa = np.concatenate([complete, gappy], axis=1)
    fa[[5, 60, 90, 120], 13 + np.arange(4)] = np.nan
    fb = np.concatenate([complete[10:110], gappy[20:120]], axis=1)
    assert direct_mismatch(fa, fb, -20) < 0.6 * direct_mismatch(fa, fb, -10)
    assert search_offset(fa, fb, 30.0).lag == -20
