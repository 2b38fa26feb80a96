"""Defect 3 of issue 13: a tree keeps its colour across edits and undo (app.tree_colors), in
the view's pixels and the forest's swatches alike."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.tree_colors import PALETTE, TreeColors
from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio


def _trees(motion) -> dict[frozenset, int]:
    """Each tree as its set of joints -> the colour slot its joints got (all the same)."""
    return {frozenset(np.flatnonzero(motion.tree_roots == r).tolist()): int(r) for r in motion.roots}


def _edit(motion, kind: int, joint: int, earlier):
    if kind == 0:
        return split(motion, joint)
    if kind == 1:
        return shift_root(motion, joint)
    if kind == 2:
        return join(motion, joint)
    if kind == 3:
        return split_all(motion)
    if kind == 4:
        return join_all(motion)
    return earlier


def test_a_tree_the_edit_did_not_touch_keeps_its_colour_and_undo_gives_back_all_colours():
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    rng = np.random.default_rng(13)
    book = TreeColors()
    seen: list[tuple[object, np.ndarray]] = [(motion, book.slots(motion))]
    current = motion
    for _ in range(40):
        kind = rng.integers(6)
        joint = int(rng.integers(current.n_joints))
        earlier = seen[int(rng.integers(len(seen)))][0]  # undo / a history jump
        try:
            edited = _edit(current, kind, joint, earlier)
        except OperationError:  # refused (not a root, nothing to join): try another
            continue
        before = book.slots(current)
        after = book.slots(edited)
        for tree, root in _trees(edited).items():
            members = np.array(sorted(tree))
            assert np.unique(after[members]).size == 1, "a tree in several colours"
            if tree in _trees(current):
                assert after[root] == before[root], "an untouched tree changed colour"
        for old, slots in seen:
            if old is edited:
                assert np.array_equal(after, slots), "back to an earlier motion, other colours"
        seen.append((edited, after))
        current = edited


def test_new_trees_take_unused_colours_first():
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    book = TreeColors()
    parts = split(split(split(motion, 2), 8), 20)
    slots = book.slots(parts)
    per_tree = [int(slots[r]) for r in parts.roots]
    assert len(set(per_tree)) == len(per_tree) == 4
    # another skeleton starts afresh: its first tree is blue again
    other = parts.joint_slice([0, 1])
    assert np.array_equal(book.colors(other), np.tile(PALETTE[0], (2, 1)))


@pytest.mark.gui
def test_the_view_and_the_forest_keep_a_trees_colour_after_split_all_and_undo(qtbot, studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    names = studio.state.motion.names
    femur = names.index("LeftUpLeg")
    commands.split_here(studio.state, femur)
    scene = studio.view.scene
    orange = np.rint(PALETTE[1] * 255)

    def leg_pixel() -> np.ndarray:
        x, y, _ = scene.joint_screen_positions()[names.index("LeftLeg")]
        return screen_image(studio)[round(y), round(x)].astype(float)

    def swatch(joint: int) -> np.ndarray:
        item = studio.forest.item_for(int(studio.state.motion.tree_roots[joint]))
        image = item.icon(0).pixmap(12, 12).toImage()
        return np.array(image.pixelColor(6, 6).getRgb()[:3], float)

    split_leg = leg_pixel()
    assert np.abs(split_leg - orange).max() < 90, "the split-off leg is drawn in the second colour"
    assert np.abs(swatch(femur) - orange).max() <= 1
    commands.split_here(studio.state, names.index("LHipJoint"))  # a smaller index than the leg's
    commands.split_here(studio.state, names.index("LowerBack"))
    assert np.array_equal(leg_pixel(), split_leg), "the left leg changed colour"
    assert np.abs(swatch(femur) - orange).max() <= 1
    studio.state.undo_stack.setIndex(1)
    assert np.array_equal(leg_pixel(), split_leg)
