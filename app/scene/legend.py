"""The error view's legend: a colour bar from 0 to the scale's top, five labels and a title,
drawn once into one texture and shown at the view's right by one screen-space quad for each
of its seven pieces (the bar, each label, the title), so that the empty texels between them
cost nothing.

VTK's ``vtkScalarBarActor`` draws the same as a dozen props, and lays itself out again at
every render in which the camera has moved (it watches the renderer's time, which follows
the camera's): a cost paid on every frame while the view follows the figure. This legend is
built when the layer's error scale is (:meth:`app.scene.ghost_layer.GhostLayers.build`) and
costs one actor of textured quads a frame (:class:`app.scene.labels.ScreenQuads`), placed
again only when the view's size changes. One quad per piece rather than one over the whole
picture, so that the mostly empty space between the pieces is not shaded.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.labels import ScreenQuads, box_corners

BAR_WIDTH, BAR_HEIGHT = 22, 200  # pixels
N_LABELS = 5  # 0, a quarter of the top, ..., the top
LABEL_GAP = 4  # pixels between the bar and its labels, and below the title
TEXT_COLOUR = (0.9, 0.9, 0.9)
TEXT_SIZE = 13
ANCHOR = (0.86, 0.08)  # the legend's bottom left corner, in fractions of the view's size
EDGE = 8  # pixels kept free at the view's right side: a legend that would cross it moves left
FIT_HEIGHT = 0.84  # of the view's height at most (from the anchor's 8% to 8% below the top)
FIT_WIDTH = 0.4  # of the view's width at most
PAD = 1  # texels around each piece drawn with it


def label_texts(top: float) -> list[str]:
    """The labels from 0 to ``top``, bottom first, three significant digits."""
    return [f"{value:.3g}" for value in np.linspace(0.0, top, N_LABELS)]


def legend_layout(top: float, units: str, colours: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The legend's picture and its pieces: ``(image, boxes)``.

    ``image`` (H, W, 4) uint8 RGBA, rows bottom first (VTK's order): the bar (``colours`` of
    (BAR_HEIGHT,) values from 0 at its bottom to ``top`` -> (BAR_HEIGHT, 3) in [0, 1]) on
    the left, each label centred on its height right of it, the title "error (units)"
    centred above; transparent elsewhere. ``boxes`` (2 + N_LABELS, 4) int: the texels of
    each piece as (x0, y0, x1, y1), ends excluded, rows from the bottom: the bar, the
    labels bottom first, the title; nothing is drawn outside them."""
    labels = label_texts(top)
    tiles, dims = parts.render_texts([*labels, f"error ({units})"], TEXT_COLOUR, TEXT_SIZE)
    label_height = max(h for _, h in dims[:-1])
    title_w, title_h = dims[-1]
    bottom = (label_height + 1) // 2  # the lowest label centred on the bar's bottom row
    width = max(BAR_WIDTH + LABEL_GAP + max(w for w, _ in dims[:-1]), title_w)
    height = bottom + BAR_HEIGHT + label_height // 2 + LABEL_GAP + title_h
    image = np.zeros((height, width, 4), np.uint8)
    values = (np.arange(BAR_HEIGHT) + 0.5) / BAR_HEIGHT * top
    image[bottom : bottom + BAR_HEIGHT, :BAR_WIDTH, :3] = parts.rgb_bytes(colours(values))[:, None]
    image[bottom : bottom + BAR_HEIGHT, :BAR_WIDTH, 3] = 255
    boxes = [(0, bottom, BAR_WIDTH, bottom + BAR_HEIGHT)]
    for k, (tile, (w, h)) in enumerate(zip(tiles[:-1], dims[:-1], strict=True)):
        centre = bottom + round(k * (BAR_HEIGHT - 1) / (N_LABELS - 1))
        row = min(max(centre - h // 2, 0), height - h)
        image[row : row + h, BAR_WIDTH + LABEL_GAP : BAR_WIDTH + LABEL_GAP + w] = tile
        boxes.append((BAR_WIDTH + LABEL_GAP, row, BAR_WIDTH + LABEL_GAP + w, row + h))
    left = (width - title_w) // 2
    image[height - title_h :, left : left + title_w] = tiles[-1]
    boxes.append((left, height - title_h, left + title_w, height))
    return image, np.array(boxes, dtype=np.int64)


def legend_fit(view: tuple[int, int], image: tuple[int, int]) -> tuple[float, float]:
    """(shift, scale) of a legend of ``image`` (width, height) pixels in a view of ``view``
    (width, height) pixels: shrunk (never enlarged) to at most :data:`FIT_HEIGHT` of the
    view's height and :data:`FIT_WIDTH` of its width, and moved left by ``shift`` pixels from
    :data:`ANCHOR` where its right side would come nearer than :data:`EDGE` to the view's
    (not beyond the view's left side)."""
    view_width, view_height = view
    width, height = image
    scale = min(1.0, FIT_HEIGHT * view_height / height, FIT_WIDTH * view_width / width)
    left = ANCHOR[0] * view_width
    shift = min(max(left + scale * width + EDGE - view_width, 0.0), left)
    return shift, scale


class LegendPart(ScreenQuads):
    """The legend's texture, :attr:`image` (H, W, 4), and a quad for each of its pieces
    (:attr:`boxes`, :func:`legend_layout`), the picture's bottom left at :data:`ANCHOR` of
    the view: one texel a pixel until :meth:`fit` shrinks it to a small view; :meth:`place`
    puts it there before each render."""

    def __init__(self, top: float, units: str, colours: Callable[[np.ndarray], np.ndarray]) -> None:
        self.top = float(top)
        self.image, pieces = legend_layout(top, units, colours)
        height, width = self.image.shape[:2]
        #: (K, 4) the quads' texels (x0, y0, x1, y1): each piece and one texel around it, so
        #: that a shrunk (interpolated) legend keeps the soft edge it has in one quad
        self.boxes = np.clip(pieces + np.array([-PAD, -PAD, PAD, PAD]), 0, (width, height, width, height))
        super().__init__(len(self.boxes))
        self._corners = box_corners(self.boxes)  # (K, 4, 2) texels, placed scaled to the view
        self.set_texture(self.image, self._corners / (width, height))
        self.actor.GetTexture().InterpolateOff()  # one texel a pixel until fitted
        self.fitted = (0.0, 1.0)  # (shift, scale) of the picture now
        #: (left, bottom, right, top) display pixels of the whole picture at the last placement
        self.outline = np.zeros(4)

    def fit(self, view: tuple[int, int]) -> None:
        """Shrink and move the quad for a view of (width, height) pixels
        (:func:`legend_fit`), a shrunk texture interpolated."""
        fitted = legend_fit(view, (self.image.shape[1], self.image.shape[0]))
        if fitted != self.fitted:
            self.fitted = fitted
            self.actor.GetTexture().SetInterpolate(fitted[1] < 1.0)

    def place(self, view: tuple[int, int]) -> None:
        """Fit the legend to a view of (width, height) display pixels and put it there, the
        picture's bottom left at :data:`ANCHOR` of the view moved left by the fit's shift,
        each piece's quad on its texels (nothing written while the view keeps its size)."""
        self.fit(view)
        shift, scale = self.fitted
        left, bottom = ANCHOR[0] * view[0] - shift, ANCHOR[1] * view[1]
        height, width = self.image.shape[:2]
        self.outline = np.array([left, bottom, left + scale * width, bottom + scale * height])
        self.place_corners((left, bottom) + scale * self._corners, view)


def legend_part(top: float, units: str, colours: Callable[[np.ndarray], np.ndarray]) -> LegendPart:
    """The legend of an error scale from 0 to ``top`` (``units`` in its title), coloured by
    ``colours`` (values (N,) -> (N, 3) in [0, 1])."""
    return LegendPart(top, units, colours)
