"""Trim and resample: exact at the kept frames, slerp/lerp in between (scipy as the oracle)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from gmr_studio.core.edits.clip import resample, trim
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from gmr_studio.core.timebase.sampling import resample_grid as resample_positions
from tests.conftest import random_motion, shared_path


@pytest.fixture(scope="module")
def walk():
    return load_gmr(shared_path("cmu/subject01/01_01.bvh"))


def test_trim_keeps_the_frames_and_their_world_positions(walk):
    trimmed = trim(walk, 100, 350)
    assert trimmed.n_frames == 250 and trimmed.frame_time == walk.frame_time
    reference, _ = reference_forward_kinematics(walk)
    positions, _ = reference_forward_kinematics(trimmed)
    np.testing.assert_array_equal(positions, reference[100:350])
    trimmed.check_invariants()
    assert trim(walk, None, None) is walk
    for bad in ((5, 5), (-1, 3), (0, walk.n_frames + 1), (10, 2)):
        with pytest.raises(OperationError, match="frame range"):
            trim(walk, *bad)


def test_resample_to_a_divisor_rate_keeps_every_fourth_frame_exactly(walk):
    quarter = resample(walk, walk.frame_rate / 4)
    assert quarter.n_frames == (walk.n_frames - 1) // 4 + 1
    assert quarter.frame_time == pytest.approx(4 * walk.frame_time, rel=1e-12)
    np.testing.assert_array_equal(quarter.rotations, walk.rotations[::4])
    np.testing.assert_array_equal(quarter.translations, walk.translations[::4])
    quarter.check_invariants()


def test_a_rate_dividing_the_printed_one_takes_every_nth_frame_as_it_is(walk):
    # 0.0083333 s is 120 Hz printed to 7 decimals: 60 and 40 Hz are every 2nd and 3rd frame,
    # not slerps drifting off the frames by the rounding (0.4 frames after 100,000 frames)
    for rate, every in ((60.0, 2), (40.0, 3), (120.0, 1)):
        resampled = resample(walk, rate)
        assert resampled.n_frames == (walk.n_frames - 1) // every + 1
        np.testing.assert_array_equal(resampled.rotations, walk.rotations[::every])
        np.testing.assert_array_equal(resampled.translations, walk.translations[::every])
        assert resampled.frame_time == (walk.frame_time if every == 1 else 1 / rate)
    long = resample_positions(100_000, walk.frame_time, 60.0)
    np.testing.assert_array_equal(long, np.arange(0.0, 100_000.0, 2.0))


def test_resample_between_frames_is_slerp_and_lerp_and_kept_times_are_exact(walk):
    clip = trim(walk, 0, 400).replace(frame_time=1 / 120)  # the file says 0.0083333 s
    rate = 50.0  # 120 Hz -> 50 Hz: new frame k at source frame 2.4 k, every 5th one a source frame
    resampled = resample(clip, rate)
    where = np.arange(resampled.n_frames) * clip.frame_rate / rate
    assert resampled.n_frames == int(np.floor(399 / 2.4)) + 1
    source_times = np.arange(clip.n_frames)
    oracle_rotations = np.empty_like(resampled.rotations)
    for j in range(clip.n_joints):
        oracle_rotations[:, j] = Slerp(source_times, Rotation.from_matrix(np.array(clip.rotations[:, j])))(
            where
        ).as_matrix()
    oracle_translations = np.stack(
        [[np.interp(where, source_times, clip.translations[:, j, a]) for a in range(3)] for j in range(clip.n_joints)]
    ).transpose(2, 0, 1)
    np.testing.assert_allclose(resampled.rotations, oracle_rotations, rtol=0, atol=1e-12)
    np.testing.assert_allclose(resampled.translations, oracle_translations, rtol=0, atol=1e-12 * clip.size)
    mine, _ = reference_forward_kinematics(resampled)
    oracle, _ = reference_forward_kinematics(
        clip.replace(rotations=oracle_rotations, translations=oracle_translations, frame_time=1 / rate)
    )
    np.testing.assert_allclose(mine, oracle, rtol=0, atol=1e-11 * clip.size)
    kept = np.flatnonzero(np.arange(resampled.n_frames) % 5 == 0)
    source, _ = reference_forward_kinematics(clip)
    np.testing.assert_array_equal(mine[kept], source[(kept * 12) // 5])
    resampled.check_invariants()


def test_resample_of_the_files_own_frame_time_interpolates_near_the_source_frames(walk):
    # 0.0083333 s is not 1/120 s: 50 Hz frames fall 5e-5 frames past the source ones
    where = resample_positions(walk.n_frames, walk.frame_time, 50.0)
    assert where[5] == pytest.approx(12.0 + 12 * (1 / (120 * 0.0083333) - 1), abs=1e-12)


def test_resample_positions_snap_to_source_frames_and_stop_at_the_last():
    where = resample_positions(11, 1 / 30, 90)  # three times as many frames
    assert where.size == 31 and where[-1] == 10.0
    np.testing.assert_array_equal(where[::3], np.arange(11.0))
    assert resample_positions(7, 0.1, 10 / 3).tolist() == [0.0, 3.0, 6.0]
    with pytest.raises(ValueError, match="frame rate"):
        resample_positions(5, 0.1, 0.0)


def test_upsampling_a_random_post_motion_keeps_every_source_frame(rng):
    motion = random_motion(rng, [-1, 0, 1, 0], n_frames=12, convention="post")
    doubled = resample(motion, 2 * motion.frame_rate)
    assert doubled.n_frames == 23 and doubled.convention == "post"
    np.testing.assert_array_equal(doubled.rotations[::2], motion.rotations)
    np.testing.assert_array_equal(doubled.translations[::2], motion.translations)
    assert resample(motion, motion.frame_rate) is motion


def test_resample_a_bvh_in_its_own_convention():
    motion = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    half = resample(trim(motion, 0, 201).replace(frame_time=1 / 120), 60.0)
    np.testing.assert_array_equal(half.rotations, motion.rotations[0:201:2])
