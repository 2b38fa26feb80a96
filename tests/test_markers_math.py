"""Procrustes fits, the pelvis frame, swing/twist limbs and the reference search, against
independent computations (scipy, brute force)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.markers import match as match_module
from gmr_studio.core.markers.limbs import about_axis, least_change_twists, limb_rotation, swing, twist_angle, twist_of
from gmr_studio.core.markers.match import best_matches
from gmr_studio.core.markers.pelvis import pelvis_rotations
from gmr_studio.core.markers.procrustes import fit_rigid, frame_from_triple
from gmr_studio.core.rotations.euler import rotation_angle


def test_fit_rigid_recovers_a_rigid_motion_and_agrees_with_scipy(rng):
    template = rng.normal(size=(5, 3))
    truth = Rotation.random(50, random_state=1).as_matrix()
    shift = rng.normal(size=(50, 3))
    points = np.einsum("fab,kb->fka", truth, template) + shift[:, None]
    rotations, translations, rms, ok = fit_rigid(template, points)
    assert ok.all() and rms.max() < 1e-12
    np.testing.assert_allclose(rotations, truth, atol=1e-12)
    np.testing.assert_allclose(translations, shift, atol=1e-12)
    noisy = points + rng.normal(size=points.shape) * 0.05
    rotations = fit_rigid(template, noisy)[0]
    centred_t = template - template.mean(axis=0)
    for f in range(5):
        expected, _ = Rotation.align_vectors(noisy[f] - noisy[f].mean(axis=0), centred_t)
        np.testing.assert_allclose(rotations[f], expected.as_matrix(), atol=1e-9)


def test_fit_rigid_never_returns_a_reflection_and_handles_missing_points(rng):
    template = rng.normal(size=(4, 3))
    mirrored = template * np.array([1.0, 1.0, -1.0])  # the best orthogonal fit is a reflection
    rotations, _, rms, ok = fit_rigid(template, mirrored[None])
    assert ok.all() and np.linalg.det(rotations[0]) == pytest.approx(1.0) and rms[0] > 0
    points = np.broadcast_to(template, (3, 4, 3)).copy()
    points[1, 0] = np.nan  # three of four left: still a fit
    points[2, :2] = np.nan  # two left: no fit
    rotations, translations, rms, ok = fit_rigid(template, points)
    assert list(ok) == [True, True, False]
    np.testing.assert_allclose(rotations[1], np.eye(3), atol=1e-12)
    assert np.isnan(translations[2]).all() and np.isnan(rms[2])
    line = np.outer(np.arange(4.0), [1.0, 2.0, 3.0])
    assert not fit_rigid(line, line[None])[3][0]  # collinear template: the roll is free


def test_frame_from_triple_follows_the_note_and_flags_degenerate_triples():
    x1, x2, x3 = np.array([0.0, 0, 0]), np.array([-1.0, 0, 0]), np.array([0.0, -2, 0])
    frames, ok, coincident, collinear = frame_from_triple(x1, x2, x3)
    assert ok and not coincident and not collinear
    np.testing.assert_allclose(frames, np.eye(3), atol=1e-15)  # p1 = x, p2 = y, p3 = z
    triples = np.array(
        [
            [x1, x2, x3],
            [x1, x1, x3],  # X1 = X2
            [x1, x2, [3.0, 0, 0]],  # on one line
            [x1, x1, x1],  # all three coincide
            [x1, [np.nan] * 3, x3],
        ]
    )
    _, ok, coincident, collinear = frame_from_triple(triples[:, 0], triples[:, 1], triples[:, 2])
    assert list(ok) == [True, False, False, False, False]
    assert list(coincident) == [False, True, False, True, False]
    assert list(collinear) == [False, False, True, False, False]


def test_pelvis_rotations_are_exact_on_a_rigid_triple_for_both_methods(rng):
    home = np.array([[0.0, 1.0, 0.0], [0.2, 0.4, 0.3], [-0.2, 0.4, 0.3]])
    truth = Rotation.random(40, random_state=3).as_matrix()
    triple = np.einsum("fab,kb->fka", truth, home) + rng.normal(size=(40, 1, 3))
    for method in ("note", "points"):
        rotations, residuals, valid, reasons = pelvis_rotations(triple, home, method=method)
        assert valid.all() and reasons == [] and residuals.max() < 1e-12
        np.testing.assert_allclose(rotations, truth, atol=1e-12)
    # a deformed triangle: a residual of the size of the deformation, still a rotation
    bent = triple.copy()
    bent[:, 2] += 0.01
    rotations, residuals, _, _ = pelvis_rotations(bent, home)
    assert np.all((residuals > 1e-3) & (residuals < 0.02))
    np.testing.assert_allclose(np.linalg.det(rotations), 1.0)
    assert rotation_angle(np.swapaxes(rotations, -1, -2) @ truth).max() < 0.1


def test_pelvis_without_home_is_the_frame_itself(rng):
    triple = rng.normal(size=(6, 3, 3))
    rotations, residuals, valid, _ = pelvis_rotations(triple, None)
    frames = frame_from_triple(triple[:, 0], triple[:, 1], triple[:, 2])[0]
    np.testing.assert_allclose(rotations, frames, atol=1e-12)
    assert valid.all() and np.isfinite(residuals).all()


def test_degenerate_pelvis_frames_are_flagged_and_do_not_touch_good_ones(rng):
    home = np.array([[0.0, 0, 0], [1.0, 0, 0], [0.0, 1, 0]])
    truth = Rotation.random(8, random_state=5).as_matrix()
    triple = np.einsum("fab,kb->fka", truth, home)
    clean = pelvis_rotations(triple, home)[0]
    bad = triple.copy()
    bad[1] = np.nan  # all markers missing
    bad[3, 1] = bad[3, 0]  # coincident
    bad[5, 2] = 2 * bad[5, 1] - bad[5, 0]  # collinear
    rotations, residuals, valid, reasons = pelvis_rotations(bad, home, labels=("root", "lhip", "rhip"))
    assert list(np.flatnonzero(~valid)) == [1, 3, 5]
    assert np.array_equal(rotations[valid], clean[valid]) and np.isnan(residuals[~valid]).all()
    np.testing.assert_array_equal(rotations[~valid], np.broadcast_to(np.eye(3), (3, 3, 3)))
    text = " | ".join(reasons)
    assert "pelvis marker root missing in frames 1" in text
    assert "coincide in frames 3" in text and "collinear in frames 5" in text


def test_swing_twist_decomposition_rebuilds_any_rotation(rng):
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    rotations = Rotation.random(500, random_state=7).as_matrix()
    gamma = twist_of(rotations, u)
    np.testing.assert_allclose(limb_rotation(u, rotations @ u, gamma), rotations, atol=1e-12)
    # the swing is the shortest rotation: its angle is the angle between u and c
    c = rotations @ u
    angle = rotation_angle(swing(u, c))
    np.testing.assert_allclose(angle, np.arccos(np.clip(c @ u, -1, 1)), atol=1e-7)
    # bone reversed: a half turn that still takes u to -u
    half = swing(u, -u[None])[0]
    np.testing.assert_allclose(half @ u, -u, atol=1e-15)
    np.testing.assert_allclose(half @ half.T, np.eye(3), atol=1e-15)


def test_twist_angle_is_exact_for_rotations_about_the_axis(rng):
    u = np.array([0.0, 0.6, 0.8])
    gamma = rng.uniform(-np.pi, np.pi, 100)
    np.testing.assert_allclose(twist_angle(about_axis(u, gamma), u), gamma, atol=1e-12)


def test_least_change_twists_agree_with_a_brute_force_search(rng):
    u = np.array([0.0, 0.0, 1.0])
    steps = Rotation.from_rotvec(rng.normal(size=(6, 3)) * 0.3).as_matrix()
    c = np.array([np.linalg.multi_dot([np.eye(3), *steps[:f]]) @ u if f else u for f in range(7)])
    gamma = least_change_twists(u, c)
    grid = np.linspace(-np.pi, np.pi, 72001)
    for f in range(1, 7):
        previous = limb_rotation(u, c[f - 1], gamma[f - 1])
        candidates = limb_rotation(u, np.broadcast_to(c[f], (grid.size, 3)), grid)
        best = grid[np.argmin(rotation_angle(np.swapaxes(candidates, -1, -2) @ previous))]
        assert abs(np.angle(np.exp(1j * (gamma[f] - best)))) < 1e-4


def brute_force_matches(query, present, reference, query_times, reference_times, exclude):
    d = np.sum(((query[:, None] - reference[None]) ** 2).sum(axis=3) * present[:, None], axis=2)
    if exclude is not None:
        d[np.abs(query_times[:, None] - reference_times[None]) <= exclude] = np.inf
    return np.where(np.isfinite(d.min(axis=1)), d.argmin(axis=1), -1)


@pytest.mark.parametrize("exclude", [None, 0.3])
def test_best_matches_agree_with_brute_force_in_small_chunks(rng, monkeypatch, exclude):
    monkeypatch.setattr(match_module, "CHUNK_ELEMENTS", 50)
    reference = rng.normal(size=(40, 5, 3))
    query = reference[rng.integers(0, 40, 30)] + rng.normal(size=(30, 5, 3)) * 0.3
    present = rng.random((30, 5)) > 0.2
    times_q, times_r = np.arange(30) / 10, np.arange(40) / 10
    index, distance = best_matches(
        query, present, reference, query_times=times_q, reference_times=times_r, exclude_within=exclude
    )
    expected = brute_force_matches(query, present, reference, times_q, times_r, exclude)
    np.testing.assert_array_equal(index, expected)
    if exclude is not None:
        assert np.all(np.abs(times_q - times_r[index]) > exclude)
    rms = np.sqrt(np.sum(((query - reference[index]) ** 2).sum(axis=2) * present, axis=1) / present.sum(axis=1))
    np.testing.assert_allclose(distance, rms, rtol=1e-9)


def test_an_exact_match_wins_and_ties_go_to_the_nearest_time(rng):
    reference = rng.normal(size=(10, 4, 3))
    reference[7] = reference[2]  # the same pose twice
    times = np.arange(10.0)
    index, distance = best_matches(
        reference, np.ones((10, 4), bool), reference, query_times=times, reference_times=times
    )
    np.testing.assert_array_equal(index, np.arange(10))  # frame 7 matches itself, not frame 2
    assert distance.max() < 1e-12
    all_excluded = best_matches(
        reference[:1], np.ones((1, 4), bool), reference, query_times=times[:1], reference_times=times,
        exclude_within=100.0,
    )  # fmt: skip
    assert all_excluded[0][0] == -1 and np.isnan(all_excluded[1][0])
