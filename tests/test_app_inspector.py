"""The inspector (app/docks/inspector.py). A bare inspector over a state holding a small
random motion: what it says of the frame, a joint, markers and the pelvis, angles checked
against scipy's Euler decomposition and positions and matrices against the state's own
arrays. In the real window: BVH and GMR local transforms from the right joint's channels,
numbers at the motion's precision, no lag behind the timeline during playback."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.app.docks.inspector import Inspector
from gmr_studio.app.model import commands
from gmr_studio.app.model.formatting import (
    format_angles,
    format_lengths,
    format_matrix,
    format_number,
    length_decimals,
)
from gmr_studio.app.model.joint_transforms import bvh_local, bvh_world_rotation, gmr_local
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.analysis.curves import values_at
from gmr_studio.core.edits.operations import split
from gmr_studio.core.formats.bvh import read_bvh_with_channels
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import random_motion, shared_path

studio = app_fixtures.studio

CMU = "cmu/subject01/01_01.bvh"


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
    bvh_world = bvh_world_rotation(motion, snapshot.rotations, f, j)
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


# ------------------------------------------------------------------------- in the window
@pytest.mark.gui
def test_head_shows_its_own_file_channels_and_its_end_site_none(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    _, channels = read_bvh_with_channels(shared_path(CMU))
    state.select(state.motion.joint_index("Head"))
    state.set_frame(619)
    text = flat(studio.inspector.text())
    bvh_part = text.split("(BVH)", 2)[2].split("(GMR)")[0]  # after the channels rows
    assert "BVH channels of Head, as in the file" in bvh_part
    assert f"Euler ZYX (the file's channel values): {format_angles(channels.angles['Head'][619])}" in bvh_part
    gmr_part = text.split("pre-rotation [R, R t] (GMR)")[1].split("World position")[0]
    assert "bone Neck1 -> Head" in gmr_part and "the file's BVH channels of Neck1" in gmr_part
    assert format_angles(channels.angles["Neck1"][619]) in gmr_part
    state.select(state.motion.joint_index("Head_End"))
    text = flat(studio.inspector.text())
    assert "Channels (BVH) none" in text and "no rotation channels" in text


@pytest.mark.gui
def test_offsets_after_split_all_and_join_all_show_no_float_noise(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    original = state.motion
    assert commands.split_everything(state) and commands.join_everything(state)
    for name in ("LeftUpLeg", "LeftHand", "Head", "RThumb"):
        state.select(state.motion.joint_index(name))
        text = flat(studio.inspector.text())
        offset_row = text.split("Offset ", 1)[1].split(" Channels")[0]
        assert "e-" not in offset_row and "e+" not in offset_row
        assert offset_row == format_lengths(original.offsets[original.joint_index(name)], original.size)


def test_lengths_round_to_the_motions_precision():
    assert format_lengths(np.array([4.983, 9.917e-14, -4.891e-14]), 35.0) == "4.983 0 0"
    assert format_number(-1e-15, 5) == "0" and format_number(-4e-7, 6) == "0" and format_number(2.5e-6, 5) == "0"
    rng = np.random.default_rng(1)
    for size in (0.017, 1.7, 35.0, 1700.0):
        values = rng.normal(scale=size, size=200)
        decimals = length_decimals(size)
        shown = np.array([float(format_number(v, decimals)) for v in values])
        # within half a step of the value, and the step is 1e-6 of the size (7 digits)
        assert np.abs(shown - values).max() <= 0.5 * 10.0**-decimals * (1 + 1e-9)
        assert 10.0**-decimals <= 1e-5 * size


@pytest.mark.gui
def test_the_inspector_shows_the_timelines_frame_while_playing(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    state.select(state.motion.joint_index("LeftHand"))
    behind: list[tuple[int, int | None]] = []

    def check(frame: int) -> None:  # connected after the inspector: runs once it has updated
        if studio.inspector.shown_frame() != frame:
            behind.append((frame, studio.inspector.shown_frame()))

    state.frame_changed.connect(check)
    studio.player.play()
    qtbot.waitUntil(lambda: state.frame > 40, timeout=10000)
    studio.player.pause()
    assert not behind, f"the inspector lagged: {behind[:5]}"
    assert f"Frame {state.frame} of" in studio.inspector.text()


@pytest.mark.gui
def test_text_is_selectable_by_mouse_and_copied(qtbot, studio):
    from PyQt6.QtCore import QPoint, Qt
    from PyQt6.QtWidgets import QApplication

    open_file(studio, shared_path(CMU))
    studio.state.select(studio.state.motion.joint_index("LeftLeg"))
    label = studio.inspector.label
    top_left = label.document.documentLayout().blockBoundingRect(label.document.firstBlock()).topLeft()
    start = QPoint(round(top_left.x()) + label.MARGIN, round(top_left.y()) + label.MARGIN + 2)
    qtbot.mousePress(label, Qt.MouseButton.LeftButton, pos=start)
    qtbot.mouseMove(label, start + QPoint(60, 0))  # no button down in the move event: send it
    label.mouseMoveEvent(_move(start + QPoint(60, 0)))
    selected = label.selected_text()  # the first ~60 px of "Frame 0 of 0-2751"
    assert len(selected) >= 4 and "Frame 0 of 0-2751".startswith(selected)
    label.select_all()
    label.copy()
    assert flat(QApplication.clipboard().text()) == flat(studio.inspector.text())


def _move(point):
    from PyQt6.QtCore import QEvent, QPointF, Qt
    from PyQt6.QtGui import QMouseEvent

    where = QPointF(point)
    left = Qt.MouseButton.LeftButton
    return QMouseEvent(
        QEvent.Type.MouseMove, where, where, Qt.MouseButton.NoButton, left, Qt.KeyboardModifier.NoModifier
    )


@pytest.mark.gui
def test_world_rotations_are_the_joints_own_not_its_parents(qtbot, studio):
    # planted bug: the parent's GMR world rotation shown as the joint's
    from gmr_studio.app.model.formatting import format_matrix
    from gmr_studio.core.kinematics.fk import world_rotations

    open_file(studio, shared_path(CMU))
    state = studio.state
    post, _ = read_bvh_with_channels(shared_path(CMU))
    bvh_world = world_rotations(post)  # the file's own chain of channels, independent of the app's FK
    for name, parent in (("Head", "Neck1"), ("LeftForeArm", "LeftArm")):
        state.select(state.motion.joint_index(name))
        state.set_frame(619)
        text = flat(studio.inspector.text())
        bvh_part = text.split("BVH: the frame its children hang in")[1].split("GMR: the frame")[0]
        gmr_part = text.split("GMR: the frame of the bone that ends at it")[1]
        # GMR: the rotation of the bone parent -> joint, which a BVH hangs in the parent's frame
        gmr_expected = bvh_world[619, post.joint_index(parent)]
        bvh_expected = bvh_world[619, post.joint_index(name)]
        assert np.abs(gmr_expected - bvh_expected).max() > 0.05  # the two differ visibly
        assert flat(format_matrix(gmr_expected)) in gmr_part
        assert flat(format_matrix(bvh_expected)) in bvh_part


@pytest.mark.gui
def test_scrolled_text_is_drawn_where_the_scroll_area_shows_it(qtbot, studio):
    """The text is drawn only in the exposed part (its clip follows the scroll): scrolled to
    the end, the shown part still holds text, as many text pixels as an unclipped drawing."""
    from PyQt6.QtGui import QImage, QPainter
    from PyQt6.QtWidgets import QApplication

    open_file(studio, shared_path(CMU))
    studio.state.select(studio.state.motion.joint_index("LeftHand"))
    studio.inspector_dock.show()
    inspector = studio.inspector
    qtbot.waitExposed(inspector)
    bar = inspector.verticalScrollBar()
    assert bar.maximum() > 0  # the text is taller than the dock
    bar.setValue(bar.maximum())
    QApplication.processEvents()
    shown = inspector.viewport().grab().toImage()
    # the same part drawn by the document alone, without any clip
    label = inspector.label
    full = QImage(label.size(), QImage.Format.Format_ARGB32)
    full.fill(label.palette().color(label.backgroundRole()))
    painter = QPainter(full)
    painter.translate(label.MARGIN, label.MARGIN)
    label.document.drawContents(painter)
    painter.end()
    top = -label.y()  # the label's row at the viewport's top

    def text_pixels(image, first_row):
        rows = np.arange(first_row, first_row + inspector.viewport().height())
        pixels = [[image.pixelColor(x, y).lightness() for x in range(0, image.width(), 2)] for y in rows[::2]]
        background = np.median(pixels)
        return int((np.abs(np.array(pixels) - background) > 60).sum())

    drawn, expected = text_pixels(shown, 0), text_pixels(full, top)
    assert expected > 200
    assert abs(drawn - expected) <= 0.1 * expected


@pytest.mark.gui
def test_a_frame_change_rewrites_the_numbers_in_place_and_a_selection_stays(qtbot, studio):
    from PyQt6.QtGui import QTextCursor, QTextDocument

    from gmr_studio.app.docks.rich_text import SLOT_CLOSE, SLOT_OPEN
    from gmr_studio.app.model import pelvis_recovery

    open_file(studio, shared_path(CMU), markers=shared_path("cmu/subject01/01_01.c3d"))
    state = studio.state
    assert pelvis_recovery.recover_pelvis_frames(state, quiet=True)
    state.set_overlay("pelvis", True)
    state.select(state.motion.joint_index("LeftHand"))
    state.select_marker(0)
    state.set_frame(100)  # the pelvis recovered (not at frame 0), marker 0 seen
    label = studio.inspector.label
    # every number: the frame and its time, two angle lines, two local transforms (a note,
    # 3 rows, a translation, where the angles come from and the angles), the world position,
    # two world rotations (3 rows and angles), the
    # marker, the pelvis residual and rotation (3 rows); the text read (the sections off
    # screen were left as at frame 0, where the pelvis was not recovered)
    assert "Pelvis rotation" in label.plain_text()
    assert label.slots_held == 2 + 2 + 2 * 7 + 1 + 2 * 4 + 1 + 1 + 3 == 32
    start = label.plain_text().index("World position")
    label.cursor.setPosition(start)
    label.cursor.setPosition(start + len("World position"), QTextCursor.MoveMode.KeepAnchor)
    for frame in (101, 500, 2000, 3):
        state.set_frame(frame)
        whole = QTextDocument()
        whole.setHtml(label.text().replace(SLOT_OPEN, "").replace(SLOT_CLOSE, ""))
        assert label.plain_text() == whole.toPlainText()  # as if parsed whole
        assert f"Frame {frame} of 0-2751" in studio.inspector.text()
        assert label.selected_text() == "World position" and label.slots_held == 32


@pytest.mark.gui
def test_a_new_frame_builds_only_the_sections_on_screen_and_the_rest_when_seen(qtbot, studio, monkeypatch):
    """Sections whose numbers are off screen keep an earlier frame's text (stale) and are
    not computed; reading the text, or scrolling them into sight, gives the frame's own."""
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.docks import inspector as inspector_module
    from gmr_studio.app.model.formatting import format_matrix

    open_file(studio, shared_path(CMU))
    state, inspector = studio.state, studio.inspector
    studio.inspector_dock.show()
    qtbot.waitExposed(inspector)
    state.select(state.motion.joint_index("LeftHand"))
    state.set_frame(100)
    inspector.verticalScrollBar().setValue(0)
    QApplication.processEvents()
    label = inspector.label
    on_screen = label.slots_on_screen()
    assert any(on_screen) and not all(on_screen)  # the top numbers shown, the world rotations not
    computed = []
    world_rotation = inspector_module.bvh_world_rotation
    monkeypatch.setattr(inspector_module, "bvh_world_rotation", lambda *a: computed.append(a[2]) or world_rotation(*a))

    def first_row(frame: int) -> str:  # the BVH world rotation's first row at ``frame``
        return format_matrix(world_rotation(state.motion, state.rotations, frame, state.selected)).split("\n")[0]

    state.set_frame(101)
    assert computed == []  # the BVH world rotation's section is off screen: not computed
    assert label.slots_pending > 0 and "Frame 101 of" in label.document.toPlainText()
    assert first_row(101) not in label.document.toPlainText()  # an earlier frame's numbers still there
    text = inspector.text()  # read: every section as it is now
    assert computed == [101] and first_row(101) in text and label.slots_pending == 0
    computed.clear()
    state.set_frame(2000)
    assert computed == []
    bar = inspector.verticalScrollBar()
    bar.setValue(bar.maximum())  # the bottom sections into sight: built as the frame is now
    inspector.viewport().grab()
    assert computed == [2000] and first_row(2000) in label.document.toPlainText()


@pytest.mark.gui
def test_channels_are_called_the_files_own_only_while_they_are(qtbot, studio):
    """Issue 40.4: as read, a BVH joint's channels are the file's own values; split there, they
    are computed from the edited motion (and said so, in the inspector and the curves dock);
    a joint the edit left alone keeps the file's values; undone, the file's own again. A
    glTF's channels, whose file stores quaternions, are never called the file's own."""
    open_file(studio, shared_path(CMU))
    state = studio.state
    _, channels = read_bvh_with_channels(shared_path(CMU))
    studio.curves_dock.show()
    studio.curves.set_quantity("channels")

    def caption() -> str:  # what the inspector says the channels are, and the numbers
        return flat(studio.inspector.text()).split("channels (", 1)[1].split(" gmr-euler")[0]

    arm = state.motion.joint_index("LeftArm")
    state.select(arm)
    state.set_frame(100)
    values = format_angles(channels.angles["LeftArm"][100])
    own = f"the file's own values, as written: Zrotation Yrotation Xrotation): {values} deg"
    assert caption() == own
    assert studio.curves.channels_note.text() == "the file's own values, as written"
    assert commands.split_here(state, arm)
    edited = caption()
    assert edited.startswith("computed from the edited motion, in the file's channel columns: Zrotation Yrotation")
    assert "file's own" not in edited and values not in edited
    assert studio.curves.channels_note.text() == "computed from the edited motion, in the file's channel columns"
    state.select(state.motion.joint_index("Head"))
    assert caption().startswith("the file's own values, as written, this joint unchanged by the edits: ")
    state.undo_stack.undo()
    state.select(arm)
    assert caption() == own
    open_file(studio, shared_path("gltf/mjolnir-zig_RiggedSimple.glb"))
    for joint in range(state.motion.n_joints):
        state.select(joint)
        said = caption()
        assert "file's own" not in said and "computed; the file stores quaternions" in said


@pytest.mark.gui
@pytest.mark.parametrize("width", [1280, 1600])
def test_after_a_split_every_line_of_the_inspector_fits_its_column(qtbot, studio, width):
    """Issue 40.8a: split at LeftArm in a window 1600 (and 1280) pixels wide, no line of the
    selected joint's text, its local [R, t] matrices included, runs past the dock's edge."""
    from PyQt6.QtWidgets import QApplication

    studio.resize(width, 1000)
    studio.default_layout()  # the side column as a window this wide opens with it
    open_file(studio, shared_path(CMU))
    state = studio.state
    assert commands.split_here(state, state.motion.joint_index("LeftArm"))
    state.select(state.motion.joint_index("LeftArm"))
    state.set_frame(100)
    qtbot.wait(50)  # the docks laid out at the window's size
    QApplication.processEvents()
    label = studio.inspector.label
    text = flat(studio.inspector.text())
    bvh_part, gmr_part = text.split("Local, post-rotation")[1].split("Local, pre-rotation")
    assert "translation t: 12.84608 23.19387 -16.89282" in bvh_part
    assert "translation R t: 12.84608 23.19387 -16.89282" in gmr_part
    assert label.document.idealWidth() <= label.document.textWidth() + 0.5
    assert label.width() <= studio.inspector.viewport().width()
