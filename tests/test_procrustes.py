"""``fit_rigid`` against an independent computation: Horn's quaternion method, frame by frame,
with noise and missing points; its RMS over the present points only."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.markers.procrustes import fit_rigid
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
