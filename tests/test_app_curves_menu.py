"""The clip and world edits from the Edit menu: Trim to range, Resample..., Mirror
left/right, Up axis..., Scale lengths....

Each is triggered through the menu's own QAction (the Resample dialog is answered as a user
would), checked against the core, and undone to the very same snapshot.
"""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import QTimer
from PyQt6.QtGui import QAction
from PyQt6.QtWidgets import QApplication, QInputDialog

from gmr_studio.app.model.state import Snapshot
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.edits.clip import resample
from gmr_studio.core.edits.mirror import mirror
from gmr_studio.core.formats.bvh import write_bvh
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.rigs import make_rig
from gmr_studio.core.space.up_axis import Y_TO_Z, up_axis_of
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path
from tests.test_app_problems import figure_pixels

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

WALK = "cmu/subject02/02_01.amc"


def edit_menu_action(window, text: str) -> QAction:
    """The Edit menu's action whose text (without '&') is ``text``."""
    menu = next(a.menu() for a in window.menuBar().actions() if a.text().replace("&", "") == "Edit")
    return next(a for a in menu.actions() if a.text().replace("&", "") == text)


def answer_rate_dialog(rate: float | str | None) -> None:
    """Answer the next QInputDialog with ``rate`` (a number, or a choice's text; None:
    cancel it) once it is shown."""

    def answer() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QInputDialog):
            QTimer.singleShot(20, answer)
            return
        if rate is None:
            dialog.reject()
            return
        if isinstance(rate, str):
            assert rate in dialog.comboBoxItems()
            dialog.setTextValue(rate)
        else:
            dialog.setDoubleValue(rate)
        dialog.accept()

    QTimer.singleShot(0, answer)


def test_the_clip_edits_are_disabled_without_a_motion(studio):
    for text in ("Trim to range", "Resample...", "Mirror left/right", "Up axis...", "Scale lengths..."):
        assert not edit_menu_action(studio, text).isEnabled()


def test_trim_to_range_from_the_menu_applies_only_to_a_range_and_undoes(studio):
    open_file(studio, shared_path(WALK))
    state, trim = studio.state, edit_menu_action(studio, "Trim to range")
    assert not trim.isEnabled()  # no range yet
    state.set_frame_range(0, state.n_frames)
    assert not trim.isEnabled()  # the whole motion: nothing to trim
    before = state.snapshot
    state.set_frame_range(57, 210)
    assert trim.isEnabled()
    trim.trigger()
    assert state.motion.n_frames == 153 and state.frame_range is None and not trim.isEnabled()
    np.testing.assert_array_equal(state.positions, before.positions[57:210])
    np.testing.assert_array_equal(state.motion.rotations, before.motion.rotations[57:210])
    state.undo_stack.undo()
    assert state.snapshot is before
    np.testing.assert_array_equal(state.positions, world_positions(before.motion))


def test_resample_from_the_menu_asks_the_rate_and_undoes(studio):
    open_file(studio, shared_path(WALK))
    state, action = studio.state, edit_menu_action(studio, "Resample...")
    before = state.snapshot
    assert action.isEnabled() and state.motion.frame_rate == pytest.approx(120.0)
    answer_rate_dialog(None)
    action.trigger()
    assert state.snapshot is before and state.undo_stack.count() == 0  # cancelled: nothing done
    answer_rate_dialog(40.0)
    action.trigger()
    expected = resample(before.motion, 40.0)
    assert state.motion.frame_rate == pytest.approx(40.0) and state.motion.n_frames == expected.n_frames
    np.testing.assert_array_equal(state.positions, before.positions[::3])  # 120 -> 40 Hz keeps every third frame
    np.testing.assert_array_equal(state.motion.rotations, expected.rotations)
    state.undo_stack.undo()
    assert state.snapshot is before
    state.undo_stack.redo()
    np.testing.assert_array_equal(state.positions, before.positions[::3])


def test_mirror_from_the_menu_swaps_sides_twice_to_the_identity_and_undoes(studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    state, action = studio.state, edit_menu_action(studio, "Mirror left/right")
    before = state.snapshot
    assert action.isEnabled()
    action.trigger()
    expected, _ = mirror(before.motion)
    # the document's kinematics reflected (not computed afresh): the result's FK to rounding
    np.testing.assert_allclose(state.positions, world_positions(expected), rtol=0, atol=1e-12 * expected.size)
    left, right = state.motion.joint_index("LeftFoot"), state.motion.joint_index("RightFoot")
    lateral = np.abs(before.positions[:, left] - before.positions[:, right]).mean(axis=0).argmax()
    keep = [a for a in range(3) if a != lateral]
    np.testing.assert_allclose(
        state.positions[:, left, keep], before.positions[:, right, keep], atol=1e-12 * state.motion.size
    )
    action.trigger()
    np.testing.assert_allclose(state.positions, before.positions, atol=1e-12 * state.motion.size)
    state.undo_stack.undo()
    state.undo_stack.undo()
    assert state.snapshot is before


def test_mirror_says_the_pairs_it_swapped_in_the_status_bar(studio, tmp_path):
    write_bvh(make_rig("second_life"), tmp_path / "second_life.bvh")
    open_file(studio, tmp_path / "second_life.bvh")
    edit_menu_action(studio, "Mirror left/right").trigger()
    assert studio.status.text() == (
        "Mirror left/right: swapped 10 left/right pairs: lCollar/rCollar, lShldr/rShldr, lForeArm/rForeArm, "
        "lHand/rHand, and 6 more"
    )
    names = ["mEyeLeft" if name == "figureHair" else name for name in studio.state.motion.names]
    studio.state.open_document(Snapshot.of(studio.state.motion.replace(names=names)), None)
    studio.curves.mirror_button.click()  # the dock's button: the same command
    assert studio.status.text().startswith("Mirror left/right: swapped 10 left/right pairs: lCollar/rCollar, ")
    assert studio.status.text().endswith(", and 6 more; no partner for mEyeLeft (left as they are)")


def test_mirror_is_disabled_when_no_joint_names_a_side(studio):
    open_file(studio, shared_path(WALK))
    assert studio.curves.mirror_button.isEnabled()
    motion = studio.state.motion
    anonymous = motion.replace(names=tuple(f"joint{j}" for j in range(motion.n_joints)))
    studio.state.open_document(Snapshot.of(anonymous), None)
    assert not edit_menu_action(studio, "Mirror left/right").isEnabled()
    assert not studio.curves.mirror_button.isEnabled()  # the dock's button follows the same rule
    assert edit_menu_action(studio, "Resample...").isEnabled() and studio.curves.resample_button.isEnabled()


def test_up_axis_from_the_menu_turns_the_world_and_the_view_keeps_the_figure_upright(studio):
    open_file(studio, demo_folder() / MOTION_FILE)  # Y up
    state, action = studio.state, edit_menu_action(studio, "Up axis...")
    before, picture = state.snapshot, screen_image(studio)
    answer_rate_dialog(None)
    action.trigger()
    assert state.snapshot is before  # cancelled: nothing done
    answer_rate_dialog("Z up")
    action.trigger()
    assert up_axis_of(state.motion) == "z" and studio.status.text() == "Z up"
    # the document's kinematics turned (not computed afresh): the result's FK to rounding
    size = state.motion.size
    np.testing.assert_allclose(state.positions, before.positions @ Y_TO_Z.T, rtol=0, atol=1e-12 * size)
    np.testing.assert_allclose(state.positions, world_positions(state.motion), rtol=0, atol=1e-9 * size)
    # drawn Z up, the figure stands as it stood: about the same pixels, taller than wide
    after = screen_image(studio)
    figure_before, figure_after = figure_pixels(picture), figure_pixels(after)
    assert abs(int(figure_after.sum()) - int(figure_before.sum())) < 0.2 * figure_before.sum()
    rows, columns = np.nonzero(figure_after)
    assert np.ptp(rows) > np.ptp(columns)
    state.undo_stack.undo()
    assert state.snapshot is before and up_axis_of(state.motion) == "y"


def test_scale_lengths_from_the_menu_scales_every_position_and_undoes(studio):
    open_file(studio, shared_path(WALK))
    state, action = studio.state, edit_menu_action(studio, "Scale lengths...")
    before = state.snapshot
    answer_rate_dialog(2.54)
    action.trigger()
    assert state.motion.size == pytest.approx(2.54 * before.motion.size, rel=1e-12)
    np.testing.assert_allclose(state.positions, 2.54 * before.positions, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(state.rotations, before.rotations)  # lengths only
    state.undo_stack.undo()
    assert state.snapshot is before
