"""Onion skins: ghost poses of the document every N frames around the current frame.

:func:`onion_frames` is pure (which frames, how opaque); :class:`OnionSkins` draws them in a
plotter with their own actors (they survive the scene's rebuilds); :class:`OnionMenu` puts
View > Onion skin (show, spacing, poses each side, comparison layers too) in a window and
keeps it in step with the state; the comparison layers' onion poses are drawn by
:class:`~app.layer_onion.LayerOnions`, given with :meth:`OnionMenu.attach`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
import pyvista as pv
from PyQt6.QtGui import QAction, QActionGroup
from PyQt6.QtWidgets import QMainWindow

from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.app.scene import vtk_parts as parts

if TYPE_CHECKING:
    from gmr_studio.app.scene.layer_onion import LayerOnions

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


def bone_pairs(parents: np.ndarray) -> np.ndarray:
    """(B, 2) joint index pairs (parent, child) of a forest's bones."""
    children = np.flatnonzero(parents >= 0)
    return np.column_stack([parents[children], children])


class OnionSkins:
    """Ghost skeletons in a plotter, one actor per ghost (each its own opacity)."""

    def __init__(self, plotter: pv.BasePlotter, request_render: Callable[[], None]) -> None:
        self.plotter = plotter
        self.request_render = request_render
        self.parts: list[parts.Part] = []
        self.frames = np.zeros(0, dtype=np.int64)
        self.opacities = np.zeros(0)
        self._signs = np.zeros(0)

    def show(self, snapshot: Snapshot | None, frame: int, step: int, count: int) -> None:
        if snapshot is None or snapshot.motion.n_frames == 0:
            self.clear()
            return
        frames, distance = onion_frames(frame, snapshot.motion.n_frames, step, count)
        opacity = ghost_opacity(distance, count)
        pairs = bone_pairs(snapshot.motion.parents)
        if len(self.parts) != len(frames) or not np.array_equal(np.sign(distance), self._signs):
            self._remove_all()
            for d in distance:
                color = BEFORE_COLOR if d < 0 else AFTER_COLOR
                part = parts.segments_part(snapshot.motion.n_joints, pairs, color=tuple(color), width=2.5)
                self.parts.append(part)
                self.plotter.renderer.AddActor(part.actor)
            self._signs = np.sign(distance)
        for part, f, alpha in zip(self.parts, frames, opacity, strict=True):
            part.set_points(snapshot.positions[f])
            part.actor.GetProperty().SetOpacity(float(alpha))
        self.frames, self.opacities = frames, opacity
        self.request_render()

    def _remove_all(self) -> None:
        for part in self.parts:
            self.plotter.renderer.RemoveActor(part.actor)
        self.parts = []

    def clear(self) -> None:
        had = bool(self.parts)
        self._remove_all()
        self.frames, self.opacities, self._signs = np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0)
        if had:
            self.request_render()


class OnionMenu:
    """View > Onion skin: show (Shift+O), comparison layers too, every N frames, poses each
    side; draws the document's with OnionSkins and the layers' with the attached LayerOnions."""

    def __init__(self, window: QMainWindow, state: StudioState, scene, menu) -> None:
        self.state = state
        self.skins = OnionSkins(scene.plotter, scene.render)
        self.layer_onions: LayerOnions | None = None
        self.step, self.count = 10, 3
        sub = menu.addMenu("&Onion skin")
        self.toggle = QAction("&Show onion skin", window, checkable=True, shortcut="Shift+O")
        self.toggle.toggled.connect(lambda _: self.update())
        sub.addAction(self.toggle)
        window.addAction(self.toggle)
        self.include_layers = QAction("Include &comparison layers", window, checkable=True, checked=True)
        self.include_layers.setStatusTip("onion poses of every shown comparison layer too, in the layer's colour")
        self.include_layers.toggled.connect(lambda _: self.update())
        sub.addAction(self.include_layers)
        for title, values, current, setter in (
            ("Every {} frames", STEPS, self.step, self._set_step),
            ("{} poses each side", COUNTS, self.count, self._set_count),
        ):
            sub.addSeparator()
            group = QActionGroup(window)
            for value in values:
                action = QAction(title.format(value), window, checkable=True)
                action.setChecked(value == current)
                action.triggered.connect(lambda _=False, v=value, s=setter: s(v))
                group.addAction(action)
                sub.addAction(action)
        for signal in (state.frame_changed, state.document_changed, state.motion_changed):
            signal.connect(lambda *_: self.update())

    def attach(self, layer_onions: LayerOnions) -> None:
        """Draw the comparison layers' onion poses with ``layer_onions`` from now on, following
        its layers (added, removed, recomputed, shown, colour, opacity)."""
        self.layer_onions = layer_onions
        layers = layer_onions.layers
        layers.changed.connect(self.update)
        layers.appearance_changed.connect(self._on_layer_appearance_changed)
        self.update()

    def _on_layer_appearance_changed(self, index: int) -> None:
        if self.layer_onions is not None:
            self.layer_onions.restyle(index)
        self.update()

    def _set_step(self, value: int) -> None:
        self.step = value
        self.update()

    def _set_count(self, value: int) -> None:
        self.count = value
        self.update()

    def update(self) -> None:
        snapshot = self.state.snapshot
        if not self.toggle.isChecked():
            self.skins.clear()
        else:
            self.skins.show(snapshot, self.state.frame, self.step, self.count)
        if self.layer_onions is None:
            return
        if (
            self.toggle.isChecked()
            and self.include_layers.isChecked()
            and snapshot is not None
            and snapshot.motion.n_frames
        ):
            frames, distance = onion_frames(self.state.frame, snapshot.motion.n_frames, self.step, self.count)
            self.layer_onions.show(frames, distance, self.count)
        else:
            self.layer_onions.clear()
