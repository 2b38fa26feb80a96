"""The 3D scene: a skeleton forest and its overlays in a PyVista plotter (no Qt here).

Actors are built once per motion (:meth:`SkeletonScene.set_snapshot`); a frame only writes
coordinates from the state's caches into the existing point arrays and renders once
(:meth:`SkeletonScene.show_frame`). An edit rebuilds the actors in place and never moves
the camera: positions are invariant under the operations, so the skeleton stays exactly
where it was while its colours, root marks and soft links change.

What is drawn (sizes are fractions of ``Motion.size``, so any unit works):

- joints as spheres, each tree of the forest in its own colour, kept across edits and undo
  (:mod:`app.tree_colors`);
  roots as cubes of their tree's colour; bones as tubes; soft links as thin dashed lines,
  and so is the bone from an anchor (:attr:`core.motion.Motion.anchors`, e.g. a ``Root``
  left at the origin while the hips walk away), which is no part of the figure: the size,
  ground, camera, up axis and followed point are the figure's;
- a ground grid under the lowest point of the whole motion, as large as its path;
- switchable: joint axes (world rotation triads, X red, Y green, Z blue), the trail of the
  selected joint (its last second), joint labels, markers (gaps not drawn; labels of the
  hovered and selected marker), the recovered pelvis frame as an RGB triad.

The up axis (Y or Z) is the one the file's comments state, else the one detected from the
motion (:func:`up_axis_of`), and the camera's up follows it, so Y-up and Z-up files both
stand upright.
"""

from __future__ import annotations

import re
import weakref

import numpy as np
import pyvista as pv

from gmr_studio.app.model.alignment import detect_up_axis
from gmr_studio.app.model.state import OVERLAYS, MarkerOverlay, PelvisOverlay, Snapshot
from gmr_studio.app.model.tree_colors import PALETTE, TreeColors
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.picking import project_points

TREE_COLORS = PALETTE  # the trees' colours, in the order new trees get them
BACKGROUND = (0.16, 0.17, 0.20)
GROUND_COLOR = (0.36, 0.38, 0.42)
# everything is opaque: translucency costs a separate pass, several ms a frame in software GL
SELECTION_COLOR = (1.0, 0.85, 0.1)
SOFT_LINK_COLOR = (0.62, 0.62, 0.66)  # faded: dashed and grey
MARKER_COLOR = (0.92, 0.92, 0.95)
AXIS_COLORS = np.eye(3) * 0.9 + 0.05
JOINT_RADIUS = 0.016  # of Motion.size
BONE_RADIUS = 0.0065
MARKER_RADIUS = 0.009
AXIS_LENGTH = 0.06
PELVIS_AXIS_LENGTH = 0.16
TRAIL_SECONDS = 1.0
DASHES = 8


def up_axis_of(snapshot: Snapshot) -> int:
    """1 (Y) or 2 (Z): what the file's comments state (``up axis: z``, as ``gmr convert``
    writes), else what the motion shows (:func:`app.alignment.detect_up_axis`)."""
    from gmr_studio.core.conversions import up_axis_of as stated_up_axis

    if any(re.match(r"\s*up axis:\s*[yz]\b", comment, re.IGNORECASE) for comment in snapshot.motion.comments):
        return 1 if stated_up_axis(snapshot.motion) == "y" else 2
    return detect_up_axis(actor_positions(snapshot))


def actor_positions(snapshot: Snapshot) -> np.ndarray:
    """(F, A, 3) world positions of the joints that make the figure: all but the
    :attr:`~core.motion.Motion.anchors` (a root pinned at the origin far from the actor)."""
    anchors = snapshot.motion.anchors
    return snapshot.positions[:, ~anchors] if anchors.any() else snapshot.positions


def nice_step(length: float) -> float:
    """1, 2 or 5 times a power of ten, near ``length``."""
    if not np.isfinite(length) or length <= 0:
        return 1.0
    power = 10 ** np.floor(np.log10(length))
    return float(min((1, 2, 5, 10), key=lambda m: abs(np.log(m * power / length))) * power)


class SkeletonScene:
    """Builds and updates the actors of a motion and its overlays in ``plotter``."""

    def __init__(self, plotter: pv.BasePlotter) -> None:
        self.plotter = plotter
        self.plotter.set_background(BACKGROUND)
        self.snapshot: Snapshot | None = None
        self.frame = 0
        self.selected: int | None = None
        self.overlays = dict(OVERLAYS)
        self.up_axis = 1
        self.parts: dict[str, parts.Part] = {}
        self.markers: MarkerOverlay | None = None
        self.hovered_marker: int | None = None
        self.selected_marker: int | None = None
        self.pelvis: PelvisOverlay | None = None
        self.request_repaint = None  # a callable that schedules a repaint of the view widget
        self._followed: np.ndarray | None = None  # where the followed figure was last drawn
        self.tree_colors = TreeColors()  # shared with the forest dock: the same colour per tree
        # near and far planes to fit again just before the next render (see render)
        self._clipping_stale = False
        fit = weakref.WeakMethod(self._fit_clipping_range)  # the render window must not keep the scene
        plotter.ren_win.AddObserver("StartEvent", lambda *_: (method := fit()) is not None and method())

    # ------------------------------------------------------------------- building
    def set_snapshot(self, snapshot: Snapshot | None, *, reset_camera: bool) -> None:
        """Rebuild the skeleton's actors for ``snapshot``; a new document also gets a new
        ground grid, up axis and camera, an edit keeps them."""
        self.snapshot = snapshot
        # the ground, markers and pelvis belong to the document, not to the skeleton's structure
        for name in [n for n in self.parts if n != "ground" and not n.startswith(("marker", "pelvis"))]:
            self._remove(name)
        if snapshot is None:
            self.render()
            return
        motion = snapshot.motion
        size = motion.size
        self.frame = min(self.frame, motion.n_frames - 1)
        colors = self.tree_colors.colors(motion)
        r = JOINT_RADIUS * size
        self._add(
            "joints",
            parts.glyph_part(motion.n_joints, pv.Sphere(radius=r, theta_resolution=16, phi_resolution=12), colors),
        )
        roots = motion.roots
        cube = pv.Cube(x_length=3.0 * r, y_length=3.0 * r, z_length=3.0 * r)
        self._add("roots", parts.glyph_part(len(roots), cube, colors[roots]))
        # a bone from an anchor (a joint pinned at the origin) is no part of the figure:
        # it is drawn as the soft, thin kind of link it is
        anchored = motion.anchors | motion.anchors[np.maximum(motion.parents, 0)]
        bones = np.flatnonzero((motion.parents >= 0) & ~anchored)
        pairs = np.column_stack([bones, motion.parents[bones]])
        self._add(
            "bones", parts.segments_part(motion.n_joints, pairs, 0.85 * colors[bones], tube_radius=BONE_RADIUS * size)
        )
        links = np.flatnonzero(motion.soft_parents >= 0)
        anchor_bones = np.flatnonzero((motion.parents >= 0) & anchored)
        self._soft_links = np.vstack(
            [
                np.column_stack([links, motion.soft_parents[links]]),
                np.column_stack([anchor_bones, motion.parents[anchor_bones]]),
            ]
        )
        dash_pairs = np.arange(2 * DASHES * len(self._soft_links)).reshape(-1, 2)
        self._add(
            "soft_links",
            parts.segments_part(len(dash_pairs) * 2, dash_pairs, color=SOFT_LINK_COLOR, width=1.5),
        )
        axis_pairs = np.arange(6 * motion.n_joints).reshape(-1, 2)
        self._add(
            "axes",
            parts.segments_part(6 * motion.n_joints, axis_pairs, np.tile(AXIS_COLORS, (motion.n_joints, 1)), width=2.5),
        )
        self._trail_length = int(min(motion.n_frames, round(TRAIL_SECONDS * motion.frame_rate) + 1))
        trail_pairs = np.column_stack([np.arange(self._trail_length - 1), np.arange(1, self._trail_length)])
        self._add(
            "trails",
            parts.segments_part(self._trail_length, trail_pairs, color=SELECTION_COLOR, width=2.5),
        )
        self._add("labels", parts.label_part(motion.n_joints, list(motion.names)))
        self._add("selection", parts.glyph_part(1, pv.Sphere(radius=1.9 * r), color=SELECTION_COLOR))
        self.parts["selection"].actor.GetProperty().SetRepresentationToWireframe()
        if reset_camera or "ground" not in self.parts:
            self.up_axis = up_axis_of(snapshot)
            self._build_ground(actor_positions(snapshot), size)
        if reset_camera:
            self._reset_camera()
        self._apply_visibility()
        self.show_frame(self.frame)

    def _build_ground(self, positions: np.ndarray, size: float) -> None:
        self._remove("ground")
        up = self.up_axis
        across = [a for a in (0, 1, 2) if a != up]
        flat = positions.reshape(-1, 3)
        flat = flat[np.isfinite(flat).all(axis=1)]
        low, high = flat.min(axis=0), flat.max(axis=0)
        step = nice_step(size / 4)
        margin = 0.4 * size
        start = np.floor((low[across] - margin) / step) * step
        stop = np.ceil((high[across] + margin) / step) * step
        lines_a = np.arange(start[0], stop[0] + step / 2, step)
        lines_b = np.arange(start[1], stop[1] + step / 2, step)
        points = []
        for value in lines_a:
            points += [(value, start[1]), (value, stop[1])]
        for value in lines_b:
            points += [(start[0], value), (stop[0], value)]
        coords = np.zeros((len(points), 3))
        coords[:, across] = np.array(points)
        coords[:, up] = low[up]
        pairs = np.arange(len(points)).reshape(-1, 2)
        ground = parts.segments_part(len(points), pairs, color=GROUND_COLOR, width=1.0)
        ground.set_points(coords)
        self._add("ground", ground)
        self.ground_bounds = (low, high, low[up])

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
        up_axis = self.up_axis
        up = np.eye(3)[up_axis]
        across = [a for a in (0, 1, 2) if a != up_axis]
        path = actor_positions(self.snapshot)[:, :, across].mean(axis=1)  # (F, 2) horizontal centroid path
        travel = np.zeros(3)
        spread = path - path.mean(axis=0)
        if len(path) > 1 and np.abs(spread).max() > 0.5 * self.snapshot.motion.size:
            _, _, vt = np.linalg.svd(spread, full_matrices=False)
            travel[across] = vt[0]
        else:  # standing still: look along the skeleton's default front
            travel = np.array([1.0, 0.0, 0.0])
        side = np.cross(up, travel)
        if side @ np.array([1.0, 1.0, 1.0]) < 0:
            side = -side
        direction = side * 1.0 + travel * 0.3 + up * 0.45
        centre = (low + high) / 2
        self.plotter.camera_position = [tuple(centre + direction), tuple(centre), tuple(up)]
        self.plotter.reset_camera(bounds=np.column_stack([low, high]).ravel())
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

    def reset_camera(self) -> None:
        if self.snapshot is not None:
            self._reset_camera()
            self.render()

    def _add(self, name: str, part: parts.Part) -> None:
        self._remove(name)
        self.parts[name] = part
        self.plotter.renderer.AddActor(part.actor)

    def _remove(self, name: str) -> None:
        part = self.parts.pop(name, None)
        if part is not None:
            self.plotter.renderer.RemoveActor(part.actor)

    def set_markers(self, overlay: MarkerOverlay | None) -> None:
        """Build the marker actors (or remove them)."""
        for name in ("markers", "marker_labels", "marker_selection"):
            self._remove(name)
        self.markers = overlay
        self.hovered_marker = self.selected_marker = None
        if overlay is not None and self.snapshot is not None:
            size = self.snapshot.motion.size
            sphere = pv.Sphere(radius=MARKER_RADIUS * size, theta_resolution=10, phi_resolution=8)
            self._add("markers", parts.glyph_part(overlay.positions.shape[1], sphere, color=MARKER_COLOR))
            self._add("marker_labels", parts.label_part(2, ["", ""], color=(1.0, 0.95, 0.6)))
            self._add(
                "marker_selection",
                parts.glyph_part(1, pv.Sphere(radius=2.0 * MARKER_RADIUS * size), color=SELECTION_COLOR),
            )
            self.parts["marker_selection"].actor.GetProperty().SetRepresentationToWireframe()
        self._apply_visibility()
        self.show_frame(self.frame)

    def set_pelvis(self, pelvis: PelvisOverlay | None) -> None:
        self._remove("pelvis")
        self.pelvis = pelvis
        if pelvis is not None:
            self._add("pelvis", parts.segments_part(6, np.arange(6).reshape(3, 2), AXIS_COLORS, width=5.0))
        self._apply_visibility()
        self.show_frame(self.frame)

    # ----------------------------------------------------------------- switching
    def set_overlay(self, name: str, shown: bool) -> None:
        self.overlays[name] = bool(shown)
        if name == "follow" and self.snapshot is not None:
            self._followed = self._follow_point(self.frame) if shown else None
        self._apply_visibility()
        self.show_frame(self.frame)

    def set_selection(self, joint: int | None) -> None:
        self.selected = joint
        self._apply_visibility()
        self.show_frame(self.frame)

    def set_marker_highlight(self, hovered: int | None, selected: int | None) -> None:
        self.hovered_marker, self.selected_marker = hovered, selected
        if "marker_labels" in self.parts and self.markers is not None:
            labels = self.markers.markers.labels
            parts.set_labels(
                self.parts["marker_labels"], [labels[m] if m is not None else "" for m in (hovered, selected)]
            )
        self._apply_visibility()
        self.show_frame(self.frame)

    def _apply_visibility(self) -> None:
        shown = self.overlays
        has_selection = self.selected is not None
        rules = {
            "ground": shown["ground"],
            "soft_links": shown["soft_links"],
            "axes": shown["axes"],
            "trails": shown["trails"] and has_selection,
            "labels": shown["labels"],
            "selection": has_selection,
            "markers": shown["markers"],
            "marker_labels": shown["markers"] and shown["marker_labels"],
            "marker_selection": shown["markers"] and self.selected_marker is not None,
            "pelvis": shown["pelvis"],
        }
        for name, part in self.parts.items():
            part.set_visible(rules.get(name, True))

    def is_shown(self, name: str) -> bool:
        """The actor named ``name`` exists and is visible."""
        return name in self.parts and self.parts[name].visible

    # -------------------------------------------------------------------- frames
    def show_frame(self, frame: int, render: bool = True) -> None:
        """Write frame ``frame`` of the caches into the actors (and render once)."""
        if self.snapshot is None:
            return
        motion = self.snapshot.motion
        frame = int(min(max(frame, 0), motion.n_frames - 1))
        self.frame = frame
        if self.overlays.get("follow"):
            self._follow(frame)
        points = self.snapshot.positions[frame]
        size = motion.size
        self.parts["joints"].set_points(points)
        self.parts["bones"].set_points(points)
        self.parts["roots"].set_points(points[motion.roots])
        if self.parts["labels"].visible:
            self.parts["labels"].set_points(points)
        if len(self._soft_links) and self.parts["soft_links"].visible:
            a, b = points[self._soft_links[:, 0]], points[self._soft_links[:, 1]]
            t = np.arange(2 * DASHES) / (2 * DASHES - 1)
            self.parts["soft_links"].set_points((a[:, None] + (b - a)[:, None] * t[None, :, None]).reshape(-1, 3))
        if self.parts["axes"].visible:
            self._update_axes(self.parts["axes"], points, self.snapshot.rotations[frame], AXIS_LENGTH * size)
        if self.selected is not None:
            self.parts["selection"].set_points(points[self.selected][None])
            if self.parts["trails"].visible:
                first = frame - self._trail_length + 1
                index = np.clip(np.arange(first, frame + 1), 0, None)
                self.parts["trails"].set_points(self.snapshot.positions[index, self.selected])
        self._show_overlays(frame, size)
        if render:
            self.render()

    def _show_overlays(self, frame: int, size: float) -> None:
        if self.markers is not None and "markers" in self.parts and self.parts["markers"].visible:
            positions = self.markers.positions[frame]
            present = np.isfinite(positions).all(axis=1)
            parts.set_some_points(self.parts["markers"], positions)
            label_points = np.array(
                [
                    positions[m] if m is not None else np.full(3, np.nan)
                    for m in (self.hovered_marker, self.selected_marker)
                ]
            )
            self.parts["marker_labels"].set_points(label_points)
            if self.selected_marker is not None:
                self.parts["marker_selection"].set_points(positions[self.selected_marker][None])
                self.parts["marker_selection"].set_visible(bool(present[self.selected_marker]))
        if self.pelvis is not None and "pelvis" in self.parts:
            origin = self.pelvis.origins[frame]
            valid = bool(np.isfinite(origin).all())
            self.parts["pelvis"].actor.SetVisibility(valid and self.overlays["pelvis"])
            if valid:
                self._update_axes(
                    self.parts["pelvis"], origin[None], self.pelvis.rotations[frame][None], PELVIS_AXIS_LENGTH * size
                )

    @staticmethod
    def _update_axes(part: parts.Part, origins: np.ndarray, rotations: np.ndarray, length: float) -> None:
        """Triads: for each origin (N, 3) and rotation (N, 3, 3), segments along its columns."""
        n = len(origins)
        coords = np.empty((n, 3, 2, 3))
        coords[:, :, 0] = origins[:, None]
        coords[:, :, 1] = origins[:, None] + length * np.swapaxes(rotations, 1, 2)
        part.set_points(coords.reshape(-1, 3))

    def render(self, now: bool = False) -> None:
        """Draw the scene: at once (``now``, e.g. before a screenshot), or by asking the
        widget to repaint when it has set ``request_repaint`` (a Qt OpenGL widget renders in
        its paint event anyway, so rendering here as well would draw every frame twice).

        The near and far planes are fitted to what is drawn first: kept from an earlier
        render, they clip a skeleton whose actors were rebuilt (an edit) down to fragments.
        For a repaint they are fitted once when it starts, after everything that asked for
        it (the skeleton, the comparison layers) has moved, not once per request."""
        if self.request_repaint is not None and not now:
            self._clipping_stale = True
            self.request_repaint()
        else:
            self.plotter.renderer.ResetCameraClippingRange()
            self._clipping_stale = False
            self.plotter.render()

    def _fit_clipping_range(self) -> None:
        if self._clipping_stale:
            self._clipping_stale = False
            self.plotter.renderer.ResetCameraClippingRange()

    # ------------------------------------------------------------------- picking
    def view_projection(self) -> np.ndarray:
        """(4, 4) world -> clip matrix of the current camera."""
        width, height = self.viewport()
        matrix = self.plotter.camera.GetCompositeProjectionTransformMatrix(width / max(height, 1), -1, 1)
        return np.array([[matrix.GetElement(i, j) for j in range(4)] for i in range(4)])

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
