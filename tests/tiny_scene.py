"""A small synthetic skeleton in an off-screen scene, for the drawables' tests
(``tests/test_scene_*.py``): positions written out by hand, a real
:class:`~app.scene.scene.SkeletonScene` in an off-screen PyVista plotter, no window.

The figure (:func:`figure_motion`), frame ``f`` shifted by ``0.05 f`` along x::

    Head  (0, 0.6)                      joint 3, child of Chest
    Chest (0, 0.2) ... Arm (0.4, 0.2) -- Hand (0.8, 0.2)
                       joint 4: a root split from Chest (soft link); Hand joint 5
    Hips  (0, -0.2)                     joint 1, child of Root
    Root  (0, -0.9), fixed              joint 0: an anchor (still, its one neighbour moves)

so its bones are Chest-Hips, Head-Chest and Hand-Arm; its soft links Arm-Chest (the split)
and Hips-Root (the bone from the anchor); two trees (Root's, Arm's); size 0.8.
"""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np
import pyvista as pv

from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene.scene import SkeletonScene
from gmr_studio.core.kinematics.fk import world_positions, world_rotations
from gmr_studio.core.model.motion import Motion

FIGURE_NAMES = ("Root", "Hips", "Chest", "Head", "Arm", "Hand")
FIGURE_PARENTS = (-1, 0, 1, 2, -1, 4)
FIGURE_SOFT_PARENTS = (-1, -1, -1, -1, 2, -1)
FIGURE_REST = np.array(
    [[0.0, -0.9, 0.0], [0.0, -0.2, 0.0], [0.0, 0.2, 0.0], [0.0, 0.6, 0.0], [0.4, 0.2, 0.0], [0.8, 0.2, 0.0]]
)
FIGURE_SIZE = 0.8


def posed_motion(names, parents, world: np.ndarray, soft_parents=None) -> Motion:
    """A motion whose world positions are ``world`` (F, J, 3) exactly: identity rotations,
    every joint translated by its offset from its parent (a root: its world position)."""
    world = np.asarray(world, dtype=np.float64)
    n_frames, n_joints, _ = world.shape
    parents = np.asarray(parents, dtype=np.int64)
    local = world - np.where((parents >= 0)[None, :, None], world[:, np.maximum(parents, 0)], 0.0)
    return Motion(
        names=tuple(names),
        parents=parents,
        offsets=local[0],
        rotation_orders=("XYZ",) * n_joints,
        has_translation=np.ones(n_joints, bool),
        rotations=np.broadcast_to(np.eye(3), (n_frames, n_joints, 3, 3)).copy(),
        translations=local,
        frame_time=1 / 30,
        convention="pre",
        soft_parents=soft_parents,
    )


def figure_world(n_frames: int = 3) -> np.ndarray:
    """(F, 6, 3) the figure's positions: the rest shifted by 0.05 f along x, Root fixed."""
    world = np.repeat(FIGURE_REST[None], n_frames, axis=0)
    world[:, 1:, 0] += 0.05 * np.arange(n_frames)[:, None]
    return world


def figure_motion(n_frames: int = 3) -> Motion:
    """The module docstring's figure."""
    return posed_motion(FIGURE_NAMES, FIGURE_PARENTS, figure_world(n_frames), FIGURE_SOFT_PARENTS)


def snapshot_of(motion: Motion) -> Snapshot:
    return Snapshot(motion, world_positions(motion), world_rotations(motion))


@contextmanager
def scene_of(snapshot: Snapshot | None, size: tuple[int, int] = (160, 160)):
    """A :class:`SkeletonScene` showing ``snapshot`` (or nothing) off screen; closed after."""
    plotter = pv.Plotter(off_screen=True, window_size=size)
    try:
        scene = SkeletonScene(plotter)
        scene.set_snapshot(snapshot, reset_camera=True)
        yield scene
    finally:
        plotter.close()


def props_of(renderer) -> list:
    """The view props of a VTK renderer, in order."""
    props = renderer.GetViewProps()
    return [props.GetItemAsObject(i) for i in range(props.GetNumberOfItems())]


def holds(renderer, actor) -> bool:
    """Whether ``actor`` is in ``renderer`` (compared by VTK object)."""
    return any(prop is actor for prop in props_of(renderer))


def look_down_at(scene: SkeletonScene, centre, half_height: float) -> None:
    """Only the figure and what was added to the scene, seen from +z down onto the x-y plane
    (parallel projection, y up, ``half_height`` world units from the centre to the top edge;
    the ground, the soft links and the following camera switched off)."""
    for overlay in ("ground", "soft_links", "follow"):
        scene.set_overlay(overlay, False)
    scene.plotter.enable_parallel_projection()
    camera = scene.plotter.camera
    camera.focal_point = tuple(centre)
    camera.position = (centre[0], centre[1], centre[2] + 5.0)
    camera.up = (0.0, 1.0, 0.0)
    camera.parallel_scale = half_height


def picture(scene: SkeletonScene) -> np.ndarray:
    """(H, W, 3) int: the scene as drawn now (its front layer too)."""
    from gmr_studio.app.media.video import scene_image

    return scene_image(scene).astype(int)
