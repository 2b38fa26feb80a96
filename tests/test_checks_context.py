"""What the checks read (core.checks.context): the cache, the up axis and units a file states, the
middles on exact values, findings' levels and frames, runs per joint and their merging; the
passes over the frames (core.checks.passes) in both backends."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.checks.context import FILE_UNITS, CheckData, joint_runs, merge_runs, runs
from gmr_studio.core.checks.passes import (
    block_counts_at_most,
    column_medians,
    cosines_below,
    deviations_and_block_counts,
    flat_indices_above,
    joint_coordinates,
    largest_steps,
    medians_and_deviations,
    middles,
    root_jumps,
    second_differences,
    skate_windows,
    step_angles,
    step_cosines,
    steps_within,
)
from gmr_studio.core.kinematics.engine import have_numba
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import UNITS
from tests.checks_walk import clean_walk


def _data(facts: FileFacts | None = None, first=0) -> CheckData:
    motion = clean_walk(30.0, seconds=0.2).replace(facts=facts or FileFacts(up_axis="y"))
    positions = np.zeros((motion.n_frames, motion.n_joints, 3))
    return CheckData(motion, positions, 2.0, first=first)


def test_cached_computes_once_per_key():
    data, calls = _data(), []
    assert data.cached("a", lambda: calls.append("a") or 1) == 1
    assert data.cached("a", lambda: calls.append("again") or 2) == 1
    assert data.cached("b", lambda: calls.append("b") or None) is None
    assert data.cached("b", lambda: calls.append("b again") or 3) is None
    assert calls == ["a", "b"]


def test_the_data_of_a_motion():
    data = _data()
    assert (data.n_frames, data.frame_time, data.up, data.units) == (6, 1 / 30.0, 1, FILE_UNITS)
    stated = _data(FileFacts(unit=UNITS["cm"], up_axis="z"))
    assert (stated.up, stated.units) == (2, "cm")


def test_middles_and_deviations_on_exact_values():
    """P = 0, 1, 4 (x) and 0, 0, 2 (y): the middle frame is 1 - 2 = -1 in x, 0 - 1 = -1 in y."""
    data = _data()
    positions = np.zeros((3, 2, 3))
    positions[:, 0, 0] = [0.0, 1.0, 4.0]
    positions[:, 0, 1] = [0.0, 0.0, 2.0]
    data = CheckData(data.motion, positions, 1.0)
    np.testing.assert_array_equal(middles(positions), [[[-1.0, -1.0, 0.0], [0.0, 0.0, 0.0]]])
    np.testing.assert_allclose(data.deviations, [[np.sqrt(2.0), 0.0]], rtol=1e-15)
    assert data.middle_products.shape == (0, 2)
    np.testing.assert_array_equal(positions[1, 0], [1.0, 0.0, 0.0])  # not changed in place


def test_a_finding_at_the_files_frames():
    data = _data(first=5)
    finding = data.finding("pop", np.array([2, 0]), 1, 3, 2, np.float64(0.5), "cm")
    assert (finding.joints, finding.names, finding.start, finding.end) == ((2, 0), ("Spine1", "Hips"), 6, 8)
    assert (finding.severity, finding.value, type(finding.value)) == ("warning", 0.5, float)
    assert [data.finding("pop", [], 0, 0, level, 1.0, "cm").severity for level in (1, 2, 3)] == [
        "info",
        "warning",
        "error",
    ]
    for level in (0, 4):
        with pytest.raises(ValueError, match=f"a pop finding needs a severity level of 1 to 3, not {level}"):
            data.finding("pop", [], 0, 0, level, 1.0, "cm")


def test_runs_of_each_joint():
    mask = np.array([[1, 0], [1, 1], [0, 1], [1, 1]], bool)
    np.testing.assert_array_equal(joint_runs(mask), [[0, 0, 2], [0, 3, 4], [1, 1, 4]])
    assert joint_runs(mask).dtype == np.int64
    assert joint_runs(np.zeros((3, 2), bool)).shape == (0, 3)
    np.testing.assert_array_equal(runs(np.array([0, 1, 1, 0, 1], bool)), [[1, 3], [4, 5]])


def test_merge_runs_across_gaps():
    found = np.array([[0, 2], [3, 5], [7, 8], [11, 12]])
    np.testing.assert_array_equal(merge_runs(found, 0), found)
    np.testing.assert_array_equal(merge_runs(found, 1), [[0, 5], [7, 8], [11, 12]])
    np.testing.assert_array_equal(merge_runs(found, 2), [[0, 8], [11, 12]])
    np.testing.assert_array_equal(merge_runs(found, 3), [[0, 12]])
    np.testing.assert_array_equal(merge_runs(found[:1], 5), [[0, 2]])
    assert merge_runs(found[:0], 5).shape == (0, 2)


def test_two_runs_merge():
    np.testing.assert_array_equal(merge_runs(np.array([[0, 2], [3, 5]]), 1), [[0, 5]])


def test_check_data_is_frozen_compared_by_identity_and_keeps_its_cache_out_of_repr():
    data = _data()
    twin = CheckData(data.motion, data.positions, data.size)
    assert data == data and data != twin and len({data, twin}) == 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        data.size = 3.0
    data.cached("big", lambda: "cached value")
    assert "cached value" not in repr(data) and "shared" not in repr(data)


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_the_passes_over_the_frames_on_exact_values(backend):
    """Joint 0's middles -1 then 1 (x), their product -1; joint 1's middle -1.5 (z) and then
    a gap; the largest steps of any joint; the angles between consecutive rotations."""
    if backend == "numba" and not have_numba():
        pytest.skip("numba is not installed")
    positions = np.zeros((4, 2, 3))
    positions[:, 0, 0] = [0.0, 1.0, 4.0, 5.0]  # middles: 1 - 2 = -1, 4 - 3 = 1
    positions[:, 1, 2] = [0.0, 0.0, 3.0, np.nan]
    deviations, products = second_differences(positions, backend=backend)
    np.testing.assert_allclose(deviations[:, 0], [1.0, 1.0], rtol=1e-15)
    np.testing.assert_allclose(deviations[:, 1], [1.5, np.nan], rtol=1e-15)
    np.testing.assert_allclose(products, [[-1.0, np.nan]], rtol=1e-15)
    np.testing.assert_allclose(largest_steps(positions, backend=backend), [1.0, 9.0, 1.0], rtol=1e-15)
    assert np.isnan(largest_steps(positions, [1], backend=backend)[2])  # every step NaN: NaN
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 degrees about z
    rotations = np.stack([np.eye(3), quarter, quarter])[:, None]
    np.testing.assert_allclose(step_angles(rotations, backend=backend), [[90.0], [0.0]], rtol=1e-15)


@pytest.mark.skipif(not have_numba(), reason="numba is not installed")
def test_the_compiled_passes_agree_with_numpy(rng):
    positions = rng.normal(size=(50, 7, 3))
    positions[20, 3] = np.nan  # a gap
    rotations = Rotation.random(150, random_state=3).as_matrix().reshape(30, 5, 3, 3)
    rotations[7, 2] = np.nan
    for compiled, reference in (
        (second_differences(positions, backend="numba"), second_differences(positions, backend="numpy")),
        ((largest_steps(positions, backend="numba"),), (largest_steps(positions, backend="numpy"),)),
        ((largest_steps(positions, [6, 3], backend="numba"),), (largest_steps(positions, [6, 3], backend="numpy"),)),
        ((step_angles(rotations, backend="numba"),), (step_angles(rotations, backend="numpy"),)),
        ((step_cosines(rotations, [4, 0], backend="numba"),), (step_cosines(rotations, [4, 0], backend="numpy"),)),
    ):
        for got, expected in zip(compiled, reference, strict=True):
            np.testing.assert_allclose(got, expected, rtol=1e-14, atol=1e-14)
            assert np.array_equal(np.isnan(got), np.isnan(expected))


@pytest.mark.skipif(not have_numba(), reason="numba is not installed")
def test_the_compiled_selections_agree_with_numpy(rng):
    """The steps below a cosine, the medians and their deviations, the counts per block:
    the same from the kernels as from numpy (selections; the cosines to rounding, as above)."""
    rotations = Rotation.random(600, random_state=4).as_matrix().reshape(100, 6, 3, 3)
    rotations[40:60, 2] = rotations[40, 2]  # held still: cosine 1
    rotations[7, 1] = np.nan
    for joints, limit in ((None, 0.2), ([5, 0, 3], -0.5), (None, 2.0), (None, -2.0)):
        got, expected = (
            cosines_below(rotations, joints, limit),
            cosines_below(rotations, joints, limit, backend="numpy"),
        )
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_allclose(got[1], expected[1], rtol=1e-14, atol=1e-14)  # sums of 9 products
    many = Rotation.random(6000, random_state=5).as_matrix().reshape(1000, 6, 3, 3)
    np.testing.assert_array_equal(cosines_below(many, None, 2.0)[0], np.arange(999 * 6))  # beyond the first guess
    values = np.round(rng.normal(size=(1001, 5)), 1)  # many ties
    values[:, 4] = 3.0  # all equal
    for step in (1, 2, 5, 1001, 2000):
        for n in (1001, 1000, 2):
            got, expected = (
                medians_and_deviations(values[:n], step),
                medians_and_deviations(values[:n], step, backend="numpy"),
            )
            np.testing.assert_array_equal(got[0], expected[0])
            np.testing.assert_array_equal(got[1], expected[1])
    close = 0.3 + np.spacing(0.3) * np.arange(6)  # values that differ in their last bits
    near = rng.choice(np.concatenate([close, -close, [0.0, 1e300, -1e-300]]), size=(1001, 3))
    for n in (1001, 1000, 17, 16, 3, 1):
        got, expected = medians_and_deviations(near[:n]), medians_and_deviations(near[:n], backend="numpy")
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_array_equal(got[1], expected[1])
    values[3, 1], values[4, 2] = np.nan, np.inf  # left to numpy: NaN, and NaN from |inf - inf|
    for got, expected in zip(medians_and_deviations(values), medians_and_deviations(values, backend="numpy")):
        np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(column_medians(values[:, :2]), np.median(values[:, :2], axis=0))
    np.testing.assert_array_equal(column_medians(values), np.median(values, axis=0))  # NaN: numpy's
    for block, limit in ((24, 0.0), (10, -0.5), (7, np.inf), (1000, 0.1), (2000, 0.0)):
        got = block_counts_at_most(values, block, limit)
        np.testing.assert_array_equal(got, block_counts_at_most(values, block, limit, backend="numpy"))
    positions = rng.normal(size=(100, 4, 3))
    positions[30, 1] = np.nan
    deviations, products = second_differences(positions)
    for block, limit in ((10, 0.0), (7, -0.5), (97, 0.1), (98, 0.0)):  # products not kept, counted
        got = deviations_and_block_counts(positions, block, limit)
        np.testing.assert_array_equal(got[0], deviations)
        np.testing.assert_array_equal(got[1], block_counts_at_most(products, block, limit))
        np.testing.assert_array_equal(got[1], deviations_and_block_counts(positions, block, limit, backend="numpy")[1])


def test_joint_coordinates_are_the_positions_of_those_joints(rng):
    positions = rng.normal(size=(40, 6, 3))
    for backend in ("numpy", "numba") if have_numba() else ("numpy",):
        coordinates = joint_coordinates(positions[3:], [5, 0, 2], backend=backend)
        assert coordinates.shape == (3, 3, 37) and coordinates.flags.c_contiguous
        np.testing.assert_array_equal(coordinates.transpose(2, 1, 0), positions[3:, [5, 0, 2]])


@pytest.mark.skipif(not have_numba(), reason="numba is not installed")
def test_candidates_and_root_jumps_are_numpys(rng):
    """The values above their column's limit, in order (past the first guess of room), and the
    roots' jumps and changes of velocity: the very numbers numpy gives."""
    values = rng.normal(size=(3000, 4))
    values[5, 1] = np.nan
    for limits in ([0.0, 1.0, -np.inf, np.nan], [-10.0] * 4, [10.0] * 4):
        np.testing.assert_array_equal(flat_indices_above(values, limits), np.flatnonzero(values > limits))
    positions = rng.normal(size=(60, 5, 3)) * 100.0
    positions[30, 2] = np.nan
    for roots in ([0], [2, 4]):
        for got, expected in zip(root_jumps(positions, roots), root_jumps(positions, roots, backend="numpy")):
            np.testing.assert_array_equal(got, expected)
    assert root_jumps(positions[:3], [0])[0].shape == (0, 1)


@pytest.mark.skipif(not have_numba(), reason="numba is not installed")
def test_the_skate_windows_are_numpys(rng):
    """Feet planted in runs, moving a little or more, a gap: the steps covered by sliding
    windows and the stillest steps, the same from the kernel as from numpy, for windows of
    1 to 5 frames and groups of one to three joints."""
    x, y = rng.normal(size=(2, 3, 200)).cumsum(axis=2) * 0.1
    x[1, 50] = np.nan
    planted = np.repeat(rng.random((40, 3)) < 0.7, 5, axis=0)  # (F, K) in runs of 5 frames
    for w in (1, 3, 5):
        for group in ([0], [2, 1], [0, 1, 2]):
            for limit in (0.0, 0.05, 0.3):
                got = skate_windows(x, y, planted, group, w, limit)
                expected = skate_windows(x, y, planted, group, w, limit, backend="numpy")
                np.testing.assert_array_equal(got[0], expected[0])
                np.testing.assert_array_equal(got[1], expected[1])
    covered, stillest = skate_windows(x[:, :2], y[:, :2], planted[:2], [0], 1, 0.0)
    assert covered.shape == stillest.shape == (1,)


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_steps_within_a_tolerance_are_the_largest_steps_within_it(backend):
    """Held frames, a step of exactly the tolerance, a joint in a gap, every joint in a gap."""
    if backend == "numba" and not have_numba():
        pytest.skip("numba is not installed")
    positions = np.zeros((6, 3, 3))
    positions[2:, 0, 0] = 2.0  # joint 0 steps by 2 (4 squared) from frame 1 to 2
    positions[4, 1] = np.nan  # joint 1 in a gap at frame 4
    positions[5, :, 1] = 1.0  # every joint steps by 1 from 4 to 5 (joint 1 from its gap)
    for joints, tolerance in ((None, 1.0), (None, 4.0), ([1], 0.0), ([0, 2], 0.5)):
        expected = largest_steps(positions, joints, backend="numpy") <= tolerance
        np.testing.assert_array_equal(steps_within(positions, joints, tolerance, backend=backend), expected)
    np.testing.assert_array_equal(steps_within(positions, None, 1.0, backend=backend), [True, False, True, True, True])
    np.testing.assert_array_equal(steps_within(positions, [1], 1.0, backend=backend), [True, True, True, False, False])
