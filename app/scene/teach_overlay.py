"""The classroom's drawing in the 3D view: the selected joint's chain, and its bone turned both ways.

:func:`teaching_geometry` is pure: for a snapshot, a joint, a frame and the slider's amount
(0: the joint's rotation replaced by the identity, 1: its value at this frame) it gives

- ``chain``: (C, 3) the world positions from the joint's root to the joint;
- ``pre``: (2, 3) the bone that GMR's pre-rotation ``R_j`` turns: from the parent to the
  joint, with ``R_j`` scaled (``p_parent + W_parent R_j(a) t_j``);
- ``post``: (2K, 3) the bones that BVH's post-rotation turns: from the joint to each of its K
  children, with the rotation the children share in BVH scaled (``p_j + W_j R_c(a) t_c``).

At amount 1 both equal the posed skeleton. :class:`TeachOverlay` is the scene's drawable of
them, in the front layer (over the figure's tubes and spheres).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing
from gmr_studio.core.analysis.classroom import scaled_rotation

CHAIN_COLOR = (1.0, 0.85, 0.2)
PRE_COLOR = (0.95, 0.3, 0.85)
POST_COLOR = (0.2, 0.85, 0.95)


@dataclasses.dataclass(frozen=True)
class TeachingGeometry:
    chain: np.ndarray
    pre: np.ndarray
    post: np.ndarray


def teaching_geometry(snapshot: Snapshot, joint: int, frame: int, amount: float) -> TeachingGeometry:
    """Chain and turned bones of ``joint`` at ``frame`` (see the module docstring)."""
    motion = snapshot.motion
    positions, rotations = snapshot.positions[frame], snapshot.rotations_at(frame)
    chain = positions[motion.path_from_root(joint)]
    parent = motion.parents[joint]
    if parent >= 0:
        turned = scaled_rotation(motion.rotations[frame, joint], amount)
        tip = positions[parent] + rotations[parent] @ turned @ motion.translations[frame, joint]
        pre = np.stack([positions[parent], tip])
    else:
        pre = np.repeat(positions[joint][None], 2, axis=0)
    post = []
    for child in motion.children[joint]:
        turned = scaled_rotation(motion.rotations[frame, child], amount)
        post += [positions[joint], positions[joint] + rotations[joint] @ turned @ motion.translations[frame, child]]
    post_points = np.array(post).reshape(-1, 3) if post else np.repeat(positions[joint][None], 2, axis=0)
    return TeachingGeometry(chain, pre, post_points)


class TeachOverlay(Drawing):
    """The classroom's drawing: the chain, the pre-rotation bone, the post-rotation bones of
    :attr:`joint` with the slider's :attr:`amount`, while :attr:`shown` (the Teach dock is)."""

    front = True

    def __init__(self) -> None:
        super().__init__()
        self.shown = False
        self.joint: int | None = None
        self.amount = 1.0
        self.geometry: TeachingGeometry | None = None

    def _joint(self, scene) -> int | None:
        if scene.snapshot is None or self.joint is None or not 0 <= self.joint < scene.snapshot.motion.n_joints:
            return None
        return self.joint

    def wanted(self, scene) -> bool:
        return self.shown and self._joint(scene) is not None

    def build(self, scene) -> None:
        super().build(scene)
        self.geometry = None
        joint = self._joint(scene)
        if not self.shown or joint is None:
            return
        geometry = teaching_geometry(scene.snapshot, joint, min(scene.frame, scene.snapshot.motion.n_frames - 1), 1.0)
        n = len(geometry.chain)
        chain_pairs = np.column_stack([np.arange(n - 1), np.arange(1, n)])
        for name, count, pairs, color, width in (  # flat lines: their colours are exact on screen
            ("chain", n, chain_pairs, CHAIN_COLOR, 4.0),
            ("pre", 2, np.array([[0, 1]]), PRE_COLOR, 7.0),
            ("post", len(geometry.post), np.arange(len(geometry.post)).reshape(-1, 2), POST_COLOR, 7.0),
        ):
            self.add(name, parts.segments_part(count, pairs, color=color, width=width))

    def show_frame(self, frame: int) -> None:
        joint = self._joint(self.scene)
        if not self.parts or joint is None:
            return
        geometry = teaching_geometry(self.scene.snapshot, joint, frame, self.amount)
        self.parts["chain"].set_points(geometry.chain)
        self.parts["pre"].set_points(geometry.pre)
        self.parts["post"].set_points(geometry.post)
        self.geometry = geometry

    def extent(self) -> np.ndarray:
        """The document's joints, grown by its size: a bone turned about its joint stays
        within its length of it."""
        return self.scene.document_box(self.scene.snapshot.motion.size) if self.parts else EMPTY_BOX

    def set_visible(self, shown: bool) -> None:
        super().set_visible(shown)
        if not shown:
            self.geometry = None
