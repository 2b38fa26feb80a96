"""Highlights drawn over the figure: joints ringed in red (the audit's failing joints,
following the frame) and the alignment dialog's pivot."""

from __future__ import annotations

import numpy as np
import pyvista as pv

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing, box_of

HIGHLIGHT_COLOUR = (1.0, 0.15, 0.15)
HIGHLIGHT_RADIUS = 0.04  # of the motion's size: around the document's joints (0.016)


class JointsHighlight(Drawing):
    """Red translucent spheres around the joints named :attr:`names` (those the document has)."""

    def __init__(self) -> None:
        super().__init__()
        self.names: tuple[str, ...] = ()
        self.joints = np.zeros(0, dtype=np.int64)

    @property
    def part(self) -> parts.Part | None:
        return self.parts.get("highlight")

    def build(self, scene) -> None:
        super().build(scene)
        motion = scene.snapshot.motion if scene.snapshot is not None else None
        names = self.names if motion is not None else ()
        self.joints = np.array([motion.joint_index(n) for n in names if n in motion.names], dtype=np.int64)
        if not self.joints.size:
            return
        part = self.add(
            "highlight", parts.sphere_part(len(self.joints), HIGHLIGHT_RADIUS * motion.size, color=HIGHLIGHT_COLOUR)
        )
        part.actor.GetProperty().SetOpacity(0.7)

    def show_frame(self, frame: int) -> None:
        if self.part is not None:
            self.part.set_points(self.scene.snapshot.positions[frame, self.joints])

    def extent(self) -> np.ndarray:
        return self.scene.document_box(HIGHLIGHT_RADIUS * self.scene.snapshot.motion.size) if self.parts else EMPTY_BOX


PIVOT_COLOR = (1.0, 0.25, 0.85)


class PivotMarker(Drawing):
    """A point drawn as a sphere on a vertical line (the alignment dialog's pivot):
    :attr:`point` (3,) or None, ``up`` the scene's up axis."""

    def __init__(self) -> None:
        super().__init__()
        self.point: np.ndarray | None = None

    def build(self, scene) -> None:
        super().build(scene)
        if self.point is None or scene.snapshot is None:
            return
        size = scene.snapshot.motion.size
        up = np.zeros(3)
        up[scene.up_axis] = 0.6 * size
        line = pv.Line(self.point - up, self.point + up)
        marker = pv.Sphere(radius=0.03 * size, center=self.point).merge(line.tube(radius=0.006 * size))
        part = parts.glyph_part(1, marker, color=PIVOT_COLOR)  # one glyph at the origin: the marker as built
        part.actor.GetProperty().LightingOff()
        self.add("pivot", part)

    def show_frame(self, frame: int) -> None:
        pass  # the pivot does not follow the frame: the dialog moves it

    def extent(self) -> np.ndarray:
        if not self.parts:
            return EMPTY_BOX
        return box_of(self.point, 0.6 * self.scene.snapshot.motion.size)  # the sphere on its vertical line
