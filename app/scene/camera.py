"""The scene's camera and the view's projection, a part of :class:`~app.scene.scene.SkeletonScene`.

:class:`SceneCamera` is the camera half of the scene (a base class, no state of its own):
where the camera stands for a new document (:meth:`SceneCamera._reset_camera`: from the
side of the motion's main direction of travel), following the figure, framing a joint, and
the world -> screen projection that picking, labels and the markers' hover use. It reads the
scene's ``plotter``, ``snapshot``, ``frame``, ``overlays``, ``up_axis``, ``ground_bounds``,
``markers`` and ``_followed``, and calls its ``render``.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv

from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene.figure import JOINT_RADIUS
from gmr_studio.app.scene.picking import project_points
from gmr_studio.core.space.heading import travel_axis


def actor_positions(snapshot: Snapshot) -> np.ndarray:
    """(F, A, 3) world positions of the joints that make the figure: all but the
    :attr:`~core.model.motion.Motion.anchors` (a root pinned at the origin far from the actor)."""
    anchors = snapshot.motion.anchors
    return snapshot.positions[:, ~anchors] if anchors.any() else snapshot.positions


#: the share of the view's half width or height a fitted box reaches (:meth:`SceneCamera.fit_box`)
FIT_FILL = 0.9
FIT_STEPS = 4  # refinements of a fitted box's distance (perspective makes it a fixed point)
#: frames of the take the camera's travel fit looks at, at most (evenly spread over it)
TRAVEL_SAMPLES = 2000


class SceneCamera:
    """The camera and projection methods of :class:`~app.scene.scene.SkeletonScene` (see the module)."""

    def display_positions(self, points: np.ndarray) -> np.ndarray:
        """(N, 2) display pixels (x right, y up from the bottom left of the render window)
        of world ``points`` (N, 3) under the current camera; NaN for points behind it."""
        width, height = self.display_size()
        screen = project_points(
            np.asarray(points, dtype=np.float64).reshape(-1, 3), self.view_projection(), (width, height)
        )
        behind = ~((screen[:, 2] >= -1) & (screen[:, 2] <= 1))
        xy = np.column_stack([screen[:, 0], height - screen[:, 1]])
        xy[behind] = np.nan
        return xy

    def display_size(self) -> tuple[int, int]:
        """(width, height) pixels of the render window: the display pixels' range."""
        width, height = self.plotter.render_window.GetSize()
        return int(width), int(height)

    def _follow_point(self, frame: int) -> np.ndarray:
        """(3,) the point the camera follows: the joints' centroid, on the floor."""
        point = self.snapshot.positions[frame, ~self.snapshot.motion.anchors].mean(axis=0)
        point[self.up_axis] = self.ground_bounds[2]
        return point

    def _reset_camera(self) -> None:
        """Look from the side of the motion's main direction of travel (a walk crosses the
        screen), a little from the front and above, up the detected up axis; frame the
        figure at this frame when following it, else the whole motion."""
        low, high, floor = self.ground_bounds
        if self.overlays.get("follow"):
            points = self.snapshot.positions[self.frame, ~self.snapshot.motion.anchors]
            margin = 0.12 * self.snapshot.motion.size
            low, high = points.min(axis=0) - margin, points.max(axis=0) + margin
            low[self.up_axis] = min(low[self.up_axis], floor)
            self._followed = self._follow_point(self.frame)
        size = self.snapshot.motion.size
        if np.ptp(np.stack([low, high]), axis=0).max() < 0.5 * size:  # the joints (nearly) coincide
            low, high = low - 0.25 * size, high + 0.25 * size  # frame a size around them, not a point
        up_axis = self.up_axis
        up = np.eye(3)[up_axis]
        # the one travel fit (core.space.heading) on frames spread over the take; moving less
        # than half a size is standing still
        anchors = self.snapshot.motion.anchors
        figure = ~anchors if anchors.any() else None
        travel = travel_axis(self.snapshot.positions, up_axis, figure, still_below=0.5 * size, samples=TRAVEL_SAMPLES)
        side = np.cross(up, travel)
        if side @ np.array([1.0, 1.0, 1.0]) < 0:
            side = -side
        direction = side * 1.0 + travel * 0.3 + up * 0.45
        centre = (low + high) / 2
        self.plotter.camera_position = [tuple(centre + direction), tuple(centre), tuple(up)]
        # the renderer's, not the plotter's: that one also draws the scene, before the frame is set
        self.plotter.renderer.reset_camera(render=False, bounds=np.column_stack([low, high]).ravel())
        # reset_camera fits a bounding sphere, loose for a long path: zoom until the box's
        # corners fill 90% of the view
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
        width, height = self.viewport()
        screen = project_points(corners, self.view_projection(), (width, height))
        if np.isfinite(screen).all() and width > 0 and height > 0:
            reach = max(np.abs(screen[:, 0] / width * 2 - 1).max(), np.abs(screen[:, 1] / height * 2 - 1).max())
            if reach > 0:
                self.plotter.camera.zoom(float(np.clip(0.9 / reach, 0.5, 4.0)))

    def _follow(self, frame: int) -> None:
        """Move the camera along with the figure (horizontally), keeping its view direction."""
        point = self._follow_point(frame)
        if self._followed is not None:
            delta = point - self._followed
            camera = self.plotter.camera  # VTK's setters: pyvista's also refit the clipping range, as render does
            camera.SetPosition(*(np.asarray(camera.GetPosition()) + delta))
            camera.SetFocalPoint(*(np.asarray(camera.GetFocalPoint()) + delta))
        self._followed = point

    def turn_with_the_world(self, rotation: np.ndarray) -> None:
        """Turn the camera (its position, focal point and up) by ``rotation`` (3, 3), as an
        edit turned the world (a new up axis): the figure is seen as it was."""
        camera = self.plotter.camera
        for get, put in (
            (camera.GetPosition, camera.SetPosition),
            (camera.GetFocalPoint, camera.SetFocalPoint),
            (camera.GetViewUp, camera.SetViewUp),
        ):
            put(*(rotation @ np.asarray(get())))
        if self._followed is not None:
            self._followed = rotation @ self._followed

    def reset_camera(self) -> None:
        if self.snapshot is not None:
            self._reset_camera()
            self.render()

    def frame_joint(self, joint: int | None, reach: float = 0.5) -> None:
        """Look at ``joint`` at this frame from where the camera looks now, near enough that
        ``reach`` times the motion's size around it fills the view's height; None: the whole
        figure at this frame, its box fitted to the view as it now is (:meth:`fit_box`:
        whatever room the docks leave it). A followed camera keeps following."""
        if self.snapshot is None:
            return
        size = self.snapshot.motion.size
        if joint is None:
            points = self.snapshot.positions[self.frame, ~self.snapshot.motion.anchors]
            pad = JOINT_RADIUS * size
            self.fit_box(points.min(axis=0) - pad, points.max(axis=0) + pad)
        else:
            point = self.snapshot.positions[self.frame, joint]
            camera = self.plotter.camera
            distance = reach * size / 2 / np.tan(np.radians(camera.GetViewAngle()) / 2)
            self._look_at(point, distance)
        if self.overlays.get("follow"):
            self._followed = self._follow_point(self.frame)
        self.render()

    def fit_box(self, low: np.ndarray, high: np.ndarray, fill: float = FIT_FILL) -> None:
        """Look at the box ``low``-``high`` (world points (3,)) from where the camera looks
        now, from the distance at which its corners reach ``fill`` of the view's half width
        or half height, whichever they reach first, in the view's present size.

        The box is centred on its middle point, not on the joints' centroid: a rig whose
        joints crowd the head (a face of 185 points) would otherwise have its feet fall
        below the view. The distance is refined from the projected corners (they shrink as
        one over the distance), a few times for the perspective."""
        camera = self.plotter.camera
        centre = (np.asarray(low, dtype=np.float64) + np.asarray(high, dtype=np.float64)) / 2
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
        radius = max(float(np.linalg.norm(np.asarray(high) - np.asarray(low))) / 2, 1e-9)
        distance = radius / np.sin(np.radians(camera.GetViewAngle()) / 2)  # its sphere inside the view
        width, height = self.viewport()
        for _ in range(FIT_STEPS):
            self._look_at(centre, distance)
            screen = project_points(corners, self.view_projection(), (width, height))
            if not np.isfinite(screen).all() or width <= 0 or height <= 0:
                return
            reach = max(np.abs(screen[:, 0] / width * 2 - 1).max(), np.abs(screen[:, 1] / height * 2 - 1).max())
            distance = max(distance * reach / fill, radius * 1.01)  # never inside the box

    def _look_at(self, point: np.ndarray, distance: float) -> None:
        """Put the focal point at ``point`` and the camera ``distance`` from it, along the
        direction it looks from now."""
        camera = self.plotter.camera
        direction = np.asarray(camera.GetPosition()) - np.asarray(camera.GetFocalPoint())
        direction /= max(np.linalg.norm(direction), 1e-12)
        camera.SetFocalPoint(*point)
        camera.SetPosition(*(point + distance * direction))

    # ------------------------------------------------------------------- picking
    def view_projection(self) -> np.ndarray:
        """(4, 4) world -> clip matrix of the current camera."""
        width, height = self.viewport()
        matrix = self.plotter.camera.GetCompositeProjectionTransformMatrix(width / max(height, 1), -1, 1)
        return pv.array_from_vtkmatrix(matrix)

    def viewport(self) -> tuple[int, int]:
        """(width, height) of the view in the units of mouse events (logical pixels)."""
        widget_size = getattr(self.plotter, "size", None)
        if callable(widget_size):  # a Qt widget: logical pixels
            return widget_size().width(), widget_size().height()
        width, height = self.plotter.window_size
        return int(width), int(height)

    def joint_screen_positions(self) -> np.ndarray:
        """(J, 3) pixel x, y (from the top left) and depth of every joint at this frame."""
        if self.snapshot is None:
            return np.zeros((0, 3))
        return project_points(self.snapshot.positions[self.frame], self.view_projection(), self.viewport())

    def marker_screen_positions(self) -> np.ndarray:
        """(M, 3) like :meth:`joint_screen_positions`, NaN for markers missing at this frame."""
        if self.markers is None or not self.overlays["markers"]:
            return np.zeros((0, 3))
        return project_points(self.markers.positions[self.frame], self.view_projection(), self.viewport())

    def joint_radius_pixels(self) -> float:
        """A joint sphere's radius on screen, in pixels, at the camera's distance."""
        if self.snapshot is None:
            return 0.0
        _width, height = self.viewport()
        angle = np.radians(self.plotter.camera.GetViewAngle())
        distance = self.plotter.camera.GetDistance()
        pixels_per_unit = height / (2 * distance * np.tan(angle / 2)) if distance > 0 else 0.0
        return float(JOINT_RADIUS * self.snapshot.motion.size * pixels_per_unit)

    def pick_radius(self) -> float:
        """Pixels within which a click picks a joint: a joint's drawn radius, at least 8."""
        return float(max(8.0, 1.5 * self.joint_radius_pixels()))
