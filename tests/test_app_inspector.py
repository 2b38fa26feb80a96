"""The inspector (app/docks/inspector.py). A bare inspector over a state holding a small
random motion: what it says of the frame, a joint, markers and the pelvis, angles checked
against scipy's Euler decomposition and positions and matrices against the state's own
arrays. In the real window: tests/test_app_inspector_window.py."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.app.docks.inspector import Inspector
from gmr_studio.app.model.formatting import (
    format_angles,
    format_lengths,
    format_matrix,
)
from gmr_studio.app.model.joint_transforms import bvh_local, bvh_world_rotation, gmr_local
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.analysis.curves import values_at
from gmr_studio.core.edits.operations import split
from tests.conftest import random_motion


def flat(text: str) -> str:
    return " ".join(text.split())


# ------------------------------------------------- a bare inspector over a small random motion
PARENTS = [-1, 0, 1, 2, 2]  # j2's children j3 and j4 turn independently; j1 has one child


def euler_degrees(rotation: np.ndarray, order: str) -> np.ndarray:
    """(3,) intrinsic Euler angles in ``order`` (scipy's upper-case orders are intrinsic)."""
    return Rotation.from_matrix(rotation).as_euler(order, degrees=True)


def inspector_of(qtbot, state: StudioState, height: int, width: int = 700) -> Inspector:
    """An inspector of ``state`` shown at ``width`` x ``height`` pixels."""
    inspector = Inspector(state)
    qtbot.addWidget(inspector)
    inspector.resize(width, height)
    inspector.show()
    qtbot.waitExposed(inspector)
    return inspector


@pytest.fixture
def shown(qtbot):
    """(state, inspector): shown, tall enough for every section to be on screen."""
    state = StudioState()
    return state, inspector_of(qtbot, state, 4000)


def opened(state: StudioState, seed: int = 5, parents=PARENTS, n_frames: int = 6) -> Snapshot:
    motion = random_motion(np.random.default_rng(seed), parents, n_frames=n_frames)
    snapshot = Snapshot.of(motion)
    state.open_document(snapshot, "m.gmr")
    return snapshot


@pytest.mark.gui
def test_without_a_motion_it_says_so_and_describes_no_frame(shown):
    _state, inspector = shown
    assert flat(inspector.text()) == "No motion"
    assert inspector.shown_frame() is None


@pytest.mark.gui
def test_the_frame_and_its_time_and_a_prompt_without_a_selection(shown):
    state, inspector = shown
    opened(state)
    assert flat(inspector.text()) == ("Frame 0 of 0-5 (0.000 s) Click a joint in the view or the forest to inspect it.")
    state.set_frame(4)
    assert flat(inspector.text()).startswith("Frame 4 of 0-5 (0.133 s) Click a joint")  # 1/30 s a frame
    assert inspector.shown_frame() == 4


@pytest.mark.gui
def test_a_joints_table_angles_transforms_and_world_values_at_the_frame(shown):
    state, inspector = shown
    snapshot = opened(state)
    motion = snapshot.motion
    size = motion.size
    j, f = 3, 4
    state.set_frame(f)
    state.select(j)
    text = flat(inspector.text())
    full = motion.rotation_orders[j]  # three letters already
    head = f"Frame {f} of 0-5 (0.133 s) Joint j3 (index 3) Parent j2 Soft link none"
    assert text.startswith(head)
    assert f"Offset {flat(format_lengths(motion.offsets[j], size))}" in text
    assert "Channels (BVH) none" in text  # a leaf: no rotation channels, no translation
    assert f"Channels (GMR) {' '.join(a + 'rotation' for a in full)}" in text
    # the two rotation quantities as the curves compute them (unwrapped over the take), the
    # GMR one composing (by scipy) the joint's local GMR rotation
    computed = "the motion's rotation as Euler angles in the joint's order, computed: "  # no file channels
    for quantity, what in (("channels", computed), ("gmr-euler", "the GMR rotation: ")):
        columns, values = values_at(motion, j, quantity, f, snapshot.positions, None)
        labels = " ".join(c.rsplit(".", 1)[1] for c in columns)
        assert f"{quantity} ({what}{labels}): {flat(format_angles(values))} deg" in text
    again = Rotation.from_euler(full, values, degrees=True).as_matrix()
    np.testing.assert_allclose(again, motion.rotations[f, j], atol=1e-12)  # its local GMR rotation
    assert labels == " ".join(full)
    # both local transforms as joint_transforms gives them at this frame and joint
    bvh, gmr = bvh_local(motion, f, j), gmr_local(motion, f, j)
    bvh_part = text.split("Local, post-rotation [R, t] (BVH)")[1].split("Local, pre-rotation")[0]
    assert bvh_part.strip().startswith(flat(bvh.note)) and flat(format_matrix(bvh.matrix[:, :3])) in bvh_part
    assert f"translation t: {flat(format_matrix(bvh.matrix[:, 3], size, lengths=True))}" in bvh_part
    gmr_part = text.split("Local, pre-rotation [R, R t] (GMR)")[1].split("World position")[0]
    assert "a root" not in gmr_part and gmr_part.strip().startswith(flat(gmr.note))
    assert flat(format_matrix(gmr.matrix[:, :3])) in gmr_part
    assert f"translation R t: {flat(format_matrix(gmr.matrix[:, 3], size, lengths=True))}" in gmr_part
    assert f"Euler {gmr.order} (from the matrix): {flat(format_angles(gmr.angles))} deg" in gmr_part
    # the world position and both world rotations, Euler in the joint's order
    world = text.split("World position")[1]
    assert world.strip().startswith(flat(format_matrix(snapshot.positions[f, j][None], size, lengths=True)))
    bvh_world = bvh_world_rotation(motion, snapshot.rotations[f], f, j)
    first, second = world.split("World rotation")[1:3]
    assert first.startswith(f" (BVH: the frame its children hang in), Euler {full}:")
    assert f"{flat(format_angles(euler_degrees(bvh_world, full)))} deg {flat(format_matrix(bvh_world))}" in first
    assert second.startswith(f" (GMR: the frame of the bone that ends at it), Euler {full}:")
    gmr_world = snapshot.rotations[f, j]
    assert f"{flat(format_angles(euler_degrees(gmr_world, full)))} deg {flat(format_matrix(gmr_world))}" in second


@pytest.mark.gui
def test_a_child_of_the_root_with_one_child_has_bvh_channels_and_no_root_note(shown):
    state, inspector = shown
    snapshot = opened(state)
    state.set_frame(1)
    state.select(1)  # its parent is joint 0; its one child j2 gives its BVH rotation
    text = flat(inspector.text())
    assert "Joint j1 (index 1) Parent j0 Soft link none" in text
    bvh = bvh_local(snapshot.motion, 1, 1)
    assert bvh.channels_of == "j1" and len(bvh.order) == 3
    assert f"Channels (BVH) {' '.join(a + 'rotation' for a in bvh.order)} Channels (GMR)" in text
    assert "Local, pre-rotation [R, R t] (GMR) GMR channels of j1" in text  # no root's note


@pytest.mark.gui
def test_a_root_is_marked_in_the_table_and_the_gmr_transform(shown):
    state, inspector = shown
    snapshot = opened(state)
    state.select(0)
    text = flat(inspector.text())
    assert "Joint j0 (index 0) Parent none: a root Soft link none" in text
    assert "Local, pre-rotation [R, R t] (GMR) (a root: its translation is its world position)" in text
    assert "Channels (BVH) Xposition Yposition Zposition" in text  # a root translates
    motion = snapshot.motion
    matrix = gmr_local(motion, 0, 0).matrix
    translation = flat(format_matrix(matrix[:, 3], motion.size, lengths=True))
    assert f"{flat(format_matrix(matrix[:, :3]))} translation R t: {translation}" in text


@pytest.mark.gui
def test_a_joint_whose_children_turn_independently_shows_why_it_has_no_bvh_matrix(shown):
    state, inspector = shown
    snapshot = opened(state)
    state.set_frame(2)
    state.select(2)
    text = flat(inspector.text())
    bvh_part = text.split("Local, post-rotation [R, t] (BVH)")[1].split("Local, pre-rotation")[0]
    assert flat(bvh_local(snapshot.motion, 2, 2).note) in bvh_part
    assert "[" not in bvh_part and "Euler" not in bvh_part  # no matrix, no angles


@pytest.mark.gui
def test_a_split_joint_names_its_soft_link_parent(shown):
    state, inspector = shown
    motion = random_motion(np.random.default_rng(5), PARENTS, n_frames=6)
    state.open_document(Snapshot.of(split(motion, 2)), "m.gmr")
    state.select(2)
    assert "Joint j2 (index 2) Parent none: a root Soft link j1" in flat(inspector.text())
    state.open_document(Snapshot.of(split(motion, 1)), "m.gmr")
    state.select(1)
    assert "Joint j1 (index 1) Parent none: a root Soft link j0" in flat(inspector.text())  # the root's index, 0


@pytest.mark.gui
def test_names_are_escaped(shown):
    state, inspector = shown
    motion = random_motion(np.random.default_rng(5), [-1, 0], n_frames=2)
    motion = dataclasses.replace(motion, names=("<b>", "a&b"))
    state.open_document(Snapshot.of(motion), "m.gmr")
    state.select(1)
    text = flat(inspector.text())
    assert "Joint a&b (index 1) Parent <b>" in text


@pytest.mark.gui
def test_markers_the_selected_marker_and_a_gap(shown):
    state, inspector = shown
    snapshot = opened(state)
    size = snapshot.motion.size
    positions = np.zeros((6, 2, 3))
    positions[:, 1] = [1.25, -2.5, 0.125]
    positions[3, 1] = np.nan
    computed = np.zeros((6, 2), bool)
    markers = SimpleNamespace(
        n_markers=2, source="/lab/walk.trc", rate=120.0, units="mm", labels=["LASI", "R<A>"], computed=computed
    )
    alignment = SimpleNamespace(method="fitted & scaled")
    state.marker_overlay = SimpleNamespace(markers=markers, alignment=alignment, positions=positions, computed=None)
    state.markers_changed.emit()
    text = flat(inspector.text())
    assert text.endswith("Markers: 2 from walk.trc, 120 Hz, mm aligned: fitted & scaled")
    state.selected_marker = 1
    state.marker_selection_changed.emit(1)
    assert flat(inspector.text()).endswith(f"Marker R<A>: {flat(format_lengths(positions[0, 1], size))}")
    state.set_frame(3)
    assert flat(inspector.text()).endswith("Marker R<A>: missing (a gap)")
    markers.source = ""
    state.markers_changed.emit()
    assert "Markers: 2 from a file, 120 Hz" in flat(inspector.text())
    computed[:3, 1] = True  # a quarter of the samples filled in by the capture software
    state.marker_overlay.computed = computed
    state.set_frame(2)
    state.markers_changed.emit()
    text = flat(inspector.text())
    assert "120 Hz, mm; 25% computed by the capture software" in text
    assert text.endswith(
        f"Marker R<A>: {flat(format_lengths(positions[2, 1], size))} (computed by the capture software)"
    )


@pytest.mark.gui
def test_the_pelvis_residual_and_rotation_while_the_pelvis_frames_are_shown(shown):
    state, inspector = shown
    opened(state)
    rotations = np.stack([np.eye(3)] * 6)
    rotations[2] = Rotation.from_euler("Z", 30, degrees=True).as_matrix()
    residuals = np.array([0.5, 0.25, 0.125, np.nan, 1.0, 2.0])
    source = SimpleNamespace(units="mm", fit_labels=("LASI", "RASI", "SACR"), labels=("A", "B", "C"))
    state.pelvis = SimpleNamespace(residuals=residuals, source=source, rotations=rotations)
    state.set_overlay("pelvis", True)
    state.set_frame(2)
    text = flat(inspector.text())
    assert text.endswith(
        f"Pelvis fit residual (RMS of LASI, RASI, SACR): 0.125 mm Pelvis rotation (recovered, motion axes) "
        f"{flat(format_matrix(rotations[2]))}"
    )
    state.set_frame(3)
    assert flat(inspector.text()).endswith("Pelvis fit residual (RMS of LASI, RASI, SACR): not recovered at this frame")
    source.fit_labels = ()
    state.pelvis_changed.emit()
    assert "(RMS of A, B, C)" in flat(inspector.text())
    source.labels = ()
    state.pelvis_changed.emit()
    assert "(RMS of X1, X2, X3)" in flat(inspector.text())
    state.set_overlay("pelvis", False)
    assert "Pelvis" not in flat(inspector.text())


@pytest.mark.gui
def test_more_sections_are_given_the_frame_and_the_joint(shown):
    state, inspector = shown
    opened(state)
    asked = []
    inspector.sections.append(lambda f, j: asked.append((f, j)) or [f"<p>extra {f} {j}</p>"])
    state.set_frame(2)
    state.select(1)
    assert flat(inspector.text()).endswith("extra 2 1")
    assert asked[-1] == (2, 1)


@pytest.mark.gui
def test_a_hidden_inspector_is_current_when_shown_or_read(shown):
    state, inspector = shown
    opened(state)
    state.select(1)
    inspector.hide()
    state.set_frame(3)
    state.select(2)
    assert flat(inspector.text()).startswith("Frame 3 of 0-5 (0.100 s) Joint j2 (index 2)")
    assert inspector.shown_frame() == 3
    state.set_frame(5)  # hidden again: made current when shown
    inspector.show()
    assert inspector.shown_frame() == 5
    assert flat(inspector.label.plain_text()).startswith("Frame 5 of 0-5")


@pytest.mark.gui
def test_a_short_inspector_reads_the_same_text_as_a_tall_one_at_every_frame(qtbot):
    """In a short view only the sections in sight are written at a frame change; the text
    read is the frame's all the same, as a tall inspector of the same state shows it."""
    state = StudioState()
    short = inspector_of(qtbot, state, 90, width=500)
    tall = inspector_of(qtbot, state, 4000, width=500)
    opened(state)
    state.select(3)
    for frame in (1, 4, 2):
        state.set_frame(frame)
        assert flat(short.text()) == flat(tall.text())
        assert flat(short.text()).startswith(f"Frame {frame} of 0-5")
        assert flat(short.text()).split("World rotation")[2].startswith(" (GMR")
    short.resize(500, 4000)  # made tall, every section in sight
    qtbot.wait(10)
    state.set_frame(5)
    assert flat(short.label.plain_text()) == flat(tall.label.plain_text())
