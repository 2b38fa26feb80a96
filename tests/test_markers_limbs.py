"""Limb rotations from bone directions (core/markers/limbs.py): the shapes the functions
document, the twist of a bone turned exactly a right angle, the half turn within the
antiparallel threshold, and the twists read from a marker rigid with the bone."""

from __future__ import annotations

import warnings

import numpy as np
from scipy.spatial.transform import Rotation

from gmr_studio.core.markers.limbs import (
    ANTIPARALLEL_EPSILON,
    about_axis,
    least_change_twists,
    limb_rotation,
    marker_twists,
    perpendicular,
    swing,
    twist_angle,
    twist_of,
)

#: a quarter turn about x, written out: it takes z to -y exactly
QUARTER_X = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])


def test_perpendicular_takes_any_leading_axes(rng):
    for shape in [(3,), (4, 3), (2, 5, 3)]:
        u = rng.normal(size=shape)
        u /= np.linalg.norm(u, axis=-1, keepdims=True)
        w = perpendicular(u)
        assert w.shape == shape
        np.testing.assert_allclose(np.linalg.norm(w, axis=-1), 1.0)
        np.testing.assert_allclose(np.sum(u * w, axis=-1), 0.0, atol=1e-15)
    # the axis crossed is u's smallest component: x here, so w = u x x
    np.testing.assert_allclose(perpendicular(np.array([0.0, 0.6, 0.8])), [0.0, 0.8, -0.6], atol=1e-15)


def test_twist_angle_of_one_rotation_and_of_frames_by_joints(rng):
    u = np.array([0.0, 0.6, 0.8])
    gamma = rng.uniform(-3, 3, (2, 5))
    rotations = about_axis(u, gamma)
    assert twist_angle(rotations[0, 0], u).shape == ()
    np.testing.assert_allclose(twist_angle(rotations[0, 0], u), gamma[0, 0], atol=1e-12)
    np.testing.assert_allclose(twist_angle(rotations, u), gamma, atol=1e-12)
    # one axis per rotation
    axes = Rotation.random(10, random_state=2).as_matrix()[:, :, 0].reshape(2, 5, 3)
    np.testing.assert_allclose(twist_angle(about_axis(axes, gamma), axes), gamma, atol=1e-12)


def test_the_twist_of_a_bone_turned_a_right_angle_is_exact():
    """u along z turned to -y exactly, then twisted: the swing is the quarter turn itself."""
    u = np.array([0.0, 0.0, 1.0])
    gamma = np.array([0.3, -2.0, 3.0])
    rotations = QUARTER_X @ about_axis(u, gamma)
    np.testing.assert_array_equal(rotations @ u, np.broadcast_to([0.0, -1.0, 0.0], (3, 3)))
    np.testing.assert_allclose(twist_of(rotations, u), gamma, atol=1e-12)
    np.testing.assert_allclose(limb_rotation(u, rotations @ u, twist_of(rotations, u)), rotations, atol=1e-12)


def test_directions_within_the_antiparallel_threshold_take_the_half_turn():
    u = np.array([1.0, 0.0, 0.0])
    x = ANTIPARALLEL_EPSILON - 1.0
    while 1.0 + x >= ANTIPARALLEL_EPSILON:  # the largest cosine whose 1 + cosine is within it
        x = np.nextafter(x, -2.0)
    within = np.array([x, np.sqrt(1.0 - x * x), 0.0])
    # within the threshold, and exactly against u: the half turn about u x (its smallest
    # component's axis), z here, computed without a division by zero
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        half_turns = swing(u, np.stack([within, -u]))
    np.testing.assert_array_equal(half_turns, np.broadcast_to(np.diag([-1.0, -1.0, 1.0]), (2, 3, 3)))
    # beyond it: the shortest rotation itself, which takes u to c
    y = x + 2 * ANTIPARALLEL_EPSILON
    beyond = np.array([y, np.sqrt(1.0 - y * y), 0.0])
    np.testing.assert_allclose(swing(u, beyond[None])[0] @ u, beyond, atol=1e-9)


def test_least_change_twists_of_two_directions_turn_the_second_least():
    u = np.array([0.0, 0.0, 1.0])
    c = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # a quarter turn about y, then one about -x
    gamma = least_change_twists(u, c)
    assert gamma[0] == 0.0 and abs(gamma[1]) > 1.0  # the bare swings are far apart: a real twist
    first = swing(u, c[:1])[0]
    grid = np.linspace(-np.pi, np.pi, 3601)
    closeness = np.trace(
        np.swapaxes(limb_rotation(u, np.broadcast_to(c[1], (grid.size, 3)), grid), 1, 2) @ first, axis1=1, axis2=2
    )
    best = np.trace(limb_rotation(u, c[1], gamma[1]).T @ first)
    assert best >= closeness.max() - 1e-12


def test_least_change_twists_of_one_direction_and_of_none():
    u = np.array([0.0, 0.0, 1.0])
    np.testing.assert_array_equal(least_change_twists(u, np.array([[0.0, 1.0, 0.0]])), [0.0])
    assert least_change_twists(u, np.zeros((0, 3))).shape == (0,)


def _marker_take(rng, u, gammas, marker):
    """Unit bone directions (N, 3) and a marker rigid with the bone (N, 3), both in the
    parent's frame, for twists ``gammas`` (N,) about the rest direction u."""
    c = rng.normal(size=(len(gammas), 3))
    c /= np.linalg.norm(c, axis=1, keepdims=True)
    rotations = limb_rotation(u, c, gammas)
    return c, rotations @ marker


def test_marker_twists_recover_the_twists_about_their_mean_direction(rng):
    u = np.array([0.0, 0.6, 0.8])
    gammas = np.array([0.3, -0.5, 1.1, 0.2, -0.9])
    # the marker has a part along the bone and is not at unit distance: only its turn counts
    marker = 2.5 * u + np.array([1.5, 0.48, -0.36])
    c, third = _marker_take(rng, u, gammas, marker)
    got = marker_twists(u, c, third)
    assert got.shape == (5,)
    # the same twists up to one constant, the angle of the marker's mean direction
    offset = np.angle(np.exp(1j * (gammas - got)))
    np.testing.assert_allclose(offset, offset[0], atol=1e-12)
    # the rest pose is the mean one: the twists' directions average along angle zero
    assert abs(np.sum(np.sin(got))) < 1e-12
    assert np.sum(np.cos(got)) > 0
    # the limb turned by the twists found puts the marker where it was, the rest marker
    # being the original turned by the constant
    rest_marker = about_axis(u, offset[0]) @ marker
    np.testing.assert_allclose(limb_rotation(u, c, got) @ rest_marker, third, atol=1e-12)


def test_marker_twists_of_an_unswung_bone_are_measured_from_the_mean_direction():
    u = np.array([0.0, 0.0, 1.0])
    # the marker along x then along y: mean direction at 45 degrees, twists -45 and +45
    third = np.array([[2.0, 0.0, 0.7], [0.0, 2.0, -0.3]])
    np.testing.assert_allclose(marker_twists(u, np.tile(u, (2, 1)), third), [-np.pi / 4, np.pi / 4], atol=1e-15)
    # along x, along x, along -y: mean direction below x (angle atan2(-1, 2)), no swing
    third = np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    mean_angle = np.arctan2(-1.0, 2.0)
    np.testing.assert_allclose(
        marker_twists(u, np.tile(u, (3, 1)), third), [-mean_angle, -mean_angle, -np.pi / 2 - mean_angle], atol=1e-15
    )


def test_marker_twists_undo_the_swing_of_a_bent_bone():
    # the bone turned a quarter turn about x (z to -y); the marker, rigid with it, goes from
    # x (twist 0) to x as well, and on the other frame from y to z (twist a quarter turn)
    u = np.array([0.0, 0.0, 1.0])
    c = np.array([[0.0, -1.0, 0.0], [0.0, -1.0, 0.0]])
    third = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(marker_twists(u, c, third), [-np.pi / 4, np.pi / 4], atol=1e-15)
