"""The glTF samplers and frame clock (core.formats.gltf_in.sampling): where each time falls
among the keys, the frames chosen for regular, irregular and asked rates and their limits,
STEP between keys, CUBICSPLINE against an independent Hermite spline, keys read bit for bit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline

from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.gltf_in import sampling
from gmr_studio.core.formats.gltf_in.sampling import (
    FALLBACK_RATE,
    MAX_FRAMES,
    Sampler,
    frame_times,
    normalised,
    regular_grid,
    sample,
    segments,
)
from gmr_studio.core.rotations.quaternions import slerp
from tests.gltf_builder import GltfBuilder, quaternion


# ------------------------------------------------------------------------ segments
def test_segments_before_next_gap_and_fraction_around_three_keys():
    keys = np.array([1.0, 2.0, 4.0])
    before, nxt, gap, fraction = segments(keys, np.array([0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0]))
    np.testing.assert_array_equal(before, [0, 0, 0, 1, 1, 2, 2])
    np.testing.assert_array_equal(nxt, [0, 1, 1, 2, 2, 2, 2])  # clamped at both ends
    np.testing.assert_array_equal(gap, [0, 1, 1, 2, 2, 0, 0])
    np.testing.assert_array_equal(fraction, [0, 0, 0.5, 0, 0.5, 0, 0])  # before and after the keys: held


# ------------------------------------------------------------------------ frame times
def test_no_keys_and_a_single_key_give_one_frame_at_the_fallback_rate():
    for keys, start in (([], 0.0), ([np.array([0.7])], 0.7), ([np.array([0.7]), np.array([0.7])], 0.7)):
        clock = frame_times(keys, None)
        np.testing.assert_array_equal(clock.times, [start])
        assert clock.frame_time == 1 / FALLBACK_RATE and clock.note == "a single key: one frame, 30 Hz"


def test_two_keys_are_a_grid_of_their_gap():
    clock = frame_times([np.array([0.25, 0.75])], None)
    np.testing.assert_array_equal(clock.times, [0.25, 0.75])
    assert clock.frame_time == 0.5 and clock.note == "keys every 0.5 s (2 Hz), one frame per key time"


def test_keys_on_one_grid_with_gaps_give_a_frame_per_grid_step_exactly_on_the_keys():
    keys = np.array([0.2, 0.3, 0.5], dtype=np.float32).astype(np.float64)  # as a file stores them
    clock = frame_times([keys[:2], keys[1:]], None)
    assert clock.times.size == 4 and clock.frame_time == pytest.approx(0.1, rel=1e-6)
    np.testing.assert_array_equal(clock.times[[0, 1, 3]], keys)  # bit for bit
    assert clock.times[2] == pytest.approx(0.4, rel=1e-6)
    assert clock.note == "keys every 0.1 s (10 Hz), one frame per key time"


def test_irregular_keys_are_sampled_at_the_fallback_rate_from_the_first_key():
    clock = frame_times([np.array([0.5, 0.6, 0.85])], None)  # 0.35 s: 11 steps of 1/30, 12 frames
    np.testing.assert_allclose(clock.times, 0.5 + np.arange(12) / 30, rtol=0, atol=1e-15)
    assert clock.frame_time == 1 / 30
    assert clock.note == "keys at irregular times: sampled at 30 Hz (--frame-rate to choose)"


def test_an_asked_rate_starts_at_the_first_key_covers_the_last_and_lands_on_keys():
    keys = np.array([0.5, 0.8, 1.3], dtype=np.float32).astype(np.float64)  # off the float64 grid by ~1e-8
    clock = frame_times([keys], 10.0)
    assert clock.times.size == 9 and clock.frame_time == 0.1 and clock.note == "sampled at 10 Hz (--frame-rate)"
    np.testing.assert_array_equal(clock.times[[0, 3, 8]], keys)  # moved onto the keys
    np.testing.assert_allclose(clock.times, 0.5 + np.arange(9) * 0.1, rtol=0, atol=1e-7)
    longer = frame_times([np.array([0.0, 1.05])], 10.0)  # the last frame at or after the last key
    assert longer.times.size == 12 and longer.times[-1] == pytest.approx(1.1)


def test_frames_snap_to_keys_within_the_tolerance_of_a_frame_only():
    """Tolerance 1e-4 of a 0.5 s frame: 5e-5 s. A frame just after a key (3e-5 s) or just
    before one, the last beyond the last key, takes the key; one 1e-4 s away stays."""
    keys = np.array([1.0, 1.99997, 2.50003, 3.0001, 3.99997])
    clock = frame_times([keys], 2.0)
    np.testing.assert_array_equal(clock.times, [1.0, 1.5, 1.99997, 2.50003, 3.0, 3.5, 3.99997])
    np.testing.assert_array_equal(frame_times([np.array([0.7])], 2.0).times, [0.7])


def test_a_frame_exactly_at_the_snap_tolerance_snaps_to_the_key_before_it(monkeypatch):
    """A quarter of a 1 s frame (binary: the distances are exact): frame 2 lies exactly that
    far from the keys 1.75 and 2.25 and takes the one before it; frame 1 is farther from any."""
    monkeypatch.setattr(sampling, "SNAP_TOLERANCE", 0.25)
    clock = frame_times([np.array([0.0, 1.75, 2.25, 3.0])], 1.0)
    np.testing.assert_array_equal(clock.times, [0.0, 1.0, 1.75, 3.0])


def test_the_frames_reach_the_last_key_and_their_limit_is_inclusive():
    assert frame_times([np.array([0.0, MAX_FRAMES - 1.0])], 1.0).times.size == MAX_FRAMES
    assert frame_times([np.array([0.0, 2.0])], 2.0).times.size == 5  # no frame beyond the last key
    assert frame_times([np.array([0.0, 2.0 + 1e-9])], 2.0).times.size == 5  # float32 noise above it neither
    with pytest.raises(ValueError, match=r"^the animation lasts 1e\+06 s: 2000001 frames at 2 Hz, more than 2000000$"):
        frame_times([np.array([0.0, MAX_FRAMES / 2])], 2.0)


# ------------------------------------------------------------------------ regular grid
def test_regular_grid_counts_whole_steps_of_the_smallest_gap():
    step, index = regular_grid(np.array([1.0, 1.5, 2.5, 2.75]))
    assert step == 0.25 and index.tolist() == [0, 2, 6, 7] and index.dtype == np.int64


def test_repeated_keys_or_a_key_off_the_grid_are_no_grid():
    assert regular_grid(np.array([0.0, 0.0, 1.0])) is None  # a gap of 0: no step
    assert regular_grid(np.array([0.0, 0.1, 0.35])) is None  # 0.35 is half a step off


def test_a_key_exactly_at_the_grid_tolerance_is_on_the_grid(monkeypatch):
    """Keys 0, 1, 2.25, 3: gaps of 1, 1.25, 0.75 are 1, 2 and 1 steps of 0.75; the step is
    then 3 / 4 and key 1 lies 1/3 of a step off frame 1: on the grid at that tolerance."""
    keys = np.array([0.0, 1.0, 2.25, 3.0])
    monkeypatch.setattr(sampling, "GRID_TOLERANCE", 1.0 / 0.75 - 1.0)
    assert regular_grid(keys)[1].tolist() == [0, 1, 3, 4]
    monkeypatch.setattr(sampling, "GRID_TOLERANCE", np.nextafter(1.0 / 0.75 - 1.0, 0.0))
    assert regular_grid(keys) is None


def test_a_grid_of_max_frames_steps_is_too_long():
    assert regular_grid(np.array([0.0, 1.0, MAX_FRAMES - 1.0]))[1].tolist() == [0, 1, MAX_FRAMES - 1]
    assert regular_grid(np.array([0.0, 1.0, float(MAX_FRAMES)])) is None
    assert regular_grid(np.array([0.0, 1.0, MAX_FRAMES + 1.0])) is None  # one gap of the limit itself


# ------------------------------------------------------------------------ samplers
def test_step_holds_a_key_until_the_next_even_with_as_many_frames_as_keys():
    """Keys at 0, 0.9 and 1 s sampled at 2 Hz: three frames for three keys, but the frame
    at 0.5 s is before the second key (a shortcut once returned the keys as they were)."""
    stepped = Sampler(np.array([0.0, 0.9, 1.0]), np.array([[0.0], [1.0], [2.0]]), "STEP")
    np.testing.assert_array_equal(sample(stepped, np.array([0.0, 0.5, 1.0]), False)[:, 0], [0, 0, 2])
    np.testing.assert_array_equal(sample(stepped, np.array([0.95, 2.0]), False)[:, 0], [1, 2])


def test_step_between_keys_read_from_a_file(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root")
    builder.animation([(0, "translation", [0.0, 0.9, 1.0], [[0, 0, 0], [0, 1, 0], [0, 2, 0]], "STEP")])
    motion = read_motion(builder.save(tmp_path / "step.glb"), frame_rate=2)
    np.testing.assert_array_equal(motion.translations[:, 0, 1], [0, 0, 2])


def test_frames_on_the_keys_one_each_are_the_values_themselves():
    values = np.array([[1.0, 2.0], [3.0, 5.0]])
    on = sample(Sampler(np.array([0.0, 1.0]), values, "LINEAR"), np.array([0.0, 1.0]), False)
    assert on is values
    again = sample(Sampler(np.array([0.0, 1.0]), values, "LINEAR"), np.array([0.0, 1.0, 1.0]), False)
    np.testing.assert_array_equal(again, values[[0, 1, 1]])
    one = sample(Sampler(np.array([0.5]), values[:1], "LINEAR"), np.array([0.0, 0.5, 2.0]), False)
    np.testing.assert_array_equal(one, values[[0, 0, 0]])


def test_linear_between_keys_and_the_keys_bit_for_bit():
    values = np.array([[-0.0, 1.0], [2.0, -3.0], [4.0, 1.0]])
    lin = Sampler(np.array([0.0, 1.0, 3.0]), values, "LINEAR")
    out = sample(lin, np.array([0.0, 0.25, 1.0, 2.0, 3.0, 4.0]), False)
    np.testing.assert_array_equal(out, [[0, 1], [0.5, 0], [2, -3], [3, -1], [4, 1], [4, 1]])
    assert np.signbit(out[0, 0])  # -0.0 on its key, not -0.0 + 0 * 2


def test_linear_rotation_is_slerp_and_its_keys_are_normalised_once():
    first = np.array([0.13, -0.13, 0.64, 0.1])  # normalised twice differs in the last bit
    assert not np.array_equal(normalised(normalised(first)), normalised(first))
    second = quaternion([1, 0, 0], 80) * 2.0
    turn = Sampler(np.array([0.0, 1.0]), np.array([first, second]), "LINEAR")
    out = sample(turn, np.array([0.0, 0.25, 1.0]), True)
    np.testing.assert_array_equal(out[0], normalised(first))
    expected = slerp(normalised(first), normalised(second), np.array(0.25))
    np.testing.assert_allclose(out[1], expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, rtol=0, atol=1e-15)


def _hermite(times, values, tangents_in, tangents_out, at):
    """glTF's CUBICSPLINE by scipy's Hermite spline, one segment at a time (each segment's
    derivative: the out-tangent of its first key, the in-tangent of its last)."""
    k = np.clip(np.searchsorted(times, at, side="right") - 1, 0, len(times) - 2)
    out = np.empty((len(at), values.shape[1]))
    for f, (t, i) in enumerate(zip(at, k)):
        spline = CubicHermiteSpline(times[i : i + 2], values[i : i + 2], [tangents_out[i], tangents_in[i + 1]])
        out[f] = spline(t)
    return out


def test_cubicspline_between_keys_is_the_hermite_spline_of_its_tangents():
    times = np.array([0.0, 2.0, 2.5])
    a = np.array([[9.0, -9.0], [0.5, -2.0], [3.0, 1.0]])  # in-tangents
    v = np.array([[1.0, 0.0], [2.0, 4.0], [-1.0, 2.0]])
    b = np.array([[1.5, 3.0], [-4.0, 0.25], [7.0, 7.0]])  # out-tangents
    cubic = Sampler(times, np.stack([a, v, b], axis=1).reshape(9, 2), "CUBICSPLINE")
    at = np.array([0.0, 0.5, 1.2, 2.0, 2.2, 2.5])
    np.testing.assert_allclose(sample(cubic, at, False), _hermite(times, v, a, b, at), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(sample(cubic, times, False), v)  # on the keys: the values, not a tangent


def test_cubicspline_rotation_is_normalised():
    q = np.array([quaternion([0, 0, 1], 0), quaternion([0, 0, 1], 90)])
    tangents = np.array([[0.0, 0, 0.3, 0.1], [0.2, 0, 0.1, -0.3]])
    stored = np.stack([tangents, q, tangents[::-1]], axis=1).reshape(6, 4)
    cubic = Sampler(np.array([0.0, 1.0]), stored, "CUBICSPLINE")
    at = np.array([0.3, 0.6])
    raw = _hermite(np.array([0.0, 1.0]), q, tangents, tangents[::-1], at)
    np.testing.assert_allclose(sample(cubic, at, True), raw / np.linalg.norm(raw, axis=1)[:, None], atol=1e-15)


def test_a_zero_quaternion_becomes_the_identity():
    out = normalised(np.array([[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 2.0, 0.0]]))
    np.testing.assert_array_equal(out, [[0, 0, 0, 1], [0, 0, 1, 0]])


def test_samplers_and_clocks_are_frozen():
    clock = frame_times([np.array([0.0, 1.0])], None)
    with pytest.raises(dataclasses.FrozenInstanceError):
        clock.frame_time = 0.5  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        Sampler(np.zeros(1), np.zeros((1, 3)), "STEP").interpolation = "LINEAR"  # type: ignore[misc]
