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
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing
from gmr_studio.app.scene.figure import JOINT_RADIUS

MARK_RADIUS = 1.45 * JOINT_RADIUS  # of the motion's size: just around the joint's sphere
LEVELS = (1, 2, 3)  # info, warning, error


def draw_in_front(actor) -> None:
    """Have a sphere imposter's actor write its fragments at depth 0 (the near plane): drawn
    in its renderer, it shows in front of everything else there, whether drawn before or
    after it (what comes after fails the depth test where it is), with no second layer. The
    imposter computes its depth at the fragment shader's ``//VTK::Depth::Impl``; this line
    is put after it."""
    actor.GetShaderProperty().AddFragmentShaderReplacement(
        "//VTK::Depth::Impl", True, "//VTK::Depth::Impl\n  gl_FragDepth = 0.0;\n", False
    )


class ProblemMarks(Drawing):
    """Joints flagged at the current frame, one sphere part per drawn level, drawn in front
    of everything (:func:`draw_in_front`: at depth 0 in the main
    renderer, not in a front layer, which would cost a pass over the whole view at every
    frame with a flag): a flagged joint shows through
    the body in front of it, inside the selection's ring, which stays visible around it."""

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
            draw_in_front(part.actor)
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

    def extent(self) -> np.ndarray:
        return self.scene.document_box(MARK_RADIUS * self.scene.snapshot.motion.size) if self.parts else EMPTY_BOX

    def part_wanted(self, part: parts.Part) -> bool:
        # a level with no joint flagged at this frame is hidden: it costs no draw
        return bool(part.drawn.any())

    def flagged(self, frame: int) -> dict[int, np.ndarray]:
        """{level: joint indices} drawn at ``frame`` (for tests)."""
        if not self.parts:
            return {}
        return {level: np.flatnonzero(self.flags[frame] == level) for level in self.levels}
