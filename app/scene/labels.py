"""Screen-space pictures in front of everything: quads of one texture placed in display pixels.

:class:`ScreenQuads` holds a texture and a quad for each part of it; its quads are placed in
display pixels and kept in normalised device coordinates, which its vertex shader draws as
they are (no camera), at the normalised depth :data:`NEAR_DEPTH` just beyond the near plane:
in front of everything, drawn by VTK's usual 3D mapper with the opaque geometry, its
blending over what is drawn before it, a texel with nothing in it discarded. A quad stays
where it is while the camera moves, so a picture fixed to the view (the error view's legend,
:mod:`app.scene.legend`) is written again only when the view's size changes; the text labels
that follow points (:class:`LabelPart`: every text rendered once into one texture, one quad a
label, one texel a pixel) are written at every render.

VTK's 2D mapper, which draws display coordinates as they are, rebuilds its shader program each
time its points change and runs its pipeline at every render, a cost on every frame with joint
labels shown. Quads put into the world at the near plane before each render would cost the
camera's inverse and the points' upload at every render.
The scene draws every prop without culling (:mod:`app.scene.scene`), which matters here: the
quads' points are not world points, and a frustum culler would test them as such.
"""

from __future__ import annotations

import numpy as np
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

from gmr_studio.app.scene.vtk_parts import Part, render_texts, rgba_texture

NEAR_DEPTH = -0.999  # normalised depth of the quads (-1: the near plane): in front of everything
HIDDEN = -1e4  # display pixels left of and below any view: where a hidden label goes

# the whole fragment shader: the texel as it is (VTK's own adds colour, lighting and clipping
# terms, work on every pixel that a texture's quad does not need); a texel with
# nothing in it writes neither colour nor depth, so what is drawn after the quads still
# shows between their letters. VTK names the texture coordinates and the texture
# (``tcoordVCVSOutput``, ``actortexture``) and fills in the version and output tags.
_FRAGMENT = """//VTK::System::Dec
//VTK::Output::Dec
in vec2 tcoordVCVSOutput;
uniform sampler2D actortexture;
void main()
{
  vec4 texel = texture(actortexture, tcoordVCVSOutput);
  if (texel.a <= 0.0) { discard; }
  gl_FragData[0] = texel;
}
"""
# the points are normalised device coordinates already: drawn where they are, whatever the camera
_AS_PLACED = "//VTK::PositionVC::Impl\n  gl_Position = vec4(vertexMC.xyz, 1.0);\n"


def device_points(display: np.ndarray, view: tuple[int, int]) -> np.ndarray:
    """(K, 2) display pixels (x right, y up from the bottom left) of a view of ``view``
    (width, height) pixels -> (K, 3) normalised device coordinates at :data:`NEAR_DEPTH`
    (a view of no width or height taken as one pixel)."""
    display = np.asarray(display, dtype=np.float64).reshape(-1, 2)
    scale = 2.0 / np.maximum(np.asarray(view, dtype=np.float64), 1.0)
    return np.column_stack([display * scale - 1.0, np.full(len(display), NEAR_DEPTH)])


def box_corners(boxes: np.ndarray) -> np.ndarray:
    """(K, 4) boxes (x0, y0, x1, y1) -> (K, 4, 2) their corners in a quad's order: bottom
    left, bottom right, top right, top left (what :meth:`ScreenQuads.place_corners` takes)."""
    x0, y0, x1, y1 = np.asarray(boxes, dtype=np.float64).T
    return np.stack([np.column_stack([x0, x1, x1, x0]), np.column_stack([y0, y0, y1, y1])], axis=-1)


#: where a label may go around its point, tried in this order: (x, y) of its bottom left
#: corner from the point, in gaps (``GAP`` pixels) and the label's own width and height
#: (right and above, right and below, left and above, left and below)
SIDES = ((1, 1), (1, -1), (-1, 1), (-1, -1))
GAP = (6.0, 4.0)  # pixels between a point and its label, across and up


def spread_labels(anchors: np.ndarray, sizes: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Bottom-left corners of labels placed so that no two overlap: (N, 2) display pixels,
    NaN for a label left out.

    anchors : (N, 2) the labelled points' display pixels (NaN: not shown).
    sizes : (N, 2) each label's width and height in pixels.
    order : (N,) label indices, the most wanted first.

    Each label in ``order`` takes the first of the :data:`SIDES` of its point where it meets
    no label placed before it; when every side is taken, it is left out: where joints crowd
    (hands, feet, shoulders) the first wanted keep their names, readable, instead of a block
    of overprinted text. A plain loop over the labels and those placed: at a few dozen
    labels, numpy's overhead per label, or a grid of cells, cost more than it saves.
    """
    anchors = np.asarray(anchors, dtype=np.float64).reshape(-1, 2)
    corners = np.full_like(anchors, np.nan)
    visible = np.isfinite(anchors).all(axis=1).tolist()
    points, extents = anchors.tolist(), np.asarray(sizes, dtype=np.float64).reshape(-1, 2).tolist()
    placed: list[tuple[float, float, float, float]] = []
    gap_x, gap_y = GAP
    for k in np.asarray(order, dtype=np.int64).tolist():
        if not visible[k]:
            continue
        (x, y), (w, h) = points[k], extents[k]
        for right, up in SIDES:
            x0 = round(x + gap_x if right > 0 else x - gap_x - w)
            y0 = round(y + gap_y if up > 0 else y - gap_y - h)
            x1, y1 = x0 + w, y0 + h
            for a0, b0, a1, b1 in placed:
                if x0 < a1 and a0 < x1 and y0 < b1 and b0 < y1:
                    break  # taken: the next side
            else:
                corners[k] = x0, y0
                placed.append((x0, y0, x1, y1))
                break
    return corners


def labels_in_a_row(lefts: np.ndarray, widths: np.ndarray, gap: float, view_width: float) -> np.ndarray:
    """(N,) left edges of labels on one line, moved as little as keeps them apart: each run
    of labels that would overlap is laid side by side, ``gap`` pixels apart, in the order of
    their points and centred where they were; then the row is kept within ``view_width``.

    lefts, widths : (N,) each label's wanted left edge and its width, in pixels.
    """
    lefts = np.asarray(lefts, dtype=np.float64)
    widths = np.asarray(widths, dtype=np.float64)
    order = np.argsort(lefts + widths / 2, kind="stable").tolist()
    runs: list[list[int]] = []  # each run: its labels, left to right
    for k in order:
        runs.append([k])
        while len(runs) > 1 and _run_left(runs[-2], lefts, widths, gap) + _run_width(
            runs[-2], widths, gap
        ) + gap > _run_left(runs[-1], lefts, widths, gap):
            last = runs.pop()
            runs[-1] += last
    placed = np.empty_like(lefts)
    for run in runs:
        x = _run_left(run, lefts, widths, gap)
        for k in run:
            placed[k] = x
            x += widths[k] + gap
    row = order  # left to right: pushed right off the left edge, then left off the right one
    for before, k in zip([None, *row[:-1]], row, strict=True):
        placed[k] = max(placed[k], 0.0 if before is None else placed[before] + widths[before] + gap)
    for after, k in zip([None, *row[::-1][:-1]], row[::-1], strict=True):
        placed[k] = min(placed[k], view_width - widths[k] if after is None else placed[after] - gap - widths[k])
    return placed


def _run_width(run: list[int], widths: np.ndarray, gap: float) -> float:
    return float(widths[run].sum() + gap * (len(run) - 1))


def _run_left(run: list[int], lefts: np.ndarray, widths: np.ndarray, gap: float) -> float:
    """The left edge of ``run`` laid side by side around the mean of its labels' centres."""
    centre = float(np.mean(lefts[run] + widths[run] / 2))
    return centre - _run_width(run, widths, gap) / 2


class ScreenQuads(Part):
    """``n`` quads of one texture, placed in display pixels with :meth:`place_corners`. A
    scene draws them after its other actors (:attr:`draw_last`), so that their edges blend
    over what is behind them."""

    draw_last = True

    def __init__(self, n: int) -> None:
        super().__init__(4 * n)
        if n:
            self.mesh.faces = np.column_stack([np.full(n, 4), np.arange(4 * n).reshape(-1, 4)]).ravel()
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(self.mesh)
        mapper.ScalarVisibilityOff()
        # the shader draws the points as they are: no shift and scale of them into the buffer
        # (VTK's default recentres points far from the origin for their size, as these are)
        mapper.SetVBOShiftScaleMethod(vtkPolyDataMapper.DISABLE_SHIFT_SCALE)
        self.actor = vtkActor()
        self.actor.SetMapper(mapper)
        prop = self.actor.GetProperty()
        prop.LightingOff()  # the texels' own colours
        prop.SetColor(1.0, 1.0, 1.0)
        self.actor.ForceOpaqueOn()  # with the opaque geometry: no translucent pass for text
        self.actor.UseBoundsOff()  # device coordinates, not world points: never in the scene's bounds
        shaders = self.actor.GetShaderProperty()
        shaders.SetFragmentShaderCode(_FRAGMENT)
        shaders.AddVertexShaderReplacement("//VTK::PositionVC::Impl", True, _AS_PLACED, False)
        #: (n, 4, 2) the display pixels of each quad's corners at the last placement (before
        #: any: all 0, and the quads' points all at the view's centre, drawing nothing)
        self.corners = np.zeros((n, 4, 2))
        #: (width, height) pixels of the view the quads were last placed in
        self.view = (0, 0)

    def set_texture(self, image: np.ndarray, coords: np.ndarray) -> None:
        """Draw ``image`` (H, W, 4) uint8 RGBA, rows bottom first: quad k shows the part of
        it at texture coordinates ``coords[k]`` ((n, 4, 2), its corners in order)."""
        self.actor.SetTexture(rgba_texture(image))
        if len(coords):
            self.mesh.active_texture_coordinates = np.asarray(coords, dtype=np.float64).reshape(-1, 2)

    def place_corners(self, corners: np.ndarray, view: tuple[int, int]) -> None:
        """Put the quads' corners at ``corners`` ((n, 4, 2) display pixels: x right, y up
        from the bottom left) of a view of ``view`` (width, height) pixels; the points are
        written (and sent to the renderer) only when they or the view changed."""
        if not self.n_points:
            return
        view = (int(view[0]), int(view[1]))
        if view == self.view and np.array_equal(corners, self.corners):
            return
        self.corners[:] = corners
        self.view = view
        self._view[:] = device_points(self.corners, view)
        self.mesh.GetPoints().Modified()


class LabelPart(ScreenQuads):
    """Labels for ``texts`` drawn in ``color`` at ``size`` points: one texture, one quad
    each, one texel a pixel, placed with :meth:`place`."""

    def __init__(self, texts: list[str], color=(1.0, 1.0, 1.0), size: int = 13) -> None:
        self.texts = list(texts)
        super().__init__(len(self.texts))
        self.size = size
        self.color = color
        self._boxes = np.zeros((len(self.texts), 2))
        self._build_texture()

    def _build_texture(self) -> None:
        tiles, dims = render_texts(self.texts, self.color, self.size)
        pad = 2  # empty texels between the rows: a quad's edge never samples its neighbour
        width = max([w for w, _ in dims] + [1]) + pad
        height = max(sum(h + pad for _, h in dims), 1)
        atlas = np.zeros((height, width, 4), np.uint8)
        coords = np.zeros((len(self.texts), 4, 2))
        row = 0
        for k, (tile, (w, h)) in enumerate(zip(tiles, dims, strict=True)):
            atlas[row : row + h, :w] = tile
            u, v0, v1 = w / width, row / height, (row + h) / height
            coords[k] = [(0.0, v0), (u, v0), (u, v1), (0.0, v1)]
            self._boxes[k] = (w, h)
            row += h + pad
        self.set_texture(atlas, coords)

    def widths(self) -> np.ndarray:
        """(N,) each label's width in pixels."""
        return self._boxes[:, 0].copy()

    def heights(self) -> np.ndarray:
        """(N,) each label's height in pixels."""
        return self._boxes[:, 1].copy()

    def set_texts(self, texts: list[str]) -> None:
        """Other texts (as many as before)."""
        self.texts = list(texts)
        self._build_texture()
        self.mesh.Modified()

    def place(self, anchors: np.ndarray, view: tuple[int, int], offset: tuple[float, float] = GAP) -> None:
        """Put label k with its bottom left corner ``offset`` pixels from ``anchors[k]``
        ((N, 2) display pixels of a view of ``view`` (width, height) pixels: x right, y up
        from the bottom left; NaN hides the label), on whole pixels (each texel on one pixel)."""
        if not self.n_points:
            return
        anchors = np.asarray(anchors, dtype=np.float64).reshape(-1, 2)
        hidden = ~np.isfinite(anchors).all(axis=1)
        x0 = np.where(hidden, HIDDEN, np.round(np.nan_to_num(anchors[:, 0]) + offset[0]))
        y0 = np.where(hidden, HIDDEN, np.round(np.nan_to_num(anchors[:, 1]) + offset[1]))
        w, h = self._boxes[:, 0], self._boxes[:, 1]
        self.place_corners(box_corners(np.column_stack([x0, y0, x0 + w, y0 + h])), view)

    def place_apart(self, anchors: np.ndarray, view: tuple[int, int], order: np.ndarray) -> np.ndarray:
        """Put the labels beside ``anchors`` ((N, 2) display pixels of a view of ``view``
        pixels; NaN hides a label) where no two overlap, the first of ``order`` first
        (:func:`spread_labels`); the others hidden. Returns (N, 4) each label's box
        (x0, y0, x1, y1), NaN for a hidden one."""
        if not self.n_points:
            return np.zeros((0, 4))
        corners = spread_labels(anchors, self._boxes, order)
        boxes = np.column_stack([corners, corners + self._boxes])
        shown = np.isfinite(corners).all(axis=1)
        self.place_corners(box_corners(np.where(shown[:, None], boxes, HIDDEN)), view)
        return boxes


def label_part(texts: list[str], color=(1.0, 1.0, 1.0), size: int = 13) -> LabelPart:
    """Labels for ``texts``, placed each render with :meth:`LabelPart.place`."""
    return LabelPart(texts, color, size)
