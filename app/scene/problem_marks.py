"""The quality checks' flagged joints drawn in a warning colour at the flagged frames.

:class:`ProblemMarks` draws, at each frame, a sphere a little larger than a joint around
every joint the checks flag at that frame with a warning (orange) or an error (red): the
joint looks drawn in that colour, the bones still show where it is. Infos are not drawn
(the timeline and the Problems dock list them). ``flags`` is the (F, J) int8 array of
:func:`core.checks.joint_flags` (:attr:`app.model.problems.Problems.flags`); the window sets
it and calls ``scene.redraw(marks)`` when the findings change. A finding about the whole
pose (a rest-pose frame, a frozen stretch) flags every joint.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv

from gmr_studio.app.model.problems import LEVEL_COLOURS
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import Drawing
from gmr_studio.app.scene.figure import JOINT_RADIUS

MARK_RADIUS = 1.45 * JOINT_RADIUS  # of the motion's size: just around the joint's sphere
DRAWN_LEVELS = (2, 3)  # warning, error


class ProblemMarks(Drawing):
    """Joints flagged at the current frame, one glyph part per drawn level."""

    def __init__(self) -> None:
        super().__init__()
        self.flags: np.ndarray | None = None  # (F, J) int8 levels, or None

    def build(self, scene) -> None:
        super().build(scene)
        snapshot = scene.snapshot
        if snapshot is None or self.flags is None or self.flags.shape != snapshot.positions.shape[:2]:
            return  # flags of another motion (the checks are running again): nothing drawn
        if not (self.flags >= min(DRAWN_LEVELS)).any():
            return
        sphere = pv.Sphere(radius=MARK_RADIUS * snapshot.motion.size, theta_resolution=16, phi_resolution=12)
        for level in DRAWN_LEVELS:
            part = parts.glyph_part(0, sphere, color=LEVEL_COLOURS[level])
            part.actor.GetProperty().LightingOff()  # flat: the same colour from every side
            self.add(f"problems_{level}", part)

    def show_frame(self, frame: int) -> None:
        if not self.parts:
            return
        positions = self.scene.snapshot.positions[frame]
        levels = self.flags[frame]
        for level in DRAWN_LEVELS:
            parts.set_some_points(self.parts[f"problems_{level}"], positions[levels == level])

    def flagged(self, frame: int) -> dict[int, np.ndarray]:
        """{level: joint indices} drawn at ``frame`` (for tests)."""
        if not self.parts:
            return {}
        return {level: np.flatnonzero(self.flags[frame] == level) for level in DRAWN_LEVELS}
