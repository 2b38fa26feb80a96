"""The root fit's edges the mutation run found untested (core/markers/root_fit.py, issue 24).

A skeleton is a forest: a second tree (a prop, a split-off limb) never follows the pelvis
root's translation, measured or not; and the translation is the weighted mean of the
differences whatever the weights' sum, one unweighted joint (sum 1) or light weights (sum
below 1: large calibration variances).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.markers.root_fit import hanging_from_root, root_translations
from gmr_studio.core.model.motion import Motion, build_translations


def forest() -> Motion:
    """Two trees: pelvis (0) with its spine (3), and a prop (1) with its tip (2); the last
    joint belongs to the pelvis's tree, so it is placed before the prop's root is reached."""
    offsets = np.array([[0.0, 90.0, 0.0], [40.0, 0.0, 0.0], [0.0, 0.0, 10.0], [0.0, 20.0, 0.0]])
    return Motion(
        names=["pelvis", "prop", "prop_tip", "spine"],
        parents=np.array([-1, -1, 1, 0]),
        offsets=offsets,
        rotation_orders=["ZYX"] * 4,
        has_translation=np.array([True, True, False, False]),
        rotations=np.broadcast_to(np.eye(3), (3, 4, 3, 3)).copy(),
        translations=build_translations(3, offsets, {}),
        frame_time=1 / 30,
    )


def test_another_trees_joints_never_follow_the_root():
    skeleton = forest()
    assert list(skeleton.topological_order) == [0, 3, 1, 2]
    have = np.ones((3, 4), bool)
    have[1, 1] = False  # the prop's root unmeasured in frame 1, everything unmeasured in frame 2
    have[2] = False
    expected = np.tile([True, False, False, True], (3, 1))
    # as solve_positions passes it (every other root of the skeleton is a root of its own), and without
    for split_roots in ({1}, set()):
        np.testing.assert_array_equal(hanging_from_root(skeleton, 0, split_roots, have), expected)
    np.testing.assert_array_equal(hanging_from_root(skeleton, 1, {0}, have), ~expected)


def test_one_joint_or_light_weights_still_move_the_root():
    positions = np.zeros((2, 3, 3))
    measured = np.array(
        [
            [[np.nan] * 3, [2.0, -1.0, 0.5], [np.nan] * 3],  # one joint seen: weight 1 in all
            [[1.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 8.0]],
        ]
    )
    use = np.ones((2, 3), bool)
    np.testing.assert_array_equal(root_translations(positions, measured, use)[0], [2.0, -1.0, 0.5])
    weights = np.array([0.5, 0.25, 0.125])  # sum 0.875
    shift = root_translations(positions, measured, use, weights)
    np.testing.assert_allclose(shift[1], [0.5, 1.0, 1.0] / np.float64(0.875), rtol=1e-15)
    np.testing.assert_array_equal(shift[0], [2.0, -1.0, 0.5])  # weight 0.25 alone: the joint itself
