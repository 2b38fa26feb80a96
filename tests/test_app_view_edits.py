"""Defect 1 of issue 13: an edit changes colours and root marks, nothing moves, the ground
stays, and undo gives back the very same picture. Checked on the pixels of the real window."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.tools.gallery import dilate, figure_mask, ground_mask
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

# root cubes (3 joint radii wide) stick out of the joint spheres they replace by at most
# their half-diagonal less a radius: 1.6 joint radii, 2 with perspective and rounding
CUBE_MARGIN = 2.0


def _edits(window):
    motion = window.state.motion
    names = motion.names
    hips = names.index("LeftUpLeg") if "LeftUpLeg" in names else int(motion.children[0][0])
    arm = names.index("LeftArm") if "LeftArm" in names else int(motion.children[hips][0])
    return {
        "shift root": lambda: commands.shift_root_to(window.state, arm),
        "split here": lambda: commands.split_here(window.state, hips),
        "split all": lambda: commands.split_everything(window.state),
        "join to parent": lambda: commands.split_here(window.state, arm) and commands.join_to_parent(window.state, arm),
    }


def _check_same_figure(before: np.ndarray, after: np.ndarray, screen: np.ndarray, radius: float, what: str) -> None:
    figure_before, figure_after = figure_mask(before), figure_mask(after)
    assert figure_after.sum() > 0.5 * figure_before.sum(), f"{what}: the figure vanished"
    stray = figure_after & ~dilate(figure_before, int(np.ceil(CUBE_MARGIN * radius)))
    assert stray.sum() == 0, f"{what}: {stray.sum()} figure pixels where there was no figure"
    x, y = np.rint(screen[:, 0]).astype(int), np.rint(screen[:, 1]).astype(int)
    near = dilate(figure_after, 2)
    assert near[y, x].all(), f"{what}: joints {np.flatnonzero(~near[y, x])} are no longer drawn"
    # the grid, away from where the figure is or was, is pixel for pixel the same
    away = ~dilate(figure_before | figure_after, 2)
    grid_before, grid_after = ground_mask(before) & away, ground_mask(after) & away
    assert grid_before.sum() > 1000, "no ground grid in the first place"
    assert np.array_equal(grid_before, grid_after), f"{what}: the ground grid changed"


@pytest.mark.parametrize("edit", ["shift root", "split here", "split all", "join to parent"])
def test_an_edit_moves_nothing_keeps_the_ground_and_undo_restores_the_picture(qtbot, studio, edit):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    studio.state.set_frame(40)
    before = screen_image(studio)
    screen = studio.view.scene.joint_screen_positions()
    radius = studio.view.scene.joint_radius_pixels()
    assert _edits(studio)[edit](), f"{edit} was refused"
    qtbot.wait(10)
    after = screen_image(studio)
    _check_same_figure(before, after, screen, radius, edit)
    assert studio.view.scene.is_shown("ground")
    studio.state.undo_stack.setIndex(0)  # a jump in Edit > History, back to the file as opened
    qtbot.wait(10)
    assert np.array_equal(screen_image(studio), before), f"undo of {edit} does not give back the picture"


def test_edits_on_the_demo_and_a_history_jump_forward(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE)
    before = screen_image(studio)
    screen = studio.view.scene.joint_screen_positions()
    radius = studio.view.scene.joint_radius_pixels()
    commands.split_everything(studio.state)
    commands.join_everything(studio.state)
    studio.state.undo_stack.setIndex(0)
    studio.state.undo_stack.setIndex(1)  # forward to "Split all"
    qtbot.wait(10)
    _check_same_figure(before, screen_image(studio), screen, radius, "history jump to Split all")
