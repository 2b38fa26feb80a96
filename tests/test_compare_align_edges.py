"""The alignment record at its edges (core/compare/align.py): the default is the identity, the
scales and rotations compose as documented, the JSON's numbers, and "none" fits nothing."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gmr_studio.core.compare.align import Alignment, fit_alignment, rms_distance
from gmr_studio.core.rotations.euler import matrix_from_euler
from gmr_studio.core.space.similarity import Similarity


def test_the_default_alignment_is_the_identity_on_a_clock_not_searched():
    alignment = Alignment()
    points = np.array([[1.0, -2.0, 3.5], [0.25, 0.0, -7.0]])
    np.testing.assert_array_equal(alignment.apply(points), points)
    turns = matrix_from_euler(np.radians([[10.0, 20.0, 30.0]]), "ZYX")
    np.testing.assert_array_equal(alignment.apply_rotations(turns), turns)
    assert alignment.total.scale == 1.0
    np.testing.assert_array_equal(alignment.total.rotation, np.eye(3))
    assert alignment.to_json() == {
        "kind": "none",
        "rotation": np.eye(3).tolist(),
        "translation": [0.0, 0.0, 0.0],
        "scale": 1.0,
        "units_scale": 1.0,
        "up_rotation": np.eye(3).tolist(),
        "offset_frames": 0.0,
        "offset_seconds": 0.0,
        "offset_found": False,
        "offset_search": None,
        "rms_before": None,
        "rms_after": None,
        "notes": [],
    }


def test_units_up_axis_and_fit_compose_as_documented():
    """``b' = scale * R @ (units_scale * Q @ b) + t`` for points; ``R Q W Q^T`` for rotations."""
    rotation = matrix_from_euler(np.radians([[0.0, 0.0, 90.0]]), "ZYX")[0]
    up = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # Y up to Z up
    alignment = Alignment(
        kind="similarity", space=Similarity(up, 0.01), fit=Similarity(rotation, 2.0, np.array([1.0, 2.0, 3.0])),
        rms_before=0.5, rms_after=float("nan"),
    )  # fmt: skip
    assert alignment.total.scale == 0.02
    np.testing.assert_array_equal(alignment.total.rotation, rotation @ up)
    b = np.array([[100.0, 200.0, -300.0]])
    expected = 2.0 * rotation @ (0.01 * up @ b[0]) + [1.0, 2.0, 3.0]
    np.testing.assert_allclose(alignment.apply(b)[0], expected, rtol=0, atol=1e-12)
    turn = matrix_from_euler(np.radians([[30.0, 0.0, 0.0]]), "ZYX")
    np.testing.assert_allclose(alignment.apply_rotations(turn)[0], rotation @ up @ turn[0] @ up.T, atol=1e-15)
    document = alignment.to_json()
    assert document["rms_before"] == 0.5 and document["rms_after"] is None
    assert document["scale"] == 2.0 and document["units_scale"] == 0.01


def test_an_alignment_is_frozen_and_compared_by_identity():
    one, other = Alignment(), Alignment()
    assert one == one and one != other and len({one, other}) == 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        one.kind = "rigid"  # type: ignore[misc]


def test_none_fits_nothing_and_rms_leaves_missing_points_out():
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [np.nan, 0.0, 0.0]])
    rotation, translation, scale = fit_alignment(a, a + 5.0, "none")
    np.testing.assert_array_equal(rotation, np.eye(3))
    np.testing.assert_array_equal(translation, np.zeros(3))
    assert scale == 1.0 and isinstance(scale, float)
    assert rms_distance(a, a + np.array([3.0, 4.0, 0.0])) == 5.0
    assert math.isnan(rms_distance(a[2:], a[2:]))
