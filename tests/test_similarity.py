"""The one similarity transform (core/space/similarity.py): marker maps, the marker alignment
and comparisons all move points with it; it inverts, composes and turns orientations exactly."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.space.similarity import Similarity, fit_similarity

PERMUTATION = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])  # marker (x, y, z) -> (y, z, x)


def test_points_go_there_and_back_and_orientations_change_axes():
    transform = Similarity(PERMUTATION, 2.0, np.array([1.0, -1.0, 0.5]))
    point = np.array([[1.0, 2.0, 3.0]])
    np.testing.assert_allclose(transform.apply(point), [[2 * 2.0 + 1.0, 2 * 3.0 - 1.0, 2 * 1.0 + 0.5]])
    np.testing.assert_allclose(transform.inverse().apply(transform.apply(point)), point, rtol=1e-15)
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # about the source's z
    np.testing.assert_allclose(transform.change_frames(turn), PERMUTATION @ turn @ PERMUTATION.T)
    assert transform.scale == 2.0 and type(transform.scale) is float
    assert np.isnan(transform.apply(np.full((1, 3), np.nan))).all()


def test_one_after_the_other_is_their_composition(rng):
    first = Similarity(Rotation.random(random_state=1).as_matrix(), 0.01, rng.normal(size=3))
    second = Similarity(Rotation.random(random_state=2).as_matrix(), 25.4, rng.normal(size=3))
    points = rng.normal(size=(20, 3))
    both = first.then(second)
    np.testing.assert_allclose(both.apply(points), second.apply(first.apply(points)), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(both.inverse().apply(both.apply(points)), points, atol=1e-12)


def test_a_turn_about_a_pivot_keeps_the_pivot_and_the_distances_to_it(rng):
    transform = Similarity(PERMUTATION, 0.5, np.array([3.0, -1.0, 2.0]))
    pivot = np.array([10.0, 4.0, -7.0])
    points = rng.normal(size=(30, 3))
    for axis in "xyz":
        turned = transform.turned_about(axis, np.pi / 2, pivot)
        before, after = transform.apply(points), turned.apply(points)
        np.testing.assert_allclose(np.linalg.norm(after - pivot, axis=1), np.linalg.norm(before - pivot, axis=1))
        column = "xyz".index(axis)
        np.testing.assert_allclose(after[:, column], before[:, column], atol=1e-12)


def test_the_identity_is_only_the_identity():
    assert Similarity().is_identity
    assert not Similarity(scale=0.5).is_identity
    assert not Similarity(PERMUTATION).is_identity
    assert not Similarity(translation=np.array([0.0, 0.0, 1e-9])).is_identity


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((np.eye(2),), "orthonormal 3x3"),
        ((np.array([[1.0, 1e-8, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),), "orthonormal 3x3"),
        ((np.eye(3), 0.0), "a positive scale"),
        ((np.eye(3), -1.0), "a positive scale"),
        ((np.eye(3), np.nan), "a positive scale"),
        ((np.eye(3), 1.0, np.zeros(2)), "a finite translation of 3 numbers"),
        ((np.eye(3), 1.0, np.array([0.0, np.nan, 0.0])), "a finite translation of 3 numbers"),
    ],
)
def test_what_is_not_a_similarity_is_refused(arguments, message):
    with pytest.raises(ValueError, match=message):
        Similarity(*arguments)


def test_rotations_orthonormal_to_a_billionth_are_taken_and_a_reflection_too():
    nearly = np.array([[1.0, 4e-10, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    assert Similarity(nearly).rotation[0, 1] == 4e-10
    assert Similarity(-PERMUTATION).rotation[0, 1] == -1.0  # an axis flip read from a file


def test_the_fit_recovers_a_known_transform(rng):
    truth = Similarity(Rotation.random(random_state=5).as_matrix(), 2.5, np.array([1.0, -2.0, 0.5]))
    b = rng.normal(size=(100, 3))
    fitted = fit_similarity(truth.apply(b), b)
    np.testing.assert_allclose(fitted.rotation, truth.rotation, atol=1e-12)
    assert fitted.scale == pytest.approx(2.5, rel=1e-12)
    np.testing.assert_allclose(fitted.translation, truth.translation, atol=1e-12)
