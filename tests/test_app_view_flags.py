"""``gmr-studio FILE --split J ... --screenshot OUT.png``: gmr edit's flags, applied through
the app's undoable commands, in order; without --screenshot the window opens with them
applied and unsaved."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

from gmr_studio.app.arguments import build_arguments
from gmr_studio.app.main import apply_steps_once_loaded
from gmr_studio.app.model.edit_steps import apply_steps
from gmr_studio.app.tools.gallery import dilate, figure_mask
from gmr_studio.core.edits.operations import shift_root, split, split_all
from gmr_studio.core.formats import load_gmr
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path
from tests.test_app_cli import STUDIO, read_png

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

CMU = "cmu/subject01/01_01.bvh"


def _studio(*args) -> subprocess.CompletedProcess:
    return subprocess.run([*STUDIO, *map(str, args)], capture_output=True, text=True, timeout=120)


def test_the_flags_are_gmr_edits_in_the_order_given():
    args = build_arguments().parse_args(["x.bvh", "--split", "A", "--split-all", "--shift-root", "B", "--join-all"])
    assert [step[0] for step in args.steps] == ["split", "split_all", "shift_root", "join_all"]
    assert [step[1] for step in args.steps if step[0] in ("split", "shift_root")] == ["A", "B"]
    assert build_arguments().parse_args(["x.bvh", "--remove-dummies"]).steps[0][0] == "remove_dummies"


def test_a_screenshot_after_edits_shows_the_same_figure_in_new_colours(tmp_path):
    path = shared_path(CMU)
    plain, edited = tmp_path / "plain.png", tmp_path / "edited.png"
    assert _studio(path, "--screenshot", plain, "--size", "480x360", "--frame", 30).returncode == 0
    flags = ["--split", "LeftUpLeg", "--shift-root", "RightHand", "--split-all"]
    result = _studio(path, *flags, "--screenshot", edited, "--size", "480x360", "--frame", 30)
    assert result.returncode == 0, result.stderr
    before, after = read_png(plain), read_png(edited)
    assert not np.array_equal(before, after), "the edits changed nothing in the picture"
    figure_before, figure_after = figure_mask(before), figure_mask(after)
    assert (figure_after & ~dilate(figure_before, 8)).sum() == 0
    assert (figure_before & ~dilate(figure_after, 8)).sum() < 0.05 * figure_before.sum()


def test_a_refused_or_unknown_edit_stops_the_steps_with_its_message(qtbot, studio):
    path = shared_path(CMU)
    open_file(studio, path)
    flags = build_arguments().parse_args
    problem = apply_steps(studio.state, flags([str(path), "--split", "LeftUpLeg", "--split", "NoSuchJoint"]).steps)
    assert problem == "--split NoSuchJoint: unknown joint 'NoSuchJoint'"
    assert studio.state.undo_stack.count() == 1, "the steps before it are applied"
    problem = apply_steps(studio.state, flags([str(path), "--join", "LeftLeg", "--split-all"]).steps)
    assert problem.startswith("--join: ") and "not a root" in problem
    assert studio.state.undo_stack.count() == 1
    assert apply_steps(studio.state, flags([str(path), "--join-all", "--join-all"]).steps) is None


def test_the_window_opens_with_the_edits_applied_unsaved_and_undoable(qtbot, studio):
    path = shared_path(CMU)
    steps = build_arguments().parse_args([str(path), "--split", "LeftUpLeg", "--shift-root", "RightHand"]).steps
    apply_steps_once_loaded(studio, steps)
    open_file(studio, path)
    motion = load_gmr(path)
    expected = shift_root(split(motion, "LeftUpLeg"), "RightHand")
    assert np.array_equal(studio.state.motion.parents, expected.parents)
    assert np.array_equal(studio.state.motion.soft_parents, expected.soft_parents)
    assert studio.state.modified and studio.state.undo_stack.count() == 2
    studio.state.undo_stack.setIndex(0)
    assert np.array_equal(studio.state.motion.parents, motion.parents)
    open_file(studio, path)  # a later document is left alone
    assert studio.state.undo_stack.count() == 0
    assert not np.array_equal(split_all(motion).parents, studio.state.motion.parents)


def test_gmr_edit_takes_remove_dummies_in_its_place_among_the_steps(tmp_path):
    from gmr_studio.core.cli import main as gmr
    from gmr_studio.core.edits.dummies import remove_dummies

    path = shared_path(CMU)
    out = tmp_path / "out.gmr"
    assert gmr(["edit", str(path), "-o", str(out), "--remove-dummies", "--split", "LeftUpLeg"]) == 0
    expected = split(remove_dummies(load_gmr(path))[0], "LeftUpLeg")
    written = load_gmr(out)

    def links(motion) -> dict[str, str]:  # the file may list the joints in another order
        return {motion.names[j]: motion.names[p] for j, p in enumerate(motion.soft_parents) if p >= 0}

    assert sorted(written.names) == sorted(expected.names)
    assert links(written) == links(expected) == {"LeftUpLeg": "Hips"}
