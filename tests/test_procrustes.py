"""The rigid fits of core/markers/procrustes.py against independent computations: ``fit_rigid``
against Horn's quaternion method, frame by frame, with noise and missing points (its RMS over
the present points only); ``frame_from_triple``'s degeneracy verdicts against side lengths and
sines computed apart, at any scale and on their exact boundaries, without NaN arithmetic."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gmr_studio.core.markers.procrustes import fit_rigid, frame_from_triple
from gmr_studio.core.rotations.euler import matrix_from_euler


def horn_fit(template: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Best rotation, translation and RMS of one frame's present points (K, 3) each, by the
    largest eigenvector of Horn's 4x4 matrix (no SVD), and a plain loop for the RMS."""
    s = template - template.mean(axis=0)
    x = points - points.mean(axis=0)
    m = s.T @ x  # m[a, b] = sum s_a x_b
    (sxx, sxy, sxz), (syx, syy, syz), (szx, szy, szz) = m
    n = np.array(
        [
            [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
            [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
            [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
            [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
        ]
    )
    w, x_, y, z = np.linalg.eigh(n)[1][:, -1]
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x_ * y - w * z), 2 * (x_ * z + w * y)],
            [2 * (x_ * y + w * z), 1 - 2 * (x_ * x_ + z * z), 2 * (y * z - w * x_)],
            [2 * (x_ * z - w * y), 2 * (y * z + w * x_), 1 - 2 * (x_ * x_ + y * y)],
        ]
    )
    translation = points.mean(axis=0) - rotation @ template.mean(axis=0)
    squared = 0.0
    for k in range(len(points)):
        squared += float(np.sum((rotation @ template[k] + translation - points[k]) ** 2))
    return rotation, translation, (squared / len(points)) ** 0.5


def test_fit_and_rms_match_a_per_frame_quaternion_fit_with_noise_and_gaps(rng):
    frames, count = 60, 7
    template = rng.normal(scale=100.0, size=(count, 3))
    truth = matrix_from_euler(rng.uniform(-np.pi, np.pi, (frames, 3)), "ZYX")
    shift = rng.normal(scale=500.0, size=(frames, 3))
    points = np.einsum("fab,kb->fka", truth, template) + shift[:, None] + rng.normal(scale=2.0, size=(frames, count, 3))
    present = rng.random((frames, count)) > 0.3
    present[:5] = True  # some frames complete
    present[5, 3:] = False  # exactly three points
    present[6, 2:] = False  # two points: no fit
    points[~present] = np.nan
    rotations, translations, rms, ok = fit_rigid(template, points)
    assert ok.tolist() == (present.sum(axis=1) >= 3).tolist()
    checked = 0
    for f in np.flatnonzero(ok):
        rotation, translation, expected_rms = horn_fit(template[present[f]], points[f, present[f]])
        np.testing.assert_allclose(rotations[f], rotation, rtol=0, atol=1e-10)
        np.testing.assert_allclose(translations[f], translation, rtol=0, atol=1e-8)
        np.testing.assert_allclose(rms[f], expected_rms, rtol=1e-10)
        checked += 1
    assert checked >= 50
    assert np.isnan(rms[6]) and np.isnan(translations[6]).all()
    # the RMS is that of the present points: ~ noise * sqrt(3 (n - 2) / n) for n points, not diluted
    assert 2.0 < np.median(rms[ok]) < 4.0


def test_the_fit_is_a_least_squares_minimum(rng):
    template = rng.normal(scale=10.0, size=(5, 3))
    points = template @ matrix_from_euler(np.array([0.3, -1.1, 2.0]), "XYZ").T + 4.0
    points = points + rng.normal(scale=0.5, size=points.shape)
    rotations, translations, rms, ok = fit_rigid(template, points[None])
    best = np.sqrt(np.mean(np.sum((template @ rotations[0].T + translations[0] - points) ** 2, axis=-1)))
    assert ok[0] and abs(rms[0] - best) <= 1e-12 * best
    for axis in np.eye(3):
        for angle in (1e-3, -1e-3):
            turned = matrix_from_euler(angle * axis, "XYZ") @ rotations[0]
            moved = template @ turned.T + translations[0]
            centred = moved - moved.mean(axis=0) + points.mean(axis=0)
            worse = np.sqrt(np.mean(np.sum((centred - points) ** 2, axis=-1)))
            assert worse > best


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
