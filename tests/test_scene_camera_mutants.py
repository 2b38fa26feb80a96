"""The scene's camera (app/scene/camera.py, issue 24) on the tiny synthetic skeleton
(:mod:`tests.tiny_scene`): where it stands for a new document (from the side of the main
direction of travel, a little from the front and above, the box it frames filling 90% of
the view), following the figure along the floor, framing a joint, and the world -> screen
projection that picking and the labels use."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gmr_studio.app.scene.camera import SceneCamera, actor_positions
from gmr_studio.app.scene.figure import JOINT_RADIUS
from gmr_studio.app.scene.picking import project_points
from tests.tiny_scene import (
    FIGURE_NAMES,
    FIGURE_PARENTS,
    FIGURE_SIZE,
    FIGURE_SOFT_PARENTS,
    figure_motion,
    figure_world,
    posed_motion,
    scene_of,
    snapshot_of,
)

pytestmark = pytest.mark.gui
WIDTH, HEIGHT = 200, 160


def snapshot_from(world):
    return snapshot_of(posed_motion(FIGURE_NAMES, FIGURE_PARENTS, world, FIGURE_SOFT_PARENTS))


def view_direction(scene) -> np.ndarray:
    """(3,) unit vector from the focal point to the camera."""
    camera = scene.plotter.camera
    direction = np.asarray(camera.GetPosition()) - np.asarray(camera.GetFocalPoint())
    return direction / np.linalg.norm(direction)


def unit(vector) -> np.ndarray:
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def reach_of(scene, low, high) -> float:
    """How far the box's corners reach towards the view's edges (1: to the edge)."""
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
    screen = project_points(corners, scene.view_projection(), scene.viewport())
    return max(np.abs(screen[:, 0] / WIDTH * 2 - 1).max(), np.abs(screen[:, 1] / HEIGHT * 2 - 1).max())


def test_the_actors_positions_leave_out_the_anchor_only():
    snapshot = snapshot_of(figure_motion())
    np.testing.assert_array_equal(actor_positions(snapshot), snapshot.positions[:, 1:])
    world = figure_world()
    world[:, 0, 0] += 0.05 * np.arange(3)  # the Root moves too: no anchor
    free = snapshot_from(world)
    assert actor_positions(free) is free.positions


def test_a_standing_figure_is_seen_from_its_side_front_and_above_filling_the_view():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        # following: the figure at this frame with a margin of 0.12 of its size, down to the floor
        np.testing.assert_allclose(view_direction(scene), unit([0.3, 0.45, 1.0]), atol=1e-9)
        assert scene.plotter.camera.GetViewUp() == pytest.approx((0.0, 1.0, 0.0))
        margin = 0.12 * FIGURE_SIZE
        low, high = snapshot.positions[0, 1:].min(axis=0) - margin, snapshot.positions[0, 1:].max(axis=0) + margin
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (low + high) / 2, atol=1e-9)
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)
        centroid = snapshot.positions[0, 1:].mean(axis=0)
        np.testing.assert_allclose(scene._followed, [centroid[0], -0.2, centroid[2]])
        scene.set_overlay("follow", False)
        scene.reset_camera()  # the whole motion: the ground's bounds
        low, high, floor = scene.ground_bounds
        assert floor == pytest.approx(-0.2)
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (low + high) / 2, atol=1e-9)
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)


def test_a_followed_figure_above_the_floor_is_framed_down_to_the_floor():
    world = figure_world()
    world[1, 1:, 1] += 2.0  # a jump at frame 1
    snapshot = snapshot_from(world)
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.show_frame(1)
        scene.reset_camera()
        margin = 0.12 * snapshot.motion.size
        low, high = world[1, 1:].min(axis=0) - margin, world[1, 1:].max(axis=0) + margin
        low[1] = -0.2  # the floor
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (low + high) / 2, atol=1e-9)
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)


def test_a_walk_is_seen_from_the_side_of_its_travel():
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:, 2] += 0.1 * np.arange(30)[:, None]  # walking 2.9 along +z (the size: 0.8)
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)
        # travel along z (either sign), the side: +x (the side whose coordinates sum positive)
        assert direction[0] > 0 and abs(direction[2]) == pytest.approx(0.3 * direction[0], abs=1e-6)
        assert direction[1] == pytest.approx(0.45 * direction[0], abs=1e-6)
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:, 0] -= 0.1 * np.arange(30)[:, None]  # walking along -x: seen from +z
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)
        assert direction[2] > 0 and abs(direction[0]) == pytest.approx(0.3 * direction[2], abs=1e-6)
        assert direction[1] == pytest.approx(0.45 * direction[2], abs=1e-6)
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:, 2] += 0.1 * np.arange(30)[:, None] * (np.arange(30)[:, None] < 5)  # 0.4 along z
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:  # no more than half the size: still
        np.testing.assert_allclose(view_direction(scene), unit([0.3, 0.45, 1.0]), atol=1e-9)


def test_a_z_up_figure_is_seen_with_z_up():
    world = figure_world()[..., [0, 2, 1]]
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        assert scene.up_axis == 2
        np.testing.assert_allclose(view_direction(scene), unit([0.3, 1.0, 0.45]), atol=1e-9)
        assert scene.plotter.camera.GetViewUp() == pytest.approx((0.0, 0.0, 1.0))
        np.testing.assert_allclose(scene._followed[2], world[0, 1:, 2].min())


def test_joints_that_nearly_coincide_are_framed_with_a_size_around_them():
    world = np.repeat(figure_world(1), 2, axis=0)
    world[:] = [0.3, 0.1, 0.2]  # every joint at one point
    snapshot = snapshot_from(world)
    size = snapshot.motion.size
    assert size == 1.0  # no extent: the size falls back to 1
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.set_overlay("follow", False)
        scene.reset_camera()
        low, high, _floor = scene.ground_bounds
        assert low == pytest.approx(high)
        low, high = low - 0.25 * size, high + 0.25 * size
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)


def test_following_moves_position_and_focal_point_by_the_figures_step():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera
        position, focal = np.array(camera.GetPosition()), np.array(camera.GetFocalPoint())
        scene.show_frame(2)
        np.testing.assert_allclose(np.array(camera.GetPosition()) - position, [0.1, 0, 0], atol=1e-9)
        np.testing.assert_allclose(np.array(camera.GetFocalPoint()) - focal, [0.1, 0, 0], atol=1e-9)
        scene._followed = None  # nowhere yet: the camera stays, the point is taken
        scene.show_frame(0)
        np.testing.assert_allclose(np.array(camera.GetPosition()) - position, [0.1, 0, 0], atol=1e-9)
        np.testing.assert_allclose(scene._followed[0], snapshot.positions[0, 1:, 0].mean())


def test_framing_a_joint_keeps_the_view_direction_at_the_distance_that_fits_the_reach():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.show_frame(2)
        direction = view_direction(scene)
        calls: list = []
        scene.request_repaint = lambda: calls.append(1)
        camera = scene.plotter.camera
        half = np.tan(np.radians(camera.GetViewAngle()) / 2)
        scene.frame_joint(3)
        np.testing.assert_allclose(camera.GetFocalPoint(), snapshot.positions[2, 3], atol=1e-12)
        np.testing.assert_allclose(view_direction(scene), direction, atol=1e-9)
        assert camera.GetDistance() == pytest.approx(0.5 * FIGURE_SIZE / 2 / half)
        assert calls == [1]
        scene.frame_joint(5, reach=2.0)
        assert camera.GetDistance() == pytest.approx(2.0 * FIGURE_SIZE / 2 / half)
        scene.frame_joint(None, reach=0.1)  # the whole figure: the middle of its box, fitted to the view
        pose = snapshot.positions[2, 1:]
        np.testing.assert_allclose(camera.GetFocalPoint(), (pose.min(axis=0) + pose.max(axis=0)) / 2, atol=1e-12)
        np.testing.assert_allclose(view_direction(scene), direction, atol=1e-9)
        x, y = scene.joint_screen_positions()[1:, :2].T
        assert (x > 0).all() and (x < WIDTH).all() and (y > 0).all() and (y < HEIGHT).all()
        assert max(np.ptp(x) / WIDTH, np.ptp(y) / HEIGHT) > 0.5  # fitted, not a speck
        centroid = snapshot.positions[2, 1:].mean(axis=0)
        np.testing.assert_allclose(scene._followed, [centroid[0], -0.2, centroid[2]])
        scene.set_overlay("follow", False)
        del calls[:]
        scene.frame_joint(3)
        assert scene._followed is None and calls == [1]


def test_without_a_document_the_camera_is_left_alone():
    with scene_of(None, size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera
        before = camera.GetPosition(), camera.GetFocalPoint()
        calls: list = []
        scene.request_repaint = lambda: calls.append(1)
        scene.reset_camera()
        scene.frame_joint(0)
        assert (camera.GetPosition(), camera.GetFocalPoint()) == before and calls == []
        assert scene.joint_screen_positions().shape == (0, 3)
        assert scene.joint_radius_pixels() == 0.0 and scene.pick_radius() == 8.0


def test_reset_camera_renders_once():
    with scene_of(snapshot_of(figure_motion()), size=(WIDTH, HEIGHT)) as scene:
        calls: list = []
        scene.request_repaint = lambda: calls.append(1)
        scene.plotter.camera.SetPosition(5.0, 5.0, 5.0)
        scene.reset_camera()
        np.testing.assert_allclose(view_direction(scene), unit([0.3, 0.45, 1.0]), atol=1e-9)
        assert calls == [1]


def pinhole(scene, points) -> np.ndarray:
    """(N, 2) pixels from the top left of ``points`` by the camera's own position and angle."""
    camera = scene.plotter.camera
    eye, focal, up = (np.asarray(v) for v in (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp()))
    back = unit(eye - focal)
    right = unit(np.cross(up, back))
    true_up = np.cross(back, right)
    relative = np.asarray(points) - eye
    depth = -relative @ back
    f = HEIGHT / 2 / np.tan(np.radians(camera.GetViewAngle()) / 2)
    return np.column_stack([WIDTH / 2 + f * (relative @ right) / depth, HEIGHT / 2 - f * (relative @ true_up) / depth])


def test_the_projection_is_the_cameras_pinhole_in_pixels():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        assert scene.viewport() == (WIDTH, HEIGHT)
        screen = scene.joint_screen_positions()
        assert screen.shape == (6, 3)
        np.testing.assert_allclose(screen[:, :2], pinhole(scene, snapshot.positions[0]), atol=1e-6)
        assert ((screen[:, 2] > -1) & (screen[:, 2] < 1)).all()
        scene.show_frame(2)
        np.testing.assert_allclose(
            scene.joint_screen_positions()[:, :2], pinhole(scene, snapshot.positions[2]), atol=1e-6
        )
        display = scene.display_positions(snapshot.positions[2])
        np.testing.assert_allclose(display[:, 0], scene.joint_screen_positions()[:, 0])
        np.testing.assert_allclose(display[:, 1], HEIGHT - scene.joint_screen_positions()[:, 1])
        camera = scene.plotter.camera
        eye, focal = np.array(camera.GetPosition()), np.array(camera.GetFocalPoint())
        _near, far = camera.GetClippingRange()
        behind, beyond = eye + (eye - focal), eye + (focal - eye) / np.linalg.norm(focal - eye) * 2 * far
        flat = scene.display_positions([behind, beyond, snapshot.positions[2, 3]])
        assert np.isnan(flat[:2]).all() and np.isfinite(flat[2]).all()
        assert scene.display_positions(snapshot.positions[2, 3]).shape == (1, 2)


def test_a_qt_widgets_size_is_the_viewport():
    widget = SimpleNamespace(size=lambda: SimpleNamespace(width=lambda: 90, height=lambda: 70), window_size=(180, 140))
    assert SceneCamera.viewport(SimpleNamespace(plotter=widget)) == (90, 70)  # logical pixels
    plain = SimpleNamespace(size=(180, 140), window_size=(np.int64(180), 140.0))
    assert SceneCamera.viewport(SimpleNamespace(plotter=plain)) == (180, 140)


def test_markers_project_only_while_shown():
    snapshot = snapshot_of(figure_motion())
    positions = np.repeat(np.array([[[0.1, 0.6, 0.0], [np.nan, np.nan, np.nan]]]), 3, axis=0)
    positions[2, 1] = snapshot.positions[2, 5]
    overlay = SimpleNamespace(positions=positions, markers=SimpleNamespace(labels=["HEAD", "HAND"]))
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        assert scene.marker_screen_positions().shape == (0, 3)
        scene.set_markers(overlay)
        screen = scene.marker_screen_positions()
        assert screen.shape == (2, 3) and np.isfinite(screen[0]).all() and np.isnan(screen[1]).all()
        np.testing.assert_allclose(screen[0, :2], pinhole(scene, positions[0, :1])[0], atol=1e-6)
        scene.show_frame(2)
        np.testing.assert_allclose(scene.marker_screen_positions()[1], scene.joint_screen_positions()[5], atol=1e-9)
        scene.set_overlay("markers", False)
        assert scene.marker_screen_positions().shape == (0, 3)


def test_a_joints_radius_on_screen_and_the_pick_radius():
    with scene_of(snapshot_of(figure_motion()), size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera
        camera.SetViewAngle(30.0)
        focal = np.array(camera.GetFocalPoint())
        camera.SetPosition(*(focal + np.array([0.0, 0.0, 0.1])))
        per_unit = HEIGHT / (2 * 0.1 * np.tan(np.radians(15.0)))
        radius = JOINT_RADIUS * FIGURE_SIZE * per_unit
        assert scene.joint_radius_pixels() == pytest.approx(radius) and radius > 8
        assert scene.pick_radius() == pytest.approx(1.5 * radius)
        camera.SetPosition(*(focal + np.array([0.0, 0.0, 100.0])))
        assert scene.joint_radius_pixels() == pytest.approx(radius / 1000)
        assert scene.pick_radius() == 8.0 and isinstance(scene.pick_radius(), float)


def test_display_pixels_keep_points_from_the_near_to_the_far_plane_exactly():
    """With the identity for the camera's matrix the clip coordinates are the points: depth
    -1 and 1 are the near and far planes, both drawn."""
    window = SimpleNamespace(GetSize=lambda: (100, 50))
    flat = SimpleNamespace(plotter=SimpleNamespace(render_window=window), view_projection=lambda: np.eye(4))
    flat.display_size = lambda: SceneCamera.display_size(flat)
    points = np.array([[0.0, 0.0, -1.0], [1.0, 1.0, 1.0], [-1.0, -0.5, 0.0], [0.0, 0.0, 1.000001], [0.0, 0.0, -1.01]])
    xy = SceneCamera.display_positions(flat, points)
    # x right from the left edge, y up from the bottom
    np.testing.assert_allclose(xy[:3], [[50.0, 25.0], [100.0, 50.0], [0.0, 12.5]])
    assert np.isnan(xy[3:]).all()


def test_the_projection_of_a_view_one_pixel_high_or_less():
    with scene_of(None, size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera

        def matrix(width, height):
            view = SimpleNamespace(plotter=scene.plotter, viewport=lambda: (width, height))
            return SceneCamera.view_projection(view)

        def expected(aspect):
            vtk = camera.GetCompositeProjectionTransformMatrix(aspect, -1, 1)
            return np.array([[vtk.GetElement(i, j) for j in range(4)] for i in range(4)])

        np.testing.assert_allclose(matrix(100, 1), expected(100.0))
        np.testing.assert_allclose(matrix(100, 0), expected(100.0))
        np.testing.assert_allclose(matrix(100, 4), expected(25.0))


def test_a_camera_at_its_focal_point_gives_a_joint_no_radius():
    camera = SimpleNamespace(GetViewAngle=lambda: 30.0, GetDistance=lambda: 0.0)
    view = SimpleNamespace(
        snapshot=snapshot_of(figure_motion()), viewport=lambda: (100, 100), plotter=SimpleNamespace(camera=camera)
    )
    assert SceneCamera.joint_radius_pixels(view) == 0.0


def test_a_walk_of_two_frames_is_seen_from_the_side_of_its_travel():
    world = np.repeat(figure_world(1), 2, axis=0)
    world[1, 1:, 2] += 1.0  # half a step each side of the mean: more than half the size (0.8)
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)
        assert direction[0] > 0 and abs(direction[2]) == pytest.approx(0.3 * direction[0], abs=1e-6)


def test_a_figure_away_from_the_origin_is_framed_at_its_own_corners():
    world = figure_world() + np.array([3.0, 0.0, -2.0])
    snapshot = snapshot_from(world)
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        margin = 0.12 * FIGURE_SIZE
        low, high = world[0, 1:].min(axis=0) - margin, world[0, 1:].max(axis=0) + margin
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (low + high) / 2, atol=1e-9)
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)


def test_a_figure_that_grows_from_a_point_is_framed_with_a_size_around_it_while_a_point():
    world = np.repeat(figure_world(1) * 2.5, 2, axis=0)  # frame 1: the figure, 2.0 high
    world[0, 1:] = [0.3, world[1, 1:, 1].min(), 0.0]  # frame 0: its joints at one point on the floor
    snapshot = snapshot_from(world)
    size = snapshot.motion.size
    assert size == pytest.approx(2.0)
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:  # following, at frame 0
        point = world[0, 1]
        low, high = point - 0.12 * size - 0.25 * size, point + 0.12 * size + 0.25 * size
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (low + high) / 2, atol=1e-9)
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)


def test_the_side_looked_from_is_the_one_whose_coordinates_sum_positive():
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:] += 0.1 * np.arange(30)[:, None, None] * np.array([0.8, 0.0, 0.6])  # a walk along (0.8, 0, 0.6)
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)  # side (-0.6, 0, 0.8): its sum 0.2, the other's -0.2
        np.testing.assert_allclose(direction @ [-0.6, 0.0, 0.8], 1.0 / np.linalg.norm([1.0, 0.3, 0.45]), atol=1e-6)


def test_a_view_of_no_height_is_not_zoomed():
    with scene_of(snapshot_of(figure_motion()), size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera
        assert camera.GetViewAngle() < 29.0  # zoomed in from the reset's 30 degrees
        scene.viewport = lambda: (WIDTH, 0)  # a widget not laid out yet
        scene.reset_camera()
        assert camera.GetViewAngle() == pytest.approx(30.0)  # the reset's own angle, not zoomed
        scene.viewport = lambda: (WIDTH, 1)
        scene.reset_camera()
        assert camera.GetViewAngle() < 29.0
        scene.viewport = lambda: (1, HEIGHT)  # a collapsed widget: the box far too wide for it
        scene.reset_camera()
        assert camera.GetViewAngle() == pytest.approx(60.0)  # zoomed out twofold at most


def test_a_long_walk_in_a_wide_view_is_zoomed_at_most_fourfold():
    world = np.repeat(figure_world(1), 100, axis=0)
    world[:, 1:, 0] += 0.1 * np.arange(100)[:, None]  # 9.9 along x: a thin box across a wide view
    with scene_of(snapshot_from(world), size=(800, 100)) as scene:
        scene.set_overlay("follow", False)
        scene.reset_camera()
        assert scene.plotter.camera.GetViewAngle() == pytest.approx(30.0 / 4.0)  # zoom divides the angle


EIGHTHS = np.array(
    [[0.0, -1.0, 0.0], [0.0, -0.25, 0.0], [0.0, 0.25, 0.0], [0.0, 0.75, 0.0], [0.5, 0.25, 0.0], [1.0, 0.25, 0.0]]
)  # the figure in exact binary fractions: size 1 exactly


def walked(travel, up: int = 1, n_frames: int = 30) -> np.ndarray:
    """(F, 6, 3) the exact figure walking 0.1 a frame along ``travel`` (its height along ``up``)."""
    rest = EIGHTHS if up == 1 else EIGHTHS[:, [0, 2, 1]]
    world = np.repeat(rest[None], n_frames, axis=0)
    world[:, 1:] += 0.1 * np.arange(n_frames)[:, None, None] * np.asarray(travel)
    return world


@pytest.mark.parametrize(
    ("up", "travel", "side"),
    [
        (1, (0.6, 0.0, 0.8), (0.8, 0.0, -0.6)),
        (2, (0.6, 0.8, 0.0), (0.8, -0.6, 0.0)),
        (2, (0.8, 0.6, 0.0), (-0.6, 0.8, 0.0)),
    ],
)
def test_the_side_of_a_walk_is_the_one_whose_coordinates_sum_positive(up, travel, side):
    with scene_of(snapshot_from(walked(travel, up)), size=(WIDTH, HEIGHT)) as scene:
        assert scene.up_axis == up
        np.testing.assert_allclose(view_direction(scene) @ side, 1.0 / np.linalg.norm([1.0, 0.3, 0.45]), atol=1e-6)


def test_a_spread_of_exactly_half_the_size_is_standing_still():
    world = np.repeat(EIGHTHS[None], 2, axis=0)
    world[1, 1:, 2] += 1.0  # the path's centroid 0.5 either side of its mean: half the size exactly
    snapshot = snapshot_from(world)
    assert snapshot.motion.size == 1.0
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        np.testing.assert_allclose(view_direction(scene), unit([0.3, 0.45, 1.0]), atol=1e-9)


def test_a_box_of_exactly_half_the_size_is_not_widened():
    world = np.repeat(EIGHTHS[None] * 2.0, 2, axis=0)  # frame 1: the figure, size 2, floor -0.5
    world[0, 1:] = [0.5, 0.26, 0.0]  # frame 0: one point; with its margin 0.24, 1.0 above the floor
    snapshot = snapshot_from(world)
    assert snapshot.motion.size == 2.0
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:  # following, at frame 0
        low, high = np.array([0.26, -0.5, -0.24]), np.array([0.74, 0.5, 0.24])
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), (low + high) / 2, atol=1e-9)
        assert reach_of(scene, low, high) == pytest.approx(0.9, abs=0.015)


def test_display_size_is_the_render_windows_and_display_positions_use_it():
    """The display pixels' range is the render window's size; a point projected at a view
    wider than high lands where the camera's matrix puts it."""
    with scene_of(snapshot_of(figure_motion()), size=(WIDTH, HEIGHT)) as scene:
        assert scene.display_size() == (WIDTH, HEIGHT)
        assert all(type(v) is int for v in scene.display_size())
        point = scene.snapshot.positions[0, :1]
        clip = np.append(point[0], 1.0) @ scene.view_projection().T
        ndc = clip[:2] / clip[3]
        expected = [(ndc[0] + 1) / 2 * WIDTH, (ndc[1] + 1) / 2 * HEIGHT]
        np.testing.assert_allclose(scene.display_positions(point), [expected], atol=1e-6)
