"""View > Onion skin: the menu that sets :class:`~app.scene.onion.OnionSettings`.

Show (Shift+O), comparison layers too, every N frames, poses each side. The document's
poses (:class:`~app.scene.onion.OnionSkins`) and the layers' (:class:`~app.scene.layer_onion.
LayerOnions`) are drawables of the scene; this menu only changes their settings and asks the
scene to draw them again.
"""

from __future__ import annotations

from PyQt6.QtGui import QAction, QActionGroup
from PyQt6.QtWidgets import QMainWindow

from gmr_studio.app.model.layers import Layers
from gmr_studio.app.scene.layer_onion import LayerOnions
from gmr_studio.app.scene.onion import COUNTS, STEPS, OnionSettings, OnionSkins


class OnionMenu:
    """The Onion skin submenu of ``menu``, drawing into ``scene``."""

    def __init__(self, window: QMainWindow, scene, layers: Layers, menu) -> None:
        self.scene = scene
        self.settings = OnionSettings()
        self.skins = OnionSkins(self.settings)
        self.layer_onions = LayerOnions(layers, self.settings)
        scene.add_drawable(self.skins, before=scene.figure)
        scene.add_drawable(self.layer_onions, before=scene.figure)
        sub = menu.addMenu("&Onion skin")
        self.toggle = QAction("&Show onion skin", window, checkable=True, shortcut="Shift+O")
        self.toggle.toggled.connect(lambda shown: self._set(shown=shown))
        sub.addAction(self.toggle)
        window.addAction(self.toggle)
        self.include_layers = QAction("Include &comparison layers", window, checkable=True, checked=True)
        self.include_layers.setStatusTip("onion poses of every shown comparison layer too, in the layer's colour")
        self.include_layers.toggled.connect(lambda shown: self._set(include_layers=shown))
        sub.addAction(self.include_layers)
        for title, values, current, name in (
            ("Every {} frames", STEPS, self.settings.step, "step"),
            ("{} poses each side", COUNTS, self.settings.count, "count"),
        ):
            sub.addSeparator()
            group = QActionGroup(window)
            for value in values:
                action = QAction(title.format(value), window, checkable=True)
                action.setChecked(value == current)
                action.triggered.connect(lambda _=False, v=value, n=name: self._set(**{n: v}))
                group.addAction(action)
                sub.addAction(action)

    @property
    def step(self) -> int:
        return self.settings.step

    @property
    def count(self) -> int:
        return self.settings.count

    def set_step(self, value: int) -> None:
        self._set(step=value)

    def set_count(self, value: int) -> None:
        self._set(count=value)

    def _set(self, **changes) -> None:
        for name, value in changes.items():
            setattr(self.settings, name, value)
        if set(changes) == {"step"}:  # the same actors, other frames
            self.scene.show_frame(self.scene.frame)
            return
        for drawable in (self.skins, self.layer_onions):
            self.scene.redraw(drawable, render=False)
        self.scene.render()
