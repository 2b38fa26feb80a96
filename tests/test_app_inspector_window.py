"""The inspector in the main window on real files: file channels, rounding, playback, selection
and copying, scrolling, partial rebuilds and column widths (the bare inspector over a small
random motion: tests/test_app_inspector.py)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.formatting import (
    format_angles,
    format_lengths,
    format_matrix,
    format_number,
    length_decimals,
)
from gmr_studio.core.formats.bvh import read_bvh_with_channels
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path
from tests.test_app_inspector import flat

studio = app_fixtures.studio

CMU = "cmu/subject01/01_01.bvh"


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
        return format_matrix(world_rotation(state.motion, state.rotations[frame], frame, state.selected)).split("\n")[0]

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
