"""The problem marks (app/scene/problem_marks.py, issue 24) on the tiny synthetic skeleton
(:mod:`tests.tiny_scene`): a flat sphere in its level's colour around each joint the checks
flag at the frame, drawn in front of everything, levels below the chosen one left out, nothing for
flags of another motion."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

from gmr_studio.app.model.problems import LEVEL_COLOURS
from gmr_studio.app.scene.problem_marks import ProblemMarks
from gmr_studio.app.scene.vtk_parts import draws_anything
from tests.tiny_scene import FIGURE_SIZE, figure_motion, holds, look_down_at, picture, scene_of, snapshot_of

pytestmark = pytest.mark.gui


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
            assert part.radius == pytest.approx(1.45 * 0.016 * FIGURE_SIZE)  # just around the joint's sphere
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
    flagged a warning: a disc of flat orange 1.45 joint radii round (18.6 pixels) over the
    yellow wire ring, which shows around it; at a frame without a flag, no orange."""
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)
        scene.set_selection(2)
        marks = marks_in(scene, flags_of({(0, 2): 2}))
        scene.show_frame(0)
        image = picture(scene)
        orange = (np.abs(image - np.rint(np.array(LEVEL_COLOURS[2]) * 255)) <= 2).all(axis=-1)
        rows, columns = np.nonzero(orange)
        reach = np.hypot(rows - 100, columns - 100)
        assert 17.5 <= reach.max() <= 19.5
        assert orange[100, 83:118].all()  # the whole disc, the ring's lines under it hidden
        yellow = (image[..., 0] > 150) & (image[..., 1] > 120) & (image[..., 2] < 100) & ~orange
        assert yellow[100, 120:124].any() and yellow[100, 76:80].any()  # the ring around it
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
        assert 17.5 <= np.hypot(rows - 100, columns - 100).max() <= 19.5 and red[100, 85:116].all()
        assert (image[~red] >= 250).all(axis=-1).mean() > 0.95  # the board covers the rest: the figure hidden
        assert not draws_anything(scene.front_renderer)  # no second layer to draw
        marks.set_visible(False)
        assert (picture(scene) >= 250).all()  # without the mark, only the board


def test_the_marks_box_is_the_documents_joints_grown_by_a_marks_radius():
    """The marks are drawn at flagged joints only, always within the document's joints at
    every frame grown by their radius (1.45 joint radii); no flags, no part: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of
    from gmr_studio.app.scene.figure import JOINT_RADIUS

    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        np.testing.assert_array_equal(marks_in(scene, None).extent(), EMPTY_BOX)
        marks = marks_in(scene, FLAGS)
        box = marks.extent()
        pad = 1.45 * JOINT_RADIUS * FIGURE_SIZE
        np.testing.assert_allclose(box, box_of(snapshot.positions, pad), rtol=0, atol=1e-15)
        assert box[1, 0] == pytest.approx(0.8 + 0.1 + pad)  # the hand at the last frame
