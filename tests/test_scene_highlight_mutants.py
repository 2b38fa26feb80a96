"""The highlights (app/scene/highlight.py, issue 24) on the tiny synthetic skeleton
(:mod:`tests.tiny_scene`): the audit's red translucent spheres around the joints it names
(those the document has), following the frame, and the alignment dialog's pivot, a sphere
on a vertical line built where the pivot is."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.scene.highlight import JointsHighlight, PivotMarker
from tests.tiny_scene import FIGURE_SIZE, figure_motion, holds, look_down_at, picture, scene_of, snapshot_of

pytestmark = pytest.mark.gui


def test_a_new_highlight_rings_nothing():
    highlight = JointsHighlight()
    assert highlight.names == () and highlight.joints.shape == (0,) and highlight.part is None
    highlight.show_frame(0)  # nothing to write
    assert highlight.parts == {}


def test_the_named_joints_the_document_has_are_ringed_in_red_and_follow_the_frame():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        highlight = JointsHighlight()
        highlight.names = ("Head", "Tail", "Hips")  # no Tail here: left out
        scene.add_drawable(highlight)
        assert highlight.joints.tolist() == [3, 1] and highlight.joints.dtype == np.int64
        part = highlight.part
        assert part is highlight.parts["highlight"] and part.n_points == 2 and part.visible
        assert holds(scene.plotter.renderer, part.actor)
        assert part.radius == pytest.approx(0.04 * FIGURE_SIZE)
        prop = part.actor.GetProperty()
        assert prop.GetColor() == pytest.approx((1.0, 0.15, 0.15))
        assert 0.0 < prop.GetOpacity() < 1.0  # translucent: the joint shows through
        np.testing.assert_allclose(part.mesh.points, snapshot.positions[0, [3, 1]])
        scene.show_frame(2)
        np.testing.assert_allclose(part.mesh.points, snapshot.positions[2, [3, 1]])
        highlight.names = ("Tail",)
        scene.redraw(highlight)
        assert highlight.joints.shape == (0,) and highlight.part is None
        scene.show_frame(1)  # nothing drawn, nothing to write


def test_without_a_snapshot_no_joint_is_ringed():
    with scene_of(None) as scene:
        highlight = JointsHighlight()
        highlight.names = ("Head",)
        highlight.build(scene)
        assert highlight.joints.shape == (0,) and highlight.part is None


def _pivot_points(scene, point, up_axis: int) -> np.ndarray:
    """The pivot marker's (N, 3) points as built for ``point`` with ``up_axis`` up."""
    scene.up_axis = up_axis
    pivot = PivotMarker()
    pivot.point = np.asarray(point, dtype=np.float64)
    scene.add_drawable(pivot)
    part = pivot.parts["pivot"]
    assert part.n_points == 1 and part.visible  # one glyph, at the origin: the marker as built
    np.testing.assert_array_equal(part.mesh.points, [[0.0, 0.0, 0.0]])
    prop = part.actor.GetProperty()
    assert prop.GetColor() == pytest.approx((1.0, 0.25, 0.85)) and not prop.GetLighting()
    return np.asarray(part.actor.GetMapper().GetSource().GetPoints().GetData()).reshape(-1, 3)


@pytest.mark.parametrize("up_axis", [1, 2])
def test_the_pivot_is_a_sphere_on_a_vertical_line_through_the_point(up_axis):
    point = np.array([0.3, -0.2, 0.5])
    size = FIGURE_SIZE
    with scene_of(snapshot_of(figure_motion())) as scene:
        points = _pivot_points(scene, point, up_axis) - point
        across = [a for a in (0, 1, 2) if a != up_axis]
        along, radial = points[:, up_axis], np.linalg.norm(points[:, across], axis=1)
        # the line reaches 0.6 of the size above and below the point
        assert along.max() == pytest.approx(0.6 * size) and along.min() == pytest.approx(-0.6 * size)
        # the sphere: 0.03 of the size around the point
        assert radial.max() == pytest.approx(0.03 * size, rel=0.02)
        sphere = np.linalg.norm(points, axis=1) < 0.031 * size
        assert np.linalg.norm(points[sphere], axis=1).max() == pytest.approx(0.03 * size, rel=0.02)
        # the tube around the line, beyond the sphere: 0.006 of the size thick
        tube = np.abs(along) > 0.04 * size
        assert radial[tube].max() == pytest.approx(0.006 * size, rel=0.02)
        assert np.abs(along[tube]).max() == pytest.approx(0.6 * size)


def test_the_pivot_stays_put_and_is_not_drawn_without_a_point_or_a_snapshot():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        pivot = PivotMarker()
        scene.add_drawable(pivot)
        assert pivot.point is None and pivot.parts == {}
        pivot.point = np.array([0.1, 0.2, 0.3])
        scene.redraw(pivot)
        before = np.asarray(pivot.parts["pivot"].mesh.points).copy()
        scene.show_frame(2)  # the pivot does not follow the frame
        np.testing.assert_array_equal(pivot.parts["pivot"].mesh.points, before)
    with scene_of(None) as scene:
        pivot = PivotMarker()
        pivot.point = np.array([0.1, 0.2, 0.3])
        pivot.build(scene)
        assert pivot.parts == {}


def test_the_picture_a_red_translucent_sphere_the_joint_seen_through_it():
    """Chest (frame 0, at (0, 0.2)) seen from above, 1000 pixels a unit, highlighted: a red
    disc 0.04 of the size round (32 pixels), the joint's blue showing through at its centre."""
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)
        plain = picture(scene)
        highlight = JointsHighlight()
        highlight.names = ("Chest",)
        scene.add_drawable(highlight)
        image = picture(scene)
        reddened = (image[..., 0] - plain[..., 0] > 40) & (image[..., 0] > image[..., 1] + 40)
        rows, columns = np.nonzero(reddened)
        assert 31.0 <= np.hypot(rows - 100, columns - 100).max() <= 33.5
        assert reddened[100, 100] and image[100, 100, 2] > plain[2, 2, 2] + 20  # blue through the red
        assert not reddened[:, :66].any() and not reddened[:, 135:].any()


def _vtk_bounds(actor) -> np.ndarray:
    bounds = np.array(actor.GetBounds())
    return np.stack([bounds[0::2], bounds[1::2]])


def test_the_highlights_boxes_hold_the_spheres_at_every_frame_and_the_pivots_line():
    """A highlight's box is the document's joints at every frame grown by the spheres'
    radius; the pivot's, its point grown by the line's half length (0.6 of the size), which
    holds the sphere and the tube; nothing built: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of

    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        highlight = JointsHighlight()
        scene.add_drawable(highlight)
        np.testing.assert_array_equal(highlight.extent(), EMPTY_BOX)  # no joint named: no part
        highlight.names = ("Head", "Hand")
        scene.redraw(highlight)
        box = highlight.extent()
        np.testing.assert_allclose(box, box_of(snapshot.positions, 0.04 * FIGURE_SIZE), rtol=0, atol=1e-15)
        for frame in range(3):
            scene.show_frame(frame)
            drawn = _vtk_bounds(highlight.part.actor)
            assert (drawn[0] >= box[0] - 1e-12).all() and (drawn[1] <= box[1] + 1e-12).all(), frame
        pivot = PivotMarker()
        scene.add_drawable(pivot)
        np.testing.assert_array_equal(pivot.extent(), EMPTY_BOX)  # no point: no part
        pivot.point = np.array([0.1, 0.2, 0.3])
        scene.redraw(pivot)
        box = pivot.extent()
        np.testing.assert_allclose(box, [[0.1 - 0.48, 0.2 - 0.48, 0.3 - 0.48], [0.1 + 0.48, 0.2 + 0.48, 0.3 + 0.48]])
        drawn = _vtk_bounds(pivot.parts["pivot"].actor)
        assert (drawn[0] >= box[0] - 1e-6).all() and (drawn[1] <= box[1] + 1e-6).all()
        assert drawn[1, scene.up_axis] == pytest.approx(box[1, scene.up_axis])  # the line reaches the box's top
