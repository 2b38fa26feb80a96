"""Euler angles and rotation matrices, checked against scipy (an independent implementation)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.rotations.euler import (
    EULER_ORDERS,
    complete_order,
    euler_from_matrix,
    matrix_from_euler,
    nearest_rotation,
    rotation_about_axis,
    rotation_angle,
)


@pytest.mark.parametrize("order", EULER_ORDERS)
def test_matrix_from_euler_matches_scipy_intrinsic(order, rng):
    angles = rng.uniform(-np.pi, np.pi, (200, 3))
    expected = Rotation.from_euler(order, angles).as_matrix()  # upper case: intrinsic
    np.testing.assert_allclose(matrix_from_euler(angles, order), expected, atol=1e-14)


@pytest.mark.parametrize("order", EULER_ORDERS)
def test_order_reads_left_to_right_as_a_product(order, rng):
    a, b, c = rng.uniform(-3, 3, 3)
    expected = rotation_about_axis(order[0], a) @ rotation_about_axis(order[1], b) @ rotation_about_axis(order[2], c)
    np.testing.assert_allclose(matrix_from_euler([a, b, c], order), expected, atol=1e-15)


def test_elementary_rotations_are_right_handed():
    quarter = np.pi / 2
    np.testing.assert_allclose(rotation_about_axis("X", quarter) @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(rotation_about_axis("Y", quarter) @ [0, 0, 1], [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(rotation_about_axis("Z", quarter) @ [1, 0, 0], [0, 1, 0], atol=1e-15)


@pytest.mark.parametrize("order", EULER_ORDERS)
def test_euler_round_trip_in_principal_range(order, rng):
    angles = rng.uniform(-np.pi, np.pi, (500, 3))
    angles[:, 1] = rng.uniform(-np.pi / 2 + 1e-3, np.pi / 2 - 1e-3, 500)
    np.testing.assert_allclose(euler_from_matrix(matrix_from_euler(angles, order), order), angles, atol=1e-12)


@pytest.mark.parametrize("order", EULER_ORDERS)
@pytest.mark.parametrize("middle", [np.pi / 2, -np.pi / 2])
def test_gimbal_lock_gives_finite_angles_that_rebuild_the_matrix(order, middle, rng):
    angles = rng.uniform(-np.pi, np.pi, (50, 3))
    angles[:, 1] = middle
    matrices = matrix_from_euler(angles, order)
    recovered = euler_from_matrix(matrices, order)
    assert np.isfinite(recovered).all()
    np.testing.assert_allclose(recovered[:, 2], 0.0)
    np.testing.assert_allclose(matrix_from_euler(recovered, order), matrices, atol=1e-12)


@pytest.mark.parametrize("order", EULER_ORDERS)
def test_angles_near_gimbal_lock_rebuild_the_matrix_to_rounding(order, rng):
    """Middle angles within 1e-14..1e-2 rad of +-90 degrees: each of the first and last angles
    is ill-conditioned there (errors grow as eps / cos), yet the three together rebuild the
    matrix to a few eps (before the fix, 2e-12 at cos = 1e-4: the boxing take's hip)."""
    angles = rng.uniform(-np.pi, np.pi, (3000, 3))
    distance = 10.0 ** rng.uniform(-14, -2, 3000)
    angles[:, 1] = np.pi / 2 * rng.choice([-1.0, 1.0], 3000) - np.sign(angles[:, 1]) * distance
    matrices = matrix_from_euler(angles, order)
    rebuilt = matrix_from_euler(euler_from_matrix(matrices, order), order)
    assert np.abs(rebuilt - matrices).max() <= 8 * np.finfo(float).eps


def test_euler_from_matrix_agrees_with_scipy_on_unique_solutions(rng):
    for order in EULER_ORDERS:
        angles = rng.uniform(-3, 3, (100, 3))
        angles[:, 1] = rng.uniform(-1.5, 1.5, 100)
        matrices = matrix_from_euler(angles, order)
        expected = Rotation.from_matrix(matrices).as_euler(order)
        np.testing.assert_allclose(euler_from_matrix(matrices, order), expected, atol=1e-10)


def test_partial_orders_leave_missing_axes_at_zero(rng):
    z = rng.uniform(-3, 3, 10)
    np.testing.assert_allclose(matrix_from_euler(z[:, None], "Z"), rotation_about_axis("Z", z), atol=1e-15)
    xy = rng.uniform(-3, 3, (10, 2))
    expected = rotation_about_axis("X", xy[:, 0]) @ rotation_about_axis("Y", xy[:, 1])
    np.testing.assert_allclose(matrix_from_euler(xy, "xy"), expected, atol=1e-15)
    assert complete_order("Z") == "ZXY" and complete_order("yx") == "YXZ"


@pytest.mark.parametrize("order", ["", "XX", "XYZW", "ABC"])
def test_bad_orders_are_refused(order):
    with pytest.raises(ValueError, match="distinct letters"):
        matrix_from_euler(np.zeros(max(len(order), 1)), order)


def test_nearest_rotation_corrects_reflections_and_noise(rng):
    rotations = Rotation.random(100, random_state=1).as_matrix()
    noisy = rotations + rng.normal(scale=1e-3, size=rotations.shape)
    fixed = nearest_rotation(noisy)
    np.testing.assert_allclose(np.linalg.det(fixed), 1.0, atol=1e-12)
    assert rotation_angle(np.swapaxes(fixed, -1, -2) @ rotations).max() < 5e-3
    reflection = np.diag([1.0, 1.0, -1.0])
    result = nearest_rotation(reflection)
    assert np.linalg.det(result) == pytest.approx(1.0)
    np.testing.assert_allclose(result @ result.T, np.eye(3), atol=1e-14)


def test_rotation_angle_matches_scipy_magnitude(rng):
    rotations = Rotation.random(200, random_state=2)
    np.testing.assert_allclose(rotation_angle(rotations.as_matrix()), rotations.magnitude(), atol=1e-12)
