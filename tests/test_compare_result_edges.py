"""A comparison's summaries and documents at their edges (core/compare/result.py): no frames, no
joints, a joint never compared, every sample finite or none, rotations in the JSON and the CSV,
the documents' numbers against the arrays they come from."""

from __future__ import annotations

import csv
import dataclasses
import math
import warnings

import numpy as np
import pytest

from gmr_studio.core.compare.align import Alignment
from gmr_studio.core.compare.result import Comparison, quantiles, summarize


def comparison(position_error, rotation_error=None, *, frames=None, units="m", **fields) -> Comparison:
    """A Comparison of J joints a0.. (A) and b0.. (B) with the given (F, J) errors."""
    position_error = np.asarray(position_error, dtype=np.float64)
    n_frames, n_joints = position_error.shape
    frames = np.arange(n_frames) if frames is None else np.asarray(frames)
    positions = np.zeros((n_frames, n_joints, 3))
    return Comparison(
        names_a=tuple(f"a{j}" for j in range(n_joints)),
        names_b=tuple(f"b{j}" for j in range(n_joints)),
        index_a=np.arange(n_joints),
        index_b=np.arange(n_joints),
        unmatched_a=["x"],
        unmatched_b=[],
        frames=frames,
        times=frames / 100.0,
        positions_a=positions,
        positions_b=positions,
        position_error=position_error,
        rotation_error=None if rotation_error is None else np.asarray(rotation_error, dtype=np.float64),
        alignment=Alignment(),
        units=units,
        size_a=1.75,
        **fields,
    )


def test_every_sample_finite_gives_means_per_joint_and_per_frame():
    errors = np.array([[1.0, 2.0, 3.0], [5.0, 6.0, 10.0]])  # 2 frames, 3 joints
    summary = summarize(errors, np.array([4, 9]), ("a", "b", "c"))
    np.testing.assert_array_equal(summary.per_joint_mean, [3.0, 4.0, 6.5])
    np.testing.assert_array_equal(summary.per_frame, [2.0, 7.0])
    np.testing.assert_array_equal(summary.per_joint_max, [5.0, 6.0, 10.0])
    np.testing.assert_array_equal(summary.per_joint_max_frame, [9, 9, 9])
    assert (summary.mean, summary.max, summary.max_frame, summary.max_joint, summary.count) == (4.5, 10.0, 9, "c", 6)
    assert summary.median == 4.0 and summary.p95 == pytest.approx(np.quantile(errors, 0.95), abs=0)
    # frozen, compared and hashed by identity (its arrays have no one truth value)
    again = summarize(errors, np.array([4, 9]), ("a", "b", "c"))
    assert summary == summary and summary != again and len({summary, again}) == 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        summary.mean = 0.0  # type: ignore[misc]


def test_a_joint_never_compared_has_no_max_and_no_frame():
    errors = np.array([[1.0, np.nan, 2.0], [4.0, np.nan, np.nan], [0.5, np.nan, 3.0]])
    summary = summarize(errors, np.array([10, 11, 12]), ("a", "b", "c"))
    np.testing.assert_array_equal(summary.per_joint_max_frame, [11, -1, 12])
    np.testing.assert_array_equal(summary.per_joint_max, [4.0, np.nan, 3.0])
    np.testing.assert_array_equal(summary.per_joint_mean, [5.5 / 3, np.nan, 2.5])
    np.testing.assert_array_equal(summary.per_frame, [1.5, 4.0, 1.75])
    assert (summary.max, summary.max_frame, summary.max_joint, summary.count) == (4.0, 11, "a", 5)
    joints = comparison(errors, frames=[10, 11, 12]).to_json()["joints"]
    assert [j["max_frame"] for j in joints] == [11, None, 12]
    assert [j["max"] for j in joints] == [4.0, None, 3.0]
    # frame 0 is a frame like any other
    assert comparison(np.array([[2.0], [1.0]])).to_json()["joints"][0]["max_frame"] == 0


@pytest.mark.parametrize("shape", [(0, 3), (4, 0), (3, 2)])
def test_nothing_compared_gives_no_numbers(shape):
    """No frames, no joints, or every sample missing: NaN statistics, frame -1, no joint, and
    no warning (no mean of an empty slice)."""
    errors = np.full(shape, np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        summary = summarize(errors, np.arange(shape[0]) + 5, tuple(f"j{j}" for j in range(shape[1])))
    assert summary.count == 0 and summary.max_frame == -1 and summary.max_joint == ""
    assert all(math.isnan(v) for v in (summary.mean, summary.median, summary.p95, summary.max))
    assert summary.per_joint_mean.shape == summary.per_joint_max.shape == (shape[1],)
    assert np.isnan(summary.per_joint_mean).all() and np.isnan(summary.per_joint_max).all()
    np.testing.assert_array_equal(summary.per_joint_max_frame, np.full(shape[1], -1))
    assert summary.per_frame.shape == (shape[0],) and np.isnan(summary.per_frame).all()


def test_the_json_document_of_a_comparison_with_rotations():
    position = np.array([[0.1, 0.2], [0.4, 0.3], [0.0, 0.1]])
    rotation = np.array([[1.0, np.nan], [2.0, np.nan], [6.0, np.nan]])  # b1 has no rotation (a root)
    result = comparison(position, rotation, frames=[3, 4, 5], label_a="A.bvh", label_b="B.amc")
    document = result.to_json()
    assert (document["a"], document["b"], document["units"], document["size_a"]) == ("A.bvh", "B.amc", "m", 1.75)
    assert (document["frames"], document["first_frame"], document["last_frame"]) == (3, 3, 5)
    assert document["compared"] == 6 and document["mpjpe"] == pytest.approx(1.1 / 6, abs=1e-15)
    assert document["max"] == {"value": 0.4, "frame": 4, "joint": "a0"}
    assert document["rotation"]["max"] == {"value": 6.0, "frame": 5, "joint": "a0"}
    assert document["rotation"]["mean_deg"] == 3.0 and document["rotation"]["median_deg"] == 2.0
    first, second = document["joints"]
    assert first == {
        "name": "a0", "match": "b0", "mean": pytest.approx(0.5 / 3, abs=1e-15), "max": 0.4, "max_frame": 4,
        "rotation_mean_deg": 3.0, "rotation_max_deg": 6.0,
    }  # fmt: skip
    assert second["rotation_mean_deg"] is None and second["rotation_max_deg"] is None
    assert document["unmatched_a"] == ["x"] and document["unmatched_b"] == []
    assert document["alignment"] == Alignment().to_json()
    assert comparison(position, units=None).to_json()["units"] == "file units"


def test_the_json_document_of_nothing_compared():
    document = comparison(np.full((2, 1), np.nan), np.full((2, 1), np.nan)).to_json()
    assert document["compared"] == 0 and document["mpjpe"] is None and document["p95"] is None
    assert document["max"] == {"value": None, "frame": None, "joint": None}
    assert document["rotation"]["max"] == {"value": None, "frame": None, "joint": None}
    assert document["joints"][0]["max_frame"] is None
    empty = comparison(np.zeros((0, 2))).to_json()
    assert empty["frames"] == 0 and empty["first_frame"] is None and empty["last_frame"] is None
    assert "rotation" not in empty


def test_the_csv_has_a_row_per_frame_with_rotations_after_positions():
    position = np.array([[0.25, np.nan], [0.5, 1.0]])
    rotation = np.array([[10.0, 20.0], [30.0, np.nan]])
    rows = list(csv.reader(comparison(position, rotation, frames=[7, 8]).to_csv().splitlines()))
    assert rows[0] == ["frame", "time", "mpjpe", "a0", "a1", "a0 deg", "a1 deg"]
    assert rows[1] == ["7", "0.070000", "0.25", "0.25", "", "10", "20"]
    assert rows[2] == ["8", "0.080000", "0.75", "0.5", "1", "30", ""]
    header = next(csv.reader(comparison(position).to_csv().splitlines()))
    assert header == ["frame", "time", "mpjpe", "a0", "a1"]  # no rotations: no angle columns


def test_a_comparison_is_frozen_and_counts_its_frames_and_pairs():
    result = comparison(np.zeros((4, 3)), frames=[2, 3, 5, 8])
    assert (result.n_frames, result.n_pairs) == (4, 3)
    assert [result.row_of_frame(f) for f in (2, 5, 8, 4, 9, 0)] == [0, 2, 3, None, None, None]
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.units = "cm"  # type: ignore[misc]
    assert result.position is result.position  # computed once


def test_a_quantile_halfway_between_two_values_is_numpys_to_the_bit():
    # numpy's lerp takes b - (b - a)(1 - t) from t = 0.5 on: here 1 ulp from a + (b - a) t
    values = np.array([0.0002697867137638703, 0.06369616873214544])
    assert quantiles(values, (0.5,)) == (float(np.quantile(values, 0.5)),) == (0.03198297772295466,)
    with pytest.raises(TypeError):
        quantiles(values, (0.5,), True)  # type: ignore[misc]  # overwrite is keyword-only


def test_comparisons_are_compared_and_hashed_by_identity():
    one, other = comparison(np.ones((2, 2))), comparison(np.ones((2, 2)))
    assert one == one and one != other and len({one, other}) == 2
