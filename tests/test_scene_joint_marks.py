"""What the view draws at joints (app/scene/highlight.py, app/scene/problem_marks.py) on the
tiny synthetic skeleton (:mod:`tests.tiny_scene`): the audit's red translucent spheres around
the joints it names (those the document has), following the frame; the alignment dialog's
pivot, a sphere on a vertical line through a point; and the checks' marks, a flat disc in its
level's colour around each joint flagged at the frame, seen in front of everything, levels
below the chosen one left out, nothing for flags of another motion."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

from gmr_studio.app.model.problems import LEVEL_COLOURS
from gmr_studio.app.scene.figure import JOINT_RADIUS
from gmr_studio.app.scene.highlight import HIGHLIGHT_COLOUR, HIGHLIGHT_RADIUS, PIVOT_COLOR, JointsHighlight, PivotMarker
from gmr_studio.app.scene.problem_marks import MARK_RADIUS, ProblemMarks
from gmr_studio.app.scene.vtk_parts import draws_anything
from tests.tiny_scene import FIGURE_SIZE, figure_motion, holds, look_down_at, picture, scene_of, snapshot_of

pytestmark = pytest.mark.gui


# ---------------------------------------------------------------------- the audit's highlight
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
        assert part.radius == pytest.approx(HIGHLIGHT_RADIUS * FIGURE_SIZE) and HIGHLIGHT_RADIUS > JOINT_RADIUS
        prop = part.actor.GetProperty()
        assert prop.GetColor() == pytest.approx(HIGHLIGHT_COLOUR)
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
    assert prop.GetColor() == pytest.approx(PIVOT_COLOR) and not prop.GetLighting()
    return np.asarray(part.actor.GetMapper().GetSource().GetPoints().GetData()).reshape(-1, 3)


@pytest.mark.parametrize("up_axis", [1, 2])
def test_the_pivot_is_a_sphere_on_a_vertical_line_through_the_point(up_axis):
    point = np.array([0.3, -0.2, 0.5])
    size = FIGURE_SIZE
    with scene_of(snapshot_of(figure_motion())) as scene:
        points = _pivot_points(scene, point, up_axis) - point
        across = [a for a in (0, 1, 2) if a != up_axis]
        along, radial = points[:, up_axis], np.linalg.norm(points[:, across], axis=1)
        # a vertical line as long above the point as below, longer than the figure is high
        reach = along.max()
        assert along.min() == pytest.approx(-reach) and reach > 0.4 * size
        # a sphere round the point, wider than the line and larger than a joint
        sphere = radial.max()
        assert JOINT_RADIUS * size < sphere < 0.1 * size
        assert np.linalg.norm(points[np.abs(along) <= sphere], axis=1).max() == pytest.approx(sphere, rel=0.05)
        # the line beyond the sphere: a thin tube along the up axis, centred on the point
        tube = np.abs(along) > 1.2 * sphere
        assert radial[tube].max() < 0.4 * sphere and np.abs(along[tube]).max() == pytest.approx(reach)


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
    disc of the highlight's radius, the joint's blue showing through at its centre."""
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)
        plain = picture(scene)
        highlight = JointsHighlight()
        highlight.names = ("Chest",)
        scene.add_drawable(highlight)
        image = picture(scene)
        reddened = (image[..., 0] - plain[..., 0] > 40) & (image[..., 0] > image[..., 1] + 40)
        rows, columns = np.nonzero(reddened)
        radius = HIGHLIGHT_RADIUS * FIGURE_SIZE * 1000
        assert radius - 1.0 <= np.hypot(rows - 100, columns - 100).max() <= radius + 1.5
        assert reddened[100, 100] and image[100, 100, 2] > plain[2, 2, 2] + 20  # blue through the red
        assert not reddened[:, : int(100 - radius - 2)].any() and not reddened[:, int(100 + radius + 3) :].any()


def _vtk_bounds(actor) -> np.ndarray:
    bounds = np.array(actor.GetBounds())
    return np.stack([bounds[0::2], bounds[1::2]])


def test_the_highlights_boxes_hold_the_spheres_at_every_frame_and_the_pivots_line():
    """A highlight's box is the document's joints at every frame grown by the spheres'
    radius; the pivot's, its point grown by the line's half length, which holds the sphere
    and the tube; nothing built: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of

    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        highlight = JointsHighlight()
        scene.add_drawable(highlight)
        np.testing.assert_array_equal(highlight.extent(), EMPTY_BOX)  # no joint named: no part
        highlight.names = ("Head", "Hand")
        scene.redraw(highlight)
        box = highlight.extent()
        np.testing.assert_allclose(box, box_of(snapshot.positions, HIGHLIGHT_RADIUS * FIGURE_SIZE), rtol=0, atol=1e-15)
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
        np.testing.assert_allclose(box.mean(axis=0), [0.1, 0.2, 0.3])  # around the point, a cube
        assert np.ptp(np.diff(box, axis=0)) == pytest.approx(0.0, abs=1e-12)
        drawn = _vtk_bounds(pivot.parts["pivot"].actor)
        assert (drawn[0] >= box[0] - 1e-6).all() and (drawn[1] <= box[1] + 1e-6).all()
        assert drawn[1, scene.up_axis] == pytest.approx(box[1, scene.up_axis])  # the line reaches the box's top


# ------------------------------------------------------------------------ the checks' marks
def flags_of(levels: dict[tuple[int, int], int], n_frames: int = 3, n_joints: int = 6) -> np.ndarray:
    """(F, J) int8 levels: ``{(frame, joint): level}``, 0 elsewhere."""
    flags = np.zeros((n_frames, n_joints), np.int8)
    for (frame, joint), level in levels.items():
        flags[frame, joint] = level
    return flags


#: frame 0: Head a warning, Hand an error; frame 1: Hips info, Hand an error; frame 2 clean
FLAGS = flags_of({(0, 3): 2, (0, 5): 3, (1, 1): 1, (1, 5): 3})


def marks_in(scene, flags: np.ndarray | None, min_level: int | None = None) -> ProblemMarks:
    marks = ProblemMarks()
    marks.flags = flags
    if min_level is not None:
        marks.min_level = min_level
    scene.add_drawable(marks)
    return marks


def test_each_level_flagged_gets_a_flat_part_in_its_colour_in_the_main_renderer():
    with scene_of(snapshot_of(figure_motion())) as scene:
        marks = marks_in(scene, FLAGS)
        assert marks.levels == (1, 2, 3) and set(marks.parts) == {"problems_1", "problems_2", "problems_3"}
        for level in (1, 2, 3):
            part = marks.parts[f"problems_{level}"]
            assert holds(scene.plotter.renderer, part.actor) and not holds(scene.front_renderer, part.actor)
            assert part.n_points == 6  # a sphere per joint, hidden where not flagged
            assert part.radius == pytest.approx(MARK_RADIUS * FIGURE_SIZE)
            assert JOINT_RADIUS < MARK_RADIUS < 2 * JOINT_RADIUS  # just around the joint's sphere
            prop = part.actor.GetProperty()
            assert prop.GetColor() == pytest.approx(LEVEL_COLOURS[level]) and not prop.GetLighting()


def test_the_joints_flagged_at_the_frame_are_drawn_at_their_positions():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        marks = marks_in(scene, FLAGS)
        expected = {0: {1: [], 2: [3], 3: [5]}, 1: {1: [1], 2: [], 3: [5]}, 2: {1: [], 2: [], 3: []}}
        for frame in (0, 1, 2, 0):
            scene.show_frame(frame)
            assert {level: joints.tolist() for level, joints in marks.flagged(frame).items()} == expected[frame]
            for level, joints in expected[frame].items():
                part = marks.parts[f"problems_{level}"]
                drawn = np.zeros(6, bool)
                drawn[joints] = True
                np.testing.assert_array_equal(part.drawn, drawn)
                np.testing.assert_allclose(part.mesh.points[drawn], snapshot.positions[frame, joints])
                assert part.visible == bool(joints)  # a level with nothing flagged here is hidden


def test_levels_below_the_chosen_one_and_levels_never_flagged_get_no_part():
    with scene_of(snapshot_of(figure_motion())) as scene:
        assert ProblemMarks().min_level == 1  # the Problems model's default (app/model/problems.py): all levels
        assert marks_in(scene, FLAGS, min_level=2).levels == (2, 3)
        assert marks_in(scene, FLAGS, min_level=3).levels == (3,)
        only_info = marks_in(scene, flags_of({(2, 0): 1}))
        assert only_info.levels == (1,) and set(only_info.parts) == {"problems_1"}
        scene.show_frame(2)
        assert {k: v.tolist() for k, v in only_info.flagged(2).items()} == {1: [0]}
        assert only_info.parts["problems_1"].visible
        assert marks_in(scene, flags_of({})).levels == ()


def test_a_hidden_drawing_keeps_its_marks_hidden_at_a_new_frame():
    with scene_of(snapshot_of(figure_motion())) as scene:
        marks = marks_in(scene, FLAGS)
        marks.set_visible(False)
        marks.show_frame(1)
        assert not any(part.visible for part in marks.parts.values())
        marks.set_visible(True)
        marks.show_frame(1)
        assert [marks.parts[f"problems_{level}"].visible for level in (1, 2, 3)] == [True, False, True]


def test_no_marks_without_flags_a_snapshot_or_with_flags_of_another_motion():
    with scene_of(snapshot_of(figure_motion())) as scene:
        for flags in (None, FLAGS[:, :5], FLAGS[:2], FLAGS[None]):
            marks = marks_in(scene, flags)
            assert marks.levels == () and marks.parts == {}
            assert marks.flagged(0) == {}
            marks.show_frame(0)  # nothing to write
    with scene_of(None) as scene:
        marks = ProblemMarks()
        marks.flags = FLAGS
        marks.build(scene)
        assert marks.levels == () and marks.parts == {} and marks.flagged(0) == {}


def test_the_picture_a_flagged_joint_in_its_flat_colour_over_the_ring():
    """Chest (frame 0, at (0, 0.2)) seen from above, 1000 pixels a unit, selected and
    flagged a warning: a disc of flat orange just around the joint over the yellow wire
    ring, which shows around it; at a frame without a flag, no orange."""
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)
        scene.set_selection(2)
        marks = marks_in(scene, flags_of({(0, 2): 2}))
        scene.show_frame(0)
        image = picture(scene)
        orange = (np.abs(image - np.rint(np.array(LEVEL_COLOURS[2]) * 255)) <= 2).all(axis=-1)
        rows, columns = np.nonzero(orange)
        reach = np.hypot(rows - 100, columns - 100)
        radius = MARK_RADIUS * FIGURE_SIZE * 1000
        assert radius - 1.0 <= reach.max() <= radius + 1.0
        inner = int(radius) - 1
        assert orange[100, 100 - inner : 100 + inner + 1].all()  # the whole disc, the ring's lines under it hidden
        yellow = (image[..., 0] > 150) & (image[..., 1] > 120) & (image[..., 2] < 100) & ~orange
        ring = scene.figure.parts["selection"].radius * 1000
        outside = [round(100 + ring), round(100 - ring)]
        assert yellow[100, outside[0] - 2 : outside[0] + 3].any() and yellow[100, outside[1] - 2 : outside[1] + 3].any()
        scene.show_frame(2)
        assert not marks.flagged(2)[2].size
        image = picture(scene)
        assert not (np.abs(image - np.rint(np.array(LEVEL_COLOURS[2]) * 255)) <= 2).all(axis=-1).any()


def test_a_flagged_joint_shows_through_what_is_in_front_of_it_and_needs_no_second_layer():
    """Chest flagged an error, seen from above through an opaque white board between it and
    the camera: the board hides the figure but not the red disc; the front layer is not drawn."""
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)
        marks = marks_in(scene, flags_of({(0, 2): 3}))
        scene.plotter.add_mesh(pv.Plane(center=(0.0, 0.2, 0.3), i_size=1.0, j_size=1.0), color="white", lighting=False)
        scene.show_frame(0)
        image = picture(scene)
        red = (np.abs(image - np.rint(np.array(LEVEL_COLOURS[3]) * 255)) <= 2).all(axis=-1)
        rows, columns = np.nonzero(red)
        radius = MARK_RADIUS * FIGURE_SIZE * 1000
        assert radius - 1.0 <= np.hypot(rows - 100, columns - 100).max() <= radius + 1.0
        assert red[100, 100 - int(radius) + 2 : 100 + int(radius) - 1].all()
        assert (image[~red] >= 250).all(axis=-1).mean() > 0.95  # the board covers the rest: the figure hidden
        assert not draws_anything(scene.front_renderer)  # no second layer to draw
        marks.set_visible(False)
        assert (picture(scene) >= 250).all()  # without the mark, only the board


def test_the_marks_box_is_the_documents_joints_grown_by_a_marks_radius():
    """The marks are drawn at flagged joints only, always within the document's joints at
    every frame grown by their radius; no flags, no part: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of

    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        np.testing.assert_array_equal(marks_in(scene, None).extent(), EMPTY_BOX)
        marks = marks_in(scene, FLAGS)
        box = marks.extent()
        pad = MARK_RADIUS * FIGURE_SIZE
        np.testing.assert_allclose(box, box_of(snapshot.positions, pad), rtol=0, atol=1e-15)
        assert box[1, 0] == pytest.approx(0.8 + 0.1 + pad)  # the hand at the last frame
