"""The scene's own overlays: ground, joint axes, trail, joint labels, markers, pelvis triads.

Each is a :class:`~app.scene.drawable.Drawing`, built from the scene (snapshot, size, up axis,
overlays, selection) and updated in place on a frame change. Sizes are fractions of
``Motion.size``, so any unit works.

- :class:`Ground`: a grid under the lowest point of the whole motion, as large as its path
  (built with a new document, kept across edits);
- :class:`JointAxes`: each joint's world rotation as a triad (X red, Y green, Z blue);
- :class:`Trail`: the selected joint's last second;
- :class:`JointLabels`: joint names next to the joints, in screen space (one texture);
- :class:`Markers`: the markers (gaps not drawn), the hovered and selected marker's labels
  and the selected marker's ring;
- :class:`PelvisTriad`: the pelvis frame recovered from the markers, as an RGB triad.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing, box_of
from gmr_studio.app.scene.figure import SELECTION_COLOR
from gmr_studio.app.scene.labels import label_part
from gmr_studio.core.library.drawing import GROUND_COLOR, MARKER_COLOR

MARKER_LABEL_COLOR = (1.0, 0.95, 0.6)
AXIS_COLORS = np.eye(3) * 0.9 + 0.05
MARKER_RADIUS = 0.009
AXIS_LENGTH = 0.06
PELVIS_AXIS_LENGTH = 0.16
TRAIL_SECONDS = 1.0


def nice_step(length: float) -> float:
    """1, 2 or 5 times a power of ten, near ``length``."""
    if not np.isfinite(length) or length <= 0:
        return 1.0
    power = 10 ** np.floor(np.log10(length))
    return float(min((1, 2, 5, 10), key=lambda m: abs(np.log(m * power / length))) * power)


def ground_lines(positions: np.ndarray, size: float, up: int) -> tuple[np.ndarray, tuple]:
    """The grid under ``positions`` (..., 3): (2 L, 3) segment end points, and the bounds
    ``(low (3,), high (3,), floor height)``."""
    across = [a for a in (0, 1, 2) if a != up]
    low, high = box_of(positions)
    step = nice_step(size / 4)
    margin = 0.4 * size
    start = np.floor((low[across] - margin) / step) * step
    stop = np.ceil((high[across] + margin) / step) * step
    a = np.arange(start[0], stop[0] + step / 2, step)
    b = np.arange(start[1], stop[1] + step / 2, step)
    ends = np.concatenate(
        [
            np.stack(
                [np.column_stack([a, np.full_like(a, start[1])]), np.column_stack([a, np.full_like(a, stop[1])])], 1
            ),
            np.stack(
                [np.column_stack([np.full_like(b, start[0]), b]), np.column_stack([np.full_like(b, stop[0]), b])], 1
            ),
        ]
    ).reshape(-1, 2)
    coords = np.zeros((len(ends), 3))
    coords[:, across] = ends
    coords[:, up] = low[up]
    return coords, (low, high, low[up])


def triad_points(origins: np.ndarray, rotations: np.ndarray, length: float) -> np.ndarray:
    """(N * 6, 3) segment end points of triads: for each origin (N, 3) and rotation
    (N, 3, 3), one segment along each column."""
    coords = np.empty((len(origins), 3, 2, 3))
    coords[:, :, 0] = origins[:, None]
    coords[:, :, 1] = origins[:, None] + length * np.swapaxes(rotations, 1, 2)
    return coords.reshape(-1, 3)


class Ground(Drawing):
    """The ground grid: built for a new document (:meth:`SkeletonScene.set_snapshot` with a
    camera reset), kept across edits (positions are invariant under the operations)."""

    bounds: tuple | None = None

    def build(self, scene) -> None:
        if not scene.new_document and self.parts:
            return
        super().build(scene)
        if scene.snapshot is None:
            self.bounds = None
            return
        coords, self.bounds = ground_lines(scene.figure_box(), scene.snapshot.motion.size, scene.up_axis)
        grid = parts.segments_part(len(coords), np.arange(len(coords)).reshape(-1, 2), color=GROUND_COLOR, width=1.0)
        grid.set_points(coords)
        self.box = box_of(coords)
        self.add("ground", grid)

    def extent(self) -> np.ndarray:
        return self.box if self.parts else EMPTY_BOX

    def wanted(self, scene) -> bool:
        return scene.overlays["ground"]

    def show_frame(self, frame: int) -> None:
        pass


class JointAxes(Drawing):
    """Each joint's world rotation as a triad."""

    def build(self, scene) -> None:
        super().build(scene)
        if scene.snapshot is None:
            return
        n = scene.snapshot.motion.n_joints
        pairs = np.arange(6 * n).reshape(-1, 2)
        self.add("axes", parts.segments_part(6 * n, pairs, np.tile(AXIS_COLORS, (n, 1)), width=2.5))

    def wanted(self, scene) -> bool:
        return scene.overlays["axes"]

    def extent(self) -> np.ndarray:
        return self.scene.document_box(AXIS_LENGTH * self.scene.snapshot.motion.size) if self.parts else EMPTY_BOX

    def show_frame(self, frame: int) -> None:
        if self.parts:
            snapshot = self.scene.snapshot
            length = AXIS_LENGTH * snapshot.motion.size
            self.parts["axes"].set_points(triad_points(snapshot.positions[frame], snapshot.rotations[frame], length))


class Trail(Drawing):
    """The selected joint's path over its last :data:`TRAIL_SECONDS`."""

    def build(self, scene) -> None:
        super().build(scene)
        if scene.snapshot is None:
            return
        motion = scene.snapshot.motion
        self.length = int(min(motion.n_frames, round(TRAIL_SECONDS * motion.frame_rate) + 1))
        pairs = np.column_stack([np.arange(self.length - 1), np.arange(1, self.length)])
        self.add("trails", parts.segments_part(self.length, pairs, color=SELECTION_COLOR, width=2.5))

    def wanted(self, scene) -> bool:
        return scene.overlays["trails"] and scene.selected is not None

    def extent(self) -> np.ndarray:
        return self.scene.document_box() if self.parts else EMPTY_BOX

    def show_frame(self, frame: int) -> None:
        if self.parts and self.scene.selected is not None:
            index = np.clip(np.arange(frame - self.length + 1, frame + 1), 0, None)
            self.parts["trails"].set_points(self.scene.snapshot.positions[index, self.scene.selected])


class JointLabels(Drawing):
    """Joint names beside the joints: one texture of every name, quads placed in screen
    space just before each render (so they follow the camera too), where no two overlap
    (:meth:`app.scene.labels.LabelPart.place_apart`): the selected joint's first, then the
    joints nearest their roots (the body's main joints before fingers, toes and end sites);
    a name with no free side of its joint is left out."""

    def build(self, scene) -> None:
        super().build(scene)
        self.order = np.zeros(0, np.int64)
        if scene.snapshot is not None:
            motion = scene.snapshot.motion
            self.add("labels", label_part(list(motion.names)))
            self.order = np.argsort(motion.depths, kind="stable")

    def wanted(self, scene) -> bool:
        return scene.overlays["labels"]

    def extent(self) -> np.ndarray:
        return EMPTY_BOX  # drawn in screen space

    def show_frame(self, frame: int) -> None:
        pass

    def before_render(self) -> None:
        if self.parts and self._visible:
            anchors = self.scene.display_positions(self.scene.snapshot.positions[self.scene.frame])
            order, selected = self.order, self.scene.selected
            if selected is not None and selected < len(order):
                order = np.concatenate([[selected], order[order != selected]])
            self.parts["labels"].place_apart(anchors, self.scene.display_size(), order)


class Markers(Drawing):
    """The marker overlay (:class:`~app.model.state.MarkerOverlay`): spheres at the markers
    present at the frame, the labels of the hovered and selected marker, the selected one's ring."""

    def __init__(self) -> None:
        super().__init__()
        self.overlay = None
        self.hovered: int | None = None
        self.selected: int | None = None

    def build(self, scene) -> None:
        super().build(scene)
        if self.overlay is None or scene.snapshot is None:
            return
        size = scene.snapshot.motion.size
        self.add(
            "markers", parts.sphere_part(self.overlay.positions.shape[1], MARKER_RADIUS * size, color=MARKER_COLOR)
        )
        self._box = None  # measured when first asked
        self.add("marker_labels", label_part(self._label_texts(), color=MARKER_LABEL_COLOR))
        camera = scene.plotter.renderer.GetActiveCamera()
        self.add("marker_selection", parts.ring_part(2.0 * MARKER_RADIUS * size, camera, color=SELECTION_COLOR))

    def _label_texts(self) -> list[str]:
        labels = self.overlay.markers.labels
        return [labels[m] if m is not None else "" for m in (self.hovered, self.selected)]

    def set_highlight(self, hovered: int | None, selected: int | None) -> None:
        self.hovered, self.selected = hovered, selected
        if "marker_labels" in self.parts:
            self.parts["marker_labels"].set_texts(self._label_texts())
            self.set_visible(self._visible)  # the labels are drawn only while they have a text

    def wanted(self, scene) -> bool:
        return scene.overlays["markers"]

    def extent(self) -> np.ndarray:
        """The markers at every frame, grown by the selected one's ring (the labels are in
        screen space)."""
        if not self.parts:
            return EMPTY_BOX
        if self._box is None:
            self._box = box_of(self.overlay.positions, 2.0 * MARKER_RADIUS * self.scene.snapshot.motion.size)
        return self._box

    def part_wanted(self, part: parts.Part) -> bool:
        if part is self.parts.get("marker_labels"):  # an empty label's quad would cost a draw
            shown = self.hovered is not None or self.selected is not None
            return shown and self.scene is not None and self.scene.overlays["marker_labels"]
        if part is self.parts.get("marker_selection"):
            return self.selected is not None and self._present(self.selected)
        return True

    def _present(self, marker: int) -> bool:
        return bool(
            np.isfinite(self.overlay.positions[min(self.scene.frame, len(self.overlay.positions) - 1), marker]).all()
        )

    def show_frame(self, frame: int) -> None:
        if not self.parts:
            return
        positions = self.overlay.positions[frame]
        self.parts["markers"].set_points(positions)
        if self.selected is not None:
            self.parts["marker_selection"].set_points(positions[self.selected][None])
        self.parts["marker_selection"].set_visible(self._visible and self.part_wanted(self.parts["marker_selection"]))

    def before_render(self) -> None:
        if self.hovered is None and self.selected is None:
            return  # no marker label to place (the labels' texts are empty)
        if "marker_labels" in self.parts and self._visible:
            positions = self.overlay.positions[self.scene.frame]
            points = np.array(
                [positions[m] if m is not None else np.full(3, np.nan) for m in (self.hovered, self.selected)]
            )
            self.parts["marker_labels"].place(self.scene.display_positions(points), self.scene.display_size())


class PelvisTriad(Drawing):
    """The pelvis frame recovered from the markers (:class:`~app.model.state.PelvisOverlay`);
    not drawn at frames where it could not be recovered."""

    def __init__(self) -> None:
        super().__init__()
        self.pelvis = None

    def build(self, scene) -> None:
        super().build(scene)
        if self.pelvis is not None and scene.snapshot is not None:
            self.box = box_of(self.pelvis.origins, PELVIS_AXIS_LENGTH * scene.snapshot.motion.size)
            self.add("pelvis", parts.segments_part(6, np.arange(6).reshape(3, 2), AXIS_COLORS, width=5.0))

    def wanted(self, scene) -> bool:
        return scene.overlays["pelvis"]

    def extent(self) -> np.ndarray:
        return self.box if self.parts else EMPTY_BOX

    def show_frame(self, frame: int) -> None:
        if not self.parts:
            return
        origin = self.pelvis.origins[frame]
        valid = bool(np.isfinite(origin).all())
        self.parts["pelvis"].set_visible(valid and self._visible)
        if valid:
            length = PELVIS_AXIS_LENGTH * self.scene.snapshot.motion.size
            self.parts["pelvis"].set_points(triad_points(origin[None], self.pelvis.rotations[frame][None], length))
