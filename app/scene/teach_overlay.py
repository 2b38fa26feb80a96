"""The classroom's drawing in the 3D view: the selected joint's chain, and its bone turned both ways.

:func:`teaching_geometry` is pure: for a snapshot, a joint, a frame and the slider's amount
(0: the joint's rotation replaced by the identity, 1: its value at this frame) it gives

- ``chain``: (C, 3) the world positions from the joint's root to the joint;
- ``pre``: (2, 3) the bone that GMR's pre-rotation ``R_j`` turns: from the parent to the
  joint, with ``R_j`` scaled (``p_parent + W_parent R_j(a) t_j``);
- ``post``: (2K, 3) the bones that BVH's post-rotation turns: from the joint to each of its K
  children, with the rotation the children share in BVH scaled (``p_j + W_j R_c(a) t_c``).

At amount 1 both equal the posed skeleton. :class:`TeachOverlay` draws them with its own
actors (they survive the scene's rebuilds).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pyvista as pv

from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.core.classroom import scaled_rotation

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
    positions, rotations = snapshot.positions[frame], snapshot.rotations[frame]
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


def _front_layer(plotter: pv.BasePlotter):
    """A transparent renderer drawn over the scene with the scene's camera: what the
    classroom draws stays visible in front of the figure's tubes and spheres."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    window = plotter.render_window
    front = vtkRenderer()
    front.SetLayer(1)
    window.SetNumberOfLayers(max(2, window.GetNumberOfLayers()))
    front.SetActiveCamera(plotter.renderer.GetActiveCamera())
    front.InteractiveOff()
    front.SetViewport(plotter.renderer.GetViewport())
    window.AddRenderer(front)
    return front


class TeachOverlay:
    """The classroom's actors in a plotter: the chain, the pre-rotation bone, the post-rotation
    bones. ``request_render`` schedules a render."""

    def __init__(self, plotter: pv.BasePlotter, request_render: Callable[[], None]) -> None:
        self.plotter = plotter
        self.request_render = request_render
        self.renderer = _front_layer(plotter)
        self.parts: dict[str, parts.Part] = {}
        self.geometry: TeachingGeometry | None = None
        self._shapes: dict[str, int] = {}

    def _replace(self, name: str, part: parts.Part) -> None:
        old = self.parts.pop(name, None)
        if old is not None:
            self.renderer.RemoveActor(old.actor)
        self.parts[name] = part
        self.renderer.AddActor(part.actor)

    def show(self, snapshot: Snapshot | None, joint: int | None, frame: int, amount: float) -> None:
        """Draw for ``joint`` (None or no snapshot: hide everything)."""
        if snapshot is None or joint is None or not 0 <= joint < snapshot.motion.n_joints:
            self.clear()
            return
        geometry = teaching_geometry(snapshot, joint, frame, amount)
        chain_pairs = np.column_stack([np.arange(len(geometry.chain) - 1), np.arange(1, len(geometry.chain))])
        for name, points, pairs, color, width in (
            ("chain", geometry.chain, chain_pairs, CHAIN_COLOR, 4.0),
            ("pre", geometry.pre, np.array([[0, 1]]), PRE_COLOR, 7.0),
            ("post", geometry.post, np.arange(len(geometry.post)).reshape(-1, 2), POST_COLOR, 7.0),
        ):
            if self._shapes.get(name) != len(points):  # flat lines: their colours are exact on screen
                self._replace(name, parts.segments_part(len(points), pairs, color=color, width=width))
                self._shapes[name] = len(points)
            self.parts[name].set_points(points)
        self.geometry = geometry
        self.request_render()

    def clear(self) -> None:
        for part in self.parts.values():
            self.renderer.RemoveActor(part.actor)
        self.parts.clear()
        self._shapes.clear()
        if self.geometry is not None:
            self.geometry = None
            self.request_render()
