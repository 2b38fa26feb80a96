"""Issue 21, items 8 and 10: keyboard redo works (no ambiguous shortcut), and the marker and
pelvis switches look off while there is nothing to show."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtGui import QKeySequence
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.model import commands
from gmr_studio.app.window.actions import redo_shortcuts
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio


def test_redo_keys_are_each_given_once(qapp):
    keys = [key.toString() for key in redo_shortcuts()]
    assert keys[0] == "Ctrl+Shift+Z" and len(keys) == len(set(keys))


def test_keyboard_undo_and_redo_by_key_events(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    joint = state.motion.joint_index("lfemur")
    assert commands.shift_root_to(state, joint)
    root_after = state.motion.roots.tolist()
    studio.activateWindow()
    qtbot.waitUntil(studio.isActiveWindow, timeout=3000)  # shortcuts reach the active window
    qtbot.keyClick(studio, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    QApplication.processEvents()
    assert state.motion.roots.tolist() != root_after and state.undo_stack.index() == 0
    ambiguous = []
    for action in studio.findChildren(type(studio.actions["redo"])):
        shortcuts = [s.toString() for s in action.shortcuts()]
        if "Ctrl+Shift+Z" in shortcuts and action is not studio.actions["redo"]:
            ambiguous.append(action.text())
    assert not ambiguous, f"Ctrl+Shift+Z also on {ambiguous}"
    qtbot.keyClick(studio, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    QApplication.processEvents()
    assert state.undo_stack.index() == 1 and state.motion.roots.tolist() == root_after
    assert QKeySequence("Ctrl+Shift+Z") in studio.actions["redo"].shortcuts()


def test_marker_and_pelvis_switches_are_off_with_nothing_to_show(qtbot, studio):
    actions, state = studio.actions, studio.state
    open_file(studio, demo_folder() / MOTION_FILE)
    assert state.overlays["markers"] and state.overlays["pelvis"]  # the user's choice, kept
    for name in ("markers", "marker_labels", "pelvis"):
        action = actions[f"overlay_{name}"]
        assert not action.isEnabled() and not action.isChecked(), name
    walk = shared_path("cmu/subject01/01_01.bvh")
    studio.files.open_path(str(walk), markers=str(walk.with_suffix(".c3d")), ask=False, wait=True)
    QApplication.processEvents()
    assert actions["overlay_markers"].isEnabled() and actions["overlay_markers"].isChecked()
    assert studio.view.scene.is_shown("markers")
    actions["overlay_markers"].trigger()  # the switch still switches
    assert not state.overlays["markers"] and not studio.view.scene.is_shown("markers")
