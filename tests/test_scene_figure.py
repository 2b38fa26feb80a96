"""The figure as drawn (app/scene/figure.py) on a tiny synthetic skeleton (:mod:`tests.tiny_scene`):
which joint pairs are bones and which are dashed links, each tree in its colour, joints and
bones sized to the motion, the points written in place each frame, a tint that draws some
joints otherwise until cleared, the selection's ring around its joint shown only with a
selection, and the picture: a joint's disc, its bones and the ring where and as large as
they should be."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model.tree_colors import PALETTE
from gmr_studio.app.scene.figure import (
    BONE_RADIUS,
    JOINT_RADIUS,
    SELECTION_COLOR,
    SOFT_LINK_COLOR,
    SkeletonFigure,
    SoftLinks,
    dash_points,
    figure_bones,
)
from gmr_studio.app.scene.vtk_parts import rgb_bytes
from tests.tiny_scene import (
    FIGURE_SIZE,
    figure_motion,
    holds,
    look_down_at,
    picture,
    posed_motion,
    scene_of,
    snapshot_of,
)

pytestmark = pytest.mark.gui
TREES = np.array([0, 0, 0, 0, 1, 1])  # the figure's joints: Root's tree, then Arm's


def test_bones_leave_out_the_anchors_bone_and_links_hold_it_and_the_split():
    motion = figure_motion()
    assert motion.anchors.tolist() == [True, False, False, False, False, False]
    bones, links = figure_bones(motion)
    assert bones.dtype == np.int64 and links.dtype == np.int64
    assert bones.tolist() == [[2, 1], [3, 2], [5, 4]]
    assert links.tolist() == [[4, 2], [1, 0]]  # the split root to its soft parent, the anchor's bone


def test_bones_and_links_of_joint_zero_without_anchors():
    world = np.array([[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]])
    motion = posed_motion(("Hips", "Head", "Arm", "Hand"), (-1, 0, -1, 2), world, (-1, -1, 0, -1))
    assert not motion.anchors.any()
    bones, links = figure_bones(motion)
    assert bones.tolist() == [[1, 0], [3, 2]]
    assert links.tolist() == [[2, 0]]
    single = posed_motion(("Hips", "Head"), (-1, 0), world[:, :2])
    bones, links = figure_bones(single)
    assert bones.tolist() == [[1, 0]] and links.shape == (0, 2)


def test_dashes_split_a_line_into_equal_steps_from_end_to_end():
    a, b = np.array([[1.0, 2.0, 3.0], [0.0, 0.0, 0.0]]), np.array([[16.0, 2.0, 3.0], [0.0, -3.0, 0.0]])
    points = dash_points(a, b)
    assert points.shape == (2, 16, 3)  # eight dashes: sixteen points, consecutive pairs
    np.testing.assert_allclose(points[0, :, 0], np.arange(1.0, 17.0))
    np.testing.assert_allclose(points[0, :, 1:], np.broadcast_to([2.0, 3.0], (16, 2)))
    np.testing.assert_allclose(points[1, :, 1], -np.arange(16) / 5.0)
    np.testing.assert_allclose(dash_points(a, b, dashes=2)[0, :, 0], [1.0, 6.0, 11.0, 16.0])


def test_the_figures_parts_their_sizes_and_colours():
    with scene_of(snapshot_of(figure_motion())) as scene:
        figure = scene.figure
        assert scene.snapshot.motion.size == pytest.approx(FIGURE_SIZE)
        r = JOINT_RADIUS * FIGURE_SIZE
        assert set(figure.parts) == {"joints", "roots", "bones", "selection"}
        for part in figure.parts.values():
            assert holds(scene.plotter.renderer, part.actor) and not holds(scene.front_renderer, part.actor)
        joints = figure.parts["joints"]
        assert joints.n_points == 6 and joints.radius == pytest.approx(r)
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], rgb_bytes(PALETTE[TREES]))
        roots = figure.parts["roots"]
        assert roots.n_points == 2 and figure.roots.tolist() == [0, 4]
        np.testing.assert_array_equal(roots.mesh.point_data["colors"], rgb_bytes(PALETTE[[0, 1]]))
        cube = np.reshape(roots.actor.GetMapper().GetSource().GetBounds(), (3, 2))
        assert (cube[:, 0] < -r).all() and (cube[:, 1] > r).all()  # a root's cube holds its joint's sphere
        np.testing.assert_allclose(cube[:, 0], -cube[:, 1])  # centred on it
        bones = figure.parts["bones"]
        assert bones.pairs.tolist() == [[2, 1], [3, 2], [5, 4]]
        assert bones.radius == pytest.approx(BONE_RADIUS * FIGURE_SIZE) and bones.radius < r
        colours = np.asarray(bones.mesh.point_data["colors"]).astype(float)
        trees = rgb_bytes(PALETTE[[0, 0, 1]]).astype(float)
        cosine = (colours * trees).sum(axis=1) / np.linalg.norm(colours, axis=1) / np.linalg.norm(trees, axis=1)
        assert (cosine > 0.999).all() and (colours.sum(axis=1) < trees.sum(axis=1)).all()  # each tree's, darker
        ring = figure.parts["selection"]
        assert ring.n_points == 1 and r < ring.radius < 3 * r  # around the joint
        circle = np.asarray(ring.circle.points)
        np.testing.assert_allclose(np.linalg.norm(circle[:, :2], axis=1), ring.radius, rtol=1e-12)
        assert not circle[:, 2].any()  # in the follower's x-y plane, which it turns to the camera
        assert ring.actor.GetCamera() is scene.plotter.renderer.GetActiveCamera()
        assert ring.actor.GetProperty().GetColor() == pytest.approx(SELECTION_COLOR)


def test_a_frame_is_written_into_the_same_arrays():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        figure = scene.figure
        arrays = {name: part.mesh.GetPoints().__this__ for name, part in figure.parts.items()}
        scene.set_selection(3)
        scene.show_frame(2)
        positions = snapshot.positions[2]
        np.testing.assert_allclose(figure.parts["joints"].mesh.points, positions)
        np.testing.assert_allclose(figure.parts["roots"].mesh.points, positions[[0, 4]])
        np.testing.assert_allclose(figure.parts["bones"].mesh.points, positions[[[2, 1], [3, 2], [5, 4]]].mean(axis=1))
        np.testing.assert_allclose(figure.parts["selection"].mesh.points, positions[[3]])
        np.testing.assert_allclose(figure.parts["selection"].actor.GetPosition(), positions[3])
        scene.set_selection(5)
        scene.show_frame(1)
        np.testing.assert_allclose(figure.parts["selection"].mesh.points, snapshot.positions[1][[5]])
        np.testing.assert_allclose(figure.parts["selection"].actor.GetPosition(), snapshot.positions[1][5])
        assert {name: part.mesh.GetPoints().__this__ for name, part in figure.parts.items()} == arrays


def test_a_tint_draws_some_joints_in_other_colours_and_sizes_until_cleared():
    snapshot = snapshot_of(figure_motion())
    r, big = JOINT_RADIUS * FIGURE_SIZE, 1.3 * JOINT_RADIUS * FIGURE_SIZE
    own = rgb_bytes(PALETTE[TREES])
    with scene_of(snapshot) as scene:
        figure = scene.figure
        joints = figure.parts["joints"]
        assert figure.tint is None
        rgb = np.array([[10, 20, 30], [40, 50, 60]], np.uint8)
        figure.tint_joints(np.array([1, 5]), rgb, big)
        colours = np.asarray(joints.mesh.point_data["colors"])
        np.testing.assert_array_equal(colours[[1, 5]], rgb)
        np.testing.assert_array_equal(colours[[0, 2, 3, 4]], own[[0, 2, 3, 4]])
        np.testing.assert_allclose(joints.mesh.point_data["radius"], [r, big, r, r, r, big], rtol=1e-6)
        scene.show_frame(2)  # a frame keeps the sizes (and the colours: not written by a frame)
        np.testing.assert_allclose(joints.mesh.point_data["radius"], [r, big, r, r, r, big], rtol=1e-6)
        np.testing.assert_array_equal(np.asarray(joints.mesh.point_data["colors"])[[1, 5]], rgb)
        figure.tint_joints(np.array([1, 5]), rgb[::-1], big)  # new colours, written in place
        np.testing.assert_array_equal(np.asarray(joints.mesh.point_data["colors"])[[1, 5]], rgb[::-1])
        figure.tint_joints(np.array([3]), rgb[:1], big)  # other joints: the earlier ones back
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], np.vstack([own[:3], rgb[:1], own[4:]]))
        np.testing.assert_allclose(joints.mesh.point_data["radius"], [r, r, r, big, r, r], rtol=1e-6)
        scene.redraw(figure)  # rebuilt, the same joints: tinted as before
        joints = figure.parts["joints"]
        np.testing.assert_array_equal(np.asarray(joints.mesh.point_data["colors"])[3], rgb[0])
        np.testing.assert_allclose(joints.mesh.point_data["radius"], [r, r, r, big, r, r], rtol=1e-6)
        figure.clear_tint()
        assert figure.tint is None
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], own)
        np.testing.assert_allclose(joints.mesh.point_data["radius"], r, rtol=1e-6)
        figure.clear_tint()  # nothing tinted: nothing to do
        np.testing.assert_array_equal(joints.mesh.point_data["colors"], own)
    two_joints = np.array([[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]] * 2)  # (frames, joints, 3)
    with scene_of(snapshot_of(figure_motion())) as scene:  # a tint one past the new figure's joints dropped
        scene.figure.tint_joints(np.array([0, 2]), rgb, big)
        scene.set_snapshot(snapshot_of(posed_motion(["a", "b"], [-1, 0], two_joints)), reset_camera=False)
        assert scene.figure.tint is None
        np.testing.assert_allclose(
            scene.figure.parts["joints"].sizes, JOINT_RADIUS * scene.snapshot.motion.size, rtol=1e-6
        )
    with scene_of(snapshot_of(figure_motion())) as scene:  # a smaller figure: a tint beyond its joints dropped
        figure = scene.figure
        figure.tint_joints(np.array([5]), rgb[:1], big)
        scene.set_snapshot(snapshot_of(posed_motion(["a", "b"], [-1, 0], two_joints)), reset_camera=False)
        assert figure.tint is None and figure.parts["joints"].n_points == 2
        figure.tint_joints(np.array([], np.int64), np.zeros((0, 3), np.uint8), big)  # no joint: nothing drawn otherwise
        assert figure.tint is not None
        scene.redraw(figure)
        assert figure.parts["joints"].sizes.tolist() == pytest.approx([JOINT_RADIUS * scene.snapshot.motion.size] * 2)


def test_the_ring_shows_with_a_selection_only():
    with scene_of(snapshot_of(figure_motion())) as scene:
        figure = scene.figure
        others = [figure.parts[name] for name in ("joints", "roots", "bones")]
        ring = figure.parts["selection"]
        assert all(part.visible for part in others) and not ring.visible
        scene.set_selection(0)  # joint 0: a selection, though its index is falsy
        assert all(part.visible for part in others) and ring.visible
        figure.set_visible(False)
        assert not any(part.visible for part in [*others, ring])
        scene.set_selection(None)
        figure.set_visible(True)
        assert all(part.visible for part in others) and not ring.visible


def test_without_a_snapshot_nothing_is_built_or_drawn():
    with scene_of(None) as scene:
        for drawable in (SkeletonFigure(), SoftLinks()):
            drawable.build(scene)
            assert drawable.parts == {}
            drawable.show_frame(0)  # nothing to write
            assert drawable.parts == {}


def test_soft_links_are_dashed_grey_lines_between_the_linked_joints():
    snapshot = snapshot_of(figure_motion())
    with scene_of(snapshot) as scene:
        links = next(d for d in scene.drawables if isinstance(d, SoftLinks))
        part = links.parts["soft_links"]
        assert links.links.tolist() == [[4, 2], [1, 0]]
        assert part.n_points == 32 and part.visible
        assert holds(scene.plotter.renderer, part.actor)
        lines = part.mesh.lines.reshape(-1, 3)
        np.testing.assert_array_equal(lines, np.column_stack([np.full(16, 2), np.arange(32).reshape(16, 2)]))
        assert part.actor.GetProperty().GetColor() == pytest.approx(SOFT_LINK_COLOR)
        assert max(SOFT_LINK_COLOR) - min(SOFT_LINK_COLOR) < 0.1  # grey
        scene.show_frame(1)
        positions = snapshot.positions[1]
        expected = dash_points(positions[[4, 1]], positions[[2, 0]]).reshape(-1, 3)
        np.testing.assert_allclose(part.mesh.points, expected)
        scene.set_overlay("soft_links", False)
        assert not links.wanted(scene) and not part.visible
        scene.set_overlay("soft_links", True)
        assert links.wanted(scene) and part.visible


def test_a_figure_without_links_draws_no_dash():
    world = np.array([[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0.5, 0.0, 0.0], [0.5, 1.0, 0.0]]])
    with scene_of(snapshot_of(posed_motion(("Hips", "Head"), (-1, 0), world))) as scene:
        links = next(d for d in scene.drawables if isinstance(d, SoftLinks))
        assert links.links.shape == (0, 2) and links.parts["soft_links"].n_points == 0
        scene.show_frame(1)
        np.testing.assert_allclose(scene.figure.parts["joints"].mesh.points, world[1])


def _along(rgb: np.ndarray, colour) -> np.ndarray:
    """Cosine between each pixel's RGB and ``colour``'s (1: the same hue, any shading)."""
    colour = np.asarray(colour, dtype=float)
    return rgb @ colour / np.maximum(np.linalg.norm(rgb, axis=-1) * np.linalg.norm(colour), 1e-9)


def _yellow(image: np.ndarray) -> np.ndarray:
    """(H, W) the pixels of the ring's yellow (1, 0.85, 0.1), alone or blended with the blue,
    not the orange of the other tree's joints (0.98, 0.49, 0.05) lit from the front."""
    return (image[..., 0] > 150) & (image[..., 1] > 150) & (image[..., 2] < 100)


def test_the_picture_a_joint_its_bones_and_the_ring_in_their_colours_and_sizes():
    """Chest (frame 0, at (0, 0.2)) seen from above, 1000 pixels a unit: its sphere a disc
    of its radius in its tree's blue, the bones up to Head and down to Hips as thick as
    theirs, the selection's yellow ring around it, the joint showing through it."""
    joint_px, bone_px = JOINT_RADIUS * FIGURE_SIZE * 1000, BONE_RADIUS * FIGURE_SIZE * 1000
    with scene_of(snapshot_of(figure_motion()), size=(200, 200)) as scene:
        look_down_at(scene, (0.0, 0.2, 0.0), 0.1)
        image = picture(scene)
        background = image[2, 2]
        drawn = np.abs(image - background).max(axis=-1) > 30
        blue = PALETTE[0]
        joint = np.flatnonzero(drawn[100])  # the row through the joint's centre (bones vertical)
        assert abs(joint.min() - (100 - joint_px)) <= 1.5 and abs(joint.max() - (100 + joint_px)) <= 1.5
        assert _along(image[100, 100], blue) > 0.99 and image[100, 100].max() > 0.8 * 255 * blue.max()
        for row in (30, 170):  # 70 pixels above and below: a bone
            bone = np.flatnonzero(drawn[row])
            assert abs(bone.min() - (100 - bone_px)) <= 1.5 and abs(bone.max() - (100 + bone_px)) <= 1.5
            assert _along(image[row, 100], blue) > 0.99
        assert not drawn[:, :80].any() and not drawn[:, 121:].any()  # nothing else in view
        scene.set_selection(2)
        image = picture(scene)
        yellow = _yellow(image)
        rows, columns = np.nonzero(yellow)
        reach = np.hypot(rows - 99.5, columns - 99.5)
        ring_px = scene.figure.parts["selection"].radius * 1000
        assert joint_px + 2 <= reach.min() and reach.max() <= ring_px + 3  # a ring: nothing yellow inside it
        assert ring_px - reach.min() < 3  # a thin line, not a disc
        assert _along(image[100, 100], blue) > 0.99  # the joint inside the ring is not covered
        around = np.unique(np.floor(np.degrees(np.arctan2(rows - 99.5, columns - 99.5)) / 10))
        assert len(around) >= 30  # all round, but where the bones in front hide it: 30 of 36 tens of degrees
        assert np.median(_along(image[yellow], SELECTION_COLOR)) > 0.99  # edges blend with the blue
        camera = scene.plotter.camera  # seen from the side (+x) now: the ring still faces the camera
        camera.position, camera.up = (5.0, 0.2, 0.0), (0.0, 1.0, 0.0)
        image = picture(scene)
        rows, columns = np.nonzero(_yellow(image))
        reach = np.hypot(rows - 99.5, columns - 99.5)
        assert joint_px + 2 <= reach.min() and reach.max() <= ring_px + 3 and np.ptp(columns) > 1.8 * ring_px


def test_the_figures_box_is_its_joints_at_every_frame_grown_by_the_ring_and_the_links_box_its_joints():
    """The figure draws joints, bones, a root's cube and the selection's ring (twice a
    joint's radius) at its joints: their box at every frame grown by the ring holds them;
    the soft links' dashes are between joints: the joints' box; nothing built: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of
    from gmr_studio.app.scene.figure import JOINT_RADIUS

    snapshot = snapshot_of(figure_motion(3))
    with scene_of(snapshot) as scene:
        np.testing.assert_allclose(
            scene.figure.extent(), box_of(snapshot.positions, 2.0 * JOINT_RADIUS * FIGURE_SIZE), rtol=0, atol=1e-15
        )
        links = next(d for d in scene.drawables if isinstance(d, SoftLinks))
        np.testing.assert_array_equal(links.extent(), box_of(snapshot.positions))
    with scene_of(None) as scene:
        for drawable in (SkeletonFigure(), SoftLinks()):
            scene.add_drawable(drawable)
            np.testing.assert_array_equal(drawable.extent(), EMPTY_BOX)
