"""The quality checks' flagged joints drawn in a warning colour at the flagged frames.

:class:`ProblemMarks` draws, at each frame, a sphere a little larger than a joint around
every joint the checks flag at that frame, in its severity's flat colour
(:data:`app.model.problems.LEVEL_COLOURS`: info light blue, warning orange, error red): the
joint looks drawn in that colour, the bones still show where it is. ``flags`` is the (F, J)
int8 array of :func:`core.checks.joint_flags` (:attr:`app.model.problems.Problems.flags`) and
levels below ``min_level`` are not drawn (the Problems dock's "show" choice); the window
sets both and calls ``scene.redraw(marks)`` when they change. A finding about the whole pose
(a rest-pose frame, a frozen stretch) flags every joint.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.app.model.problems import LEVEL_COLOURS
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import Drawing
from gmr_studio.app.scene.figure import JOINT_RADIUS

MARK_RADIUS = 1.45 * JOINT_RADIUS  # of the motion's size: just around the joint's sphere
LEVELS = (1, 2, 3)  # info, warning, error


class ProblemMarks(Drawing):
    """Joints flagged at the current frame, one glyph part per drawn level, in the front
    layer: a flagged joint shows over the selection's wire ring (which stays visible around
    it) and through the body in front of it."""

    front = True

    def __init__(self) -> None:
        super().__init__()
        self.flags: np.ndarray | None = None  # (F, J) int8 levels, or None
        self.min_level = 1  # levels below are not drawn
        self.levels: tuple[int, ...] = ()  # the levels drawn (a part each)

    def build(self, scene) -> None:
        super().build(scene)
        self.levels = ()
        snapshot = scene.snapshot
        if snapshot is None or self.flags is None or self.flags.shape != snapshot.positions.shape[:2]:
            return  # flags of another motion (the checks are running again): nothing drawn
        self.levels = tuple(level for level in LEVELS if level >= self.min_level and (self.flags == level).any())
        for level in self.levels:
            part = parts.sphere_part(
                snapshot.positions.shape[1], MARK_RADIUS * snapshot.motion.size, color=LEVEL_COLOURS[level]
            )
            part.actor.GetProperty().LightingOff()  # flat: the same colour from every side
            self.add(f"problems_{level}", part)

    def show_frame(self, frame: int) -> None:
        if not self.parts:
            return
        positions = self.scene.snapshot.positions[frame]
        levels = self.flags[frame]
        for level in self.levels:
            part = self.parts[f"problems_{level}"]
            part.set_points(np.where((levels == level)[:, None], positions, np.nan))
            part.set_visible(self._visible and self.part_wanted(part))

    def part_wanted(self, part: parts.Part) -> bool:
        # a level with no joint flagged at this frame is hidden: the front layer is then
        # left undrawn (:func:`~app.scene.vtk_parts.draws_anything`)
        return bool(part.drawn.any())

    def flagged(self, frame: int) -> dict[int, np.ndarray]:
        """{level: joint indices} drawn at ``frame`` (for tests)."""
        if not self.parts:
            return {}
        return {level: np.flatnonzero(self.flags[frame] == level) for level in self.levels}
