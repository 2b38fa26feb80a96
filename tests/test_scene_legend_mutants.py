"""The error legend (app/scene/legend.py, issue 24's mutation tests): its texture laid out to
the pixel (a 22 x 200 bar, five labels of 13-point light grey text, each centred on its
height, the title centred above), the screen-space quad that shows it one texel a pixel at
(0.86, 0.08) of the view, and the pixels it covers there (an off-screen scene, no window)."""

from __future__ import annotations

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy

from gmr_studio.app.scene.labels import NEAR_DEPTH, box_corners
from gmr_studio.app.scene.legend import (
    EDGE,
    label_texts,
    legend_fit,
    legend_image,
    legend_layout,
    legend_part,
)
from gmr_studio.app.scene.vtk_parts import render_texts, rgb_bytes

pytestmark = pytest.mark.gui
WIDE, HIGH = 22, 200  # the bar, pixels
GAP = 4  # between the bar and the labels, and between the top label and the title
GREY, POINTS = (0.9, 0.9, 0.9), 13  # the text's colour and size


def ramp(values: np.ndarray) -> np.ndarray:
    """A colour map that tells every value apart: (N,) in [0, 2] -> (N, 3)."""
    t = np.asarray(values) / 2.0
    return np.column_stack([t, 1.0 - t, 0.25 + 0.5 * t])


def layout(top: float, units: str):
    """The texts' tiles and sizes as the legend should use them: labels, then the title."""
    return render_texts([*label_texts(top), f"error ({units})"], GREY, POINTS)


@pytest.mark.parametrize(
    ("top", "units"),
    [
        (2.0, "a unit with a long name"),  # the title is the widest: it sets the width
        (1234.5, "m"),  # the top label, "1.23e+03", is the widest: the bar and its labels set the width
    ],
)
def test_the_texture_holds_the_bar_the_labels_on_their_heights_and_the_title_centred(top, units):
    tiles, dims = layout(top, units)
    image = legend_image(top, units, lambda v: ramp(v * 2.0 / top))
    label_h = max(h for _, h in dims[:-1])
    title_w, title_h = dims[-1]
    labels_w = WIDE + GAP + max(w for w, _ in dims[:-1])
    assert (title_w > labels_w) == (units != "m")  # each case sets the width as its comment says
    bottom = (label_h + 1) // 2  # the bar's bottom row: the lowest label's middle row
    height = bottom + HIGH + label_h // 2 + GAP + title_h
    assert image.shape == (height, max(labels_w, title_w), 4) and image.dtype == np.uint8
    expected = np.zeros_like(image)
    values = (np.arange(HIGH) + 0.5) / HIGH * 2.0  # each bar row at its value's colour, bottom first
    expected[bottom : bottom + HIGH, :WIDE, :3] = rgb_bytes(ramp(values))[:, None]
    expected[bottom : bottom + HIGH, :WIDE, 3] = 255
    for k, (tile, (w, h)) in enumerate(zip(tiles[:-1], dims[:-1], strict=True)):
        middle = bottom + [0, 50, 100, 149, 199][k]  # 0, a quarter... the top: on their bar rows
        expected[middle - h // 2 : middle - h // 2 + h, WIDE + GAP : WIDE + GAP + w] = tile
    left = (image.shape[1] - title_w) // 2
    expected[height - title_h :, left : left + title_w] = tiles[-1]
    np.testing.assert_array_equal(image, expected)
    written = image[..., 3] > 0
    written[bottom : bottom + HIGH, :WIDE] = False  # the text alone, not the bar
    text = image[..., :3][written]
    assert (text == text[:, :1]).all() and text.max() == 229  # light grey (0.9) text and its dark shadow


def test_the_pieces_are_the_bar_each_label_and_the_title_and_nothing_is_drawn_outside_them():
    top, units = 2.0, "m"
    image, boxes = legend_layout(top, units, ramp)
    np.testing.assert_array_equal(image, legend_image(top, units, ramp))
    _tiles, dims = layout(top, units)
    label_h = max(h for _, h in dims[:-1])
    bottom = (label_h + 1) // 2
    assert boxes.dtype == np.int64 and boxes.shape == (7, 4)
    np.testing.assert_array_equal(boxes[0], [0, bottom, WIDE, bottom + HIGH])  # the bar
    for k, (w, h) in enumerate(dims[:-1]):  # each label on its bar row, right of the gap
        middle = bottom + [0, 50, 100, 149, 199][k]
        np.testing.assert_array_equal(boxes[1 + k], [WIDE + GAP, middle - h // 2, WIDE + GAP + w, middle - h // 2 + h])
    title_w, title_h = dims[-1]
    left = (image.shape[1] - title_w) // 2
    np.testing.assert_array_equal(boxes[6], [left, image.shape[0] - title_h, left + title_w, image.shape[0]])
    inside = np.zeros(image.shape[:2], bool)
    for x0, y0, x1, y1 in boxes:
        inside[y0:y1, x0:x1] = True
    assert not image[~inside].any()  # every written texel in a piece
    assert inside.mean() < 0.6  # and the pieces well under the picture: the empty texels not drawn


def test_the_quads_show_the_pieces_and_a_texel_around_them_one_texel_a_pixel_at_the_views_right():
    part = legend_part(2.0, "m", ramp)
    assert part.top == 2.0 and isinstance(part.top, float)
    height, width = part.image.shape[:2]
    pieces = legend_layout(2.0, "m", ramp)[1]
    expected_boxes = np.clip(pieces + np.array([-1, -1, 1, 1]), 0, (width, height, width, height))
    np.testing.assert_array_equal(part.boxes, expected_boxes)
    assert (part.boxes[:, :2] == 0).any() and (part.boxes[:, 2] == width).any()  # clipped to the picture
    np.testing.assert_array_equal(
        part.mesh.faces, np.column_stack([np.full(7, 4), np.arange(28).reshape(7, 4)]).ravel()
    )
    corners = box_corners(expected_boxes)  # (7, 4, 2): bottom left, bottom right, top right, top left
    np.testing.assert_array_equal(
        corners[0], [[0, pieces[0, 1] - 1], [23, pieces[0, 1] - 1], [23, pieces[0, 3] + 1], [0, pieces[0, 3] + 1]]
    )
    np.testing.assert_allclose(part.mesh.active_texture_coordinates, (corners / (width, height)).reshape(-1, 2))
    texels = part.actor.GetTexture().GetInput()
    assert texels.GetDimensions() == (width, height, 1)
    np.testing.assert_array_equal(vtk_to_numpy(texels.GetPointData().GetScalars()), part.image.reshape(-1, 4))
    assert not part.actor.GetTexture().GetInterpolate() and not part.actor.GetMapper().GetScalarVisibility()
    assert part.draw_last and not part.actor.GetUseBounds()
    assert part.outline.shape == (4,) and not part.outline.any()  # not placed yet
    part.place((2000, 1000))  # room enough: at (0.86, 0.08) of the view, one texel a pixel
    x, y = 0.86 * 2000, 0.08 * 1000
    np.testing.assert_allclose(part.outline, [x, y, x + width, y + height])
    np.testing.assert_allclose(part.corners, corners + np.array([x, y]))
    placed = (corners + np.array([x, y])).reshape(-1, 2)
    # x / 1000 - 1, y / 500 - 1 at the near depth
    device = np.column_stack([placed / 1000 * (1, 2) - 1, np.full(len(placed), NEAR_DEPTH)])
    np.testing.assert_allclose(part.mesh.points, device, rtol=0, atol=1e-15)
    written = part.mesh.GetPoints().GetMTime()
    part.place((2000, 1000))  # the same view: nothing written
    assert part.mesh.GetPoints().GetMTime() == written


def test_the_legend_covers_its_pixels_in_the_view_upright():
    from tests.tiny_scene import picture, scene_of

    part = legend_part(2.0, "m", ramp)
    size = (800, 600)
    with scene_of(None, size=size) as scene:
        scene.plotter.set_background((0, 0, 0))
        scene.plotter.renderer.AddActor(part.actor)
        scene.plotter.renderer.ResetCameraClippingRange()
        part.place(size)
        image = picture(scene)
    height, width = part.image.shape[:2]
    x0, y0 = round(0.86 * size[0]), round(0.08 * size[1])  # the quad's bottom left, from the bottom left
    drawn = image[size[1] - y0 - height : size[1] - y0, x0 : x0 + width][::-1]  # rows bottom first
    over_black = part.image[..., :3].astype(int) * part.image[..., 3:].astype(int) // 255
    assert np.abs(drawn - over_black).max() <= 3
    outside = image.copy()
    outside[size[1] - y0 - height : size[1] - y0, x0 : x0 + width] = 0
    assert not outside.any()


@pytest.mark.parametrize(
    ("view", "expected"),
    [
        ((1000, 1000), (0.0, 1.0)),  # room enough: as drawn, at the anchor
        ((1000, 200), (0.0, 0.84)),  # short: 84% of the height (8% free above and below)
        ((200, 1000), (60.0, 0.8)),  # narrow: 40% of the width, moved left to keep 8 pixels free
        ((10, 1000), (8.6, 0.04)),  # narrower than its anchor allows: moved to the view's left side
    ],
)
def test_a_legend_is_shrunk_and_moved_to_fit_the_view(view, expected):
    shift, scale = legend_fit(view, (100, 200))
    assert (shift, scale) == pytest.approx(expected, abs=1e-12)
    left = 0.86 * view[0] - shift
    assert left >= -1e-12 and scale * 200 <= 0.84 * view[1] + 1e-9 and scale * 100 <= 0.4 * view[0] + 1e-9
    assert left + scale * 100 <= view[0] - EDGE + 1e-9 or left == pytest.approx(0.0)


def test_a_fitted_quad_is_shrunk_and_moved_and_a_shrunk_texture_smoothed():
    part = legend_part(2.0, "m", ramp)
    height, width = part.image.shape[:2]
    assert part.fitted == (0.0, 1.0)  # as built: one texel a pixel at the anchor
    part.fit((2000, 2000))  # room enough: as built
    assert part.fitted == (0.0, 1.0) and not part.actor.GetTexture().GetInterpolate()
    shift, scale = legend_fit((300, 200), (width, height))
    assert scale < 1 and shift > 0
    part.place((300, 200))
    assert part.fitted == (shift, scale) and part.actor.GetTexture().GetInterpolate()
    left, bottom = 0.86 * 300 - shift, 0.08 * 200
    right, top = left + scale * width, bottom + scale * height
    np.testing.assert_allclose(part.outline, [left, bottom, right, top])
    np.testing.assert_allclose(
        part.corners, (left, bottom) + scale * box_corners(part.boxes)
    )  # each piece shrunk with it
    assert right <= 300 - EDGE + 1e-9
    part.place((2000, 2000))  # room again: one texel a pixel
    np.testing.assert_allclose(part.outline[2:] - part.outline[:2], [width, height])
    np.testing.assert_allclose(np.ptp(part.corners[0], axis=0), np.diff(part.boxes[0].reshape(2, 2), axis=0)[0])
    assert not part.actor.GetTexture().GetInterpolate()
