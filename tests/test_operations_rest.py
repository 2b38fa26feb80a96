"""Operations on motions without frames, offset bits through split and join, and fixed
examples for shift root's translation-channel bookkeeping (issue 17, issue 14 item 10)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import random_motion, shared_path

#: a skeleton-only BVH: offsets with bits that a sum and a difference do not give back
ZERO_FRAMES = """HIERARCHY
ROOT Hips
{
  OFFSET 0.7 91.3 -2.9
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Spine
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT Head
    {
      OFFSET 0.1 2.3 0.3
      CHANNELS 3 Zrotation Yrotation Xrotation
      End Site
      {
        OFFSET 0 0.5 0
      }
    }
  }
  JOINT LeftUpLeg
  {
    OFFSET 1.1 -0.2 0.03
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT LeftLeg
    {
      OFFSET 0 -4.4 1e-7
      CHANNELS 3 Zrotation Yrotation Xrotation
    }
  }
}
MOTION
Frames: 0
Frame Time: 0.0333333
"""


def rest_positions(motion) -> np.ndarray:
    """(J, 3) rest-pose world positions, computed joint by joint from the offsets."""
    out = np.full((motion.n_joints, 3), np.nan)
    for j in motion.topological_order:
        p = motion.parents[j]
        out[j] = motion.offsets[j] if p < 0 else out[p] + motion.offsets[j]
    return out


@pytest.fixture
def skeleton(tmp_path):
    path = tmp_path / "zero.bvh"
    path.write_text(ZERO_FRAMES)
    motion = pre_from_post(read_bvh(path))
    assert motion.n_frames == 0
    return motion


def test_split_and_join_of_every_joint_without_frames_restore_the_bits(skeleton):
    rest = rest_positions(skeleton)
    for j in np.flatnonzero(skeleton.parents >= 0):
        parted = split(skeleton, j)
        assert parted.parents[j] == -1 and parted.soft_parents[j] == skeleton.parents[j]
        # the skeleton does not move: the new root stands where the joint stood
        np.testing.assert_allclose(rest_positions(parted), rest, rtol=0, atol=1e-14 * skeleton.size)
        joined = join(parted, j)
        np.testing.assert_array_equal(joined.parents, skeleton.parents)
        np.testing.assert_array_equal(joined.offsets, skeleton.offsets)
        np.testing.assert_array_equal(rest_positions(joined), rest)
        assert not joined.has_translation[j]


def test_split_all_and_join_all_without_frames_restore_the_bits(skeleton):
    everything = split_all(skeleton)
    np.testing.assert_array_equal(everything.offsets, rest_positions(skeleton))
    restored = join_all(everything)
    np.testing.assert_array_equal(restored.parents, skeleton.parents)
    np.testing.assert_array_equal(restored.offsets, skeleton.offsets)
    assert (restored.soft_parents < 0).all() and not restored.has_translation[1:].any()


def test_shift_root_there_and_back_without_frames(skeleton):
    rest = rest_positions(skeleton)
    for j in range(skeleton.n_joints):
        shifted = shift_root(skeleton, j)
        np.testing.assert_allclose(rest_positions(shifted), rest, rtol=0, atol=1e-14 * skeleton.size)
        back = shift_root(shifted, "Hips")
        np.testing.assert_array_equal(back.parents, skeleton.parents)
        np.testing.assert_array_equal(back.offsets[1:], skeleton.offsets[1:])  # negated twice: exact
        np.testing.assert_allclose(back.offsets[0], skeleton.offsets[0], rtol=0, atol=1e-14 * skeleton.size)
        np.testing.assert_array_equal(back.has_translation, skeleton.has_translation)


def test_a_split_joint_without_frames_joins_from_its_rest_pose(skeleton):
    # a link whose offset was not kept (a GMR file read back) is measured on the rest pose
    parted = split(skeleton, "LeftLeg")
    forgotten = parted.replace(link_offsets=None)
    assert np.isnan(forgotten.link_offsets).all()
    joined = join(forgotten, "LeftLeg")
    j = skeleton.joint_index("LeftLeg")
    np.testing.assert_allclose(joined.offsets[j], skeleton.offsets[j], rtol=0, atol=1e-14 * skeleton.size)


def test_the_edit_command_keeps_the_offset_of_a_skeleton_only_file(tmp_path):
    source, out = tmp_path / "zero.bvh", tmp_path / "out.bvh"
    source.write_text(ZERO_FRAMES)
    assert main(["edit", str(source), "--split", "Spine", "--join", "Spine", "-o", str(out)]) == 0
    text = out.read_text()
    assert "OFFSET 0 1 0" in text and "Frames: 0" in text
    assert main(["edit", str(source), "--split-all", "--join-all", "-o", str(out)]) == 0
    written, original = read_bvh(out), read_bvh(source)
    # every joint of the file comes back with its offset bits (the childless LeftLeg, named,
    # gains a zero End Site of its own: names are kept through export)
    for name in original.names:
        np.testing.assert_array_equal(
            written.offsets[written.names.index(name)], original.offsets[original.names.index(name)]
        )


@pytest.fixture(scope="module")
def cmu():
    return pre_from_post(read_bvh(shared_path("cmu/subject01/01_01.bvh")))


def test_split_all_then_join_all_gives_the_offsets_bit_for_bit(cmu):
    restored = join_all(split_all(cmu))
    np.testing.assert_array_equal(restored.offsets, cmu.offsets)
    np.testing.assert_array_equal(restored.parents, cmu.parents)
    assert np.abs(world_positions(restored) - world_positions(cmu)).max() <= 1e-12 * cmu.size


def test_split_then_join_of_every_joint_gives_the_offset_bit_for_bit(cmu):
    short = cmu.frame_slice(slice(0, 40))
    for j in np.flatnonzero(short.parents >= 0):
        np.testing.assert_array_equal(join(split(short, j), j).offsets, short.offsets, err_msg=short.names[j])


def test_a_split_below_a_shifted_link_keeps_the_negated_offset(skeleton):
    # the link goes on the parent's side (the subtree already leads away): its offset is -t
    step = shift_root(split(skeleton, "LeftUpLeg"), "LeftLeg")  # LeftUpLeg holds the link
    step = split(step, "LeftUpLeg")  # cut LeftUpLeg from LeftLeg, its parent now
    leg = skeleton.joint_index("LeftLeg")
    assert step.soft_parents[leg] == skeleton.joint_index("LeftUpLeg")
    np.testing.assert_array_equal(step.link_offsets[leg], skeleton.offsets[leg])  # -(-t): exact
    restored = join_all(step)
    np.testing.assert_array_equal(restored.parents, skeleton.parents)
    np.testing.assert_array_equal(restored.offsets, skeleton.offsets)


def test_an_edited_bone_gets_its_measured_offset_not_the_kept_one(cmu):
    parted = split(cmu, "LeftForeArm")
    j = parted.joint_index("LeftForeArm")
    translations = parted.translations.copy()
    translations[:, j] += parted.rotations[:, j] @ np.array([0.0, 1.0, 0.0])  # one unit along the bone's y
    joined = join(parted.replace(translations=translations), j)
    assert not joined.has_translation[j]
    assert np.abs(joined.offsets[j] - cmu.offsets[j]).max() > 0.5
    assert_positions(joined, parted.replace(translations=translations), 1e-12)


def assert_positions(a, b, relative):
    assert np.abs(world_positions(a) - world_positions(b)).max() <= relative * a.size


# ----------------------------------------------- shift root: translation channels, fixed
# The unseeded property runs found mutations of shift_root's bookkeeping of translation
# channels only when the random path happened to cross a translating bone or a static
# root; these examples cross them every time.


def test_shift_root_across_a_stretching_bone(rng):
    motion = random_motion(rng, [-1, 0, 1, 2, 1], n_frames=6, translation_joints=(2,))
    assert motion.has_translation.tolist() == [True, False, True, False, False]
    for target in (2, 3):  # onto the stretching joint, and past it
        shifted = shift_root(motion, target)
        assert_positions(shifted, motion, 1e-12)
        shifted.check_invariants()
        back = shift_root(shifted, 0)
        np.testing.assert_array_equal(back.has_translation, motion.has_translation)
        np.testing.assert_allclose(back.translations, motion.translations, rtol=0, atol=1e-12 * motion.size)
    shifted = shift_root(motion, 3)
    # the bone 1-2 stretches: reversed it is carried by 1 (child of 2) with translations -t_2
    assert shifted.has_translation.tolist() == [False, True, False, True, False]
    np.testing.assert_array_equal(shifted.translations[:, 1], -motion.translations[:, 2])
    np.testing.assert_array_equal(shifted.translations[:, 2], -motion.translations[:, 3])


def test_shift_root_of_a_static_root_gives_the_new_root_channels(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=5)
    static = motion.replace(
        has_translation=np.array([False, False, False]),
        translations=np.broadcast_to(motion.offsets, motion.translations.shape).copy(),
    )
    static.check_invariants()
    shifted = shift_root(static, 2)
    assert shifted.has_translation.tolist() == [False, False, True]  # the new root moves
    assert np.ptp(shifted.translations[:, 2], axis=0).max() > 1e-3
    shifted.check_invariants()
    assert_positions(shifted, static, 1e-12)
    back = shift_root(shifted, 0)
    assert back.has_translation.tolist() == [True, False, False]  # a root's data are its channels
    assert_positions(back, static, 1e-12)


def test_the_hypothesis_profile_follows_the_environment():
    from hypothesis import settings

    from tests.conftest import hypothesis_profile

    assert hypothesis_profile({"GMR_REQUIRE_GUI": "1"}) == "ci" and hypothesis_profile({"CI": "true"}) == "ci"
    assert hypothesis_profile({}) == "dev" and hypothesis_profile({"CI": "1", "HYPOTHESIS_PROFILE": "dev"}) == "dev"
    assert settings.get_profile("ci").derandomize and settings.get_profile("ci").database is None
    assert not settings.get_profile("dev").derandomize
    assert settings.default.derandomize == (hypothesis_profile() == "ci")


def test_a_missing_shared_file_fails_when_the_data_folder_is_present():
    from tests.conftest import DATA, shared_files

    shared_path("cmu/subject01/01_01.bvh")  # the folder is here (else this test skips)
    with pytest.raises(pytest.fail.Exception, match="is missing, though the data folder"):
        shared_path("cmu/subject01/no_such_take.bvh")
    (param,) = shared_files("no_such_folder/*.bvh")
    assert param.id == "missing:no_such_folder/*.bvh" and not param.marks and not param.values[0].exists()
    assert DATA.is_dir()
