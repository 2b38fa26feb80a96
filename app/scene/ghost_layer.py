"""Drawing the comparison layers: ghosts, and the document's error at the current frame.

:class:`GhostLayers` is one of the scene's drawables (:mod:`app.scene.drawable`), rebuilt
when the layers change (the scene rebuilds it after an edit too):

- each visible layer (:mod:`app.layers`) as a ghost skeleton: translucent bones in the
  layer's colour, at the document's frame (B on A's clock and in A's space); its joints are
  where its bones meet (and where the error lines end), a sphere drawn only for a joint no
  bone reaches (a lone root, a joint split off by itself), so a ghost split into single
  joints still shows. Spheres at every joint would be a few pixels across in a usual view,
  inside the document's joints wherever the two agree, and cost a translucent pass and
  buffers of their own for dots the bones' ends already draw;
- each visible marker-set layer (:mod:`app.marker_layers`) as small spheres in its colour
  at the document's frame (gaps not drawn);
- the error view of the active layer: the document's matched joints coloured by their
  position error at the current frame (:func:`error_colours`, a green-yellow-red map from 0
  to the comparison's largest error, with a legend in the view titled in the document's
  units), and a thin line from each matched joint to its match. The figure draws those
  joints itself, in the error's colours and a little larger
  (:meth:`app.scene.figure.SkeletonFigure.tint_joints`) rather than spheres of their own
  over the joints, which would shade each joint twice.

Everything is built once per change of the layers (added, removed, recomputed, restyled); a
frame change only writes points and colours into the existing poly data (the colours of
every compared frame are computed once, :attr:`GhostLayers.error_rgb`); the scene renders
once for all its drawables. The translucent ghosts are blended in drawing order rather than through VTK's
order-independent translucency, whose extra full-view passes cost more than the ghosts
themselves on a software renderer (the ghost is one colour per layer, so the two differ
only where a ghost's surfaces overlap, by a few levels of shading).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.app.model.layers import ComparisonLayer, Layers
from gmr_studio.app.model.marker_layers import MARKER_LAYER_RADIUS, MarkerLayer
from gmr_studio.app.model.state import StudioState
from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import EMPTY_BOX, Drawing, box_of, union_box
from gmr_studio.app.scene.figure import figure_bones
from gmr_studio.app.scene.legend import LegendPart, legend_part

#: the error colour map: anchors (position in [0, 1], RGB), interpolated linearly
COLOUR_MAP = np.array([(0.0, 0.2, 0.75, 0.35), (0.5, 1.0, 0.85, 0.1), (1.0, 0.9, 0.15, 0.1)])
NO_ERROR_COLOUR = (0.5, 0.5, 0.5)  # a matched joint not compared at this frame
LINE_COLOUR = (0.95, 0.95, 0.95)
GHOST_JOINT_RADIUS = 0.012  # of the document's size
GHOST_BONE_RADIUS = 0.005
ERROR_JOINT_RADIUS = 0.021  # just larger than the document's joints, so the colour shows


def error_colours(errors: np.ndarray, top: float) -> np.ndarray:
    """(..., J) errors -> (..., J, 3) RGB in [0, 1] on :data:`COLOUR_MAP` over ``[0, top]``; NaN grey."""
    t = np.clip(np.nan_to_num(errors, nan=0.0) / max(top, 1e-300), 0.0, 1.0)
    rgb = np.stack([np.interp(t, COLOUR_MAP[:, 0], COLOUR_MAP[:, k]) for k in (1, 2, 3)], axis=-1)
    rgb[~np.isfinite(errors)] = NO_ERROR_COLOUR
    return rgb


def error_scale_top(layer: ComparisonLayer, size: float) -> float:
    """The top of the colour scale: the comparison's largest error (or a thousandth of the
    document's size when everything agrees, so zero stays green)."""
    top = layer.comparison.position.max
    return float(top) if np.isfinite(top) and top > 1e-6 * size else 1e-3 * size


class GhostLayers(Drawing):
    """The actors of every layer and of the error view, kept in step with ``layers``."""

    def __init__(self, state: StudioState, layers: Layers) -> None:
        super().__init__()
        self.state = state
        self.layers = layers
        self.show_errors = True
        # per layer: (bones, joints) of a motion, (spheres,) of a marker set
        self.ghosts: list[tuple[parts.Part, ...]] = []
        #: per layer: (K,) the joints of a motion's ghost no bone reaches, drawn as its
        #: ``joints`` spheres (often none); None for a marker set
        self.loose: list[np.ndarray | None] = []
        #: (P,) the document's joints the error view colours (the active comparison's
        #: ``index_a``), None without an error view
        self.error_joints: np.ndarray | None = None
        self.error_lines: parts.Part | None = None
        self.legend: LegendPart | None = None
        self.top = 1.0
        #: (R, P, 3) uint8: the error colour of each matched joint at each compared frame
        #: (rows of the active comparison), what a frame change writes into the error view
        self.error_rgb = np.zeros((0, 0, 3), np.uint8)
        self._no_error_rgb = np.zeros((0, 3), np.uint8)  # (P, 3): a frame not compared
        self._oit: bool | None = None  # the renderer's own setting, restored
        self._error_radius = 0.0  # the matched joints' spheres, the scene's units
        layers.changed.connect(self._on_layers_changed)
        layers.appearance_changed.connect(lambda _index: self._on_layers_changed())

    def _on_layers_changed(self) -> None:
        if self.scene is not None:
            self.scene.redraw(self)

    # ------------------------------------------------------------------ building
    def build(self, scene) -> None:
        super().build(scene)
        renderer = scene.plotter.renderer
        if self._oit is None:
            self._oit = bool(renderer.GetUseOIT())
        self.ghosts, self.loose = [], []
        self._untint()
        self.error_joints = self.error_lines = self.legend = None
        self._box = None  # measured when first asked
        document = scene.snapshot
        renderer.SetUseOIT(self._oit)
        if document is None:
            return
        size = document.motion.size
        for index, layer in enumerate(self.layers.layers):
            if isinstance(layer, MarkerLayer):
                built = (parts.sphere_part(layer.markers.n_markers, MARKER_LAYER_RADIUS * size, color=layer.colour),)
                loose = None
            else:
                motion = layer.snapshot.motion
                pairs = figure_bones(motion)[0]
                loose = np.setdiff1d(np.arange(motion.n_joints), pairs.ravel())
                bones = parts.bone_part(pairs, GHOST_BONE_RADIUS * size, color=layer.colour)
                built = (bones, parts.sphere_part(len(loose), GHOST_JOINT_RADIUS * size, color=layer.colour))
            for k, part in enumerate(built):
                part.actor.GetProperty().SetOpacity(layer.opacity)
                part.actor.GetProperty().SetAmbient(0.6)  # translucent over a dark ground: lit brighter
                self.add(f"ghost_{index}_{k}", part)
                part.set_visible(layer.visible)
            self.ghosts.append(built)
            self.loose.append(loose)
        # blended in drawing order while ghosts are shown (see the module docstring)
        renderer.SetUseOIT(self._oit and not self.ghosts)
        active = self.layers.active
        # a comparison of another document (an edit shown before the layers are compared
        # with it; they redraw this when they are) has no error view here: its joints are
        # that document's
        if active is not None and self.show_errors and active.compared_with is document:
            self._build_error_view(active, size)

    def _build_error_view(self, layer: ComparisonLayer, size: float) -> None:
        n = layer.comparison.n_pairs
        self.error_joints = np.asarray(layer.comparison.index_a, dtype=np.int64)
        self._error_radius = ERROR_JOINT_RADIUS * size
        pairs = np.column_stack([np.arange(n), n + np.arange(n)])
        self.error_lines = self.add("error_lines", parts.segments_part(2 * n, pairs, color=LINE_COLOUR, width=1.5))
        self.top = error_scale_top(layer, size)
        self.error_rgb = parts.rgb_bytes(error_colours(layer.comparison.position_error, self.top))
        self._no_error_rgb = parts.rgb_bytes(np.broadcast_to(NO_ERROR_COLOUR, (n, 3)))
        top = self.top
        self.legend = self.add(
            "error_legend", legend_part(top, layer.comparison.units_text, lambda values: error_colours(values, top))
        )

    def extent(self) -> np.ndarray:
        """Every layer's ghost or markers at every frame, and both ends of the error lines."""
        if not self.ghosts:
            return EMPTY_BOX
        if self._box is None:
            pad = ERROR_JOINT_RADIUS * self.scene.snapshot.motion.size
            drawn = [layer.positions if isinstance(layer, MarkerLayer) else layer.ghost for layer in self.layers.layers]
            boxes = [box_of(points, pad) for points in drawn]
            active = self.layers.active
            if self.error_joints is not None and active is not None:
                comparison = active.comparison
                boxes += [box_of(comparison.positions_a, pad), box_of(comparison.positions_b, pad)]
            self._box = union_box(boxes)
        return self._box

    def remove(self) -> None:
        if self.scene is not None and self._oit is not None:
            self.scene.plotter.renderer.SetUseOIT(self._oit)
        self._untint()
        super().remove()

    def _untint(self) -> None:
        """The figure's joints in their own colours again (no error view drawn)."""
        if self.scene is not None:
            self.scene.figure.clear_tint()

    def set_show_errors(self, shown: bool) -> None:
        self.show_errors = bool(shown)
        self._on_layers_changed()

    def set_visible(self, shown: bool) -> None:
        super().set_visible(shown)
        if not shown:
            self._untint()
        elif self.scene is not None and self.scene.snapshot is not None:
            self.show_frame(self.scene.frame)

    def before_render(self) -> None:
        """Put the legend at the view's right, fitted to its size (a small view shrinks it,
        a narrow one moves it left), in front of everything."""
        if self.legend is not None:
            self.legend.place(self.scene.display_size())

    # -------------------------------------------------------------------- frames
    def show_frame(self, frame: int) -> None:
        """Write frame ``frame`` into the ghosts and the error view."""
        if not self.ghosts:
            return
        for layer, built, loose in zip(self.layers.layers, self.ghosts, self.loose, strict=True):
            if isinstance(layer, MarkerLayer):
                positions = layer.positions
                built[0].set_points(positions[min(frame, len(positions) - 1)])
                built[0].set_visible(layer.visible and self._visible)
                continue
            points = layer.ghost[min(frame, len(layer.ghost) - 1)]
            sampled = bool(np.isfinite(points).all())  # outside B's time range: not drawn
            bones, joints = built
            shown = layer.visible and sampled and self._visible
            bones.set_visible(shown and bones.n_points > 0)  # an empty part: no actor to draw
            joints.set_visible(shown and joints.n_points > 0)
            if sampled:
                bones.set_joints(points)
                joints.set_points(points[loose])
        active = self.layers.active
        if self.error_joints is not None and active is not None and active.compared_with is self.scene.snapshot:
            comparison = active.comparison
            row = comparison.row_of_frame(frame)
            if row is None:
                rgb = self._no_error_rgb
                a = b = self.state.snapshot.positions[frame, comparison.index_a]
            else:
                rgb = self.error_rgb[row]
                a, b = comparison.positions_a[row], comparison.positions_b[row]
            self.scene.figure.tint_joints(self.error_joints, rgb, self._error_radius)
            self.error_lines.set_points(np.concatenate([a, np.where(np.isfinite(b), b, a)]))
