"""The comparison's clock (core/compare/clock.py) against plain loops and scipy: one rate within
the printed frame time's rounding, B's fractional frames, the overlap refusal, rows taken,
linear and geodesic resampling in and out of B's range, in blocks and chunks, and for some
columns only."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from gmr_studio.core.compare.clock import check_overlap, sample_frames
from gmr_studio.core.timebase.clock import common_rate
from gmr_studio.core.timebase.sampling import (
    RESAMPLE_CHUNK,
    ROTATION_BLOCK,
    interpolate,
    interpolate_rotations,
    rotations_component_major,
    take,
    whole_frames,
)


def resample_by_loops(values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """B at fractional frames, one sample at a time (NaN outside [0, N - 1] by more than 1e-6)."""
    n = len(values)
    out = np.full((len(at), *values.shape[1:]), np.nan)
    whole = np.abs(at - np.rint(at)) <= 1e-6
    for row, u in enumerate(at):
        if u < -1e-6 or u > n - 1 + 1e-6:
            continue
        if whole[row]:
            out[row] = values[min(max(int(np.rint(u)), 0), n - 1)]
            continue
        low = min(max(int(np.floor(u)), 0), max(n - 2, 0))
        weight = min(max(u - low, 0.0), 1.0)
        out[row] = values[low] + (values[min(low + 1, n - 1)] - values[low]) * weight
    return out


def test_one_rate_within_the_rounding_of_a_printed_frame_time():
    assert common_rate(120.0, 1 / 0.0083333) == 120.0  # 120.0005 Hz
    assert common_rate(120.0, 120.0 * (1 - 0.9e-5)) == 120.0
    assert common_rate(120.0, 120.0 * (1 + 1.1e-5)) == 120.0 * (1 + 1.1e-5)
    assert common_rate(120.0, 120.0 * (1 - 1.1e-5)) == 120.0 * (1 - 1.1e-5)
    assert common_rate(30.0, 60.0) == 60.0 and common_rate(60.0, 30.0) == 30.0 and common_rate(24.0, 24.0) == 24.0


def test_bs_fractional_frames_of_as_frames():
    np.testing.assert_array_equal(sample_frames(4, 10.0, 20.0, 0.5), [10.0, 12.0, 14.0, 16.0])
    np.testing.assert_array_equal(sample_frames(0, 10.0, 20.0, 0.5, frames_a=[2, 5]), [14.0, 20.0])
    np.testing.assert_allclose(sample_frames(3, 10.0, 10.0 * (1 + 1e-6), -0.2), [-2.0, -1.0, 0.0], atol=1e-12)


def test_clocks_that_share_no_time_are_refused_with_the_frames_named():
    frames = np.arange(3, 8)
    for at in (np.array([-1e-6, -1.0]), np.array([9.0 + 1e-6, 12.0]), np.array([])):
        check_overlap(at, 10, frames[: len(at)], 0.0, 0.0)  # a frame inside, to the tolerance
    for at in (np.array([-2e-6, -1.0, -5.0]), np.array([9.0 + 2e-6, 10.0, 12.5])):
        with pytest.raises(ValueError, match="share no time"):
            check_overlap(at, 10, frames[:3], 0.0, 0.0)
    with pytest.raises(ValueError) as refused:
        check_overlap(np.array([12.0, 13.0, 14.0]), 10, np.array([2, 3, 4]), 10.0, 0.25)
    assert str(refused.value) == (
        "the two motions share no time: with the offset B = A +10 frames (+0.25 s), A's frames 2-4 "
        "fall at B's frames 12 to 14, outside B's 0-9; give another --offset (or 'auto')"
    )


@pytest.mark.parametrize(
    "rows", [[2, 3, 4, 5], [5], [0, 2, 1, 3], [3, 3, 3, 3], [4, 1], [1, 2, 4], [], [0, 1, 2, 3, 4, 5, 6, 7]]
)
@pytest.mark.parametrize("columns", [None, [0, 1, 2], [2, 0], [1], [0, 1]])
def test_take_is_fancy_indexing(rows, columns):
    values = np.arange(8 * 3 * 2.0).reshape(8, 3, 2)
    rows = np.array(rows, dtype=np.int64)
    picked = take(values, rows, None if columns is None else np.array(columns))
    expected = values[rows] if columns is None else values[rows][:, columns]
    np.testing.assert_array_equal(picked, expected)
    consecutive = len(rows) > 0 and np.array_equal(rows, np.arange(rows[0], rows[0] + len(rows)))
    if consecutive and columns in (None, [0, 1, 2]):
        assert np.shares_memory(picked, values)  # a view: nothing copied


@pytest.mark.parametrize(
    "at",
    [
        np.array([-3.0, -1e-6, 0.25, 1.5, 7.0, 7.0 + 1e-6, 7.5, 12.0]),  # one run inside, outside both ends
        np.array([-1.0, 2.5, 9.0, 3.25, -4.0, 6.75]),  # scattered
        np.array([0.0, 3.0, 7.0, 5.0 + 1e-7]),  # whole frames, to the tolerance
        np.array([0.5, 6.999, 1.0 + 2e-6, 0.0]),
        np.array([-2.0, 2.0, 3.0, 4.0, 9.0]),  # whole frames, one run
        np.array([8.0, 9.0]),  # none inside
        np.array([-2.0, 3.5, 9.0]),  # one inside
        np.array([1.0, 2.5, 99.0, 3.5]),  # one outside between samples inside
        np.array([], dtype=np.float64),
    ],
)
def test_resample_is_linear_between_bs_frames_and_nan_outside(at):
    rng = np.random.default_rng(8)
    values = rng.normal(size=(8, 4, 3))
    values[4, 1] = np.nan  # a gap: its neighbours' samples are NaN
    got = interpolate(values, at)
    expected = resample_by_loops(values, at)
    assert got.shape == expected.shape
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-15)
    assert np.array_equal(np.isnan(got), np.isnan(expected))
    columns = np.array([3, 1])
    np.testing.assert_allclose(interpolate(values, at, columns), expected[:, columns], rtol=1e-12, atol=1e-15)


def test_resample_of_one_frame_and_of_many_rows_in_chunks():
    single = np.arange(6.0).reshape(1, 2, 3)
    np.testing.assert_array_equal(interpolate(single, np.array([0.0, 1e-7])), single[[0, 0]])
    assert np.isnan(interpolate(single, np.array([0.5, -0.5]))).all()
    rng = np.random.default_rng(9)
    values = rng.normal(size=(40, 30, 3))  # 90 values a row: several chunks of rows
    at = np.linspace(-1.0, 40.0, 2000)
    assert len(at) * 90 > 2 * RESAMPLE_CHUNK
    np.testing.assert_allclose(interpolate(values, at), resample_by_loops(values, at), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize(
    ("angle", "atol"),
    [(1e-5, 1e-14), (np.radians(90.0 - 1e-4), 1e-12), (np.radians(90.0 + 1e-4), 1e-12)],
)
def test_steps_take_the_path_accurate_for_them(angle, atol):
    """Steps of 1e-5 rad: the chord's arcsin keeps full relative accuracy where the far path's
    axis (from 1 - cos = 5e-11) would lose half the digits; steps of 90 degrees give or take
    1e-4 (the far path): there the arcsin of the chord would lose five digits."""
    rng = np.random.default_rng(17)
    axes = rng.normal(size=(20, 3))
    steps = Rotation.from_rotvec(angle * axes / np.linalg.norm(axes, axis=1, keepdims=True)).as_matrix()
    rotations = np.empty((20, 1, 3, 3))
    rotations[0, 0] = Rotation.random(random_state=rng).as_matrix()
    for f in range(1, 20):
        rotations[f, 0] = steps[f] @ rotations[f - 1, 0]
    at = np.linspace(0.1, 18.9, 57)
    np.testing.assert_allclose(interpolate_rotations(rotations, at), slerp_by_scipy(rotations, at), rtol=0, atol=atol)


def test_whole_frames_to_the_tolerance():
    assert whole_frames(np.array([1.0, 2.0 + 9e-7, 3.0 - 9e-7])) and whole_frames(np.array([]))
    assert not whole_frames(np.array([1.0, 2.0 + 1.1e-6]))
    assert whole_frames(np.array([1e-6, -1e-6]))  # exactly the tolerance from frame 0
    values = np.arange(12.0).reshape(3, 4)
    np.testing.assert_array_equal(interpolate(values, np.array([1e-6, 2.0])), values[[0, 2]])
    points_none = np.zeros((5, 0, 3))  # no point at all
    assert interpolate(points_none, np.array([0.5, 1.5])).shape == (2, 0, 3)


def slerp_by_scipy(rotations: np.ndarray, at: np.ndarray) -> np.ndarray:
    """(F, J, 3, 3) scipy's Slerp between B's frames, NaN outside."""
    n, joints = rotations.shape[:2]
    out = np.full((len(at), joints, 3, 3), np.nan)
    inside = (at >= -1e-6) & (at <= n - 1 + 1e-6)
    for j in range(joints):
        slerp = Slerp(np.arange(n, dtype=np.float64), Rotation.from_matrix(rotations[:, j]))
        out[inside, j] = slerp(np.clip(at[inside], 0.0, n - 1)).as_matrix()
    return out


def test_rotations_in_blocks_and_for_some_columns_equal_scipy():
    rng = np.random.default_rng(10)
    n, joints = 30, 3
    steps = Rotation.from_rotvec(rng.normal(scale=0.3, size=(n * joints, 3))).as_matrix().reshape(n, joints, 3, 3)
    rotations = np.empty((n, joints, 3, 3))
    rotations[0] = Rotation.random(joints, random_state=rng).as_matrix()
    for f in range(1, n):
        rotations[f] = steps[f] @ rotations[f - 1]
    at = np.concatenate([np.linspace(-2.0, 31.0, 2 * ROTATION_BLOCK + 77), [12.5, 3.25, 3.0]])
    expected = slerp_by_scipy(rotations, at)
    got = interpolate_rotations(rotations, at)
    assert np.array_equal(np.isnan(got), np.isnan(expected))
    np.testing.assert_allclose(got, expected, atol=1e-12)
    columns = np.array([2, 0])
    np.testing.assert_allclose(interpolate_rotations(rotations, at, columns), expected[:, columns], atol=1e-12)
    # one sample; samples one frame apart (B's frames in order, a view); at 0 by the tolerance
    for at in (
        np.array([2.5]),
        np.arange(5.0) + 0.5,
        np.array([-5e-7, 2.5]),
        np.array([-1e-6, 2.5]),
        np.array([3.25, 29.0 + 5e-7]),
        np.array([3.25, 29.0 + 1e-6]),  # B's last frame by exactly the tolerance
        np.array([0.5, 2.5, 2.7]),  # frames 0, 2, 2: as many as 0 .. 2, not those
    ):
        expected = slerp_by_scipy(rotations, at)
        np.testing.assert_allclose(interpolate_rotations(rotations, at, columns), expected[:, columns], atol=1e-12)
    in_order = rotations_component_major(rotations, np.arange(3.0, 8.0))
    np.testing.assert_array_equal(np.moveaxis(in_order, -1, 0).reshape(5, 3, 3, 3), rotations[3:8])
    # whole frames, backwards: B's frames as they are
    whole = np.array([5.0, 4.0, 2.0, 29.0, 29.0 + 1e-7, -1.0, 0.0, 35.0])
    got = interpolate_rotations(rotations, whole, columns)
    np.testing.assert_array_equal(got[[0, 1, 2, 3, 4, 6]], rotations[[5, 4, 2, 29, 29, 0]][:, columns])
    assert np.isnan(got[[5, 7]]).all()
    assert rotations_component_major(rotations, np.array([]), columns).shape == (3, 3, 0)
    major = rotations_component_major(rotations, whole, columns)
    assert major.shape == (3, 3, 16)
    np.testing.assert_array_equal(np.moveaxis(major, -1, 0).reshape(8, 2, 3, 3), got)


def test_one_frame_of_rotations_is_that_frame_at_0_and_nan_elsewhere():
    frame = Rotation.random(2, random_state=np.random.default_rng(13)).as_matrix()[None]  # (1, 2, 3, 3)
    got = interpolate_rotations(frame, np.array([0.0, 5.5, -0.5]))
    np.testing.assert_array_equal(got[0], frame[0])
    assert np.isnan(got[1:]).all()


def test_a_sample_on_a_frame_beside_a_gap_is_that_frame_and_between_them_a_gap():
    """A sample on one of B's frames is that frame, whatever its neighbours; one between a
    frame and a gap is a gap."""
    values = np.array([[np.nan, 1.0], [2.0, 3.0]])
    got = interpolate(values, np.array([0.5, 1.0]))
    assert np.isnan(got[0, 0]) and got[0, 1] == 2.0 and got[1].tolist() == [2.0, 3.0]
    rotations = Rotation.random(3, random_state=np.random.default_rng(15)).as_matrix()[:, None]
    rotations[1] = np.nan
    got = interpolate_rotations(rotations, np.array([2.0, 0.5, 2.5]))
    np.testing.assert_array_equal(got[0, 0], rotations[2, 0])
    assert np.isnan(got[1:]).all()
    got = interpolate_rotations(rotations, np.array([2.0, 2.0]))  # whole frames: B's frame as it is
    np.testing.assert_array_equal(got[:, 0], rotations[[2, 2], 0])


def test_rows_wider_than_a_chunk_are_resampled_one_at_a_time():
    wide = np.random.default_rng(16).normal(size=(3, 22_000, 3))  # 66,000 values a frame
    assert wide[0].size > RESAMPLE_CHUNK
    at = np.array([0.5, 1.25])
    np.testing.assert_allclose(interpolate(wide, at), resample_by_loops(wide, at), rtol=1e-12, atol=1e-15)
