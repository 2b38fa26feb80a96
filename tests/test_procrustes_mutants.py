"""The pelvis frame of three points (core/markers/procrustes.py, frame_from_triple): its
degeneracy verdicts against side lengths and sines computed apart, at any scale, on their exact
boundaries, and without NaN arithmetic on degenerate triples (the mutation run's blind spots,
docs/reliability.md)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gmr_studio.core.markers.procrustes import frame_from_triple


def verdicts(x1, x2, x3, min_sine):
    """(coincident, collinear) from the side lengths and the sine at X1, one triple at a time."""
    coincident, collinear = [], []
    for p, q, r in zip(x1, x2, x3):
        sides = [np.linalg.norm(p - q), np.linalg.norm(p - r), np.linalg.norm(q - r)]
        close = min(sides[0], sides[1]) <= min_sine * max(sides)
        sine = np.linalg.norm(np.cross(p - q, p - r)) / (sides[0] * sides[1]) if not close else 0.0
        coincident.append(close)
        collinear.append(not close and sine <= min_sine)
    return np.array(coincident), np.array(collinear)


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_degenerate_triples_agree_with_side_lengths_and_sines_at_any_scale(rng, scale):
    n, min_sine = 3000, 0.1
    x1 = rng.normal(size=(n, 3)) * scale
    # one point (X2 or X3) at 0.01 to 1 of the other's distance from X1: in any direction for
    # half (the longest side is X2-X3 when the angle at X1 is obtuse), nearly along the other,
    # either way, for the rest (sines about the threshold)
    far = rng.normal(size=(n, 3))
    ratio = 10 ** rng.uniform(-2, 0, (n, 1))
    along = (
        rng.choice([-1.0, 1.0], (n, 1)) * far + rng.normal(size=(n, 3)) * 0.15 * np.linalg.norm(far, axis=1)[:, None]
    )
    near = np.where(rng.random((n, 1)) < 0.5, rng.normal(size=(n, 3)), along) * ratio
    swap = rng.random(n) < 0.5
    x2 = x1 + np.where(swap[:, None], far, near) * scale
    x3 = x1 + np.where(swap[:, None], near, far) * scale
    frames, ok, coincident, collinear = frame_from_triple(x1, x2, x3, min_sine)
    expected_coincident, expected_collinear = verdicts(x1, x2, x3, min_sine)
    assert 100 < expected_coincident.sum() < n - 100 and expected_collinear.sum() > 50  # both kinds, often
    np.testing.assert_array_equal(coincident, expected_coincident)
    np.testing.assert_array_equal(collinear, expected_collinear)
    np.testing.assert_array_equal(ok, ~expected_coincident & ~expected_collinear)
    good = frames[ok]
    np.testing.assert_allclose(good @ np.swapaxes(good, 1, 2), np.broadcast_to(np.eye(3), good.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(good), 1.0)
    p1 = (x1 - x2)[ok] / np.linalg.norm((x1 - x2)[ok], axis=1, keepdims=True)
    np.testing.assert_allclose(good[:, :, 0], p1, atol=1e-12)


def test_a_point_a_tenth_of_a_micron_from_x1_in_a_metre_triangle_coincides():
    """In mm, with the default threshold: 1e-4 mm is within 1e-6 of a 1000 mm side."""
    x1 = np.zeros((2, 3))
    x2 = np.array([[1e-4, 0, 0], [1000.0, 0, 0]])
    x3 = np.array([[0.0, 1000, 0], [0.0, 1e-4, 0]])
    _, ok, coincident, collinear = frame_from_triple(x1, x2, x3)
    assert list(coincident) == [True, True] and not ok.any() and not collinear.any()
    x2[0, 0], x3[1, 1] = 0.1, 0.1  # 0.1 mm: not any more
    _, ok, coincident, _ = frame_from_triple(x1, x2, x3)
    assert list(coincident) == [False, False] and ok.all()


def test_the_thresholds_are_inclusive_on_their_exact_boundaries():
    x1 = np.zeros((4, 3))
    # X1 - X2 = (5, 0, 0) and X1 - X3 = (12, 16, 0): 5 is a quarter of the longest side, 20
    x2 = -np.array([[5.0, 0, 0], [12.0, 16, 0], [5.0, 0, 0], [4.0, 0, 0]])
    x3 = -np.array([[12.0, 16, 0], [5.0, 0, 0], [3.0, 4, 0], [12.0, 16, 0]])
    _, ok, coincident, collinear = frame_from_triple(x1[:2], x2[:2], x3[:2], 0.25)
    assert list(coincident) == [True, True] and not ok.any()
    # X1 - X2 = (5, 0, 0), X1 - X3 = (3, 4, 0): the sine at X1 is 4/5 exactly, 0.8 * 5 == 4.0
    _, ok, coincident, collinear = frame_from_triple(x1[2:3], x2[2:3], x3[2:3], 0.8)
    assert not coincident[0] and collinear[0] and not ok[0]
    # 4 is under a quarter of 20: coincident; the same triangle with a smaller threshold is good
    _, ok, coincident, _ = frame_from_triple(x1[3:], x2[3:], x3[3:], 0.25)
    assert coincident[0]
    _, ok, coincident, collinear = frame_from_triple(x1[3:], x2[3:], x3[3:], 0.1)
    assert ok[0] and not coincident[0] and not collinear[0]


def test_x3_on_x1_coincides_and_a_unit_triangle_is_good():
    x1 = np.zeros(3)
    _, ok, coincident, collinear = frame_from_triple(x1, np.array([2.0, 1, 0]), x1)
    assert coincident and not ok and not collinear
    # a right isosceles triangle whose longest side is 1 exactly
    frames, ok, coincident, collinear = frame_from_triple(x1, np.array([-1.0, 0, 0]), np.array([-0.5, -0.5, 0]))
    assert ok and not coincident and not collinear
    np.testing.assert_allclose(frames, np.eye(3), atol=1e-15)


def test_degenerate_triples_are_flagged_without_dividing_by_zero():
    x1 = np.zeros((4, 3))
    x2 = np.array([[0.0, 0, 0], [0.0, 0, 0], [-1.0, 0, 0], [-1.0, 0, 0]])
    x3 = np.array([[0.0, 0, 0], [0.0, -1, 0], [-3.0, 0, 0], [2.0, 0, 0]])  # all one, X1 = X2, on one line twice
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frames, ok, coincident, collinear = frame_from_triple(x1, x2, x3)
    assert list(coincident) == [True, True, False, False] and list(collinear) == [False, False, True, True]
    assert not ok.any()
    np.testing.assert_array_equal(frames, np.broadcast_to(np.eye(3), (4, 3, 3)))
