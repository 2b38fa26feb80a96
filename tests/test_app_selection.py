"""The selection follows the joint, not its index, through every edit, undo, redo and
history jump; a removed joint clears it and what hangs on it (issue 14.2). Stale status
messages go on undo and history jumps (13.5)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

CMU = "cmu/subject01/01_01.bvh"


def selected_name(state) -> str | None:
    return None if state.selected is None else state.motion.names[state.selected]


def test_selection_follows_the_joint_through_remove_dummies_undo_redo_and_jumps(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    state.set_overlay("trails", True)
    state.set_frame(300)
    state.select(state.motion.joint_index("LeftForeArm"))
    assert state.selected == 22
    seen: list[int] = []
    state.selection_changed.connect(seen.append)
    assert commands.remove_dummy_joints(state)
    assert state.motion.names[22] == "RightArm"  # the index now names another joint
    scene = studio.view.scene
    for step in ("edit", "undo", "redo", "jump to start", "jump to end"):
        if step == "undo":
            state.undo_stack.undo()
        elif step == "redo":
            state.undo_stack.redo()
        elif step == "jump to start":
            assert commands.split_here(state, state.motion.joint_index("Spine"))
            state.undo_stack.setIndex(0)
        elif step == "jump to end":
            state.undo_stack.setIndex(state.undo_stack.count())
        assert selected_name(state) == "LeftForeArm", step
        assert scene.selected == state.selected, step
        assert "LeftForeArm" in studio.inspector.text(), step
        # the trail and the selection mark sit on the followed joint
        np.testing.assert_allclose(
            np.asarray(scene.parts["selection"].mesh.points)[0], state.positions[300, state.selected], rtol=0, atol=1e-9
        )
    assert seen and seen[-1] == state.selected


def test_a_removed_joint_clears_the_selection_and_its_trail(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    state.set_overlay("trails", True)
    state.select(state.motion.joint_index("LThumb"))  # a dummy joint
    assert commands.remove_dummy_joints(state)
    assert state.selected is None and studio.view.scene.selected is None
    assert not studio.view.scene.parts["trails"].visible
    assert "Click a joint" in studio.inspector.text()
    state.undo_stack.undo()  # it is back, but the selection was cleared: nothing reselects it
    assert state.selected is None


def test_undo_and_history_jumps_clear_stale_status_messages(qtbot, studio):
    open_file(studio, shared_path(CMU))
    state = studio.state
    assert commands.split_here(state, state.motion.joint_index("LeftFoot"))
    assert "Split" in studio.status.text()
    state.undo_stack.undo()
    assert studio.status.text() == ""
    state.show_message("something stale")
    state.undo_stack.setIndex(1)
    assert studio.status.text() == ""
