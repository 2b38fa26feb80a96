"""Resampling at the edges: rates below 1 Hz, one frame, no frames (core/edits/clip.py)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.clip import resample, trim
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.timebase.clock import times_of
from gmr_studio.core.timebase.sampling import resample_grid as resample_positions
from tests.conftest import random_motion, shared_path


def test_a_rate_below_one_hertz_is_a_rate(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=41, convention="post").replace(frame_time=0.1)  # 4 s
    slow = resample(motion, 0.5)  # a frame every 2 s: the source's frames 0, 20 and 40
    assert slow.n_frames == 3 and slow.frame_time == 2.0
    np.testing.assert_array_equal(slow.rotations, motion.rotations[[0, 20, 40]])
    np.testing.assert_array_equal(slow.translations, motion.translations[[0, 20, 40]])
    assert resample_positions(41, 0.1, 0.25).tolist() == [0.0, 40.0]
    for refused in (0.0, -1.0, np.inf, np.nan):
        with pytest.raises(OperationError, match="frame rate must be a positive number"):
            resample(motion, refused)


def test_one_frame_stays_one_frame_and_none_stays_none(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=5)
    one = trim(motion, 2, 3)
    assert resample_positions(1, motion.frame_time, 90.0).tolist() == [0.0]
    again = resample(one, 90.0)
    assert again.n_frames == 1 and again.frame_rate == 90.0
    np.testing.assert_array_equal(again.rotations, one.rotations)
    np.testing.assert_array_equal(again.translations, one.translations)
    empty = motion.replace(rotations=motion.rotations[:0], translations=motion.translations[:0])
    assert resample_positions(0, motion.frame_time, 90.0).shape == (0,)
    none = resample(empty, 90.0)
    assert none.n_frames == 0 and none.frame_rate == 90.0 and none.names == motion.names


def test_a_rate_within_rounding_of_the_files_is_the_file(rng):
    motion = random_motion(rng, [-1, 0], n_frames=5)
    assert resample(motion, motion.frame_rate * (1 + 1e-12)) is motion  # not a new motion 1e-12 apart
    # an exact float frame time is taken to carry 32-bit rounding (1e-6 of itself): beyond it
    assert resample(motion, motion.frame_rate * (1 + 1e-5)) is not motion


def test_the_last_new_frame_never_passes_the_last_source_frame(rng):
    # a ratio a little over 3 source frames per new frame: the second new frame falls 1.5e-9
    # frames past the last source frame (beyond the snapping tolerance); it is the last frame
    motion = random_motion(rng, [-1, 0, 1], n_frames=4, convention="post")
    rate = 1.0 / ((3 + 1.5e-9) * motion.frame_time)
    where = resample_positions(4, motion.frame_time, rate)
    assert where.tolist() == [0.0, 3.0]
    result = resample(motion, rate)
    np.testing.assert_array_equal(result.rotations, motion.rotations[[0, 3]])
    np.testing.assert_array_equal(result.translations, motion.translations[[0, 3]])


def test_a_take_whose_frame_time_is_printed_rounded_keeps_its_last_frame():
    # the MocapBank take says 'Frame Time: 0.033333' (30 Hz to six decimals): 31 frames end
    # at 0.99999 s, 1 s as meant, so at 15 Hz the take has 16 frames, the last at 1 s
    take = trim(read_motion(shared_path("bvh/bvh-python_test_mocapbank.bvh")), 0, 31)
    assert take.frame_time == 0.033333
    half = resample(take, 15.0)
    assert half.n_frames == 16 and times_of(half)[-1] == 1.0
    np.testing.assert_array_equal(world_positions(half)[-1], world_positions(take)[-1])
    np.testing.assert_array_equal(half.rotations[[0, -1]], take.rotations[[0, -1]])


def test_the_end_reaches_only_as_far_as_the_rounding_of_the_frame_time(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=31, convention="post")
    for frame_time, count, last in [
        (0.033333, 16, 30.0),  # 30 Hz printed to six decimals: the frame at 1 s is the last frame
        (1 / 30, 16, 30.0),
        (0.0333334, 16, 15 / (15 * 0.0333334)),  # the take ends after 1 s
        (0.03333, 15, 14 / (15 * 0.03333)),  # 30.003 Hz: 0.9999 s, 1e-4 s short of 1 s, beyond rounding
    ]:
        where = resample_positions(31, frame_time, 15.0)
        assert where.size == count and where[-1] == pytest.approx(last, abs=1e-12), frame_time
        assert resample(motion.replace(frame_time=frame_time), 15.0).n_frames == count
    half = resample(motion.replace(frame_time=0.033333), 15.0)
    np.testing.assert_array_equal(half.rotations[-1], motion.rotations[30])  # copied, not interpolated
