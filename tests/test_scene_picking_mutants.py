"""Picking's edges (app/scene/picking.py, issue 24): a point in the camera's plane, the pick
radius and the overlap's quarter radius reached exactly, missing points among present ones.
Pure numpy: the camera matrices are written out (:mod:`tests.test_app_picking`)."""

from __future__ import annotations

import numpy as np

from gmr_studio.app.scene.picking import pick_point, project_points
from tests.test_app_picking import look_from_z, perspective

CAMERA = perspective(90, 2.0, 1.0, 100.0) @ look_from_z(10.0)  # f = 1: x/depth/2, y/depth


def test_pixels_and_depth_of_points_in_front_of_the_camera():
    screen = project_points(np.array([[0.0, 0.0, 0.0], [5.0, 2.5, 5.0], [-20.0, -10.0, 0.0]]), CAMERA, (400, 300))
    # x = (x_ndc + 1) / 2 * 400, y = (1 - y_ndc) / 2 * 300; x_ndc = X / depth / 2, y_ndc = Y / depth
    np.testing.assert_allclose(screen[:, 0], [200.0, 300.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(screen[:, 1], [150.0, 75.0, 300.0], atol=1e-9)
    near, far = 1.0, 100.0
    depth = np.array([10.0, 5.0, 10.0])
    np.testing.assert_allclose(screen[:, 2], (far + near) / (far - near) - 2 * far * near / (far - near) / depth)
    one = project_points(np.array([5.0, 2.5, 5.0]), CAMERA, (400, 300))
    assert one.shape == (1, 3) and one.dtype == np.float64
    np.testing.assert_allclose(one[0], screen[1])


def test_a_point_in_the_cameras_plane_or_behind_it_has_no_pixel():
    screen = project_points(np.array([[1.0, 1.0, 10.0], [0.0, 0.0, 10.0], [1.0, 0.0, 11.0]]), CAMERA, (400, 300))
    assert np.isnan(screen).all()  # w = 0 (not infinite pixels) and w < 0


def test_the_pick_radius_and_the_overlaps_quarter_are_reached_exactly():
    screen = np.array([[8.0, 0.0, 0.5], [0.0, 0.0, 0.5]])
    assert pick_point((0.0, 8.0), screen[1:], 8.0) == 0  # on the radius: picked
    assert pick_point((8.0, 0.0), screen, 8.0) == 0
    assert pick_point((0.0, 8.25), np.array([[0.0, 0.0, 0.5]]), 8.0) is None
    # nearest at 1; a point at 1 + 8 / 4 = 3 overlaps it, nearer the camera: it wins
    screen = np.array([[1.0, 0.0, 0.5], [3.0, 0.0, 0.1]])
    assert pick_point((0.0, 0.0), screen, 8.0) == 1
    screen = np.array([[1.0, 0.0, 0.5], [3.25, 0.0, 0.1]])
    assert pick_point((0.0, 0.0), screen, 8.0) == 0  # beyond the quarter: the nearest on screen
    screen = np.array([[1.0, 0.0, 0.1], [3.0, 0.0, 0.5]])
    assert pick_point((0.0, 0.0), screen, 8.0) == 0  # overlapping, the nearest on screen also nearer


def test_missing_points_among_present_ones_are_passed_over():
    screen = np.array([[np.nan, np.nan, np.nan], [10.0, 0.0, 0.5], [np.nan, 0.0, 0.2], [np.inf, 0.0, 0.0]])
    picked = pick_point((9.0, 0.0), screen, 5.0)
    assert picked == 1 and type(picked) is int
    assert pick_point((9.0, 0.0), screen[[0, 2]], 5.0) is None
