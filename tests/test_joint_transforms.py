"""The inspector's numbers (app.joint_transforms) against the BVH file's own channels:
every joint of CMU 01_01.bvh at several frames (issue 14.1)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model.joint_transforms import bvh_local, gmr_local
from gmr_studio.core.edits.operations import shift_root, split
from gmr_studio.core.formats.bvh import read_bvh_with_channels
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.rotations.euler import matrix_from_euler, rotation_about_axis
from tests.conftest import shared_path

FRAMES = (0, 1, 619, 1500, 2751)


@pytest.fixture(scope="module")
def cmu():
    """(post motion as read, its GMR form, the file's channels)."""
    post, channels = read_bvh_with_channels(shared_path("cmu/subject01/01_01.bvh"))
    return post, pre_from_post(post), channels


def test_file_channels_are_the_values_written(cmu):
    post, _, channels = cmu
    text = shared_path("cmu/subject01/01_01.bvh").read_text().splitlines()
    first_frame = np.array(text[text.index("Frame Time: .0083333") + 1].split(), float)
    # Hips: 3 positions then Zrotation Yrotation Xrotation; LHipJoint's 3 angles follow
    np.testing.assert_array_equal(channels.angles["Hips"][0], first_frame[3:6])
    np.testing.assert_array_equal(channels.angles["LHipJoint"][0], first_frame[6:9])
    assert channels.orders["Hips"] == "ZYX" and "Head_End" not in channels.orders
    assert set(channels.orders) == {n for n, o in zip(post.names, post.rotation_orders) if o}


@pytest.mark.parametrize("frame", FRAMES)
def test_bvh_heading_shows_each_joints_own_file_channels(cmu, frame):
    post, pre, channels = cmu
    for j, name in enumerate(post.names):
        shown = bvh_local(pre, frame, j, channels)
        if not post.rotation_orders[j]:  # an End Site: no channels, [I, t]
            assert shown.channels_of is None and shown.angles is None and not pre.children[j]
            np.testing.assert_array_equal(shown.matrix[:, :3], np.eye(3))
            np.testing.assert_array_equal(shown.matrix[:, 3], post.translations[frame, j])
            continue
        assert shown.channels_of == name and shown.from_file
        assert shown.order == post.rotation_orders[j]
        np.testing.assert_array_equal(shown.angles, channels.angles[name][frame])  # the file's values
        file_matrix = matrix_from_euler(np.radians(channels.angles[name][frame]), post.rotation_orders[j])
        np.testing.assert_allclose(shown.matrix[:, :3], file_matrix, rtol=0, atol=1e-14)
        np.testing.assert_allclose(shown.matrix[:, :3], post.rotations[frame, j], rtol=0, atol=1e-14)
        np.testing.assert_array_equal(shown.matrix[:, 3], post.translations[frame, j])


@pytest.mark.parametrize("frame", FRAMES)
def test_gmr_heading_shows_the_parents_file_channels(cmu, frame):
    post, pre, channels = cmu
    for j, name in enumerate(pre.names):
        shown = gmr_local(pre, frame, j, channels)
        p = int(pre.parents[j])
        assert shown.channels_of == name
        if p < 0:  # the root: identity rotation in GMR, its world position
            np.testing.assert_array_equal(shown.matrix, np.column_stack([np.eye(3), post.translations[frame, j]]))
            continue
        rotation = post.rotations[frame, p]
        assert shown.from_file and post.names[p] in shown.note
        np.testing.assert_array_equal(shown.angles, channels.angles[post.names[p]][frame])
        np.testing.assert_allclose(shown.matrix[:, :3], rotation, rtol=0, atol=1e-14)
        np.testing.assert_allclose(shown.matrix[:, 3], rotation @ post.translations[frame, j], rtol=0, atol=1e-12)


def test_head_at_frame_619_is_heads_not_neck1s(cmu):
    """The case of the issue: Head's BVH rotation is Head's channels, its End Site has none."""
    post, pre, channels = cmu
    head, neck = pre.joint_index("Head"), pre.joint_index("Neck1")
    shown = bvh_local(pre, 619, head, channels)
    np.testing.assert_array_equal(shown.angles, channels.angles["Head"][619])
    assert not np.allclose(shown.matrix[:, :3], post.rotations[619, neck], atol=1e-6)
    end = bvh_local(pre, 619, pre.joint_index("Head_End"), channels)
    assert end.channels_of is None and "no rotation channels" in end.note


def test_after_edits_the_angles_are_computed_and_still_make_the_matrix(cmu):
    _, pre, channels = cmu
    edited = split(shift_root(pre, "LeftFoot"), "Spine1")
    for frame in (0, 619):
        for j in range(edited.n_joints):
            for shown in (bvh_local(edited, frame, j, channels), gmr_local(edited, frame, j, channels)):
                if shown.angles is None or shown.matrix is None:
                    continue
                rebuilt = matrix_from_euler(np.radians(shown.angles), shown.order)
                np.testing.assert_allclose(rebuilt, shown.matrix[:, :3], rtol=0, atol=1e-9)


def test_independent_children_have_no_single_bvh_rotation(rng):
    from tests.conftest import random_motion

    motion = random_motion(rng, [-1, 0, 0, 1], n_frames=2)
    shown = bvh_local(motion, 1, 0)
    assert shown.matrix is None and "dummy" in shown.note
    assert bvh_local(motion, 1, 1).matrix is not None  # a single child: its GMR rotation


def test_a_rotated_roots_bvh_rotation_is_its_world_rotation_times_its_childs(rng):
    # planted bug: the product's order swapped (off by up to 1.39 on a rotated root)
    from gmr_studio.core.kinematics.convention import post_from_pre
    from tests.conftest import random_motion

    motion = random_motion(rng, [-1, 0, 1, 2], n_frames=4)  # a chain: no dummies in its BVH form
    post, dummies = post_from_pre(motion)
    assert dummies == [] and post.names == motion.names
    assert np.abs(motion.rotations[:, 0] - np.eye(3)).max() > 0.5  # the root turns
    for frame in range(motion.n_frames):
        for j in range(motion.n_joints - 1):  # the leaf has no rotation channels
            shown = bvh_local(motion, frame, j)
            np.testing.assert_allclose(shown.matrix[:, :3], post.rotations[frame, j], rtol=0, atol=1e-12)
            np.testing.assert_allclose(shown.matrix[:, 3], post.translations[frame, j], rtol=0, atol=1e-12)


def test_bvh_world_rotation_is_the_frame_the_children_hang_in(rng):
    # planted bug: the joint's own (GMR) world rotation always shown
    from gmr_studio.app.model.joint_transforms import bvh_world_rotation
    from gmr_studio.core.kinematics.convention import post_from_pre
    from gmr_studio.core.kinematics.fk import world_rotations
    from tests.conftest import random_motion

    motion = random_motion(rng, [-1, 0, 1, 2, 1], n_frames=3)
    motion = motion.replace(rotations=np.concatenate([motion.rotations[:, :4], motion.rotations[:, 2:3]], axis=1))
    post, dummies = post_from_pre(motion)  # joint 1's two children share one rotation: no dummies
    assert dummies == []
    gmr_world, bvh_world = world_rotations(motion), world_rotations(post)  # independent FK of each form
    for frame in range(motion.n_frames):
        for j in (0, 1, 2):  # joints with children: the BVH frame differs from the GMR one
            shown = bvh_world_rotation(motion, gmr_world[frame], frame, j)
            np.testing.assert_allclose(shown, bvh_world[frame, j], rtol=0, atol=1e-12)
            assert np.abs(shown - gmr_world[frame, j]).max() > 1e-3
        for leaf in (3, 4):  # a leaf hangs nothing: its own GMR world rotation
            np.testing.assert_array_equal(
                bvh_world_rotation(motion, gmr_world[frame], frame, leaf), gmr_world[frame, leaf]
            )


def test_channel_rows_and_notes_say_where_each_rotation_comes_from(rng):
    # planted bugs: channel rows and notes negated (the inspector would say the opposite)
    from gmr_studio.app.model.joint_transforms import channel_names
    from tests.conftest import random_motion

    motion = random_motion(rng, [-1, 0, 1, 1], n_frames=2)
    rotations = motion.rotations.copy()
    rotations[:, 3] = rotations[:, 2]  # joint 1's two children share one rotation: a BVH rotation of j1
    orders = (*motion.rotation_orders[:2], "XYZ", "ZYX")  # ... that they store in different orders
    motion = motion.replace(rotations=rotations, rotation_orders=orders)
    assert channel_names(motion, 0, True, "ZXY") == "Xposition Yposition Zposition Zrotation Xrotation Yrotation"
    assert channel_names(motion, 1, True, "YZX") == "Yrotation Zrotation Xrotation"
    assert channel_names(motion, 2, False, "") == "none"
    root, middle = gmr_local(motion, 1, 0), gmr_local(motion, 1, 1)
    assert "a root" in root.note and middle.note == "GMR channels of j1: the rotation of the bone j0 -> j1"
    assert not middle.from_file and middle.order == motion.rotation_orders[1]  # the joint's own order
    shown = bvh_local(motion, 1, 1)
    assert shown.note == "BVH channels of j1 (the GMR rotation of its child j2)" and not shown.from_file
    assert shown.order == "XYZ" and bvh_local(motion, 1, 2).note.startswith("j2 is a leaf")
    leaf = bvh_local(motion, 1, 2)
    assert leaf.channels_of is None and not leaf.from_file and leaf.angles is None
    rebuilt = matrix_from_euler(np.radians(shown.angles), shown.order)
    np.testing.assert_allclose(rebuilt, shown.matrix[:, :3], rtol=0, atol=1e-12)


def test_notes_of_a_file_read_as_bvh(cmu):
    _, pre, channels = cmu
    head = pre.joint_index("Head")
    assert bvh_local(pre, 619, head, channels).note == "BVH channels of Head, as in the file"
    assert gmr_local(pre, 619, head, channels).note == (
        "GMR channels of Head: the rotation of the bone Neck1 -> Head, the file's BVH channels of Neck1"
    )


def test_a_joint_whose_child_is_joint_0_after_shift_root(rng):
    # planted bug: a child index 0 taken for "independent children" (child < 1)
    from gmr_studio.app.model.joint_transforms import bvh_rotation
    from gmr_studio.core.kinematics.convention import post_from_pre
    from tests.conftest import random_motion

    motion = shift_root(random_motion(rng, [-1, 0, 1], n_frames=2), 2)  # joint 0 now hangs from 1
    assert motion.parents[0] == 1 and list(motion.children[1]) == [0]
    assert bvh_rotation(motion, 1, 1)[1] == 0
    post, _ = post_from_pre(motion)
    np.testing.assert_allclose(bvh_local(motion, 1, 1).matrix[:, :3], post.rotations[1, 1], rtol=0, atol=1e-12)


def test_independent_children_are_told_apart_by_minus_one(rng):
    # the documented (None, -1) for children that turn independently; (None, None) for a leaf
    from gmr_studio.app.model.joint_transforms import LocalTransform, bvh_rotation
    from tests.conftest import random_motion

    motion = random_motion(rng, [-1, 0, 0], n_frames=2)
    assert bvh_rotation(motion, 1, 0) == (None, -1) and bvh_rotation(motion, 1, 1) == (None, None)
    shown = bvh_local(motion, 1, 0)
    assert isinstance(shown, LocalTransform) and shown.matrix is None and not shown.from_file
    # children a micro-radian apart turn independently too (shared means equal to 1e-12)
    nudged = motion.rotations.copy()
    nudged[:, 2] = nudged[:, 1] @ rotation_about_axis("X", np.full(2, 1e-6))
    assert bvh_rotation(motion.replace(rotations=nudged), 1, 0) == (None, -1)
    with pytest.raises(AttributeError):  # frozen: the inspector cannot change what it shows
        shown.note = ""
