"""Pick-to-joint mapping as pure functions: projection and nearest point within a radius, the
radius and the overlap's quarter radius reached exactly, points on or behind the camera's plane
and missing points among present ones."""

from __future__ import annotations

import numpy as np

from gmr_studio.app.scene.picking import pick_point, project_points


def perspective(fov_deg: float, aspect: float, near: float, far: float) -> np.ndarray:
    f = 1 / np.tan(np.radians(fov_deg) / 2)
    return np.array(
        [
            [f / aspect, 0, 0, 0],
            [0, f, 0, 0],
            [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
            [0, 0, -1, 0],
        ]
    )


def look_from_z(distance: float) -> np.ndarray:
    """View matrix of a camera on +Z looking at the origin, Y up."""
    view = np.eye(4)
    view[2, 3] = -distance
    return view


def test_projection_matches_a_pinhole_camera():
    width, height = 800, 600
    matrix = perspective(30, width / height, 0.1, 100) @ look_from_z(10)
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 5]], dtype=float)
    screen = project_points(points, matrix, (width, height))
    f = 1 / np.tan(np.radians(15))
    # independent pinhole: x_pixel = cx + f*(h/2)*X/depth, y grows downwards
    expected_x = width / 2 + f * (height / 2) * points[:, 0] / (10 - points[:, 2])
    expected_y = height / 2 - f * (height / 2) * points[:, 1] / (10 - points[:, 2])
    np.testing.assert_allclose(screen[:, 0], expected_x, atol=1e-9)
    np.testing.assert_allclose(screen[:, 1], expected_y, atol=1e-9)
    assert screen[3, 2] < screen[0, 2]  # nearer has smaller depth


def test_points_behind_the_camera_and_nan_are_never_picked():
    matrix = perspective(30, 1, 0.1, 100) @ look_from_z(10)
    screen = project_points(np.array([[0, 0, 20.0], [np.nan, 0, 0]]), matrix, (100, 100))
    assert np.isnan(screen).all()
    assert pick_point((50, 50), screen, 1000) is None


def test_pick_nearest_within_radius():
    screen = np.array([[10, 10, 0.5], [50, 50, 0.5], [53, 50, 0.5]], dtype=float)
    assert pick_point((49, 51), screen, 5) == 1
    assert pick_point((53.5, 50), screen, 5) == 2
    assert pick_point((30, 30), screen, 5) is None
    assert pick_point((14, 10), screen, 5) == 0
    assert pick_point((16, 10), screen, 5) is None
    assert pick_point((0, 0), np.zeros((0, 3)), 5) is None


def test_overlapping_points_pick_the_one_nearest_the_camera():
    screen = np.array([[50, 50, 0.9], [50.5, 50, 0.2], [51, 50, 0.6]])
    assert pick_point((50, 50), screen, 8) == 1


# a camera on +z 10 from the origin, 90 degrees, twice as wide as high: x/depth/2, y/depth
CAMERA = perspective(90, 2.0, 1.0, 100.0) @ look_from_z(10.0)


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
