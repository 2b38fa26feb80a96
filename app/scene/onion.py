"""Onion skins: ghost poses of the document every N frames around the current frame.

:func:`onion_frames` is pure (which frames, how opaque); :class:`OnionSettings` is what the
user chose (View > Onion skin, :mod:`app.window.onion_menu`); :class:`OnionSkins` is the
scene's drawable of the document's poses, a pool of ``2 count`` actors, one per slot
(distance ``-1, +1, -2, +2, ...`` steps), whose points, opacities and visibilities a frame
change rewrites. Poses are drawn as the view draws the figure: bones as lines, soft links
and bones from an anchor dashed (:func:`~app.scene.figure.figure_bones`). The comparison
layers' onion poses are :class:`~app.scene.layer_onion.LayerOnions`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing
from gmr_studio.app.scene.figure import dash_points, figure_bones

BEFORE_COLOR = np.array([0.35, 0.65, 1.0])  # poses earlier than the current frame
AFTER_COLOR = np.array([1.0, 0.6, 0.3])  # later ones
MAX_OPACITY = 0.65
STEPS = (2, 5, 10, 20, 30, 60)
COUNTS = (1, 2, 3, 5, 8)


def onion_frames(current: int, n_frames: int, step: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Ghost frames ``current -+ k step`` for k = 1..count inside ``[0, n_frames)``, and their
    signed distance in steps (K,) (negative before the current frame).

    Returns ``frames`` (K,) int64 and ``distance`` (K,) int64, nearest first.
    """
    if step < 1 or count < 1:
        raise ValueError("an onion skin needs a step and a count of at least 1")
    k = np.arange(1, count + 1)
    distance = np.stack([-k, k], axis=1).ravel()
    frames = current + distance * step
    keep = (frames >= 0) & (frames < n_frames)
    return frames[keep].astype(np.int64), distance[keep].astype(np.int64)


def ghost_opacity(distance: np.ndarray, count: int) -> np.ndarray:
    """Opacity (K,) of ghosts ``distance`` steps away: fading linearly to a fifth of
    :data:`MAX_OPACITY` at ``count`` steps."""
    fade = 1.0 - 0.8 * (np.abs(distance) - 1) / max(1, count - 1) if count > 1 else np.ones(len(distance))
    return MAX_OPACITY * fade


def slot_of(distance: np.ndarray) -> np.ndarray:
    """Slot (K,) of each signed distance in steps: ``-1 -> 0, +1 -> 1, -2 -> 2, +2 -> 3, ...``."""
    distance = np.asarray(distance, dtype=np.int64)
    return 2 * (np.abs(distance) - 1) + (distance > 0)


def pose_lines(motion) -> tuple[np.ndarray, np.ndarray, int]:
    """A pose drawn as lines the way the view draws the figure: returns ``pairs`` (S, 2)
    point index pairs over J joints followed by the dashes of the L links, ``links``
    (L, 2) joint pairs, and the number of points ``J + L 2 DASHES``."""
    from gmr_studio.app.scene.figure import DASHES

    bones, links = figure_bones(motion)
    n = motion.n_joints
    dashes = n + np.arange(2 * DASHES * len(links)).reshape(-1, 2)
    return np.vstack([bones[:, ::-1], dashes]).astype(np.int64), links, n + 2 * DASHES * len(links)


def pose_points(positions: np.ndarray, links: np.ndarray) -> np.ndarray:
    """(J + L 2 DASHES, 3) the points of :func:`pose_lines` for joint ``positions`` (J, 3)."""
    if not len(links):
        return positions
    return np.concatenate([positions, dash_points(positions[links[:, 0]], positions[links[:, 1]]).reshape(-1, 3)])


@dataclasses.dataclass
class OnionSettings:
    """What View > Onion skin says: shown, every ``step`` frames, ``count`` poses each side,
    the comparison layers' poses too."""

    shown: bool = False
    step: int = 10
    count: int = 3
    include_layers: bool = True

    def frames(self, current: int, n_frames: int) -> tuple[np.ndarray, np.ndarray]:
        return onion_frames(current, n_frames, self.step, self.count)


class OnionSkins(Drawing):
    """The document's onion poses: a pool of ``2 count`` line actors, one per slot."""

    def __init__(self, settings: OnionSettings) -> None:
        super().__init__()
        self.settings = settings
        self.pool: list[parts.Part] = []
        self.frames = np.zeros(0, dtype=np.int64)
        self.opacities = np.zeros(0)
        self.poses: list[parts.Part] = []  # the parts showing ``frames``, in that order

    def build(self, scene) -> None:
        super().build(scene)
        self.pool, self.poses = [], []
        self.frames, self.opacities = np.zeros(0, dtype=np.int64), np.zeros(0)
        if scene.snapshot is None or not self.settings.shown:
            return
        pairs, self.links, n_points = pose_lines(scene.snapshot.motion)
        for slot in range(2 * self.settings.count):
            color = BEFORE_COLOR if slot % 2 == 0 else AFTER_COLOR
            part = parts.segments_part(n_points, pairs, color=tuple(color), width=2.5)
            self.pool.append(self.add(f"onion_{slot}", part))

    def wanted(self, scene) -> bool:
        return self.settings.shown

    def extent(self) -> np.ndarray:
        return self.scene.document_box() if self.pool else EMPTY_BOX  # the document at other frames

    def show_frame(self, frame: int) -> None:
        if not self.pool:
            return
        snapshot = self.scene.snapshot
        frames, distance = self.settings.frames(frame, snapshot.motion.n_frames)
        opacity = ghost_opacity(distance, self.settings.count)
        slots = slot_of(distance)
        shown = np.zeros(len(self.pool), dtype=bool)
        shown[slots] = True
        for part, visible in zip(self.pool, shown, strict=True):
            part.set_visible(bool(visible) and self._visible)
        for slot, f, alpha in zip(slots, frames, opacity, strict=True):
            part = self.pool[slot]
            part.set_points(pose_points(snapshot.positions[f], self.links))
            part.actor.GetProperty().SetOpacity(float(alpha))
        self.frames, self.opacities = frames, opacity
        self.poses = [self.pool[slot] for slot in slots]
