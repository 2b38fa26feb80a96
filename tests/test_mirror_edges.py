"""Mirror at its edges (core/edits/mirror.py): each strict rule's unmatched names, pairs as (left,
right), names found through a sided parent (in any joint order), the lateral axis's threshold,
soft links to the first joint, the roots' rest offsets and a motion without frames."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.edits.mirror import mirror, side_partners
from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.euler import matrix_from_euler


def make_motion(names, parents, offsets, *, n_frames=3, soft=None, seed=0) -> Motion:
    """A GMR motion on the given tree, roots moving, every joint turning a little."""
    rng = np.random.default_rng(seed)
    offsets = np.asarray(offsets, dtype=np.float64)
    n = len(names)
    roots = [j for j in range(n) if parents[j] < 0]
    channels = {j: offsets[j] + rng.normal(scale=0.1, size=(n_frames, 3)) for j in roots}
    rotations = matrix_from_euler(rng.uniform(-0.5, 0.5, (n_frames, n, 3)), "ZYX")
    flags = np.zeros(n, bool)
    flags[roots] = True
    return Motion(
        names=list(names),
        parents=parents,
        soft_parents=soft,
        offsets=offsets,
        rotation_orders=["ZYX"] * n,
        has_translation=flags,
        rotations=rotations,
        translations=build_translations(n_frames, offsets, channels),
        frame_time=1 / 30,
    )


def test_every_strict_rule_reports_a_name_without_its_partner_once():
    names = ["Hips", "leftEye", "eye_L", "eye_l", "eye.L", "eye.l", "eye_L_End", "eye_l_end", "eye.L.001",
             "eye.l.001", "LeftHand_L", "LShape", "rshape"]  # fmt: skip
    sides = side_partners(names)
    # LeftHand_L fits two strict rules: reported once; LShape and rshape are loose: central
    assert sides.unmatched == tuple(names[1:11])
    np.testing.assert_array_equal(sides.partner, np.arange(len(names)))
    with pytest.raises(dataclasses.FrozenInstanceError):
        sides.unmatched = ()  # type: ignore[misc]


def test_a_name_paired_by_one_rule_is_not_reported_by_another():
    # LeftHand_L pairs with RightHand_L by Left/Right; its _L alone would want LeftHand_R
    names = ["Hips", "RightHand_L", "LeftHand_L"]
    sides = side_partners(names)
    assert sides.unmatched == ()
    np.testing.assert_array_equal(sides.partner, [0, 2, 1])
    np.testing.assert_array_equal(sides.pairs, [[2, 1]])


def test_pairs_are_left_then_right_whichever_comes_first():
    names = ["Hips", "RightArm", "LeftArm", "foot_r", "foot_l", "hand.L", "hand.R", "rfemur", "lfemur"]
    np.testing.assert_array_equal(side_partners(names).pairs, [[2, 1], [4, 3], [5, 6], [8, 7]])


#: children named after a sided parent, listed children first: Hand_LTip (index 0) is the
#: parent of Hand_LTipEnd, so the names are found only parents first
ENDS = ["Hand_LTip", "Hand_LTipEnd", "Hand_L", "Hips", "Hand_R", "Hand_RTip", "Hand_RTipEnd", "Hand_LStub"]
ENDS_PARENTS = [2, 0, 3, -1, 3, 4, 5, 2]


def test_children_named_after_a_sided_parent_pair_up_in_any_joint_order():
    sides = side_partners(ENDS, np.array(ENDS_PARENTS))
    partner = {ENDS[j]: ENDS[k] for j, k in enumerate(sides.partner)}
    assert partner["Hand_LTip"] == "Hand_RTip" and partner["Hand_RTip"] == "Hand_LTip"
    assert partner["Hand_LTipEnd"] == "Hand_RTipEnd" and partner["Hand_RTipEnd"] == "Hand_LTipEnd"
    assert partner["Hand_LStub"] == "Hand_LStub" and partner["Hips"] == "Hips"  # no Hand_RStub
    assert sides.unmatched == ()
    # (left, right): the side of the parent
    assert {(ENDS[a], ENDS[b]) for a, b in sides.pairs} == {
        ("Hand_L", "Hand_R"),
        ("Hand_LTip", "Hand_RTip"),
        ("Hand_LTipEnd", "Hand_RTipEnd"),
    }
    # without the parents, only the names' own rules
    assert {(ENDS[a], ENDS[b]) for a, b in side_partners(ENDS).pairs} == {("Hand_L", "Hand_R")}


def test_names_found_through_parents_deeper_than_them_in_the_list():
    # every end before its tip, every tip before its hand: only parents first finds the ends
    names = ["Hand_LTipEnd", "Hand_RTipEnd", "Hand_LTip", "Hand_RTip", "Hand_L", "Hand_R", "Hips"]
    sides = side_partners(names, np.array([2, 3, 4, 5, 6, 6, -1]))
    np.testing.assert_array_equal(sides.partner, [1, 0, 3, 2, 5, 4, 6])
    assert sides.unmatched == ()


def test_a_child_not_named_after_its_sided_parent_is_not_paired_through_it():
    # Thumb01 cut after its parent's length (6) leaves "1": Hand_R1 through Hand_L's partner
    names = ["Hips", "Hand_L", "Hand_R", "Thumb01", "Hand_R1"]
    sides = side_partners(names, np.array([-1, 0, 0, 1, 2]))
    np.testing.assert_array_equal(sides.partner, [0, 2, 1, 3, 4])


def test_a_right_parent_gives_its_named_child_the_right_side():
    names = ["Hips", "Hand_R", "Hand_L", "Hand_RTip", "Hand_LTip"]
    sides = side_partners(names, np.array([-1, 0, 0, 1, 2]))
    np.testing.assert_array_equal(sides.pairs, [[2, 1], [4, 3]])


def test_a_name_whose_own_letter_has_no_partner_pairs_through_its_parent():
    names = ["Hips", "Hand_L", "Hand_R", "Hand_L_x_L", "Hand_R_x_L"]
    assert side_partners(names).unmatched == ("Hand_L_x_L", "Hand_R_x_L")
    sides = side_partners(names, np.array([-1, 0, 0, 1, 2]))
    assert sides.unmatched == ()
    np.testing.assert_array_equal(sides.partner, [0, 2, 1, 4, 3])


def test_a_root_is_named_after_no_parent():
    # Hand_LEnd is a root (split off) named after the last joint: it is paired from its
    # partner's side only, with Hand_R's side (right) for Hand_REnd
    names = ["Hips", "Hand_R", "Hand_REnd", "Hand_LEnd", "Hand_L"]
    sides = side_partners(names, np.array([-1, 0, 1, -1, 0]))
    np.testing.assert_array_equal(sides.partner, [0, 4, 3, 2, 1])
    assert {(names[a], names[b]) for a, b in sides.pairs} == {("Hand_L", "Hand_R"), ("Hand_LEnd", "Hand_REnd")}


def test_the_mirror_of_children_found_through_their_parents():
    names, parents = ENDS[:-1], ENDS_PARENTS[:-1]  # (Hand_LStub would have no partner to move to)
    offsets = [[0.5, 0, 0], [0.5, 0, 0], [1, 0, 0], [0, 0, 0], [-1, 0, 0], [-0.5, 0, 0], [-0.5, 0, 0]]
    motion = make_motion(names, parents, offsets)
    mirrored, unmatched = mirror(motion)
    assert unmatched == ()
    sigma = side_partners(names, np.array(parents)).partner
    np.testing.assert_array_equal(sigma, [5, 6, 4, 3, 2, 0, 1])
    before, after = world_positions(motion), world_positions(mirrored)
    centre = before[0, :, 0].mean()
    expected = before[:, sigma] * [-1.0, 1.0, 1.0] + [2 * centre, 0.0, 0.0]
    np.testing.assert_allclose(after, expected, rtol=0, atol=1e-12)


def test_left_and_right_within_a_billionth_of_the_size_coincide_in_any_unit():
    names, parents = ["Hips", "LeftLeg", "RightLeg", "Head"], [-1, 0, 0, 0]
    for size in (1.0, 1000.0):  # metres or millimetres
        apart = [[0, 0, 0], [0, -size, 1e-11 * size], [0, -size, 0], [0, 0, 0]]
        with pytest.raises(OperationError, match="coincide"):
            mirror(make_motion(names, parents, apart))
        apart = [[0, 0, 0], [0, -size, 1e-8 * size], [0, -size, 0], [0, 0, 0]]
        assert mirror(make_motion(names, parents, apart))[0].n_joints == 4


def test_a_soft_link_to_the_first_joint_must_mirror_too():
    names = ["Hips", "LeftLeg", "RightLeg", "LeftFoot", "RightFoot"]
    offsets = [[0, 1, 0], [0.2, -0.5, 0], [-0.2, -0.5, 0], [0.2, 0, 0], [-0.2, 0, 0]]
    parents = [-1, 0, 0, -1, -1]
    # LeftFoot split from Hips, RightFoot from nothing: the mirror would need RightFoot - Hips
    lopsided = make_motion(names, parents, offsets, soft=[-1, -1, -1, 0, -1])
    with pytest.raises(OperationError, match="'Hips' - 'LeftFoot'"):
        mirror(lopsided)
    # both split from Hips: the mirror keeps both soft links
    both = make_motion(names, parents, offsets, soft=[-1, -1, -1, 0, 0])
    np.testing.assert_array_equal(mirror(both)[0].soft_parents, [-1, -1, -1, 0, 0])


def test_the_roots_rest_offsets_are_mirrored_across_the_plane():
    names = ["Hips", "LeftLeg", "RightLeg"]
    motion = make_motion(names, [-1, 0, 0], [[3.0, 1.0, 0.0], [0.25, -0.5, 0.0], [-0.2, -0.5, 0.1]])
    mirrored, _ = mirror(motion)
    centre = world_positions(motion)[0, :, 0].mean()
    rest, moved = world_positions(motion.rest_pose())[0], world_positions(mirrored.rest_pose())[0]
    np.testing.assert_allclose(moved, rest[[0, 2, 1]] * [-1.0, 1.0, 1.0] + [2 * centre, 0, 0], rtol=0, atol=1e-12)


def test_a_motion_without_frames_mirrors_through_the_origin():
    # left and right along z: the lateral axis is the third one
    names = ["Hips", "LeftLeg", "RightLeg"]
    offsets = np.array([[1.0, 1.0, 2.0], [0.0, -0.5, 0.3], [0.0, -0.5, -0.3]])
    empty = make_motion(names, [-1, 0, 0], offsets, n_frames=0)
    mirrored, _ = mirror(empty)
    assert mirrored.n_frames == 0
    np.testing.assert_array_equal(mirrored.offsets, offsets[[0, 2, 1]] * [1.0, 1.0, -1.0])
