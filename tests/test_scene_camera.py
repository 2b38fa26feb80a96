"""The scene's camera (app/scene/camera.py) on the tiny synthetic skeleton (:mod:`tests.tiny_scene`),
judged by what the view shows: a new document is seen from the side of its travel, a little
from the front and above, the figure and the floor under it filling most of the view; a
followed figure stays put on screen as it moves; framing a joint puts it at the centre at
the asked reach; and the world -> screen projection that picking and the labels use is the
camera's own pinhole."""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from gmr_studio.app.scene.camera import actor_positions
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


def unit(vector) -> np.ndarray:
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def view_direction(scene) -> np.ndarray:
    """(3,) unit vector from the focal point to the camera."""
    camera = scene.plotter.camera
    return unit(np.asarray(camera.GetPosition()) - np.asarray(camera.GetFocalPoint()))


def on_screen(scene, points) -> np.ndarray:
    """(N, 2) where ``points`` are in the view, from -1 to 1 across its width and height."""
    screen = project_points(np.asarray(points, dtype=float).reshape(-1, 3), scene.view_projection(), scene.viewport())
    width, height = scene.viewport()
    return np.column_stack([screen[:, 0] / width * 2 - 1, screen[:, 1] / height * 2 - 1])


def floor_point(scene, frame: int) -> np.ndarray:
    """(3,) the figure's centre at ``frame`` on the floor."""
    point = actor_positions(scene.snapshot)[frame].mean(axis=0)
    point[scene.up_axis] = scene.ground_bounds[2]
    return point


def assert_fills_the_view(scene, points, least: float = 0.55) -> None:
    """``points`` all in view, reaching at least ``least`` of the way to its edges, around its centre."""
    xy = on_screen(scene, points)
    assert np.abs(xy).max() <= 0.97, "a point is cut off at the view's edge"
    assert np.abs(xy).max() >= least, f"the points fill only {np.abs(xy).max():.0%} of the view"
    centre = (xy.min(axis=0) + xy.max(axis=0)) / 2
    assert np.abs(centre).max() <= 0.2, "the points are not around the view's centre"


def corners(low, high) -> np.ndarray:
    """(8, 3) the corners of the box from ``low`` to ``high``."""
    return np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])


def assert_seen_from_the_side_front_and_above(direction, side, front, up) -> None:
    """Mostly from ``side``, a little from ``front`` and from above."""
    along_side, along_front, along_up = direction @ side, direction @ front, direction @ up
    assert along_side > 0.7 and 0.0 < along_front < along_side and 0.0 < along_up < along_side


def test_the_actors_positions_leave_out_the_anchor_only():
    snapshot = snapshot_of(figure_motion())
    np.testing.assert_array_equal(actor_positions(snapshot), snapshot.positions[:, 1:])
    world = figure_world()
    world[:, 0, 0] += 0.05 * np.arange(3)  # the Root moves too: no anchor
    free = snapshot_from(world)
    assert actor_positions(free) is free.positions


# ---------------------------------------------------------------- a new document
def test_a_standing_figure_is_seen_from_its_side_front_and_above_filling_the_view():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        x, y, z = np.eye(3)  # standing still: the skeleton's default front, +x
        assert_seen_from_the_side_front_and_above(view_direction(scene), z, x, y)
        assert scene.plotter.camera.GetViewUp() == pytest.approx((0.0, 1.0, 0.0))
        # following: the figure at this frame and the floor under it fill the view
        assert_fills_the_view(scene, [*snapshot.positions[0, 1:], floor_point(scene, 0)])
        scene.set_overlay("follow", False)
        scene.reset_camera()  # the whole motion: the ground's box fills most of the view
        low, high, floor = scene.ground_bounds
        assert floor == pytest.approx(-0.2)
        assert_fills_the_view(scene, [*snapshot.positions[:, 1:].reshape(-1, 3), *corners(low, high)], least=0.8)


def test_a_figure_above_the_floor_is_framed_down_to_the_floor():
    world = figure_world()
    world[1, 1:, 1] += 2.0  # a jump at frame 1
    snapshot = snapshot_from(world)
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.show_frame(1)
        scene.reset_camera()
        assert_fills_the_view(scene, [*world[1, 1:], floor_point(scene, 1)])


def test_a_figure_away_from_the_origin_is_framed_where_it_is():
    world = figure_world() + np.array([3.0, 0.0, -2.0])
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        assert_fills_the_view(scene, world[0, 1:])


def test_a_walk_is_seen_from_the_side_of_its_travel_and_crosses_the_view():
    x, y, z = np.eye(3)
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:, 2] += 0.1 * np.arange(30)[:, None]  # walking 2.9 along +z (the size: 0.8)
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)  # a little along the travel, either way
        assert_seen_from_the_side_front_and_above(direction * [1, 1, np.sign(direction[2])], x, z, y)
        scene.set_overlay("follow", False)
        scene.reset_camera()  # the whole walk's box fills most of the view
        assert_fills_the_view(scene, corners(*scene.ground_bounds[:2]), least=0.8)
        start, end = on_screen(scene, [world[0, 1:].mean(axis=0), world[-1, 1:].mean(axis=0)])
        assert abs(end[0] - start[0]) > 1.0 and abs(end[1] - start[1]) < 0.5  # across the screen
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:, 0] -= 0.1 * np.arange(30)[:, None]  # walking along -x: seen from +z
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)  # a little along the travel, either way
        assert_seen_from_the_side_front_and_above(direction * [np.sign(direction[0]), 1, 1], z, x, y)


def test_a_walk_of_two_frames_is_seen_from_the_side_of_its_travel():
    world = np.repeat(figure_world(1), 2, axis=0)
    world[1, 1:, 2] += 1.0  # more than the figure's size between the two frames
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)
        assert abs(direction[0]) > 0.7 and abs(direction[2]) < abs(direction[0])


def test_a_sway_on_the_spot_is_standing_still():
    world = np.repeat(figure_world(1), 30, axis=0)
    world[:, 1:, 2] += 0.1 * np.arange(30)[:, None] * (np.arange(30)[:, None] < 3)  # 0.2 along z: a sway
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        x, y, z = np.eye(3)
        assert_seen_from_the_side_front_and_above(view_direction(scene), z, x, y)


@pytest.mark.parametrize(("up", "travel"), [(1, (0.6, 0.0, 0.8)), (2, (0.6, 0.8, 0.0)), (2, (0.8, 0.6, 0.0))])
def test_a_walk_and_its_reverse_are_seen_from_the_same_side(up, travel):
    rest = figure_world(1)[0] if up == 1 else figure_world(1)[0][:, [0, 2, 1]]
    directions = []
    for sign in (1.0, -1.0):
        world = np.repeat(rest[None], 30, axis=0)
        world[:, 1:] += sign * 0.1 * np.arange(30)[:, None, None] * np.asarray(travel)
        with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
            assert scene.up_axis == up
            directions.append(view_direction(scene))
    upward = np.eye(3)[up]
    side = unit(np.cross(upward, travel))
    for direction in directions:
        assert abs(direction @ side) > 0.7  # from the side of the travel
    assert directions[0] @ side * (directions[1] @ side) > 0  # the same side both ways


def test_a_z_up_figure_is_seen_with_z_up():
    world = figure_world()[..., [0, 2, 1]]
    with scene_of(snapshot_from(world), size=(WIDTH, HEIGHT)) as scene:
        assert scene.up_axis == 2
        x, y, z = np.eye(3)
        assert_seen_from_the_side_front_and_above(view_direction(scene), y * np.sign(view_direction(scene)[1]), x, z)
        assert scene.plotter.camera.GetViewUp() == pytest.approx((0.0, 0.0, 1.0))
        head, hips = on_screen(scene, world[0, [3, 1]])
        assert head[1] < hips[1]  # the head above the hips on screen (y down)


def test_joints_that_coincide_are_framed_with_a_size_around_them():
    world = np.repeat(figure_world(1), 2, axis=0)
    world[:] = [3.0, 0.1, -2.0]  # every joint at one point, away from the origin
    snapshot = snapshot_from(world)
    size = snapshot.motion.size
    assert size == 1.0  # no extent: the size falls back to 1
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.set_overlay("follow", False)
        scene.reset_camera()
        assert np.isfinite(scene.plotter.camera.GetPosition()).all()
        around = [world[0, 0] + d * size for d in np.array([[-0.25, 0, 0], [0.25, 0, 0], [0, 0.25, 0], [0, -0.25, 0]])]
        assert_fills_the_view(scene, around, least=0.3)
        np.testing.assert_allclose(on_screen(scene, world[0, 0]), [[0.0, 0.0]], atol=0.02)  # at the centre


def test_a_figure_that_grows_from_a_point_is_framed_around_the_point_first():
    world = np.repeat(figure_world(1) * 2.5, 2, axis=0)  # frame 1: the figure, 2.0 high
    world[0, 1:] = [0.3, world[1, 1:, 1].min(), 0.0]  # frame 0: its joints at one point on the floor
    snapshot = snapshot_from(world)
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:  # following, at frame 0
        size = snapshot.motion.size
        around = [world[0, 1] + d * size for d in np.array([[-0.25, 0, 0], [0.25, 0, 0], [0, 0.25, 0]])]
        assert_fills_the_view(scene, [world[0, 1], *around], least=0.3)
        x, _ = on_screen(scene, world[0, 1])[0]
        assert abs(x) < 0.05  # the point (on the floor) across the view's middle


# --------------------------------------------------------------------- following
def test_a_followed_figure_stays_put_on_screen_as_it_moves():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera
        position, focal = np.array(camera.GetPosition()), np.array(camera.GetFocalPoint())
        first = on_screen(scene, floor_point(scene, 0))
        scene.show_frame(2)  # the figure moved 0.1 along x, the camera with it
        np.testing.assert_allclose(on_screen(scene, floor_point(scene, 2)), first, atol=1e-9)
        np.testing.assert_allclose(np.array(camera.GetPosition()) - position, [0.1, 0, 0], atol=1e-9)
        np.testing.assert_allclose(np.array(camera.GetFocalPoint()) - focal, [0.1, 0, 0], atol=1e-9)
        scene.set_overlay("follow", False)
        scene.show_frame(0)  # not followed: the camera stays, the figure moves on screen
        np.testing.assert_allclose(np.array(camera.GetFocalPoint()) - focal, [0.1, 0, 0], atol=1e-9)
        scene.set_overlay("follow", True)  # from where the figure is now: no jump
        np.testing.assert_allclose(np.array(camera.GetFocalPoint()) - focal, [0.1, 0, 0], atol=1e-9)
        here = on_screen(scene, floor_point(scene, 0))
        scene.show_frame(1)
        np.testing.assert_allclose(np.array(camera.GetFocalPoint()) - focal, [0.15, 0, 0], atol=1e-9)
        np.testing.assert_allclose(on_screen(scene, floor_point(scene, 1)), here, atol=1e-9)


def test_a_new_document_shorter_than_the_frame_is_framed_at_its_last_frame():
    with scene_of(snapshot_of(figure_motion(6)), size=(WIDTH, HEIGHT)) as scene:
        scene.show_frame(5)
        shorter = snapshot_of(figure_motion(3))
        scene.set_snapshot(shorter, reset_camera=True)  # following: framed at frame 2
        assert scene.frame == 2
        assert_fills_the_view(scene, [*shorter.positions[2, 1:], floor_point(scene, 2)])
        here = on_screen(scene, floor_point(scene, 2))
        scene.show_frame(0)  # followed from frame 2: the figure stays put
        np.testing.assert_allclose(on_screen(scene, floor_point(scene, 0)), here, atol=1e-9)


# ----------------------------------------------------------------- framing a joint
def height_filled(scene, point, length: float) -> float:
    """The share of the view's height a segment of ``length`` through ``point``, upright on
    screen, spans."""
    direction = view_direction(scene)
    up = np.asarray(scene.plotter.camera.GetViewUp())
    up = unit(up - (up @ direction) * direction)  # upright on screen: square to the view direction
    ends = on_screen(scene, [point - up * length / 2, point + up * length / 2])
    return abs(ends[1, 1] - ends[0, 1]) / 2


def test_framing_a_joint_puts_it_at_the_centre_at_the_reach_asked():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.show_frame(2)
        direction = view_direction(scene)
        scene.frame_joint(3)  # half the figure's size around the head fills the view's height
        head = snapshot.positions[2, 3]
        np.testing.assert_allclose(scene.plotter.camera.GetFocalPoint(), head, atol=1e-12)
        np.testing.assert_allclose(on_screen(scene, head), [[0.0, 0.0]], atol=1e-9)
        np.testing.assert_allclose(view_direction(scene), direction, atol=1e-9)  # from where it looked
        assert height_filled(scene, head, 0.5 * FIGURE_SIZE) == pytest.approx(1.0, rel=1e-6)
        scene.frame_joint(5, reach=2.0)
        assert height_filled(scene, snapshot.positions[2, 5], 2.0 * FIGURE_SIZE) == pytest.approx(1.0, rel=1e-6)
        scene.frame_joint(None, reach=0.1)  # the whole figure: the middle of its box, fitted to the view
        pose = snapshot.positions[2, 1:]
        np.testing.assert_allclose(on_screen(scene, (pose.min(axis=0) + pose.max(axis=0)) / 2), [[0, 0]], atol=1e-9)
        np.testing.assert_allclose(view_direction(scene), direction, atol=1e-9)
        joints = on_screen(scene, pose)
        assert (np.abs(joints) < 1).all()  # every joint in the view
        assert np.ptp(joints, axis=0).max() > 1.0  # and fitted: more than half the view, not a speck
        here = on_screen(scene, floor_point(scene, 2))
        scene.show_frame(0)  # a followed camera keeps following from the joint framed
        np.testing.assert_allclose(on_screen(scene, floor_point(scene, 0)), here, atol=1e-9)
        scene.set_overlay("follow", False)
        scene.frame_joint(3)
        focal = scene.plotter.camera.GetFocalPoint()
        scene.show_frame(2)  # not followed: it stays on the joint's old place
        assert scene.plotter.camera.GetFocalPoint() == pytest.approx(focal)


def test_without_a_document_the_camera_is_left_alone():
    with scene_of(None, size=(WIDTH, HEIGHT)) as scene:
        camera = scene.plotter.camera
        before = camera.GetPosition(), camera.GetFocalPoint()
        scene.reset_camera()
        scene.frame_joint(0)
        assert (camera.GetPosition(), camera.GetFocalPoint()) == before
        assert scene.joint_screen_positions().shape == (0, 3)
        assert scene.joint_radius_pixels() == 0.0 and scene.pick_radius() == 8.0


@pytest.mark.parametrize("size", [(WIDTH, 0), (0, HEIGHT)])
def test_a_view_not_laid_out_yet_keeps_a_usable_camera(size):
    """A widget is 0 pixels high or wide until Qt lays it out: a reset then leaves a finite
    camera, and the figure is framed once the view has its size."""
    with scene_of(snapshot_of(figure_motion()), size=(WIDTH, HEIGHT)) as scene:
        laid_out = scene.viewport
        scene.viewport = lambda: size  # the view's size as such a widget reports it
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)  # nothing divided by the missing size
            scene.reset_camera()
        camera = scene.plotter.camera
        assert np.isfinite([*camera.GetPosition(), *camera.GetFocalPoint(), camera.GetViewAngle()]).all()
        scene.viewport = laid_out
        scene.reset_camera()
        assert_fills_the_view(scene, [*scene.snapshot.positions[0, 1:], floor_point(scene, 0)])


def test_reset_camera_brings_back_the_view_of_a_new_document():
    with scene_of(snapshot_of(figure_motion()), size=(WIDTH, HEIGHT)) as scene:
        direction = view_direction(scene)
        scene.plotter.camera.SetPosition(5.0, 5.0, 5.0)
        scene.reset_camera()
        np.testing.assert_allclose(view_direction(scene), direction, atol=1e-9)


# -------------------------------------------------------------------- projection
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


def test_display_pixels_are_from_the_bottom_left_and_nothing_behind_the_camera_or_past_the_far_plane():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot, size=(WIDTH, HEIGHT)) as scene:
        scene.show_frame(2)
        assert scene.display_size() == (WIDTH, HEIGHT)
        assert all(type(v) is int for v in scene.display_size())
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
        near, far = camera.GetClippingRange()  # drawn between the near and far planes only
        ahead = (focal - eye) / np.linalg.norm(focal - eye)
        at = scene.display_positions([eye + d * ahead for d in (0.85 * near, 1.05 * near, 0.95 * far, 1.05 * far)])
        assert np.isnan(at[0]).all() and np.isfinite(at[1:3]).all() and np.isnan(at[3]).all()


def test_display_pixels_follow_the_render_windows_size():
    with scene_of(snapshot_of(figure_motion()), size=(2 * WIDTH, HEIGHT)) as scene:
        point = scene.snapshot.positions[0, :1]
        clip = np.append(point[0], 1.0) @ scene.view_projection().T
        ndc = clip[:2] / clip[3]
        expected = [(ndc[0] + 1) / 2 * 2 * WIDTH, (ndc[1] + 1) / 2 * HEIGHT]
        np.testing.assert_allclose(scene.display_positions(point), [expected], atol=1e-6)


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
