"""The view's GPU parts (app/scene/vtk_parts.py) by the pixels they cover: imposter spheres and
bones in their colours and shading, glyphs at their own size, labels' texels where they are
placed, a selection ring round from any side (issue 24's mutation tests; an off-screen window,
100 pixels per unit)."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy

from gmr_studio.app.scene import vtk_parts as parts

pytestmark = pytest.mark.gui
SIZE = 200  # pixels; the view spans -1..1 in x and y, looking down -Z, lit from the camera


def _picture(*actors, size=(SIZE, SIZE)) -> np.ndarray:
    """(H, W, 3) uint8: the actors drawn on black under one headlight (parallel projection)."""
    plotter = pv.Plotter(off_screen=True, window_size=size, lighting="none")
    plotter.add_light(pv.Light(light_type="headlight"))
    plotter.set_background((0, 0, 0))
    for actor in actors:
        plotter.renderer.AddActor(actor)
    plotter.enable_parallel_projection()
    plotter.camera.position, plotter.camera.focal_point, plotter.camera.up = (0, 0, 10), (0, 0, 0), (0, 1, 0)
    plotter.camera.parallel_scale = size[1] / 200
    image = np.asarray(plotter.screenshot(return_img=True))[..., :3].astype(int)
    plotter.close()
    return image


def _pixel(image: np.ndarray, x: float, y: float) -> np.ndarray:
    """The pixel at scene point (x, y)."""
    return image[round(SIZE / 2 - 100 * y - 0.5), round(SIZE / 2 + 100 * x - 0.5)]


def test_spheres_have_their_colours_radius_and_lambert_shading():
    part = parts.sphere_part(3, 0.2, colors=np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]))
    part.set_points(np.array([[0.5, 0.5, 0.0], [np.nan, 0.0, 0.0], [-0.5, -0.5, 0.0]]))
    image = _picture(part.actor)
    red, blue = image[:100, 100:], image[100:, :100]
    assert not image[..., 1].any() and not image[:100, :100].any() and not image[100:, 100:].any()
    for quarter, channel in ((red, 0), (blue, 2)):
        lit = quarter[..., channel] > 0
        assert abs(lit.sum() - np.pi * 20**2) < 0.08 * np.pi * 20**2  # a disc of 20 pixels
        assert not quarter[..., 2 - channel].any()  # its own colour only: no white highlight
    # ambient 0.35 + diffuse 0.65 * cos(angle to the camera): 255 at the centre, 233 half way out
    assert _pixel(image, 0.5, 0.5)[0] >= 250 and abs(_pixel(image, 0.6, 0.5)[0] - 233) <= 8
    assert abs(_pixel(image, -0.5, -0.6)[2] - 233) <= 8
    assert 0.2 * 255 <= red[..., 0][red[..., 0] > 0].min() <= 0.45 * 255  # the rim: about ambient alone


def test_one_sphere_colour_and_radius_zero_rows_draw_nothing():
    part = parts.sphere_part(2, 0.3, color=(0.0, 1.0, 0.0))
    part.set_points(np.array([[0.0, 0.0, 0.0], [0.5, 0.5, np.nan]]))
    image = _picture(part.actor)
    assert not image[..., [0, 2]].any() and _pixel(image, 0.0, 0.0)[1] >= 250
    assert abs((image[..., 1] > 0).sum() - np.pi * 30**2) < 0.08 * np.pi * 30**2


def test_bones_have_a_colour_each():
    part = parts.bone_part(np.array([[0, 1], [2, 3]]), 0.05, colors=np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))
    part.set_joints(np.array([[-0.8, 0.5, 0.0], [0.8, 0.5, 0.0], [-0.5, -0.8, 0.0], [-0.5, 0.2, 0.0]]))
    image = _picture(part.actor)
    red_rows, red_columns = np.nonzero(image[..., 0])
    assert abs(red_columns.min() - 20) <= 1 and abs(red_columns.max() - 179) <= 1
    assert abs(red_rows.min() - 45) <= 1 and abs(red_rows.max() - 54) <= 1
    blue_rows, blue_columns = np.nonzero(image[..., 2])
    assert abs(blue_rows.min() - 80) <= 1 and abs(blue_rows.max() - 179) <= 1
    assert abs(blue_columns.min() - 45) <= 1 and abs(blue_columns.max() - 54) <= 1
    assert not image[..., 1].any() and not (image[..., 0] & image[..., 2]).any()
    assert _pixel(image, 0.0, 0.5)[0] >= 250 and _pixel(image, -0.5, -0.3)[2] >= 250


def test_one_bone_colour_is_drawn_on_every_bone():
    part = parts.bone_part(np.array([[0, 1], [1, 2]]), 0.05, color=(0.0, 1.0, 0.0))
    part.set_joints(np.array([[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.8, 0.0]]))
    image = _picture(part.actor)
    assert not image[..., [0, 2]].any()
    assert _pixel(image, 0.0, 0.0)[1] >= 250 and _pixel(image, 0.5, 0.4)[1] >= 250


def test_glyphs_are_drawn_at_their_own_size_in_their_colours():
    cube = pv.Cube(x_length=0.2, y_length=0.2, z_length=0.2)
    part = parts.glyph_part(2, cube, colors=np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))
    part.set_points(np.array([[0.5, 0.5, 0.0], [-0.5, -0.5, 0.0]]))
    image = _picture(part.actor)
    for channel, (row, column) in ((0, (50, 150)), (2, (150, 50))):
        rows, columns = np.nonzero(image[..., channel])
        assert (rows.min(), rows.max(), columns.min(), columns.max()) == (row - 10, row + 9, column - 10, column + 9)
    assert not image[..., 1].any()


def first_label_tile(part) -> np.ndarray:
    """(h, w, 4) int RGBA: the first label's texels in its part's texture (rows bottom first)."""
    image_data = part.actor.GetTexture().GetInput()
    width, height, _ = image_data.GetDimensions()
    atlas = vtk_to_numpy(image_data.GetPointData().GetScalars()).reshape(height, width, 4).astype(int)
    w, h = int(part.widths()[0]), int(part.heights()[0])
    return atlas[:h, :w]


def test_labels_show_their_texels_on_whole_pixels_in_front_of_everything_and_hidden_ones_nothing():
    """Two labels placed in display pixels of a scene (a perspective camera looking at a
    white board): the first shows its texels one a pixel, blended over the board in front
    of it, the board showing between its letters; the hidden one draws nothing. The camera
    moved and nothing placed again, the label stays on the same pixels."""
    from gmr_studio.app.scene.labels import label_part
    from tests.tiny_scene import picture, scene_of

    with scene_of(None, size=(SIZE, SIZE)) as scene:
        plotter = scene.plotter
        plotter.set_background((0, 0, 0))
        board = plotter.add_mesh(pv.Plane(center=(0, 0, 0), i_size=10, j_size=10), color="white", lighting=False)
        plotter.camera.position, plotter.camera.focal_point, plotter.camera.up = (0, 0, 5), (0, 0, 0), (0, 1, 0)
        part = label_part(["Ab", "Hello"], color=(1.0, 1.0, 0.0))
        plotter.renderer.AddViewProp(part.actor)  # after the board, as the scene puts labels last
        plotter.renderer.ResetCameraClippingRange()
        assert scene.display_size() == (SIZE, SIZE)
        part.place(np.array([[50.0, 40.0], [np.nan, 10.0]]), scene.display_size())
        tile = first_label_tile(part)
        h, w = tile.shape[:2]
        over_white = tile[..., :3] * tile[..., 3:] / 255 + 255 * (1 - tile[..., 3:] / 255)  # blended over the board
        for position in ((0, 0, 5), (1.0, -0.5, 3)):  # the second: nearer, from elsewhere, not placed again
            plotter.camera.position = position
            plotter.renderer.ResetCameraClippingRange()
            plotter.ren_win.Render()
            image = picture(scene)
            # the quad's bottom left at (56, 44) from the bottom left: image rows count from the top
            drawn = image[SIZE - 44 - h : SIZE - 44, 56 : 56 + w][::-1]
            np.testing.assert_allclose(drawn, over_white, atol=3)
            assert (tile[..., 3] == 0).any() and drawn.min() < 60  # letters and the board between them
            outside = image.copy()
            outside[SIZE - 44 - h : SIZE - 44, 56 : 56 + w] = 255
            assert (outside == 255).all()  # the other label hidden: the board everywhere else
        plotter.remove_actor(board)


def test_a_labels_empty_texels_write_no_depth_so_what_is_drawn_after_it_shows_between_its_letters():
    """A label drawn before a white board behind it (the legend's quad drawn after the labels
    is such a case): its texels with something in them are in front (near plane) and hide the
    board, blended over the black background drawn before them; its empty texels are
    discarded, writing no depth, so the board drawn after shows there."""
    from gmr_studio.app.scene.labels import label_part
    from tests.tiny_scene import picture, scene_of

    with scene_of(None, size=(SIZE, SIZE)) as scene:
        plotter = scene.plotter
        plotter.set_background((0, 0, 0))
        part = label_part(["Ab"], color=(1.0, 1.0, 0.0))
        plotter.renderer.AddViewProp(part.actor)  # before the board
        board = plotter.add_mesh(pv.Plane(center=(0, 0, 0), i_size=10, j_size=10), color="white", lighting=False)
        plotter.camera.position, plotter.camera.focal_point, plotter.camera.up = (0, 0, 5), (0, 0, 0), (0, 1, 0)
        plotter.renderer.ResetCameraClippingRange()
        part.place(np.array([[50.0, 40.0]]), scene.display_size())
        plotter.ren_win.Render()
        image = picture(scene)
        tile = first_label_tile(part)
        h, w = tile.shape[:2]
        empty = tile[..., 3] == 0
        assert empty.sum() > 20 and (~empty).sum() > 20
        drawn = image[SIZE - 44 - h : SIZE - 44, 56 : 56 + w][::-1]
        assert (drawn[empty] == 255).all()  # the board, drawn after the label, between its letters
        over_black = tile[..., :3] * tile[..., 3:] / 255  # blended over the background: the board hidden
        np.testing.assert_allclose(drawn[~empty], over_black[~empty], atol=3)
        plotter.remove_actor(board)


def _ring_picture(centre, radius: float, eye) -> np.ndarray:
    """(200, 200) bool: the pixels a white ring of ``radius`` around ``centre`` covers, seen
    from ``eye`` (a direction) in parallel projection, 100 pixels a unit, centred on it."""
    plotter = pv.Plotter(off_screen=True, window_size=(200, 200), lighting="none")
    plotter.set_background((0, 0, 0))
    ring = parts.ring_part(radius, plotter.renderer.GetActiveCamera(), width=2.0)
    ring.set_points(np.array([centre], dtype=float))
    plotter.renderer.AddActor(ring.actor)
    plotter.enable_parallel_projection()
    camera = plotter.camera
    camera.focal_point = tuple(centre)
    camera.position = tuple(np.asarray(centre) + 10 * np.asarray(eye, dtype=float))
    camera.up = (0.0, 1.0, 0.0) if abs(eye[1]) < 0.9 else (0.0, 0.0, 1.0)
    camera.parallel_scale = 1.0
    image = np.asarray(plotter.screenshot(return_img=True))[..., :3].astype(int)
    plotter.close()
    return image.max(axis=-1) > 100


@pytest.mark.parametrize("eye", [(0, 0, 1), (1, 0, 0), (0.3, 0.8, -0.5)])
def test_a_ring_faces_the_camera_round_about_its_point(eye):
    drawn = _ring_picture((0.4, -0.3, 0.2), 0.5, eye)
    rows, columns = np.nonzero(drawn)
    reach = np.hypot(rows - 99.5, columns - 99.5)
    assert 48.0 <= reach.min() and reach.max() <= 52.0  # 50 pixels round, nothing inside
    around = np.unique(np.floor(np.degrees(np.arctan2(rows - 99.5, columns - 99.5)) / 10))
    assert len(around) == 36  # all the way round
