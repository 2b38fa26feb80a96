"""The marker set itself (core/markers/markerset.py): its checks, gaps, labels, slices,
units and axes, gap filling, the gap table and resampling, on markers written by hand."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers.markerset import (
    Y_UP_TO_Z_UP,
    Z_UP_TO_Y_UP,
    MarkerSet,
    PointOutputs,
    frame_ranges,
    gap_runs,
    split_subject,
)

NAN = np.nan


def track(*xs) -> np.ndarray:
    """(F, 1, 3) positions of one marker moving along x (None: a gap)."""
    return np.array([[[NAN] * 3 if x is None else [float(x), 2.0 * x, -1.0]] for x in xs])


def one_marker(*xs, rate=10.0, **fields) -> MarkerSet:
    return MarkerSet(labels=["A"], positions=track(*xs), rate=rate, units="mm", **fields)


def outputs(n_frames: int) -> PointOutputs:
    values = np.arange(n_frames * 3 * 3, dtype=float).reshape(n_frames, 3, 3)
    return PointOutputs(
        labels=("LHipAngles", "LKneeForce", "RHipAngles"), subjects=("S", "", "S"),
        kinds=("angles", "forces", "angles"), values=values, units={"angles": "deg"},
    )  # fmt: skip


# ------------------------------------------------------------------ text and labels
def test_frame_ranges_of_masks_and_indices():
    assert frame_ranges(np.array([True, True, False, True])) == "0-1, 3"
    assert frame_ranges(np.array([9, 3, 4, 4, 5])) == "3-5, 9"  # unsorted, repeated
    assert frame_ranges(np.array([], dtype=np.int64)) == "none"
    assert frame_ranges(np.array([7])) == "7"
    assert frame_ranges(np.array([0, 2, 4])) == "0, 2, 4"
    assert frame_ranges(np.arange(0, 16, 2)) == "0, 2, 4, 6, 8, 10, 12, 14"  # eight ranges: all listed
    assert frame_ranges(np.arange(0, 18, 2)) == "0, 2, 4, 6, 8, 10, 12, 14, ... (9 ranges)"
    assert frame_ranges(np.array([0, 2, 4]), limit=3) == "0, 2, 4"
    assert frame_ranges(np.array([0, 2, 4, 5]), limit=2) == "0, 2, ... (3 ranges)"


def test_gap_runs_give_the_last_seen_frame_before_and_the_next_after():
    present = np.array([[False, True], [True, True], [False, False], [False, True], [True, False]])
    before, after = gap_runs(present)
    np.testing.assert_array_equal(before, [[-1, 0], [1, 1], [1, 1], [1, 3], [4, 3]])
    np.testing.assert_array_equal(after, [[1, 0], [1, 1], [4, 3], [4, 3], [4, 5]])
    before, after = gap_runs(np.array([False, True, False]))
    np.testing.assert_array_equal(before, [-1, 1, 1])
    np.testing.assert_array_equal(after, [1, 1, 3])


def test_split_subject_takes_the_last_colon():
    assert split_subject("Lab:Daphnee:ASISr") == ("Lab:Daphnee", "ASISr")
    assert split_subject(":LASI") == ("", "LASI")
    assert split_subject("LASI:") == ("", "LASI:")  # nothing after the colon: no subject
    assert split_subject("LASI") == ("", "LASI")


def test_index_by_bare_label_or_subject_and_select_in_the_order_given():
    positions = np.arange(2 * 3 * 3, dtype=float).reshape(2, 3, 3)
    markers = MarkerSet(
        labels=["LASI", "RASI", "LASI"], subjects=["Ann", "Ann", "Bob"], positions=positions, rate=100, units="mm",
        source="take.c3d",
    )  # fmt: skip
    assert markers.index("LASI") == 0 and markers.index("Bob:LASI") == 2 and markers.index("Ann:RASI") == 1
    with pytest.raises(OperationError, match=r"^no marker 'Bob:RASI' in take.c3d$"):
        markers.index("Bob:RASI")
    with pytest.raises(OperationError, match=r"^no marker 'X' in the marker set$"):
        markers.replace(source="").index("X")
    chosen = markers.select(["Bob:LASI", "RASI"])
    assert chosen.labels == ("LASI", "RASI") and chosen.subjects == ("Bob", "Ann")
    np.testing.assert_array_equal(chosen.positions, positions[:, [2, 1]])


# ------------------------------------------------------------------ construction
def test_fields_are_normalised_and_the_positions_read_only():
    source = track(1, 2)
    markers = MarkerSet(labels=[7], positions=source, rate=np.int64(10), units="m", notes=["read"])
    assert markers.labels == ("7",) and markers.subjects == ("",) and markers.notes == ("read",)
    assert type(markers.rate) is float and markers.rate == 10.0
    assert markers.positions.dtype == np.float64 and not markers.positions.flags.writeable
    assert (markers.n_frames, markers.n_markers, markers.frame_time) == (2, 1, 0.1)
    np.testing.assert_allclose(markers.times, [0.0, 0.1])
    assert markers.first_frame == 1 and markers.parameters == {} and markers.outputs is None


def test_marker_sets_and_outputs_are_frozen_keyword_only_and_compared_by_identity():
    markers, out = one_marker(1, 2), outputs(2)
    with pytest.raises(dataclasses.FrozenInstanceError):
        markers.rate = 20.0  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        out.labels = ()  # type: ignore[misc]
    with pytest.raises(TypeError):
        MarkerSet(["A"], track(1), 10.0, "mm")  # type: ignore[misc]
    with pytest.raises(TypeError):
        PointOutputs(out.labels, out.subjects, out.kinds, out.values)  # type: ignore[misc]
    assert markers != markers.replace() and markers == markers and len({markers, markers}) == 1
    assert out != dataclasses.replace(out) and len({out, out}) == 1


def test_a_float_array_without_partial_gaps_is_kept_not_copied():
    """A long take's positions are not copied when there is nothing to change (whole gaps
    only); a partial gap is mended in a copy."""
    source = track(1, None, 3)
    assert np.shares_memory(MarkerSet(labels=["A"], positions=source, rate=1, units="m").positions, source)
    source[0, 0, 1] = NAN
    assert not np.shares_memory(MarkerSet(labels=["A"], positions=source, rate=1, units="m").positions, source)


def test_a_nan_coordinate_makes_the_sample_a_gap_without_touching_the_input():
    source = track(1, 2, 3)
    source[1, 0, 2] = NAN
    markers = MarkerSet(labels=["A"], positions=source, rate=1, units="m")
    assert np.isnan(markers.positions[1]).all() and np.isfinite(markers.positions[[0, 2]]).all()
    assert source[1, 0, 0] == 2.0  # the caller's array is left as it was
    assert markers.present[:, 0].tolist() == [True, False, True]
    intact = MarkerSet(labels=["A"], positions=track(1, None), rate=1, units="m")
    assert intact.present[:, 0].tolist() == [True, False]


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        (dict(positions=np.zeros((2, 2, 3))), r"positions must have shape \(F, 1, 3\), not \(2, 2, 3\)"),
        (dict(positions=np.zeros((2, 3))), r"positions must have shape \(F, 1, 3\), not \(2, 3\)"),
        (dict(positions=np.zeros((2, 1, 2))), r"not \(2, 1, 2\)"),
        (dict(subjects=["a", "b"]), "subjects must give one prefix per label"),
        (dict(rate=0.0), "the frame rate must be a positive number, not 0.0"),
        (dict(rate=-5), "not -5.0"),
        (dict(rate=np.inf), "not inf"),
        (dict(rate=np.nan), "not nan"),
        (dict(units="yd"), r"unknown length unit 'yd': expected one of m, cm, mm, in, ft"),
        (dict(outputs="three frames"), "the analysis outputs must have the markers' frames"),
    ],
)
def test_bad_fields_are_refused(fields, message):
    base = dict(labels=["A"], positions=np.zeros((2, 1, 3)), rate=10.0, units="mm")
    if fields.get("outputs") == "three frames":
        fields = dict(outputs=outputs(3))
    with pytest.raises(ValueError, match=message):
        MarkerSet(**{**base, **fields})


def test_outputs_by_kind_and_sliced_with_the_frames():
    out = outputs(4)
    assert out.n_outputs == 3
    assert out.by_kind() == {"angles": ["S:LHipAngles", "S:RHipAngles"], "forces": ["LKneeForce"]}
    markers = one_marker(0, 1, 2, 3, outputs=out, first_frame=10)
    part = markers.frame_slice(slice(1, 3))
    assert part.first_frame == 11 and part.n_frames == 2
    np.testing.assert_array_equal(part.outputs.values, out.values[1:3])
    assert part.outputs.units == {"angles": "deg"} and part.outputs.labels == out.labels
    assert markers.frame_slice(slice(-1, None)).first_frame == 13
    assert one_marker(0, 1).frame_slice(slice(2, None)).first_frame == 3  # past the end: no frame
    empty = MarkerSet(labels=["A"], positions=np.zeros((0, 1, 3)), rate=10, units="mm", first_frame=5)
    assert empty.frame_slice(slice(1, 3)).first_frame == 5


# ------------------------------------------------------------------ units and axes
@pytest.mark.parametrize(
    ("units", "factor"), [("m", 1e-3), ("cm", 0.1), ("mm", 1.0), ("in", 1 / 25.4), ("ft", 1 / 304.8)]
)
def test_in_units_scales_by_the_units_ratio(units, factor):
    markers = one_marker(100, None)
    converted = markers.in_units(units)
    assert converted.units == units
    np.testing.assert_allclose(converted.positions[0, 0], np.array([100.0, 200.0, -1.0]) * factor, rtol=1e-14)
    assert np.isnan(converted.positions[1]).all()


def test_in_units_refuses_an_unknown_unit():
    with pytest.raises(ValueError, match=r"unknown length unit 'yd': expected one of m, cm, mm, in, ft"):
        one_marker(1).in_units("yd")


def test_transformed_rotates_scales_and_offsets_every_sample():
    markers = one_marker(1, None)
    moved = markers.transformed(Z_UP_TO_Y_UP, scale=2.0, offset=(10.0, 0.0, -5.0), units="cm")
    np.testing.assert_allclose(moved.positions[0, 0], [2.0 + 10.0, -2.0, -4.0 - 5.0])  # (x, z, -y) * 2 + offset
    assert moved.units == "cm" and np.isnan(moved.positions[1]).all()
    kept = markers.transformed(scale=3.0)
    np.testing.assert_allclose(kept.positions[0, 0], [3.0, 6.0, -3.0])
    assert kept.units == "mm"
    np.testing.assert_allclose(Y_UP_TO_Z_UP @ Z_UP_TO_Y_UP, np.eye(3), atol=0)


# ------------------------------------------------------------------ gaps
def test_filled_interpolates_gaps_up_to_the_limit_and_leaves_the_ends():
    markers = one_marker(None, 0, None, None, 3, None, None, None, 7, None, rate=10)
    filled = markers.filled(2)
    x = filled.positions[:, 0, 0]
    np.testing.assert_array_equal(x[[1, 2, 3, 4]], [0.0, 1.0, 2.0, 3.0])
    np.testing.assert_array_equal(filled.positions[2, 0], [1.0, 2.0, -1.0])
    assert np.isnan(x[[0, 5, 6, 7, 9]]).all()  # a gap of three, and both ends
    assert filled.notes == ("2 samples in gaps of at most 2 frames filled by linear interpolation",)
    longer = markers.filled(3)
    np.testing.assert_allclose(longer.positions[5:8, 0, 0], [4.0, 5.0, 6.0])
    assert longer.notes[-1].startswith("5 samples in gaps of at most 3 frames")


def test_filled_warns_of_nothing():
    markers = one_marker(None, 0, None, 2, 3, None, rate=10)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        filled = markers.filled(4)
    np.testing.assert_array_equal(filled.positions[:5, 0, 0], [NAN, 0.0, 1.0, 2.0, 3.0])


def test_filled_per_marker_and_nothing_to_fill_is_the_same_set():
    positions = np.concatenate([track(0, None, 2, 3), track(5, 6, None, 8)], axis=1)
    markers = MarkerSet(labels=["A", "B"], positions=positions, rate=10, units="mm", notes=("read",))
    filled = markers.filled(1)
    np.testing.assert_array_equal(filled.positions[:, :, 0], [[0, 5], [1, 6], [2, 7], [3, 8]])
    assert filled.notes[0] == "read" and filled.notes[1].startswith("2 samples")
    assert markers.filled(0) is markers
    whole = one_marker(0, 1, 2)
    assert whole.filled(5) is whole
    ends_only = one_marker(None, 1, None)
    assert ends_only.filled(5) is ends_only


def test_gap_table_counts_missing_samples_runs_and_the_longest():
    positions = np.concatenate([track(None, None, 2, None, 4, None), track(0, 1, 2, 3, 4, 5)], axis=1)
    markers = MarkerSet(labels=["A", "B"], subjects=["Ann", ""], positions=positions, rate=10, units="mm")
    assert markers.gap_table() == [
        {"label": "Ann:A", "missing": 4, "gaps": 3, "longest": 2, "computed": 0},
        {"label": "B", "missing": 0, "gaps": 0, "longest": 0, "computed": 0},
    ]
    empty = MarkerSet(labels=["A"], positions=np.zeros((0, 1, 3)), rate=10, units="mm")
    assert empty.gap_table() == [{"label": "A", "missing": 0, "gaps": 0, "longest": 0, "computed": 0}]


# ------------------------------------------------------------------ resampling
def test_resampled_interpolates_in_time_and_keeps_exact_samples():
    markers = one_marker(0, 10, None, 30, 40, rate=10, outputs=outputs(5))
    half = markers.resampled(5)  # every other frame: exact samples, no interpolation
    assert half.rate == 5.0 and half.outputs is None
    np.testing.assert_array_equal(half.positions[:, 0, 0], [0.0, NAN, 40.0])
    faster = markers.resampled(20)
    x = faster.positions[:, 0, 0]
    assert faster.n_frames == 9
    np.testing.assert_allclose(x[[0, 1, 2, 6, 7, 8]], [0.0, 5.0, 10.0, 30.0, 35.0, 40.0])
    assert np.isnan(x[[3, 4, 5]]).all()  # next to the gap, or in it
    slower = one_marker(0, 10, 20, 30, 40, rate=10).resampled(4)  # 0, 0.25 s (0.5 s is past the end)
    np.testing.assert_allclose(slower.positions[:, 0, 0], [0.0, 25.0])


def test_resampled_duration_is_floored_with_rounding_forgiven():
    """24 frames at 10 Hz last 2.3 s: 115 frames of 50 Hz after the first, though 2.3 * 50
    rounds to 114.99999999999999."""
    markers = one_marker(*range(24), rate=10)
    assert (markers.n_frames - 1) / markers.rate * 50 < 115
    fast = markers.resampled(50)
    assert fast.n_frames == 116
    np.testing.assert_allclose(fast.positions[-1, 0, 0], 23.0, rtol=1e-12)
    assert markers.resampled(7).n_frames == 17  # 2.3 s * 7 Hz = 16.1: floored


def test_resampled_counts_its_frames_as_a_motion_does():
    """Samples 0.033333 s apart (30 Hz printed to six decimals), 31 of them: at 15 Hz, 16
    frames, the last on the last sample, as core.edits.clip.resample gives a motion."""
    markers = one_marker(*range(31), rate=1 / 0.033333)
    slow = markers.resampled(15)
    assert slow.n_frames == 16 and slow.positions[-1, 0, 0] == 30.0


def test_resampled_edges():
    markers = one_marker(0, 1, rate=10)
    assert markers.resampled(10) is markers
    single = one_marker(5, rate=10, outputs=outputs(1))
    moved = single.resampled(30)
    assert moved.rate == 30.0 and moved.outputs is None and moved.n_frames == 1
    same = single.resampled(10)  # one frame: a new set without the outputs, even at its own rate
    assert same is not single and same.outputs is None and same.rate == 10.0
    slow = one_marker(0, 10, 20, 30, 40, rate=2).resampled(0.5)  # below 1 Hz: a frame every 2 s
    np.testing.assert_array_equal(slow.positions[:, 0, 0], [0.0, 40.0])
    assert slow.rate == 0.5
    with pytest.raises(ValueError, match="the frame rate must be positive"):
        markers.resampled(0)
    with pytest.raises(ValueError, match="the frame rate must be positive"):
        markers.resampled(-10)


# ------------------------------------------------------------------ computed samples
def test_computed_samples_are_a_mask_of_present_samples_carried_by_every_conversion():
    """``computed`` (F, M): present samples the capture software computed. A gap is never
    computed; selections, slices, units and axes keep the mask; a mask of another shape is
    refused."""
    positions = np.concatenate([track(0, 1, 2, None, 4), track(5, 6, 7, 8, 9)], axis=1)
    mask = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0, 0]], bool)
    markers = MarkerSet(labels=["A", "B"], positions=positions, rate=10.0, units="mm", computed=mask)
    expected = mask.copy()
    expected[3, 0] = False  # A is a gap at frame 3: not computed
    np.testing.assert_array_equal(markers.computed, expected)
    np.testing.assert_array_equal(markers.measured, markers.present & ~expected)
    assert not markers.computed.flags.writeable
    np.testing.assert_array_equal(markers.select(["B"]).computed, expected[:, [1]])
    np.testing.assert_array_equal(markers.frame_slice(slice(1, 4)).computed, expected[1:4])
    np.testing.assert_array_equal(markers.in_units("m").transformed(Z_UP_TO_Y_UP).computed, expected)
    assert not one_marker(1, 2).computed.any() and one_marker(1, 2).computed.shape == (2, 1)
    with pytest.raises(ValueError, match=r"computed must have shape \(5, 2\)"):
        markers.replace(computed=np.zeros((5, 1), bool))
    with pytest.raises(ValueError, match="need their computed mask"):
        markers.replace(positions=positions[:3])
    assert markers.replace(positions=positions[:3], computed=mask[:3]).computed.shape == (3, 2)
    assert one_marker(1, 2).replace(positions=track(1, 2, 3)).computed.shape == (3, 1)  # none computed


def test_computed_samples_dropped_filled_and_resampled():
    markers = one_marker(0, 1, 2, None, 4, 5, rate=10.0, computed=np.array([[0], [1], [0], [0], [0], [1]], bool))
    dropped = markers.without_computed()
    np.testing.assert_array_equal(dropped.present[:, 0], [True, False, True, False, True, False])
    assert not dropped.computed.any()
    assert dropped.notes[-1] == "2 computed samples (not measured: the capture software's gap filling) read as gaps"
    assert one_marker(0, 1).without_computed().notes == ()  # nothing computed: the same set
    filled = markers.filled(1)  # frame 3 interpolated here: computed too
    np.testing.assert_array_equal(filled.computed[:, 0], [False, True, False, True, False, True])
    double = markers.resampled(20.0)  # a sample between a computed one and another is computed
    np.testing.assert_array_equal(
        double.computed[:, 0], [False, True, True, True, False, False, False, False, False, True, True]
    )
    assert markers.gap_table()[0]["computed"] == 2
