"""Onion skins of the comparison layers: each shown layer's ghost at the document's onion frames.

:class:`LayerOnions` keeps, for every layer of :class:`~app.layers.Layers`, a pool of
``2 count`` skeleton actors, one per onion slot (distance ``-1, +1, -2, +2, ...`` steps from
the current frame, as :func:`~app.onion.onion_frames` orders them). A frame change only
writes points, opacities and visibilities into that pool; the pools are built again only
when the layers change (added, removed, recomputed after an edit) or the number of poses
each side does (it is one of the scene's drawables, :mod:`app.scene.drawable`). A
layer's onion pose at frame ``f`` is ``layer.ghost[f]`` (B on A's frames
and in A's space), drawn in the layer's colour as lines with a dot at every joint (the
document's onion poses are lines only, blue before and orange after), fading with distance
like the document's; frames where B has no sample (NaN) are not drawn.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.app.model.layers import GHOST_OPACITY, ComparisonLayer, Layers
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import Drawing, box_of, union_box
from gmr_studio.app.scene.onion import OnionSettings, ghost_opacity, pose_lines, pose_points, slot_of

LINE_WIDTH = 2.5  # as the document's onion poses
JOINT_DOT = 5.0  # pixels: what tells a layer's onion pose from the document's


def layer_slot_frames(ghost: np.ndarray, frames: np.ndarray, distance: np.ndarray, count: int) -> np.ndarray:
    """Which frame each of the ``2 count`` slots of a layer shows, -1 for none.

    ghost : (F_A, J_B, 3), NaN where B has no sample. frames, distance : (K,) from
    :func:`~app.onion.onion_frames`. A frame past the ghost's end (a stale ghost, before
    the layer is recomputed after an edit) or with any NaN joint is left out.

    Returns (2 count,) int64.
    """
    shown = np.full(2 * count, -1, dtype=np.int64)
    frames = np.asarray(frames, dtype=np.int64)
    inside = frames < len(ghost)
    sampled = np.zeros(len(frames), dtype=bool)
    sampled[inside] = np.isfinite(ghost[frames[inside]]).all(axis=(1, 2))
    shown[slot_of(distance[sampled])] = frames[sampled]
    return shown


def _onion_part(layer: ComparisonLayer) -> parts.Part:
    """Lines along B's bones (links dashed, as the view draws them: :func:`~app.scene.onion.pose_lines`)
    and a dot at each of its joints, in the layer's colour."""
    motion = layer.snapshot.motion
    pairs, _, n_points = pose_lines(motion)
    part = parts.segments_part(n_points, pairs, color=layer.colour, width=LINE_WIDTH)
    if motion.n_joints:
        part.mesh.verts = np.column_stack([np.ones(motion.n_joints, np.int64), np.arange(motion.n_joints)]).ravel()
    prop = part.actor.GetProperty()
    prop.SetPointSize(JOINT_DOT)
    prop.SetRenderPointsAsSpheres(True)
    return part


class LayerOnions(Drawing):
    """The onion poses of every layer, in pools of actors reused from frame to frame."""

    def __init__(self, layers: Layers, settings: OnionSettings) -> None:
        super().__init__()
        self.layers = layers
        self.settings = settings
        self.pools: list[list[parts.Part]] = []  # per layer, 2 count slots
        self.slot_frames: list[np.ndarray] = []  # per layer, (2 count,) frame of each slot, -1 none
        layers.changed.connect(self._on_layers_changed)
        layers.appearance_changed.connect(self.restyle)

    def _on_layers_changed(self) -> None:
        if self.scene is not None:
            self.scene.redraw(self)

    def wanted(self, scene) -> bool:
        return self.settings.shown and self.settings.include_layers

    def build(self, scene) -> None:
        super().build(scene)
        self.pools, self.slot_frames, self.links = [], [], []
        self._box = None  # measured when first asked
        if scene.snapshot is None or not self.wanted(scene):
            return
        count = self.settings.count
        for index, layer in enumerate(self.layers.layers):
            posed = isinstance(layer, ComparisonLayer)  # a marker-set layer has no poses to onion
            self.links.append(pose_lines(layer.snapshot.motion)[1] if posed else None)  # (L, 2)
            slots = range(2 * count) if posed else range(0)
            pool = [self.add(f"layer_onion_{index}_{slot}", _onion_part(layer)) for slot in slots]
            for part in pool:
                part.set_visible(False)
            self.pools.append(pool)
            self.slot_frames.append(np.full(2 * count, -1, dtype=np.int64))

    def extent(self) -> np.ndarray:
        """Every layer's ghost at every frame (its onion poses are some of them)."""
        if self._box is None:
            posed = [layer for layer, pool in zip(self.layers.layers, self.pools, strict=True) if pool]
            self._box = union_box([box_of(layer.ghost) for layer in posed])
        return self._box

    def set_visible(self, shown: bool) -> None:
        self._visible = bool(shown)
        if not shown:
            for part in self.parts.values():
                part.set_visible(False)

    def show_frame(self, frame: int) -> None:
        """Draw each shown layer at the onion frames around ``frame``."""
        if not self.pools:
            return
        count = self.settings.count
        frames, distance = self.settings.frames(frame, self.scene.snapshot.motion.n_frames)
        opacity = np.zeros(2 * count)
        opacity[slot_of(distance)] = ghost_opacity(distance, count)
        hidden = np.full(2 * count, -1, dtype=np.int64)
        for index, (layer, pool) in enumerate(zip(self.layers.layers, self.pools, strict=True)):
            if not pool:
                continue
            shown = layer_slot_frames(layer.ghost, frames, distance, count) if layer.visible else hidden
            scale = min(1.0, layer.opacity / GHOST_OPACITY)  # a fainter layer, fainter onion poses
            for part, f, alpha in zip(pool, shown, opacity, strict=True):
                part.set_visible(f >= 0 and self._visible)
                if f >= 0:
                    part.set_points(pose_points(layer.ghost[f], self.links[index]))
                    part.actor.GetProperty().SetOpacity(float(alpha * scale))
            self.slot_frames[index] = shown

    def restyle(self, index: int) -> None:
        """Give layer ``index``'s actors its colour (after a change in the Layers dock)."""
        if index < len(self.pools):
            for part in self.pools[index]:
                part.actor.GetProperty().SetColor(*self.layers[index].colour)
        if self.scene is not None and self.scene.snapshot is not None and self._visible:
            self.show_frame(self.scene.frame)
            self.scene.render()
