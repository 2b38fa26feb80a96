"""The figure: joints, roots, bones and the selection ring; soft links.

Sizes are fractions of ``Motion.size``, so any unit works. Each tree of the forest has its
colour (:mod:`app.model.tree_colors`, kept across edits and undo); roots are cubes of their
tree's colour; bones are cylinders placed by the glyph mapper (:func:`~app.scene.vtk_parts.bone_part`).
A bone from an anchor (:attr:`core.model.motion.Motion.anchors`: a ``Root`` left at the origin while
the hips walk away) is no part of the figure: it is drawn, like a soft link, as a thin dashed
grey line (:class:`SoftLinks`). The onion skins and filmstrips draw links the same way
(:func:`figure_bones`).
"""

from __future__ import annotations

import numpy as np
import pyvista as pv

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing
from gmr_studio.core.model.motion import Motion

SELECTION_COLOR = (1.0, 0.85, 0.1)
SOFT_LINK_COLOR = (0.62, 0.62, 0.66)  # faded: dashed and grey
JOINT_RADIUS = 0.016  # of Motion.size
BONE_RADIUS = 0.0065
DASHES = 8


def figure_bones(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """The figure's bones and its soft links, as (child, parent) joint index pairs.

    Returns ``bones`` (B, 2): every bone of a tree but those from an anchor; ``links``
    (L, 2): each split root with its soft-link parent, and each bone from an anchor.
    """
    anchored = motion.anchors | motion.anchors[np.maximum(motion.parents, 0)]
    has_parent = motion.parents >= 0
    bones = np.flatnonzero(has_parent & ~anchored)
    anchor_bones = np.flatnonzero(has_parent & anchored)
    split = np.flatnonzero(motion.soft_parents >= 0)
    links = np.vstack(
        [
            np.column_stack([split, motion.soft_parents[split]]),
            np.column_stack([anchor_bones, motion.parents[anchor_bones]]),
        ]
    ).astype(np.int64)
    return np.column_stack([bones, motion.parents[bones]]).astype(np.int64), links


def dash_points(a: np.ndarray, b: np.ndarray, dashes: int = DASHES) -> np.ndarray:
    """(L, 2 dashes, 3) points of dashed lines from ``a`` to ``b`` ((L, 3) each): consecutive
    pairs are the dashes."""
    t = np.arange(2 * dashes) / (2 * dashes - 1)
    return a[:, None] + (b - a)[:, None] * t[None, :, None]


class SkeletonFigure(Drawing):
    """Joints, roots, bones in the trees' colours, and the selected joint's ring.

    Another drawable may draw some joints in its own colours (:meth:`tint_joints`: the
    error view colours the compared joints by their error) rather than drawing spheres
    over them: each joint's sphere is then shaded once. The tint outlives a rebuild of the
    figure that keeps its joints, until :meth:`clear_tint`.
    """

    def __init__(self) -> None:
        super().__init__()
        #: the tinted joints (K,), their colours (K, 3) uint8 and radius, or None
        self.tint: tuple[np.ndarray, np.ndarray, float] | None = None
        self._tree_rgb = np.zeros((0, 3), np.uint8)  # (J, 3): the joints' own colours

    def build(self, scene) -> None:
        super().build(scene)
        snapshot = scene.snapshot
        if snapshot is None:
            return
        motion = snapshot.motion
        size = motion.size
        colors = scene.tree_colors.colors(motion)
        r = JOINT_RADIUS * size
        self.add("joints", parts.sphere_part(motion.n_joints, r, colors))
        self._tree_rgb = np.array(self.parts["joints"].colors)
        if self.tint is not None and (not len(self.tint[0]) or self.tint[0].max() < motion.n_joints):
            self.tint_joints(*self.tint)
        else:
            self.tint = None
        cube = pv.Cube(x_length=3.0 * r, y_length=3.0 * r, z_length=3.0 * r)
        self.roots = motion.roots
        self.add("roots", parts.glyph_part(len(self.roots), cube, colors[self.roots]))
        bones, _ = figure_bones(motion)
        self.add("bones", parts.bone_part(bones, BONE_RADIUS * size, 0.85 * colors[bones[:, 0]]))
        camera = scene.plotter.renderer.GetActiveCamera()
        self.add("selection", parts.ring_part(1.9 * r, camera, color=SELECTION_COLOR))

    def part_wanted(self, part: parts.Part) -> bool:
        return part is not self.parts.get("selection") or (self.scene is not None and self.scene.selected is not None)

    def tint_joints(self, joints: np.ndarray, rgb: np.ndarray, radius: float) -> None:
        """Draw joints ``joints`` (K,) in the colours ``rgb`` (K, 3) uint8 as spheres of
        ``radius`` (the scene's units), the other joints as built; written in place."""
        joints = np.asarray(joints, dtype=np.int64)
        if self.tint is not None and not np.array_equal(self.tint[0], joints):
            self.clear_tint()
        self.tint = (joints, np.array(rgb, dtype=np.uint8), float(radius))
        part = self.parts.get("joints")
        if part is None:
            return
        if (part.sizes[joints] != np.float32(radius)).any():
            part.set_sizes(joints, radius)
        part.colors[joints] = rgb  # the VTK array marked modified

    def clear_tint(self) -> None:
        """Every joint in its own colour and size again."""
        tint, self.tint = self.tint, None
        part = self.parts.get("joints")
        if tint is None or part is None:
            return
        part.set_sizes(tint[0], part.radius)
        part.colors[tint[0]] = self._tree_rgb[tint[0]]

    def extent(self) -> np.ndarray:
        """Every joint at every frame, grown by the selection's ring and a root's cube."""
        if not self.parts:
            return EMPTY_BOX
        return self.scene.document_box(2.0 * JOINT_RADIUS * self.scene.snapshot.motion.size)

    def show_frame(self, frame: int) -> None:
        if not self.parts:
            return
        points = self.scene.snapshot.positions[frame]
        self.parts["joints"].set_points(points)
        self.parts["roots"].set_points(points[self.roots])
        self.parts["bones"].set_joints(points)
        if self.scene.selected is not None:
            self.parts["selection"].set_points(points[self.scene.selected][None])


class SoftLinks(Drawing):
    """Soft links (split roots to their former parents) and bones from anchors, dashed."""

    def build(self, scene) -> None:
        super().build(scene)
        if scene.snapshot is None:
            return
        _, self.links = figure_bones(scene.snapshot.motion)
        dash_pairs = np.arange(2 * DASHES * len(self.links)).reshape(-1, 2)
        self.add("soft_links", parts.segments_part(len(dash_pairs) * 2, dash_pairs, color=SOFT_LINK_COLOR, width=1.5))

    def wanted(self, scene) -> bool:
        return scene.overlays["soft_links"]

    def extent(self) -> np.ndarray:
        return self.scene.document_box() if self.parts else EMPTY_BOX  # dashes between joints

    def show_frame(self, frame: int) -> None:
        if not self.parts or not len(self.links):
            return
        points = self.scene.snapshot.positions[frame]
        dashes = dash_points(points[self.links[:, 0]], points[self.links[:, 1]])
        self.parts["soft_links"].set_points(dashes.reshape(-1, 3))
