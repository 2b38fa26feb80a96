"""Screen-space labels in a scene (app/scene/labels.py, drawn after everything else by the scene):
placed at every render at the joints' display pixels, drawn after every other actor, in
front of the figure."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.scene.labels import LabelPart, labels_in_a_row
from tests.tiny_scene import FIGURE_NAMES, figure_motion, picture, props_of, scene_of, snapshot_of

pytestmark = pytest.mark.gui


def _labels(scene) -> LabelPart:
    return scene.parts["labels"]


def test_joint_labels_sit_at_the_joints_display_pixels_drawn_last_in_front_of_the_figure():
    with scene_of(snapshot_of(figure_motion(3)), size=(300, 300)) as scene:
        scene.set_overlay("labels", True)
        scene.show_frame(1)
        image = picture(scene)
        labels = _labels(scene)
        assert props_of(scene.plotter.renderer)[-1] is labels.actor  # drawn after everything else
        anchors = scene.display_positions(scene.snapshot.positions[1])
        np.testing.assert_array_equal(labels.corners[:, 0], np.round(anchors + np.array([6.0, 4.0])))
        assert labels.texts == list(FIGURE_NAMES)
        # each label's quad holds the device points of the pixels its corners say
        device = labels.mesh.points.reshape(-1, 4, 3)
        np.testing.assert_allclose((device[..., :2] + 1) / 2 * 300, labels.corners, atol=1e-9)
        assert labels.view == scene.display_size() == (300, 300)
        # a label's bright letters are on screen where its quad is (y from the top in the image)
        x0, y0 = labels.corners[3, 0].astype(int)  # Head's label
        w, h = int(labels.widths()[3]), int(labels.heights()[3])
        patch = image[300 - y0 - h : 300 - y0, x0 : x0 + w]
        assert (patch.min(axis=-1) > 200).sum() > 20
        scene.set_overlay("labels", False)
        without = picture(scene)[300 - y0 - h : 300 - y0, x0 : x0 + w]
        assert (without.min(axis=-1) > 200).sum() < (patch.min(axis=-1) > 200).sum() / 4


def test_labels_stay_last_when_other_drawables_are_built_again():
    with scene_of(snapshot_of(figure_motion(3))) as scene:
        scene.set_overlay("labels", True)
        renderer = scene.plotter.renderer
        last = props_of(renderer)[-1]
        assert last is _labels(scene).actor
        scene.redraw(scene.figure)  # the figure's actors made again, added at the end
        assert props_of(renderer)[-1] is _labels(scene).actor
        labels_of = [p for p in props_of(renderer) if p is _labels(scene).actor]
        assert len(labels_of) == 1  # moved, not added twice


def test_labels_of_a_drawing_after_a_front_layer_drawing_are_drawn_last_too():
    """A front-layer drawing (the classroom's) before a drawing with labels (a comparison's
    legend, added later): the labels after it are moved to the end as well."""
    from gmr_studio.app.scene.drawable import Drawing
    from gmr_studio.app.scene.labels import label_part
    from gmr_studio.app.scene.vtk_parts import sphere_part

    class InFront(Drawing):
        front = True

        def build(self, scene) -> None:
            super().build(scene)
            self.add("dot", sphere_part(1, 0.1))

        def show_frame(self, frame: int) -> None:
            pass

    class Tagged(Drawing):
        def build(self, scene) -> None:
            super().build(scene)
            self.add("tag", label_part(["tag"]))

        def show_frame(self, frame: int) -> None:
            pass

    class Plain(Drawing):  # a part not drawn last, after the labels' drawings
        def build(self, scene) -> None:
            super().build(scene)
            self.add("dot", sphere_part(1, 0.1))

        def show_frame(self, frame: int) -> None:
            pass

    with scene_of(snapshot_of(figure_motion(3))) as scene:
        scene.set_overlay("labels", True)
        scene.add_drawable(InFront())
        tagged, plain = Tagged(), Plain()
        scene.add_drawable(tagged)
        scene.add_drawable(plain)
        scene.redraw(scene.figure)  # the figure's actors made again, added at the end
        props = props_of(scene.plotter.renderer)
        assert props[-2:] == [_labels(scene).actor, tagged.parts["tag"].actor]
        assert props[-3] is scene.figure.parts[list(scene.figure.parts)[-1]].actor  # the rest in their order


class Bare:
    """A drawable that is not a :class:`Drawing` (the protocol only; no ``front``): a label
    of its own in the main renderer."""

    def __init__(self) -> None:
        self.parts: dict = {}
        self.visible = True
        self.scene = None

    def build(self, scene) -> None:
        from gmr_studio.app.scene.labels import label_part

        self.remove()
        self.scene = scene
        self.parts = {"tag": label_part(["bare"])}
        scene.plotter.renderer.AddViewProp(self.parts["tag"].actor)

    def show_frame(self, frame: int) -> None:
        pass

    def wanted(self, scene) -> bool:
        return True

    def set_visible(self, shown: bool) -> None:
        self.visible = shown
        for part in self.parts.values():
            part.actor.SetVisibility(shown)

    def remove(self) -> None:
        for part in self.parts.values():
            self.scene.plotter.renderer.RemoveViewProp(part.actor)
        self.parts = {}

    def extent(self):
        return np.array([[0.0, 0.0, 0.0], [0.0, 7.0, 0.0]])


def test_a_drawable_without_a_front_layer_is_in_the_main_renderer_its_labels_last_its_box_counted():
    with scene_of(snapshot_of(figure_motion(3))) as scene:
        scene.set_overlay("labels", True)
        bare = Bare()
        scene.add_drawable(bare)
        scene.redraw(scene.figure)
        assert props_of(scene.plotter.renderer)[-1] is bare.parts["tag"].actor
        box = scene.world_box()
        assert box is not None and box[1, 1] == 7.0  # its parts counted among the renderer's props, its box in


def _overlapping(boxes: np.ndarray) -> list[tuple[int, int]]:
    """Pairs of boxes (x0, y0, x1, y1) that share any pixel."""
    x0, y0, x1, y1 = boxes.T
    meet = (x0[:, None] < x1[None]) & (x0[None] < x1[:, None]) & (y0[:, None] < y1[None]) & (y0[None] < y1[:, None])
    return [(a, b) for a, b in zip(*np.nonzero(np.triu(meet, 1)), strict=True)]


def test_labels_crowding_one_point_take_its_free_sides_then_are_left_out():
    """Five labels of one point: the first wanted right and above it, then below, left and
    above, left and below; the fifth has no free side and is left out. A label far away
    keeps its first side."""
    from gmr_studio.app.scene.labels import spread_labels

    anchors = np.array([[100.0, 100.0]] * 5 + [[400.0, 100.0]])
    sizes = np.array([[40.0, 12.0]] * 6)
    corners = spread_labels(anchors, sizes, np.array([3, 0, 1, 2, 4, 5]))
    assert np.array_equal(corners[3], [106, 104]) and np.array_equal(corners[0], [106, 84])
    assert np.array_equal(corners[1], [54, 104]) and np.array_equal(corners[2], [54, 84])
    assert np.isnan(corners[4]).all() and np.array_equal(corners[5], [406, 104])
    shown = np.isfinite(corners).all(axis=1)
    assert _overlapping(np.column_stack([corners, corners + sizes])[shown]) == []
    # a point off screen (NaN) gets no label and takes no room
    corners = spread_labels(np.array([[np.nan, np.nan], [100.0, 100.0]]), sizes[:2], np.array([0, 1]))
    assert np.isnan(corners[0]).all() and np.array_equal(corners[1], [106, 104])


@pytest.mark.parametrize("source", ["demo", "cmu/subject01/01_01.bvh"])
def test_shown_joint_labels_never_overlap_and_the_selected_joints_is_shown(source):
    """Issue 40.8c: with labels on, around shoulders, hands and feet, no two shown labels'
    rectangles share a pixel (crowded names are left out, not overprinted); the selected
    joint's label is always among those shown, with its letters on screen."""
    from gmr_studio.app.model.loading import load_snapshot
    from gmr_studio.core.demo import MOTION_FILE, demo_folder
    from tests.conftest import shared_path

    path = demo_folder() / MOTION_FILE if source == "demo" else shared_path(source)
    snapshot = load_snapshot(path)
    motion = snapshot.motion
    hand = motion.names.index("LeftHand" if "LeftHand" in motion.names else "lhand")
    with scene_of(snapshot, size=(640, 400)) as scene:
        scene.set_overlay("labels", True)
        scene.set_selection(hand)
        for frame in (0, motion.n_frames // 3, motion.n_frames - 1):
            scene.show_frame(frame)
            image = picture(scene)
            labels = _labels(scene)
            boxes = np.column_stack([labels.corners[:, 0], labels.corners[:, 2]])
            shown = boxes[:, 0] > -1000  # the others are parked off screen
            assert _overlapping(boxes[shown]) == []
            assert shown.sum() >= motion.n_joints // 3  # thinned where crowded, not emptied
            assert shown[hand]
            x0, y0, x1, y1 = boxes[hand].astype(int)
            patch = image[400 - y1 : 400 - y0, x0:x1]
            assert (patch.min(axis=-1) > 200).sum() > 20  # its letters, white on the dark ground


def test_labels_in_a_row_keep_their_places_unless_they_would_overlap():
    widths = np.array([20.0, 30.0, 30.0, 24.0, 16.0])
    lefts = np.array([100.0, 102.0, 104.0, 400.0, 300.0])  # three poses at one spot, two apart
    placed = labels_in_a_row(lefts, widths, 8.0, 1000.0)
    np.testing.assert_array_equal(placed[3:], lefts[3:])  # apart: where they were
    run = placed[:3]  # side by side, in their points' order, 8 pixels apart ...
    np.testing.assert_allclose(run[1:] - (run + widths[:3])[:-1], 8.0)
    # ... the row centred on their labels' centres
    assert (run[0] + run[2] + widths[2]) / 2 == pytest.approx(np.mean(lefts[:3] + widths[:3] / 2))


def test_labels_in_a_row_stay_in_the_picture():
    widths = np.full(4, 40.0)
    for lefts in (np.array([-10.0, -5.0, 0.0, 2.0]), np.array([590.0, 592.0, 600.0, 610.0])):
        placed = labels_in_a_row(lefts, widths, 5.0, 640.0)
        order = np.argsort(placed)
        assert placed.min() >= 0.0 and (placed + widths).max() <= 640.0
        assert (placed[order][1:] >= (placed + widths)[order][:-1] + 5.0 - 1e-9).all()  # none overlaps
