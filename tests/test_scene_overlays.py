"""The view's overlays (app/scene/overlays.py) as drawables, on a tiny synthetic motion:
the ground grid at round steps under the path, each joint's triad (X red, Y green, Z blue),
the selected joint's trail over the last second, the joints' labels beside them, the markers
with their gaps, ring and labels, and the recovered pelvis's triad. The scene is a stand-in
with a bare VTK renderer (what the overlays read of :class:`~app.scene.scene.SkeletonScene`),
so no window opens: what is checked is where the overlays put their points and what they show.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from vtkmodules.vtkRenderingCore import vtkRenderer

from gmr_studio.app.model.state import OVERLAYS, MarkerOverlay, PelvisOverlay, Snapshot
from gmr_studio.app.scene import overlays
from gmr_studio.app.scene.figure import SELECTION_COLOR
from gmr_studio.app.scene.overlays import AXIS_LENGTH, MARKER_RADIUS, PELVIS_AXIS_LENGTH
from gmr_studio.app.scene.scene import actor_positions
from tests.conftest import random_motion

N_FRAMES = 40  # at 30 Hz: more than the trail's second (31 frames)


class StandInScene:
    """What the overlays read of a scene: a snapshot, the overlays, the selection, the frame,
    the up axis, a renderer, and a projection to display pixels (x, y) = 100 (X, Y) + (7, 9)."""

    def __init__(self, snapshot: Snapshot | None) -> None:
        self.plotter = SimpleNamespace(renderer=vtkRenderer())
        self.snapshot = snapshot
        self.new_document = True
        self.overlays = dict(OVERLAYS)
        self.selected: int | None = None
        self.frame = 0
        self.up_axis = 2

    def figure_positions(self) -> np.ndarray:
        return actor_positions(self.snapshot)

    def figure_box(self) -> np.ndarray:
        """The box of the figure's joints at every frame."""
        flat = self.figure_positions().reshape(-1, 3)
        return np.stack([flat.min(axis=0), flat.max(axis=0)])

    def display_positions(self, points: np.ndarray) -> np.ndarray:
        return 100 * np.asarray(points)[:, :2] + np.array([7.0, 9.0])

    def display_size(self) -> tuple[int, int]:
        return (2, 2)  # a display pixel (x, y) is the device point (x - 1, y - 1) the quads hold

    def document_box(self, pad: float = 0.0) -> np.ndarray:
        """The box of every joint at every frame, grown by ``pad``."""
        flat = self.snapshot.positions.reshape(-1, 3)
        return np.stack([flat.min(axis=0) - pad, flat.max(axis=0) + pad])


@pytest.fixture
def snapshot() -> Snapshot:
    return Snapshot.of(random_motion(np.random.default_rng(7), [-1, 0, 1, 1], n_frames=N_FRAMES))


def _points(part) -> np.ndarray:
    return np.asarray(part.mesh.points)


def _lines(part) -> np.ndarray:
    """(S, 2) the point pairs of a segments part."""
    return np.asarray(part.mesh.lines).reshape(-1, 3)[:, 1:]


def assert_x_red_y_green_z_blue(colours) -> None:
    """Each triad's segments coloured by their axis: X red, Y green, Z blue."""
    rgb = np.asarray(colours).reshape(-1, 3, 3)
    assert (rgb.argmax(axis=2) == [0, 1, 2]).all() and (rgb.max(axis=2) > 200).all()


def assert_beside(corners, anchors) -> None:
    """Labels just up and right of their anchors, on whole pixels."""
    offset = np.asarray(corners) - np.asarray(anchors)
    assert (offset > 0).all() and (offset < 12).all() and (np.asarray(corners) == np.round(corners)).all()


def test_nice_step_is_one_two_or_five_times_a_power_of_ten():
    cases = {1.1: 1.0, 2.1: 2.0, 4.9: 5.0, 9.0: 10.0, 0.3: 0.2, 0.04: 0.05, 250.0: 200.0, 1.0: 1.0}
    for length, step in cases.items():
        assert overlays.nice_step(length) == pytest.approx(step, rel=1e-12), length
    for length in (0.0, -3.0, math.nan, math.inf):
        assert overlays.nice_step(length) == 1.0


def _grid(across: tuple[int, int], up: int, a, b, floor: float) -> np.ndarray:
    """Expected grid: a line at each ``a`` from b[0] to b[-1], then at each ``b`` from a[0] to a[-1]."""
    ends = [((x, b[0]), (x, b[-1])) for x in a] + [((a[0], y), (a[-1], y)) for y in b]
    coords = np.zeros((2 * len(ends), 3))
    coords[:, list(across)] = np.asarray(ends, dtype=np.float64).reshape(-1, 2)
    coords[:, up] = floor
    return coords


def test_the_ground_grid_spans_the_path_with_a_margin_at_the_lowest_point():
    # size 4: a step of 1 (nice_step(4 / 4)) and a margin of 1.6; a NaN row is left out
    positions = np.array([[[0.0, 3.0, -0.5], [2.0, 4.0, 1.5]], [[np.nan, 9.0, 9.0], [1.0, 3.5, 0.0]]])
    coords, (low, high, floor) = overlays.ground_lines(positions, 4.0, 2)
    np.testing.assert_array_equal(low, [0.0, 3.0, -0.5])
    np.testing.assert_array_equal(high, [2.0, 4.0, 1.5])
    assert floor == -0.5
    np.testing.assert_array_equal(coords, _grid((0, 1), 2, range(-2, 5), range(1, 7), -0.5))
    # Y up: the grid lies in X and Z at the lowest Y; size 8: a step of 2 and a margin of 3.2
    coords, (_, _, floor) = overlays.ground_lines(positions[..., [0, 2, 1]], 8.0, 1)
    assert floor == -0.5
    np.testing.assert_array_equal(coords, _grid((0, 2), 1, range(-4, 7, 2), range(-2, 9, 2), -0.5))


@pytest.mark.parametrize(
    ("size", "a", "b"),
    [
        (6.0, range(-4, 7, 2), range(-4, 5, 2)),  # a quarter is 1.5: steps of 2 (a fifth, 1.2, would give 1)
        (4.8, range(-2, 5), range(-2, 4)),  # a quarter is 1.2: steps of 1 (a third, 1.6, would give 2)
    ],
)
def test_the_grids_step_is_the_nice_step_nearest_a_quarter_of_the_size(size, a, b):
    positions = np.array([[[0.0, 0.0, 0.0], [2.0, 1.0, 1.0]]])
    coords, _ = overlays.ground_lines(positions, size, 2)
    np.testing.assert_allclose(coords, _grid((0, 1), 2, a, b, 0.0), rtol=0, atol=1e-12)


def test_the_grid_ends_at_its_last_step_whatever_the_rounding_of_tenths():
    # steps of 0.1 (size 0.3): the lines from 0.6 to 1.1 are not multiples of 0.1 in binary,
    # yet there are six of them each way and none beyond 1.1
    positions = np.array([[[0.82, 0.82, 0.0], [0.97, 0.97, 0.1]]])
    coords, _ = overlays.ground_lines(positions, 0.3, 2)
    ticks = np.linspace(0.6, 1.1, 6)
    np.testing.assert_allclose(coords, _grid((0, 1), 2, ticks, ticks, 0.0), rtol=0, atol=1e-12)


def test_triads_run_one_segment_along_each_column_of_the_rotation():
    origins = np.array([[1.0, 2.0, 3.0], [-1.0, 0.0, 0.5]])
    rotations = np.stack([np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), np.eye(3)[[2, 0, 1]]])
    coords = overlays.triad_points(origins, rotations, 0.5)
    expected = [[o, o + 0.5 * r[:, k]] for o, r in zip(origins, rotations) for k in range(3)]
    np.testing.assert_array_equal(coords, np.reshape(expected, (-1, 3)))


def test_the_ground_is_built_for_a_new_document_and_kept_across_edits(snapshot):
    scene, ground = StandInScene(snapshot), overlays.Ground()
    ground.build(scene)
    grid = ground.parts["ground"]
    coords, bounds = overlays.ground_lines(actor_positions(snapshot), snapshot.motion.size, 2)
    np.testing.assert_array_equal(_points(grid), coords)
    np.testing.assert_array_equal(_lines(grid), np.arange(len(coords)).reshape(-1, 2))
    assert ground.bounds[2] == bounds[2] and (ground.bounds[0] == bounds[0]).all()
    assert grid.visible
    scene.new_document = False  # an edit: the same grid
    ground.build(scene)
    assert ground.parts["ground"] is grid
    scene.new_document = True  # another document: a new grid
    ground.build(scene)
    assert ground.parts["ground"] is not grid
    assert scene.plotter.renderer.GetViewProps().GetNumberOfItems() == 1  # the old one taken out
    scene.snapshot = None
    ground.build(scene)
    assert ground.parts == {} and ground.bounds is None
    scene.overlays["ground"] = False
    assert not ground.wanted(scene)
    scene.overlays["ground"] = True
    assert ground.wanted(scene)


def test_joint_axes_are_each_joints_triad_at_the_frame(snapshot):
    scene, axes = StandInScene(snapshot), overlays.JointAxes()
    axes.show_frame(0)  # not built: nothing to write
    scene.snapshot = None
    axes.build(scene)
    assert axes.parts == {}
    scene.snapshot = snapshot
    axes.build(scene)
    part, n = axes.parts["axes"], snapshot.motion.n_joints
    assert part.n_points == 6 * n
    np.testing.assert_array_equal(_lines(part), np.arange(6 * n).reshape(-1, 2))
    assert_x_red_y_green_z_blue(part.mesh.cell_data["colors"])
    axes.show_frame(17)
    length = AXIS_LENGTH * snapshot.motion.size
    expected = overlays.triad_points(snapshot.positions[17], snapshot.rotations[17], length)
    np.testing.assert_allclose(_points(part), expected, rtol=0, atol=1e-12)
    scene.overlays["axes"] = True
    assert axes.wanted(scene)
    scene.overlays["axes"] = False
    assert not axes.wanted(scene)


def test_the_trail_is_the_selected_joints_last_second(snapshot):
    scene, trail = StandInScene(snapshot), overlays.Trail()
    trail.build(scene)
    part = trail.parts["trails"]
    assert trail.length == 31 and part.n_points == 31  # 30 Hz: a second is 30 steps, 31 frames
    np.testing.assert_array_equal(_lines(part), np.column_stack([np.arange(30), np.arange(1, 31)]))
    assert part.actor.GetProperty().GetColor() == pytest.approx(SELECTION_COLOR)  # the selection's yellow
    trail.show_frame(35)  # nothing selected: nothing written
    assert not _points(part).any()
    scene.selected = 2
    trail.show_frame(35)
    np.testing.assert_array_equal(_points(part), snapshot.positions[5:36, 2])
    trail.show_frame(3)  # before a second has passed: the first frame repeated
    np.testing.assert_array_equal(_points(part), snapshot.positions[[0] * 27 + [0, 1, 2, 3], 2])
    short = Snapshot.of(random_motion(np.random.default_rng(3), [-1, 0], n_frames=10))
    trail.build(StandInScene(short))
    assert trail.length == 10 and trail.parts["trails"].n_points == 10
    for shown, selected, wanted in ((True, 2, True), (True, None, False), (False, 2, False), (False, None, False)):
        scene.overlays["trails"], scene.selected = shown, selected
        assert trail.wanted(scene) is wanted


def _corners(part) -> np.ndarray:
    """(N, 2) each label quad's bottom left corner in display pixels, once it is checked
    that the mesh holds their device points (the stand-in's view: a pixel (x, y) is the
    device point (x - 1, y - 1)), or nothing at all before any placement."""
    quads = np.asarray(part.mesh.points).reshape(-1, 4, 3)
    placed = part.view != (0, 0)
    np.testing.assert_array_equal(quads[..., :2], part.corners - 1.0 if placed else 0.0)
    return part.corners[:, 0].copy()


def test_joint_labels_are_placed_beside_the_joints_at_the_frame(snapshot):
    scene, labels = StandInScene(None), overlays.JointLabels()
    labels.build(scene)
    labels.before_render()  # nothing to place, no error
    assert labels.parts == {}
    scene.snapshot, scene.frame = snapshot, 12
    labels.build(scene)
    part = labels.parts["labels"]
    assert part.texts == list(snapshot.motion.names)
    labels.set_visible(False)
    labels.before_render()  # hidden: not placed
    assert not _corners(part).any()
    labels.set_visible(True)
    labels.before_render()
    anchors = scene.display_positions(snapshot.positions[12])
    assert_beside(_corners(part), anchors)
    placed = _corners(part)
    labels.show_frame(13)  # the frame is read from the scene just before a render
    np.testing.assert_array_equal(_corners(part), placed)
    scene.frame = 13
    labels.before_render()
    assert_beside(_corners(part), scene.display_positions(snapshot.positions[13]))
    scene.overlays["labels"] = False
    assert not labels.wanted(scene)
    scene.overlays["labels"] = True
    assert labels.wanted(scene)


def _marker_overlay(n_frames: int = N_FRAMES) -> MarkerOverlay:
    """Four markers; LASI missing at frame 2 and C7 at the last frame."""
    positions = np.random.default_rng(5).normal(size=(n_frames, 4, 3))
    positions[2, 1] = np.nan
    positions[-1, 2, 0] = np.nan
    return MarkerOverlay(SimpleNamespace(labels=("RASI", "LASI", "C7", "T10")), None, positions)


def _markers(snapshot) -> tuple[StandInScene, overlays.Markers]:
    scene, markers = StandInScene(snapshot), overlays.Markers()
    markers.overlay = _marker_overlay()
    markers.build(scene)
    return scene, markers


def test_markers_are_spheres_where_present_and_the_selected_ones_ring(snapshot):
    scene, markers = StandInScene(snapshot), overlays.Markers()
    markers.build(scene)  # no overlay: nothing drawn, nothing to update
    markers.show_frame(0)
    assert markers.parts == {}
    markers.overlay, scene.snapshot = _marker_overlay(), None
    markers.build(scene)
    assert markers.parts == {}
    scene.snapshot = snapshot
    markers.build(scene)
    size = snapshot.motion.size
    spheres, ring = markers.parts["markers"], markers.parts["marker_selection"]
    assert spheres.radius == pytest.approx(MARKER_RADIUS * size, rel=1e-12)
    assert min(spheres.actor.GetProperty().GetColor()) > 0.8  # near white
    assert ring.radius > spheres.radius  # around the marker
    np.testing.assert_allclose(np.linalg.norm(ring.circle.points, axis=1), ring.radius, rtol=1e-12)
    assert ring.actor.GetCamera() is scene.plotter.renderer.GetActiveCamera()  # turned to the view
    assert ring.actor.GetProperty().GetColor() == pytest.approx(SELECTION_COLOR)
    assert not ring.visible  # nothing selected
    positions = markers.overlay.positions
    markers.show_frame(2)
    assert spheres.n_points == 4
    np.testing.assert_array_equal(spheres.drawn, [True, False, True, True])
    np.testing.assert_array_equal(_points(spheres)[[0, 2, 3]], positions[2, [0, 2, 3]])
    scene.frame = 2
    markers.set_highlight(None, 1)  # selected where it is missing: no ring
    markers.show_frame(2)
    assert not ring.visible and not markers.part_wanted(ring)
    scene.frame = 3
    markers.show_frame(3)
    assert ring.visible and markers.part_wanted(ring)
    np.testing.assert_array_equal(_points(ring), positions[3, [1]])
    markers.set_visible(False)
    markers.show_frame(3)
    assert not ring.visible
    markers.set_visible(True)
    scene.frame = N_FRAMES + 5  # past the markers' last frame: their last frame decides
    markers.set_highlight(None, 2)
    assert not markers.part_wanted(ring)
    markers.set_highlight(None, 0)
    assert markers.part_wanted(ring) and markers.part_wanted(spheres)
    scene.overlays["markers"] = False
    assert not markers.wanted(scene)
    scene.overlays["markers"] = True
    assert markers.wanted(scene)


def test_marker_labels_name_the_hovered_and_selected_markers_beside_them(snapshot):
    scene, markers = _markers(snapshot)
    labels = markers.parts["marker_labels"]
    assert labels.texts == ["", ""]
    assert not labels.visible  # no text: no quad drawn
    markers.before_render()  # nothing to place
    assert not _corners(labels).any()
    scene.frame = 9
    markers.set_highlight(0, None)  # hovered only
    assert labels.texts == ["RASI", ""] and labels.visible
    markers.before_render()
    positions = markers.overlay.positions[9]
    assert_beside(_corners(labels)[0], scene.display_positions(positions[[0]])[0])
    assert (_corners(labels)[1] == -1e4).all()  # no selected marker: its label out of sight
    markers.set_highlight(None, 2)  # selected only
    assert labels.texts == ["", "C7"] and labels.visible
    markers.before_render()
    assert_beside(_corners(labels)[1], scene.display_positions(positions[[2]])[0])
    assert (_corners(labels)[0] == -1e4).all()
    markers.set_highlight(1, 0)
    assert labels.texts == ["LASI", "RASI"]
    scene.overlays["marker_labels"] = False  # the labels switched off: the ring stays
    markers.set_highlight(1, 0)
    assert not labels.visible and markers.parts["marker_selection"].visible
    markers.set_highlight(None, None)
    scene.overlays["marker_labels"] = True
    markers.set_highlight(None, None)
    assert not labels.visible and labels.texts == ["", ""]
    bare = overlays.Markers()  # a highlight before any overlay is drawn: nothing to place
    bare.build(StandInScene(snapshot))
    bare.set_highlight(0, 1)
    bare.before_render()
    assert bare.parts == {}


def _pelvis(n_frames: int) -> PelvisOverlay:
    """Pelvis frames turning about Z, not recovered at frame 4."""
    angles = np.linspace(0.0, 1.0, n_frames)
    c, s = np.cos(angles), np.sin(angles)
    rotations = np.zeros((n_frames, 3, 3))
    rotations[:, 0, 0], rotations[:, 0, 1], rotations[:, 1, 0], rotations[:, 1, 1] = c, -s, s, c
    rotations[:, 2, 2] = 1.0
    origins = np.random.default_rng(2).normal(size=(n_frames, 3))
    origins[4] = np.nan
    rotations[4] = np.eye(3)
    return PelvisOverlay(rotations, origins, np.zeros(n_frames), None)


def test_the_pelvis_triad_follows_the_recovered_frames(snapshot):
    scene, triad = StandInScene(snapshot), overlays.PelvisTriad()
    triad.build(scene)  # no pelvis: nothing drawn
    triad.show_frame(0)
    assert triad.parts == {}
    triad.pelvis, scene.snapshot = _pelvis(N_FRAMES), None
    triad.build(scene)
    assert triad.parts == {}
    scene.snapshot = snapshot
    triad.build(scene)
    part = triad.parts["pelvis"]
    assert part.n_points == 6
    np.testing.assert_array_equal(_lines(part), [[0, 1], [2, 3], [4, 5]])
    assert_x_red_y_green_z_blue(part.mesh.cell_data["colors"])
    triad.show_frame(6)
    length = PELVIS_AXIS_LENGTH * snapshot.motion.size
    pelvis = triad.pelvis
    expected = overlays.triad_points(pelvis.origins[[6]], pelvis.rotations[[6]], length)
    np.testing.assert_allclose(_points(part), expected, rtol=0, atol=1e-12)
    assert part.visible
    triad.show_frame(4)  # not recovered: not drawn, the points kept
    assert not part.visible
    np.testing.assert_allclose(_points(part), expected, rtol=0, atol=1e-12)
    triad.set_visible(False)
    triad.show_frame(6)
    assert not part.visible
    scene.overlays["pelvis"] = False
    assert not triad.wanted(scene)
    scene.overlays["pelvis"] = True
    assert triad.wanted(scene)


def _within(points: np.ndarray, box: np.ndarray) -> bool:
    finite = points[np.isfinite(points).all(axis=1)]
    return bool((finite >= box[0] - 1e-12).all() and (finite <= box[1] + 1e-12).all())


def test_each_overlays_box_holds_what_it_draws_at_every_frame(snapshot):
    """Each overlay says where it may draw at any frame: the grid its lines; the triads the
    joints grown by a triad's length; the trail the joints; the markers every marker grown
    by the ring around a marker; the pelvis triad its origins grown
    by its length; the labels nothing in the world (screen space); nothing built: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX

    size = snapshot.motion.size
    scene = StandInScene(None)
    drawings = [overlays.Ground(), overlays.JointAxes(), overlays.Trail(), overlays.JointLabels()]
    drawings += [overlays.Markers(), overlays.PelvisTriad()]
    ground, axes, trail, labels, markers, pelvis = drawings
    markers.overlay, pelvis.pelvis = _marker_overlay(), _pelvis(N_FRAMES)
    for drawing in drawings:
        drawing.build(scene)  # no document: nothing built
        np.testing.assert_array_equal(drawing.extent(), EMPTY_BOX)
    scene.snapshot, scene.selected = snapshot, 2
    for drawing in drawings:
        drawing.build(scene)
    flat = snapshot.positions.reshape(-1, 3)
    low, high = flat.min(axis=0), flat.max(axis=0)
    grid = _points(ground.parts["ground"])
    np.testing.assert_array_equal(ground.extent(), [grid.min(axis=0), grid.max(axis=0)])
    length = AXIS_LENGTH * size
    np.testing.assert_allclose(axes.extent(), [low - length, high + length], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trail.extent(), [low, high])
    np.testing.assert_array_equal(labels.extent(), EMPTY_BOX)
    present = markers.overlay.positions.reshape(-1, 3)
    present = present[np.isfinite(present).all(axis=1)]
    ring = markers.parts["marker_selection"].radius
    box = markers.extent()
    np.testing.assert_allclose(box, [present.min(axis=0) - ring, present.max(axis=0) + ring], rtol=0, atol=1e-15)
    origins = pelvis.pelvis.origins[np.isfinite(pelvis.pelvis.origins).all(axis=1)]
    length = PELVIS_AXIS_LENGTH * size
    np.testing.assert_allclose(
        pelvis.extent(), [origins.min(axis=0) - length, origins.max(axis=0) + length], rtol=0, atol=1e-15
    )
    for frame in range(N_FRAMES):
        for drawing in (axes, trail, markers, pelvis):
            drawing.show_frame(frame)
        assert _within(_points(axes.parts["axes"]), axes.extent()), frame
        assert _within(_points(trail.parts["trails"]), trail.extent()), frame
        assert _within(_points(markers.parts["markers"]), markers.extent()), frame
        assert _within(_points(pelvis.parts["pelvis"]), pelvis.extent()), frame
