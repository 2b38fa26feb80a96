"""The view's GPU parts (app/scene/vtk_parts.py) by their arrays and actors: the points, radii,
directions and scales written in place, the colours handed to the mappers, the labels' texture
atlas and quads, the selection ring's circle and place, and which renderers draw anything
(issue 24's mutation tests; no window)."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkTable
from vtkmodules.vtkRenderingAnnotation import vtkAxesActor
from vtkmodules.vtkRenderingCore import (
    vtkActor,
    vtkCamera,
    vtkFollower,
    vtkPolyDataMapper,
    vtkRenderer,
    vtkTextProperty,
    vtkTextRenderer,
)

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.labels import NEAR_DEPTH, LabelPart, device_points, label_part

#: VTK's mapper settings (vtkSystemIncludes.h)
SCALAR_MODE_USE_CELL_DATA, SCALAR_MODE_USE_POINT_FIELD_DATA, COLOR_MODE_DIRECT_SCALARS = 2, 3, 2


def _points_address(part: parts.Part) -> str:
    return part.mesh.GetPoints().__this__


def test_rgb_bytes_round_and_clip():
    colours = np.array([[0.0, 0.5, 1.0], [1.2, -0.1, 0.1], [0.8, 0.6, 0.2]])
    got = parts.rgb_bytes(colours)
    assert got.dtype == np.uint8
    np.testing.assert_array_equal(got, [[0, 128, 255], [255, 0, 26], [204, 153, 51]])  # 255 steps, not 256


def test_a_part_writes_its_points_in_place_and_nan_as_zero():
    part = parts.Part(3)
    assert part.n_points == 3 and part.mesh.n_points == 3
    address, stamp = _points_address(part), part.mesh.GetPoints().GetMTime()
    part.set_points(np.array([[1.0, 2.0, 3.0], [np.nan, 5.0, 6.0], [7.0, 8.0, 9.0]]))
    np.testing.assert_array_equal(part.mesh.points, [[1, 2, 3], [0, 5, 6], [7, 8, 9]])
    assert _points_address(part) == address and part.mesh.GetPoints().GetMTime() > stamp
    assert part.visible is False  # no actor yet: nothing to show or hide
    part.set_visible(True)
    assert part.visible is False


def test_an_empty_part_has_no_points_and_ignores_writes():
    part = parts.Part(0)
    assert part.n_points == 0 and part.mesh.n_points == 0
    part.set_points(np.zeros((0, 3)))
    assert part.mesh.n_points == 0


def test_visibility_follows_the_actor():
    part = parts.sphere_part(2, 0.1)
    assert part.visible is True
    part.set_visible(False)
    assert part.visible is False and part.actor.GetVisibility() == 0
    part.set_visible(True)
    assert part.visible is True


def _lighting(actor) -> tuple[float, float, float, float]:
    prop = actor.GetProperty()
    return prop.GetAmbient(), prop.GetDiffuse(), prop.GetSpecular(), prop.GetOpacity()


def test_surfaces_are_lit_the_same_opaque_way_and_default_to_white():
    cube = pv.Cube(x_length=0.1, y_length=0.1, z_length=0.1)
    for part in (parts.glyph_part(2, cube), parts.sphere_part(2, 0.1), parts.bone_part(np.array([[0, 1]]), 0.05)):
        assert _lighting(part.actor) == pytest.approx((0.35, 0.65, 0.0, 1.0))
        assert part.actor.GetProperty().GetColor() == (1.0, 1.0, 1.0)
    np.testing.assert_array_equal(parts.bone_part(np.array([[0, 1]]), 0.05).mesh.point_data["colors"], [[255] * 3])


def test_one_colour_or_a_colour_per_glyph():
    cube = pv.Cube(x_length=0.1, y_length=0.1, z_length=0.1)
    one = parts.glyph_part(2, cube, color=(0.2, 0.4, 0.6))
    assert one.actor.GetProperty().GetColor() == pytest.approx((0.2, 0.4, 0.6))
    assert one.actor.GetMapper().GetScalarVisibility() == 0 and "colors" not in one.mesh.point_data
    each = parts.glyph_part(2, cube, colors=np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), color=(0.2, 0.4, 0.6))
    mapper = each.actor.GetMapper()
    np.testing.assert_array_equal(each.mesh.point_data["colors"], [[255, 0, 0], [0, 0, 255]])
    assert mapper.GetScalarVisibility() == 1 and mapper.GetArrayName() == "colors"
    assert mapper.GetScalarMode() == SCALAR_MODE_USE_POINT_FIELD_DATA
    assert mapper.GetColorMode() == COLOR_MODE_DIRECT_SCALARS
    assert each.actor.GetProperty().GetColor() == (1.0, 1.0, 1.0)  # the per-glyph colours rule
    assert not mapper.GetScaling()  # drawn at the source's own size
    empty = parts.glyph_part(0, cube, colors=np.zeros((0, 3)))
    assert empty.actor.GetMapper().GetScalarVisibility() == 0 and empty.n_points == 0


def one_vertex_a_point(n: int) -> np.ndarray:
    """The cell array of ``n`` vertex cells, one per point: ``1 0 1 1 1 2 ...``."""
    return np.column_stack([np.ones(n, dtype=np.int64), np.arange(n)]).ravel()


def test_spheres_are_vertex_cells_with_float32_radii_and_nan_rows_get_radius_zero():
    part = parts.sphere_part(4, 0.25)
    np.testing.assert_array_equal(one_vertex_a_point(3), [1, 0, 1, 1, 1, 2])
    np.testing.assert_array_equal(part.mesh.verts, one_vertex_a_point(4))
    radii = part.mesh.point_data["radius"]
    assert radii.dtype == np.float32
    np.testing.assert_array_equal(radii, [0.25] * 4)
    assert part.drawn.tolist() == [True] * 4
    address = _points_address(part)
    points = np.array([[1.0, 2.0, 3.0], [np.nan, 1.0, 1.0], [4.0, 5.0, 6.0], [1.0, 1.0, np.inf]])
    part.set_points(points)
    np.testing.assert_array_equal(part.mesh.points, [[1, 2, 3], [0, 0, 0], [4, 5, 6], [0, 0, 0]])
    np.testing.assert_array_equal(part.mesh.point_data["radius"], [0.25, 0.0, 0.25, 0.0])
    assert part.drawn.tolist() == [True, False, True, False]
    assert _points_address(part) == address
    part.set_points(points[::-1].copy())
    assert part.drawn.tolist() == [False, True, False, True]


def test_sizes_change_the_radius_of_some_points_drawn_now_and_later_not_of_missing_ones():
    part = parts.sphere_part(4, 0.25)
    assert part.sizes.dtype == np.float32 and part.sizes.tolist() == [0.25] * 4
    part.set_points(np.array([[0.0, 0, 0], [np.nan, 0, 0], [1, 1, 1], [2, 2, 2]]))
    radius = part.mesh.GetPointData().GetArray("radius")
    stamp = radius.GetMTime()
    part.set_sizes(np.array([1, 2]), 0.5)  # the missing point 1 stays undrawn, point 2 grows at once
    assert radius.GetMTime() > stamp  # VTK told
    np.testing.assert_array_equal(part.mesh.point_data["radius"], [0.25, 0.0, 0.5, 0.25])
    np.testing.assert_array_equal(part.sizes, [0.25, 0.5, 0.5, 0.25])
    assert part.radius == 0.25  # the part's own radius kept
    part.set_points(np.arange(12.0).reshape(4, 3))  # every point drawn, each at its size
    np.testing.assert_array_equal(part.mesh.point_data["radius"], [0.25, 0.5, 0.5, 0.25])
    part.set_sizes(np.array([2]), part.radius)
    np.testing.assert_array_equal(part.mesh.point_data["radius"], [0.25, 0.5, 0.25, 0.25])
    empty = parts.sphere_part(0, 0.1)
    empty.set_sizes(np.zeros(0, np.int64), 0.2)  # nothing to size
    assert empty.sizes.shape == (0,)


def test_an_empty_sphere_part_draws_nothing():
    part = parts.sphere_part(0, 0.1, colors=np.zeros((0, 3)))
    part.set_points(np.zeros((0, 3)))
    assert part.n_points == 0 and part.drawn.shape == (0,)


def test_segments_join_their_pairs_with_one_colour_per_segment():
    pairs = np.array([[0, 1], [2, 3]])
    part = parts.segments_part(4, pairs, colors=np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))
    np.testing.assert_array_equal(part.mesh.lines, [2, 0, 1, 2, 2, 3])
    np.testing.assert_array_equal(part.mesh.cell_data["colors"], [[255, 0, 0], [0, 255, 0]])
    mapper = part.actor.GetMapper()
    assert mapper.GetScalarVisibility() == 1 and mapper.GetScalarMode() == SCALAR_MODE_USE_CELL_DATA
    assert mapper.GetColorMode() == COLOR_MODE_DIRECT_SCALARS
    assert _lighting(part.actor) == pytest.approx((1.0, 0.0, 0.0, 1.0))  # flat: lines have no normals
    assert part.actor.GetProperty().GetLineWidth() == 2.0
    assert part.actor.GetProperty().GetColor() == (1.0, 1.0, 1.0)
    one = parts.segments_part(4, pairs, color=(0.5, 0.25, 1.0), width=3.0, opacity=0.5)
    assert one.actor.GetMapper().GetScalarVisibility() == 0
    assert one.actor.GetProperty().GetColor() == (0.5, 0.25, 1.0)
    assert one.actor.GetProperty().GetLineWidth() == 3.0 and one.actor.GetProperty().GetOpacity() == 0.5
    assert parts.segments_part(4, pairs).actor.GetProperty().GetColor() == (1.0, 1.0, 1.0)


def test_segments_without_points_or_pairs_have_no_lines():
    no_points = parts.segments_part(0, np.array([[0, 1]]))
    assert no_points.mesh.n_lines == 0
    no_pairs = parts.segments_part(3, np.zeros((0, 2)), colors=np.zeros((0, 3)))
    assert no_pairs.mesh.n_lines == 0 and no_pairs.actor.GetMapper().GetScalarVisibility() == 0


def test_bones_run_between_their_joints_as_float32_directions_and_scales():
    joints = np.array([[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.3, 2.0, 0.4], [5.0, 5.0, 5.0]])
    part = parts.bone_part(np.array([[0, 1], [1, 2], [3, 3]]), 0.1, colors=np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]]))
    direction, scale = part.mesh.point_data["direction"], part.mesh.point_data["scale"]
    assert direction.dtype == np.float32 and scale.dtype == np.float32
    # before the first placing: unit x, no length, the radius
    np.testing.assert_array_equal(direction, [[1, 0, 0]] * 3)
    np.testing.assert_allclose(scale, [[0, 0.1, 0.1]] * 3, rtol=1e-6)
    np.testing.assert_array_equal(part.mesh.verts, one_vertex_a_point(3))
    address = _points_address(part)
    part.set_joints(joints)
    np.testing.assert_allclose(part.mesh.points, [[0, 1, 0], [0.15, 2, 0.2], [5, 5, 5]])
    # the zero-length bone keeps a zero direction (no NaN)
    np.testing.assert_allclose(part.mesh.point_data["direction"], [[0, 1, 0], [0.6, 0, 0.8], [0, 0, 0]], atol=1e-7)
    np.testing.assert_allclose(part.mesh.point_data["scale"], [[2, 0.1, 0.1], [0.5, 0.1, 0.1], [0, 0.1, 0.1]])
    np.testing.assert_array_equal(part.mesh.point_data["colors"], [[255, 0, 0], [0, 255, 0], [0, 0, 255]])
    assert _points_address(part) == address
    assert part.actor.GetMapper().GetScalarVisibility() == 1


def test_one_bone_colour_is_repeated_per_bone_and_no_bones_is_nothing():
    part = parts.bone_part(np.array([0, 1, 1, 2]), 0.1, color=(0.0, 0.5, 1.0))
    np.testing.assert_array_equal(part.pairs, [[0, 1], [1, 2]])
    np.testing.assert_array_equal(part.mesh.point_data["colors"], [[0, 128, 255]] * 2)
    assert part.actor.GetMapper().GetScalarVisibility() == 1
    empty = parts.bone_part(np.zeros((0, 2)), 0.1)
    empty.set_joints(np.zeros((1, 3)))
    assert empty.n_points == 0 and empty.pairs.shape == (0, 2) and not empty.mesh.point_data.keys()


def test_a_ring_is_a_closed_circle_of_48_chords_in_its_followers_plane():
    camera = vtkCamera()
    ring = parts.ring_part(0.5, camera, color=(0.2, 0.4, 0.6), width=3.0)
    assert isinstance(ring.actor, vtkFollower) and ring.actor.GetCamera() is camera
    assert ring.radius == 0.5 and isinstance(ring.radius, float) and ring.n_points == 1
    angles = np.arange(48) * (2 * np.pi / 48)  # a chord every 7.5 degrees, from +x anticlockwise
    np.testing.assert_allclose(
        ring.circle.points, 0.5 * np.column_stack([np.cos(angles), np.sin(angles), 0 * angles]), atol=1e-15
    )
    np.testing.assert_array_equal(ring.circle.lines, [49, *range(48), 0])  # one polyline, back to its start
    mapper = ring.actor.GetMapper()
    assert mapper.GetInput() is ring.circle and not mapper.GetScalarVisibility()
    prop = ring.actor.GetProperty()
    assert (prop.GetAmbient(), prop.GetDiffuse(), prop.GetSpecular()) == (1.0, 0.0, 0.0)  # flat: its colour
    assert prop.GetColor() == pytest.approx((0.2, 0.4, 0.6)) and prop.GetLineWidth() == 3.0
    plain = parts.ring_part(2, camera)
    assert plain.radius == 2.0 and isinstance(plain.radius, float)
    assert plain.actor.GetProperty().GetColor() == (1.0, 1.0, 1.0) and plain.actor.GetProperty().GetLineWidth() == 2.5


def test_a_ring_follows_its_point_by_its_actors_position():
    ring = parts.ring_part(0.5, vtkCamera())
    address, circle = ring.mesh.GetPoints().__this__, ring.circle.points.copy()
    ring.set_points(np.array([[1.0, -2.0, 3.0]]))
    np.testing.assert_array_equal(ring.mesh.points, [[1.0, -2.0, 3.0]])
    assert ring.actor.GetPosition() == (1.0, -2.0, 3.0)
    ring.set_points(np.array([[np.nan, 4.0, 5.0]]))  # a gap: read as 0 (hide the ring)
    assert ring.actor.GetPosition() == (0.0, 4.0, 5.0)
    assert ring.mesh.GetPoints().__this__ == address
    np.testing.assert_array_equal(ring.circle.points, circle)  # the circle itself never moves


def _reference_tile(text: str, color, size: int) -> np.ndarray:
    """(h, w, 4) the text as VTK's text renderer draws it at 72 dpi (a point a pixel), shadowed, not bold."""
    prop = vtkTextProperty()
    prop.SetFontSize(size)
    prop.SetColor(*color)
    prop.SetShadow(True)
    image, extent = vtkImageData(), [0, 0]
    assert vtkTextRenderer().RenderString(prop, text, image, extent, 72)
    w_img, h_img, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h_img, w_img, 4)[: extent[1], : extent[0]]


def _atlas(part: LabelPart) -> np.ndarray:
    image = part.actor.GetTexture().GetInput()
    width, height, depth = image.GetDimensions()
    assert depth == 1
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, 4)


def test_labels_are_packed_into_one_texture_each_text_as_vtk_draws_it():
    texts = ["Ab", "", "Hello"]
    part = label_part(texts, color=(1.0, 0.5, 0.0), size=15)
    tiles = [_reference_tile("Ab", (1.0, 0.5, 0.0), 15), np.zeros((1, 1, 4), np.uint8)]
    tiles.append(_reference_tile("Hello", (1.0, 0.5, 0.0), 15))
    sizes = [(t.shape[1], t.shape[0]) for t in tiles]
    assert sizes[0][1] == sizes[2][1] == 15  # a point a pixel
    np.testing.assert_array_equal(part.widths(), [w for w, _ in sizes])
    atlas = _atlas(part)
    assert atlas.shape == (sum(h + 2 for _, h in sizes), max(w for w, _ in sizes) + 2, 4)
    coords = part.mesh.active_texture_coordinates.reshape(3, 4, 2) * [atlas.shape[1], atlas.shape[0]]
    row = 0
    for k, (tile, (w, h)) in enumerate(zip(tiles, sizes, strict=True)):
        np.testing.assert_allclose(coords[k], [(0, row), (w, row), (w, row + h), (0, row + h)], atol=1e-9)
        np.testing.assert_array_equal(atlas[row : row + h, :w], tile)
        assert not atlas[row + h : row + h + 2].any() and not atlas[row : row + h, w:].any()
        row += h + 2
    np.testing.assert_array_equal(part.mesh.faces, [4, 0, 1, 2, 3, 4, 4, 5, 6, 7, 4, 8, 9, 10, 11])
    assert part.n_points == 12
    assert part.actor.GetTexture().GetInterpolate() == 0


def test_labels_default_to_white_13_point_text():
    reference = _reference_tile("Ab", (1.0, 1.0, 1.0), 13)
    for part in (label_part(["Ab"]), LabelPart(["Ab"])):
        atlas = _atlas(part)
        np.testing.assert_array_equal(atlas[: reference.shape[0], : reference.shape[1]], reference)
        assert part.widths().tolist() == [reference.shape[1]]


def test_an_empty_text_and_no_texts_keep_a_texture():
    assert _atlas(label_part([""])).shape == (3, 3, 4)
    assert label_part([""]).widths().tolist() == [1]
    empty = label_part([])
    assert _atlas(empty).shape == (1, 3, 4) and empty.n_points == 0 and empty.widths().shape == (0,)
    empty.place(np.zeros((0, 2)), VIEW)


def test_new_texts_rebuild_the_texture():
    part = label_part(["a", "b"])
    part.set_texts(["Hello", "x"])
    assert part.texts == ["Hello", "x"]
    assert part.widths().tolist() == [_reference_tile(t, (1, 1, 1), 13).shape[1] for t in ("Hello", "x")]


VIEW = (400, 200)  # pixels: a display pixel (x, y) is the device point (x / 200 - 1, y / 100 - 1)


def _device(xy) -> np.ndarray:
    """(..., 2) display pixels of :data:`VIEW` -> (..., 3) the device points the quads hold."""
    xy = np.asarray(xy, dtype=np.float64)
    return np.stack([xy[..., 0] / 200.0 - 1.0, xy[..., 1] / 100.0 - 1.0, np.full(xy.shape[:-1], NEAR_DEPTH)], -1)


def test_device_points_map_the_view_onto_minus_one_to_one_at_the_near_depth():
    display = np.array([[0.0, 0.0], [400.0, 200.0], [100.0, 150.0], [-1e4, 50.0]])
    np.testing.assert_allclose(device_points(display, VIEW), _device(display), rtol=0, atol=1e-15)
    assert NEAR_DEPTH == -0.999  # just beyond the near plane (-1), in front of everything
    np.testing.assert_array_equal(device_points([3.0, 4.0], (8, 2)), [[-0.25, 3.0, NEAR_DEPTH]])  # one pixel: (1, 3)
    np.testing.assert_array_equal(device_points([[1.0, 0.5]], (1, 1)), [[1.0, 0.0, NEAR_DEPTH]])  # a view of 1 pixel


@pytest.mark.parametrize(("view", "expected"), [((0, 100), [-1.0, 0.0]), ((100, 0), [0.0, -1.0])])
def test_device_points_of_a_view_of_no_width_or_height_are_finite(view, expected):
    """A view not laid out yet (0 pixels wide or high) is taken as one pixel that way."""
    display = [[0.0, 50.0]] if view[0] == 0 else [[50.0, 0.0]]
    np.testing.assert_array_equal(device_points(display, view), [[*expected, NEAR_DEPTH]])


def test_labels_are_placed_at_their_anchors_plus_the_offset_on_whole_pixels_and_hidden_off_screen():
    part = label_part(["Ab", "Hello", "x"])
    w = part.widths()
    h = [_reference_tile(t, (1, 1, 1), 13).shape[0] for t in part.texts]
    assert part.heights().tolist() == h
    address = _points_address(part)
    assert part.view == (0, 0)
    part.place(np.array([[10.0, 20.0], [np.nan, 5.0], [100.2, 199.6]]), VIEW)
    quads = part.mesh.points.reshape(3, 4, 3)
    for k, (x, y) in ((0, (16.0, 24.0)), (2, (106.0, 204.0))):  # 106.2 and 203.6 on whole pixels
        corners = [(x, y), (x + w[k], y), (x + w[k], y + h[k]), (x, y + h[k])]
        np.testing.assert_allclose(part.corners[k], corners)
        np.testing.assert_allclose(quads[k], _device(corners), rtol=0, atol=1e-15)
    assert (part.corners[1] <= -1e4 + 100).all() and (quads[1, :, :2] < -40).all()  # left of and below any view
    assert part.view == VIEW
    part.place(np.array([[10.0, 20.0], [1.0, 2.0], [3.0, np.inf]]), VIEW, offset=(1.0, -2.0))
    np.testing.assert_allclose(part.corners[1, 0], (2.0, 0.0))
    np.testing.assert_allclose(part.corners[0, 2], (11.0 + w[0], 18.0 + h[0]))
    np.testing.assert_allclose(quads, _device(part.corners), rtol=0, atol=1e-15)
    assert (part.corners[2] <= -1e4 + 100).all()
    assert _points_address(part) == address


def test_quads_are_written_again_only_when_they_or_the_view_change():
    """The points (and the renderer's copy of them) are left alone by a placement that
    changes nothing: a legend fixed to the view costs nothing while the camera moves."""
    part = label_part(["Ab", "x"])
    anchors = np.array([[10.0, 20.0], [30.0, 40.0]])
    part.place(anchors, VIEW)
    written = part.mesh.GetPoints().GetMTime()
    before = np.array(part.mesh.points)
    part.place(anchors.copy(), VIEW)
    assert part.mesh.GetPoints().GetMTime() == written
    part.place(anchors, (800, 200))  # the same pixels of a wider view: other device points
    assert part.mesh.GetPoints().GetMTime() > written and part.view == (800, 200)
    np.testing.assert_allclose(part.mesh.points[:, 0], (before[:, 0] + 1.0) / 2 - 1.0)
    written = part.mesh.GetPoints().GetMTime()
    part.place(anchors + np.array([0.0, 1.0]), (800, 200))  # one pixel up
    assert part.mesh.GetPoints().GetMTime() > written
    np.testing.assert_allclose(part.mesh.points[:, 1] - before[:, 1], 0.01)


def test_labels_draw_last_in_the_opaque_pass_with_the_texels_own_colours_and_no_bounds():
    part = label_part(["Ab"])
    assert part.draw_last and part.actor.GetForceOpaque() and not part.actor.GetUseBounds()
    prop = part.actor.GetProperty()
    assert not prop.GetLighting() and prop.GetColor() == (1.0, 1.0, 1.0)
    assert not part.actor.GetMapper().GetScalarVisibility()


def _renderer_with(*props) -> vtkRenderer:
    renderer = vtkRenderer()
    for prop in props:
        renderer.AddViewProp(prop)
    return renderer


def _actor_of(data) -> vtkActor:
    mapper = vtkPolyDataMapper()
    if data is not None:
        mapper.SetInputDataObject(0, data)
    actor = vtkActor()
    actor.SetMapper(mapper)
    return actor


def test_a_renderer_draws_anything_only_with_a_visible_prop_that_has_points():
    one_point = pv.PolyData(np.zeros((1, 3)))
    empty = _actor_of(pv.PolyData())
    hidden = _actor_of(one_point)
    hidden.SetVisibility(False)
    assert parts.draws_anything(_renderer_with()) is False
    assert parts.draws_anything(_renderer_with(empty)) is False
    assert parts.draws_anything(_renderer_with(hidden, empty)) is False
    assert parts.draws_anything(_renderer_with(hidden, _actor_of(one_point))) is True
    assert parts.draws_anything(_renderer_with(empty, vtkAxesActor())) is True  # no mapper: it draws itself
    assert parts.draws_anything(_renderer_with(empty, vtkActor())) is True  # a mapper to come
    assert parts.draws_anything(_renderer_with(_actor_of(None))) is True  # an input to come
    assert parts.draws_anything(_renderer_with(_actor_of(vtkTable()))) is True  # no points to count


def test_a_sphere_part_coloured_per_point_holds_its_colour_array_written_in_place():
    part = parts.sphere_part(3, 0.1, colors=np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]))
    array = part.mesh.GetPointData().GetArray("colors")
    stamp = array.GetMTime()
    np.testing.assert_array_equal(part.colors, [[255, 0, 0], [0, 255, 0], [0, 0, 255]])
    part.colors[:] = [[1, 2, 3], [4, 5, 6], [7, 8, 9]]
    np.testing.assert_array_equal(vtk_to_numpy(array), [[1, 2, 3], [4, 5, 6], [7, 8, 9]])  # VTK's own array
    assert array.GetMTime() > stamp  # marked modified: drawn anew
    assert parts.sphere_part(3, 0.1, color=(1.0, 0.0, 0.0)).colors is None
    assert parts.sphere_part(0, 0.1, np.zeros((0, 3))).colors is None
