"""The 3D scene: a list of drawables in a PyVista plotter (no Qt here).

Everything drawn in the view is a :class:`~app.scene.drawable.Drawable` held in
:attr:`SkeletonScene.drawables`: the figure (:mod:`app.scene.figure`), its overlays
(:mod:`app.scene.overlays`) and what the window adds with :meth:`SkeletonScene.add_drawable`
(comparison ghosts, onion skins, the classroom's overlay, an audit's highlight). Drawables
are built once per motion (:meth:`SkeletonScene.set_snapshot`) or when their own data change
(:meth:`SkeletonScene.redraw`); a frame asks every visible drawable to write its points from
the state's caches into the existing arrays, then renders once
(:meth:`SkeletonScene.show_frame`). An edit rebuilds the drawables in place and never moves
the camera: positions are invariant under the operations, so the skeleton stays exactly
where it was while its colours, root marks and soft links change. The camera and the view's
projection are the scene's other half (:mod:`app.scene.camera`).

The up axis (Y or Z) is the one the file's comments state, else the one detected from the
motion (:func:`core.space.up_axis.up_axis_of`), and the camera's up follows it, so Y-up and Z-up files both
stand upright.
"""

from __future__ import annotations

import weakref

import numpy as np
import pyvista as pv

from gmr_studio.app.model.state import OVERLAYS, MarkerOverlay, PelvisOverlay, Snapshot
from gmr_studio.app.model.tree_colors import PALETTE, TreeColors
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.camera import SceneCamera, actor_positions
from gmr_studio.app.scene.drawable import Drawable, box_of, union_box
from gmr_studio.app.scene.figure import JOINT_RADIUS, SELECTION_COLOR, SOFT_LINK_COLOR, SkeletonFigure, SoftLinks
from gmr_studio.app.scene.overlays import (
    GROUND_COLOR,
    MARKER_COLOR,
    Ground,
    JointAxes,
    JointLabels,
    Markers,
    PelvisTriad,
    Trail,
    nice_step,
)
from gmr_studio.core.library.drawing import BACKGROUND
from gmr_studio.core.space.up_axis import axis_index, up_axis_of, up_turn

__all__ = [
    "BACKGROUND",
    "GROUND_COLOR",
    "JOINT_RADIUS",
    "MARKER_COLOR",
    "SELECTION_COLOR",
    "SOFT_LINK_COLOR",
    "TREE_COLORS",
    "SkeletonScene",
    "actor_positions",
    "nice_step",
]

TREE_COLORS = PALETTE  # the trees' colours, in the order new trees get them
# everything is opaque: translucency costs a separate pass, several ms a frame in software GL


def one_headlight(plotter: pv.BasePlotter) -> None:
    """Light the scene with one light at the camera, VTK's own default, instead of
    pyvista's kit of five: every lit pixel of the joints, bones and markers sums each light,
    and every lit actor is handed each light's uniforms at every render. Seen from the camera
    the figure is shaded as before, its edges a little darker."""
    plotter.remove_all_lights()
    plotter.add_light(pv.Light(light_type="headlight"))


def without_culling(renderer) -> None:
    """Take VTK's frustum culler out of ``renderer``. Before every render it asks each of
    the scene's dozen actors for its bounds (a pipeline update of each, and a count of the
    processors read from /sys, since the points changed) to skip those outside the view;
    the figure, its overlays and the ground are in view, so it skipped nothing and only added
    work to each render."""
    renderer.GetCullers().RemoveAllItems()


def another_space(before: Snapshot, after: Snapshot) -> bool:
    """An edit moved the document into another space (Markers > Build skeleton replaces a
    motion in inches, Y up, by one in millimetres, Z up, and undo takes it back): its size
    changed more than fivefold, so the ground, up axis and camera are made afresh."""
    ratio = after.motion.size / before.motion.size
    return not 0.2 < ratio < 5.0


class SkeletonScene(SceneCamera):
    """The drawables of a document in ``plotter``, updated together and rendered once."""

    def __init__(self, plotter: pv.BasePlotter) -> None:
        self.plotter = plotter
        self.plotter.set_background(BACKGROUND)
        one_headlight(plotter)
        without_culling(plotter.renderer)
        self.snapshot: Snapshot | None = None
        self.frame = 0
        self.selected: int | None = None
        self.overlays = dict(OVERLAYS)
        self.up_axis = 1
        self.new_document = True  # the drawables are being built for a new document
        self.request_repaint = None  # a callable that schedules a repaint of the view widget
        self.after_render = None  # a callable called after every render (the view's: a first frame drawn)
        self._followed: np.ndarray | None = None  # where the followed figure was last drawn
        self.tree_colors = TreeColors()  # shared with the forest dock: the same colour per tree
        self._front = None
        self.ground = Ground()
        self.figure = SkeletonFigure()
        self.marker_drawing = Markers()
        self.pelvis_drawing = PelvisTriad()
        #: everything drawn, in drawing order; the window adds its own (:meth:`add_drawable`)
        self.drawables: list[Drawable] = [
            self.ground,
            self.figure,
            SoftLinks(),
            JointAxes(),
            Trail(),
            JointLabels(),
            self.marker_drawing,
            self.pelvis_drawing,
        ]
        # near and far planes to fit again just before the next render (see render), and the
        # screen-space labels placed for the camera of that render
        self._clipping_stale = False
        self._document_box: tuple[Snapshot, np.ndarray] | None = None
        before = weakref.WeakMethod(self._before_render)  # the render window must not keep the scene
        plotter.ren_win.AddObserver("StartEvent", lambda *_: (method := before()) is not None and method())
        after = weakref.WeakMethod(self._after_render)
        plotter.ren_win.AddObserver("EndEvent", lambda *_: (method := after()) is not None and method())

    # ------------------------------------------------------------------ lookups
    @property
    def parts(self) -> dict[str, parts.Part]:
        """Every part of the scene's drawables by name (``joints``, ``bones``, ``markers``...)."""
        merged: dict[str, parts.Part] = {}
        for drawable in self.drawables:
            merged.update(getattr(drawable, "parts", {}) if isinstance(getattr(drawable, "parts", None), dict) else {})
        return merged

    def is_shown(self, name: str) -> bool:
        """The part named ``name`` exists and is visible."""
        part = self.parts.get(name)
        return part is not None and part.visible

    @property
    def markers(self) -> MarkerOverlay | None:
        return self.marker_drawing.overlay

    @property
    def pelvis(self) -> PelvisOverlay | None:
        return self.pelvis_drawing.pelvis

    @property
    def hovered_marker(self) -> int | None:
        return self.marker_drawing.hovered

    @property
    def selected_marker(self) -> int | None:
        return self.marker_drawing.selected

    @property
    def ground_bounds(self) -> tuple:
        return self.ground.bounds

    @property
    def front_renderer(self):
        """A transparent renderer drawn over the scene with the scene's camera (made on first
        use): what is drawn there stays visible in front of the figure."""
        if self._front is None:
            from vtkmodules.vtkRenderingCore import vtkRenderer

            window = self.plotter.render_window
            front = vtkRenderer()
            front.SetLayer(1)
            window.SetNumberOfLayers(max(2, window.GetNumberOfLayers()))
            front.SetActiveCamera(self.plotter.renderer.GetActiveCamera())
            front.InteractiveOff()
            front.SetViewport(self.plotter.renderer.GetViewport())
            without_culling(front)
            window.AddRenderer(front)
            self._front = front
        return self._front

    def document_box(self, pad: float = 0.0) -> np.ndarray:
        """(2, 3) the box holding every joint of the document at every frame (measured once
        per snapshot), grown by ``pad``."""
        if self._document_box is None or self._document_box[0] is not self.snapshot:
            self._document_box = (self.snapshot, box_of(self.snapshot.positions))
        box = self._document_box[1]
        return np.stack([box[0] - pad, box[1] + pad])

    def world_box(self) -> np.ndarray | None:
        """(2, 3) the box holding everything the shown drawables may draw at any frame (the
        union of their :meth:`~app.scene.drawable.Drawable.extent`), or None when one of
        them cannot say, or when the main renderer holds a prop no drawable made."""
        boxes, made = [], 0
        for drawable in self.drawables:
            held = getattr(drawable, "parts", {})
            made += 0 if getattr(drawable, "front", False) else len(held)
            if drawable.visible and held:
                box = drawable.extent()
                if box is None:
                    return None
                boxes.append(box)
        if self.plotter.renderer.GetViewProps().GetNumberOfItems() != made:
            return None
        return union_box(boxes)

    def figure_positions(self) -> np.ndarray:
        """(F, A, 3) the positions that make the figure (:func:`actor_positions`)."""
        return actor_positions(self.snapshot)

    def figure_box(self) -> np.ndarray:
        """(2, 3) the box holding the figure (:meth:`figure_positions`) at every frame: the
        document's box (:meth:`document_box`, measured once) when no anchor is left out."""
        if not self.snapshot.motion.anchors.any():
            return self.document_box()
        return box_of(self.figure_positions())

    # ------------------------------------------------------------------- building
    def set_snapshot(self, snapshot: Snapshot | None, *, reset_camera: bool) -> None:
        """Build every drawable for ``snapshot``; a new document also gets a new ground grid,
        up axis and camera, an edit keeps them."""
        turned = None  # an edit that turned the world (a new up axis): the view turns with it
        if not reset_camera and snapshot is not None and self.snapshot is not None:
            reset_camera = another_space(self.snapshot, snapshot)
            up_before, up_after = "xyz"[self.up_axis], up_axis_of(snapshot.motion)
            if not reset_camera and up_after != up_before:
                turned = up_turn(up_before, up_after)
        self.snapshot = snapshot
        self.new_document = reset_camera or turned is not None or not self.ground.parts
        if snapshot is None:
            for drawable in self.drawables:
                drawable.remove()
            self.render()
            return
        self.frame = min(self.frame, snapshot.motion.n_frames - 1)
        if self.new_document:
            self.up_axis = axis_index(up_axis_of(snapshot.motion))  # core's one rule
        for drawable in self.drawables:
            drawable.build(self)
        self._draw_labels_last()
        self.new_document = False
        if reset_camera:
            self._reset_camera()
        elif turned is not None:
            self.turn_with_the_world(turned)
        self._apply_visibility()
        self.show_frame(self.frame)

    def add_drawable(self, drawable: Drawable, *, before: Drawable | None = None) -> None:
        """Draw ``drawable`` from now on (before ``before`` in drawing order, else last)."""
        index = self.drawables.index(before) if before is not None else len(self.drawables)
        self.drawables.insert(index, drawable)
        self.redraw(drawable, render=False)

    def remove_drawable(self, drawable: Drawable) -> None:
        if drawable in self.drawables:
            self.drawables.remove(drawable)
            drawable.remove()
            self.render()

    def redraw(self, drawable: Drawable, *, render: bool = True) -> None:
        """Build ``drawable`` again (its own data changed), show this frame, render."""
        drawable.build(self)
        self._draw_labels_last()
        drawable.set_visible(drawable.wanted(self))
        if self.snapshot is not None and drawable.visible:
            drawable.show_frame(self.frame)
        if render:
            self.render()

    def _draw_labels_last(self) -> None:
        """Put the parts drawn last (:attr:`app.scene.labels.ScreenQuads.draw_last`: labels and
        the legend in front of everything, whose edges blend over what is drawn before them) at
        the end of the main renderer's props, which VTK draws in order."""
        renderer = self.plotter.renderer
        for drawable in self.drawables:
            if getattr(drawable, "front", False):
                continue
            for part in getattr(drawable, "parts", {}).values():
                if getattr(part, "draw_last", False):
                    renderer.RemoveViewProp(part.actor)
                    renderer.AddViewProp(part.actor)

    def set_markers(self, overlay: MarkerOverlay | None) -> None:
        """Show the marker overlay (or none)."""
        self.marker_drawing.overlay = overlay
        self.marker_drawing.hovered = self.marker_drawing.selected = None
        self.redraw(self.marker_drawing)

    def set_pelvis(self, pelvis: PelvisOverlay | None) -> None:
        self.pelvis_drawing.pelvis = pelvis
        self.redraw(self.pelvis_drawing)

    # ----------------------------------------------------------------- switching
    def set_overlay(self, name: str, shown: bool) -> None:
        self.overlays[name] = bool(shown)
        if name == "follow" and self.snapshot is not None:
            self._followed = self._follow_point(self.frame) if shown else None
        self._apply_visibility()
        self.show_frame(self.frame)

    def set_selection(self, joint: int | None) -> None:
        self.selected = joint
        self._apply_visibility()
        self.show_frame(self.frame)

    def set_marker_highlight(self, hovered: int | None, selected: int | None) -> None:
        self.marker_drawing.set_highlight(hovered, selected)
        self._apply_visibility()
        self.show_frame(self.frame)

    def _apply_visibility(self) -> None:
        """Show what the overlays and the selection ask for (every part re-checked)."""
        for drawable in self.drawables:
            drawable.set_visible(self.snapshot is not None and drawable.wanted(self))

    # -------------------------------------------------------------------- frames
    def show_frame(self, frame: int, render: bool = True) -> None:
        """Write frame ``frame`` into every visible drawable (and render once)."""
        if self.snapshot is None:
            return
        frame = int(min(max(frame, 0), self.snapshot.motion.n_frames - 1))
        self.frame = frame
        if self.overlays.get("follow"):
            self._follow(frame)
        for drawable in self.drawables:
            if drawable.visible:
                drawable.show_frame(frame)
        if render:
            self.render()

    def _fit_clipping_range(self) -> None:
        """Fit the near and far planes to the box everything shown may occupy over the take
        (:meth:`world_box`, kept between frames): without measuring the actors, which costs
        each one a pipeline update per render once its points changed (as VTK's frustum
        culler did; both are taken out); VTK measures them only when a drawable cannot give
        its box."""
        renderer = self.plotter.renderer
        box = self.world_box() if self.snapshot is not None else None
        if box is None:
            renderer.ResetCameraClippingRange()
        elif np.isfinite(box).all():
            renderer.ResetCameraClippingRange(*box.T.ravel())  # xmin, xmax, ymin, ymax, zmin, zmax

    def render(self, now: bool = False) -> None:
        """Draw the scene: at once (``now``, e.g. before a screenshot), or by asking the
        widget to repaint when it has set ``request_repaint`` (requests before the repaint
        coalesce into one render).

        Just before every render (:meth:`_before_render`) the near and far planes are fitted
        to what is drawn (kept from an earlier render, they clip a skeleton whose actors were
        rebuilt down to fragments) and screen-space labels are placed for the camera."""
        if self.request_repaint is not None and not now:
            self._clipping_stale = True
            self.request_repaint()
        else:
            self._clipping_stale = True
            self.plotter.render()

    def _after_render(self) -> None:
        if self.after_render is not None:
            self.after_render()

    def _before_render(self) -> None:
        if self._clipping_stale:
            self._clipping_stale = False
            self._fit_clipping_range()
        if self._front is not None:
            self._front.SetDraw(parts.draws_anything(self._front))
        for drawable in self.drawables:
            hook = getattr(drawable, "before_render", None)
            if hook is not None and drawable.visible:
                hook()
