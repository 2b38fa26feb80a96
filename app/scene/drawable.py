"""One shape for everything drawn in the 3D view.

A :class:`Drawable` is built from what the scene holds (the document's snapshot, the size,
the up axis, the overlays, the selection: :class:`~app.scene.scene.SkeletonScene`), shows a
frame by writing points into the actors it built (no VTK filter, no new actor), can be shown
or hidden, and takes its actors away when removed. The scene keeps a list of drawables: on
a frame change it asks every visible one to show the frame and then renders once; after an
edit or when an overlay is switched it builds them again or shows or hides them. Nothing
else in the app adds actors to the renderer or follows the frame for the view.

:class:`Drawing` is the small base class the drawables share: its actors (``parts``, by
name, for tests and the scene's lookups) go into the scene's main renderer or into the
front layer drawn over it, and its visibility is one switch over all of them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np

from gmr_studio.app.scene import vtk_parts as parts

if TYPE_CHECKING:
    from gmr_studio.app.scene.scene import SkeletonScene


#: the box of nothing (what a drawable drawing nothing in the world holds): min +inf, max -inf
EMPTY_BOX = np.array([[np.inf] * 3, [-np.inf] * 3])


def box_of(points: np.ndarray, pad: float = 0.0) -> np.ndarray:
    """(2, 3) the smallest box (min and max corners) holding the finite points of (..., 3)
    ``points``, grown by ``pad`` on every side; :data:`EMPTY_BOX` when there is none."""
    points = np.asarray(points, dtype=np.float64)
    if points.size:  # every point finite (a document's cache): no copy of the finite ones
        # frames as rows (F, J * 3): numpy reduces long rows at once, not 3 numbers at a time
        rows = points.reshape(points.shape[0], -1) if points.ndim >= 3 else points.reshape(-1, 3)
        low, high = rows.min(axis=0).reshape(-1, 3).min(axis=0), rows.max(axis=0).reshape(-1, 3).max(axis=0)
        if np.isfinite(low).all() and np.isfinite(high).all():
            return np.stack([low - pad, high + pad])
    points = points.reshape(-1, 3)
    finite = points[np.isfinite(points).all(axis=1)]
    if not len(finite):
        return EMPTY_BOX.copy()
    return np.stack([finite.min(axis=0) - pad, finite.max(axis=0) + pad])


def union_box(boxes) -> np.ndarray:
    """(2, 3) the smallest box holding every (2, 3) box of ``boxes``."""
    stacked = np.array([EMPTY_BOX, *boxes])
    return np.stack([stacked[:, 0].min(axis=0), stacked[:, 1].max(axis=0)])


class Drawable(Protocol):
    """What the scene asks of everything it draws."""

    def build(self, scene: SkeletonScene) -> None:
        """(Re)build the actors for what ``scene`` holds now (its snapshot may be None)."""

    def show_frame(self, frame: int) -> None:
        """Write frame ``frame`` into the actors, in place; the scene renders afterwards."""

    def wanted(self, scene: SkeletonScene) -> bool:
        """Whether the scene's overlays and selection ask for this drawable to be shown."""

    @property
    def visible(self) -> bool: ...

    def set_visible(self, shown: bool) -> None: ...

    def remove(self) -> None:
        """Take every actor out of the renderer."""

    def extent(self) -> np.ndarray | None:
        """(2, 3) a box holding everything this drawable may draw at any frame of its build
        (:data:`EMPTY_BOX`: nothing in the world), or None when it cannot say: the scene
        fits the camera's near and far planes to the union of the shown drawables' boxes,
        and asks VTK to measure every actor only when one says None."""


class Drawing:
    """Base of the drawables: named parts in the scene's renderers, one visibility switch.

    Subclasses implement :meth:`build` (calling :meth:`add` for each part) and
    :meth:`show_frame`; :meth:`wanted` is True unless they say otherwise.
    """

    #: draw in the front layer (over the figure) rather than in the main renderer
    front = False

    def __init__(self) -> None:
        self.parts: dict[str, parts.Part] = {}
        self.scene: SkeletonScene | None = None
        self._visible = True

    # -- the protocol -------------------------------------------------------------
    def build(self, scene: SkeletonScene) -> None:
        self.remove()
        self.scene = scene

    def show_frame(self, frame: int) -> None:  # pragma: no cover - every drawable overrides it
        raise NotImplementedError

    def wanted(self, scene: SkeletonScene) -> bool:
        return True

    @property
    def visible(self) -> bool:
        return self._visible

    def set_visible(self, shown: bool) -> None:
        self._visible = bool(shown)
        for part in self.parts.values():
            part.set_visible(self._visible and self.part_wanted(part))

    def remove(self) -> None:
        if self.scene is not None:
            renderer = self._renderer()
            for part in self.parts.values():
                renderer.RemoveViewProp(part.actor)
        self.parts.clear()

    def extent(self) -> np.ndarray | None:
        return None  # unknown unless a subclass says (the scene then measures the actors)

    # -- for subclasses -------------------------------------------------------------
    def part_wanted(self, part: parts.Part) -> bool:
        """Whether one part is shown while the drawable is (all, unless overridden)."""
        return True

    def add(self, name: str, part: parts.Part) -> parts.Part:
        """Put ``part`` in the renderer under ``name`` (replacing a part of that name), its
        points sent to OpenGL as they are (:func:`app.scene.vtk_parts.unshifted`)."""
        parts.unshifted(part.actor)
        renderer = self._renderer()
        old = self.parts.pop(name, None)
        if old is not None:
            renderer.RemoveViewProp(old.actor)
        self.parts[name] = part
        renderer.AddViewProp(part.actor)
        part.set_visible(self._visible and self.part_wanted(part))
        return part

    def _renderer(self):
        assert self.scene is not None, "build the drawable in a scene first"
        return self.scene.front_renderer if self.front else self.scene.plotter.renderer
