"""The operations edit frames in one compiled pass (numba) or with numpy: the same results.

The numpy path is the reference. On random forests (soft links from earlier splits, an
anchor at the origin, joints with translation channels, BVH-style input for remove dummies)
every operation's two results agree to 1e-12 of the size, keep every joint's world
position to 1e-9 of the size, and the world transforms an :class:`Edited` carries over
agree with the forward kinematics of the result.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gmr_studio.core.edits import frame_programs
from gmr_studio.core.edits.dummies import remove_dummies_edit
from gmr_studio.core.edits.operations import (
    join_all_edit,
    join_edit,
    shift_root,
    shift_root_edit,
    split,
    split_all_edit,
    split_edit,
)
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.engine import MIN_FRAMES_PER_THREAD
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion
from tests.conftest import random_motion, shared_path

pytestmark = pytest.mark.skipif(not frame_programs.available(), reason="numba is not installed")
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def forests(draw, max_joints=24):
    """A GMR forest with translation channels here and there, maybe an anchor (a root
    standing still at the origin, its one child moving), maybe some joints split off."""
    n = draw(st.integers(2, max_joints))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    parents = [-1] + [int(rng.integers(0, j)) if rng.random() < 0.6 else j - 1 for j in range(1, n)]
    moving = tuple(int(j) for j in rng.choice(n, size=2, replace=False))
    motion = random_motion(rng, parents, n_frames=draw(st.integers(1, 6)), translation_joints=moving)
    if draw(st.booleans()):  # joint 0 an anchor: still at the origin, no turn
        rotations, translations = motion.rotations.copy(), motion.translations.copy()
        rotations[:, 0], translations[:, 0] = np.eye(3), 0.0
        motion = motion.replace(rotations=rotations, translations=translations, offsets=_zero_first(motion))
    for _ in range(draw(st.integers(0, 3))):
        joint = draw(st.integers(0, n - 1))
        if motion.parents[joint] >= 0:
            motion = split(motion, joint, backend="numpy")
    return motion


def _zero_first(motion: Motion) -> np.ndarray:
    offsets = motion.offsets.copy()
    offsets[0] = 0.0
    return offsets


def assert_same(numpy_result: Motion, compiled: Motion) -> None:
    """The same forest and the same numbers to 1e-12 (rotations) and 1e-12 of the size."""
    size = numpy_result.size
    assert list(compiled.parents) == list(numpy_result.parents)
    assert list(compiled.soft_parents) == list(numpy_result.soft_parents)
    assert compiled.names == numpy_result.names and compiled.rotation_orders == numpy_result.rotation_orders
    np.testing.assert_array_equal(compiled.has_translation, numpy_result.has_translation)
    np.testing.assert_allclose(compiled.rotations, numpy_result.rotations, rtol=0, atol=1e-12)
    np.testing.assert_allclose(compiled.translations, numpy_result.translations, rtol=0, atol=1e-12 * size)
    np.testing.assert_allclose(compiled.offsets, numpy_result.offsets, rtol=0, atol=1e-12 * size)
    compiled.check_invariants()


def assert_carried(before: Motion, edited) -> None:
    """Every joint where it was, and the carried world transforms those of the result."""
    positions, rotations = forward_kinematics(before)
    carried_positions, carried_rotations = edited.kinematics(positions, rotations)
    result_positions, result_rotations = forward_kinematics(edited.motion)
    tolerance = 1e-9 * before.size
    assert np.abs(result_positions - positions[:, edited.joints]).max() <= tolerance
    np.testing.assert_allclose(result_positions, carried_positions, rtol=0, atol=1e-12 * before.size)
    np.testing.assert_allclose(result_rotations, carried_rotations, rtol=0, atol=1e-12)


def both(operation, motion: Motion):
    return operation(motion, "numpy"), operation(motion, "numba")


@SETTINGS
@given(motion=forests(), data=st.data())
def test_shift_root_split_and_join_agree_with_the_numpy_path(motion, data):
    joint = data.draw(st.integers(0, motion.n_joints - 1))
    reference, compiled = both(lambda m, b: shift_root_edit(m, joint, backend=b), motion)
    assert_same(reference.motion, compiled.motion)
    np.testing.assert_array_equal(compiled.frames, reference.frames)
    assert_carried(motion, compiled)
    if motion.parents[joint] >= 0:
        reference, compiled = both(lambda m, b: split_edit(m, joint, backend=b), motion)
        assert_same(reference.motion, compiled.motion)
        assert_carried(motion, compiled)
    holders = np.flatnonzero((motion.parents < 0) & (motion.soft_parents >= 0))
    if holders.size:
        holder = int(data.draw(st.sampled_from(list(holders))))
        reference, compiled = both(lambda m, b: join_edit(m, holder, backend=b), motion)
        assert_same(reference.motion, compiled.motion)
        assert_carried(motion, compiled)


@SETTINGS
@given(motion=forests(), data=st.data())
def test_split_all_and_join_all_agree_with_the_numpy_path(motion, data):
    if data.draw(st.booleans()):  # a split tree re-rooted: join all must shift it back first
        motion = shift_root(motion, data.draw(st.integers(0, motion.n_joints - 1)))
    reference, compiled = both(lambda m, b: join_all_edit(m, backend=b), motion)
    assert_same(reference.motion, compiled.motion)
    np.testing.assert_array_equal(compiled.frames, reference.frames)
    assert_carried(motion, compiled)
    reference, compiled = both(lambda m, b: split_all_edit(m, backend=b), motion)
    assert_same(reference.motion, compiled.motion)
    assert_carried(motion, compiled)
    everything = compiled.motion
    reference, compiled = both(lambda m, b: join_all_edit(m, backend=b), everything)
    assert_same(reference.motion, compiled.motion)
    assert_carried(everything, compiled)


@SETTINGS
@given(data=st.data())
def test_remove_dummies_agrees_with_the_numpy_path_in_either_convention(data):
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    n = data.draw(st.integers(3, 16))
    parents = [-1] + [int(rng.integers(0, j)) for j in range(1, n)]
    convention = data.draw(st.sampled_from(["pre", "post"]))
    motion = random_motion(rng, parents, n_frames=data.draw(st.integers(1, 5)), convention=convention)
    offsets = motion.offsets.copy()
    dummies = [j for j in range(1, n) if rng.random() < 0.4]
    offsets[dummies] = 0.0  # zero-offset joints: dummies where they have children
    translations = motion.translations.copy()
    translations[:, dummies] = 0.0
    motion = motion.replace(offsets=offsets, translations=translations)
    (reference, names), (compiled, compiled_names) = both(lambda m, b: remove_dummies_edit(m, backend=b), motion)
    assert names == compiled_names
    assert_same(reference.motion, compiled.motion)
    if convention == "pre":
        assert_carried(motion, compiled)
    else:
        assert compiled.frames is None  # a BVH motion's world rotations are not GMR's
        with pytest.raises(ValueError, match="forward kinematics"):
            compiled.kinematics(*forward_kinematics(pre_from_post(motion)))


def split_and_moved(rng: np.random.Generator, moved: np.ndarray) -> Motion:
    """A random motion split at joint 2, whose root then moves by ``moved`` (F, 3) in the
    world, frame by frame, away from where the split left it."""
    cut = split(random_motion(rng, [-1, 0, 1, 2, 1], n_frames=len(moved)), 2)
    translations = cut.translations.copy()
    translations[:, 2] += moved
    return cut.replace(translations=translations)


def joins_of_joint_2(motion: Motion):
    return (lambda m, b: join_edit(m, 2, backend=b), lambda m, b: join_all_edit(m, backend=b))


def test_a_split_root_that_moved_on_its_own_joins_with_its_offset_in_every_frame(rng):
    motion = split_and_moved(rng, rng.normal(scale=0.3, size=(6, 3)))
    for operation in joins_of_joint_2(motion):
        reference, compiled = both(operation, motion)
        assert_same(reference.motion, compiled.motion)
        assert compiled.motion.has_translation[2]
        assert_carried(motion, compiled)


def test_a_split_root_that_moved_rigidly_joins_with_its_new_offset(rng):
    motion = split_and_moved(rng, np.zeros((6, 3)))
    motion = motion.replace(link_offsets=motion.link_offsets + 0.2)  # the kept offset no longer fits
    for operation in joins_of_joint_2(motion):
        reference, compiled = both(operation, motion)
        assert_same(reference.motion, compiled.motion)
        assert not compiled.motion.has_translation[2]
        assert np.abs(compiled.motion.offsets[2] - motion.link_offsets[2]).max() > 0.1
        np.testing.assert_array_equal(compiled.motion.translations[:, 2], np.tile(compiled.motion.offsets[2], (6, 1)))
        assert_carried(motion, compiled)


def test_a_join_of_slightly_skewed_rotations_comes_out_orthonormal_as_in_the_numpy_path(rng):
    cut = split(random_motion(rng, [-1, 0, 1, 2, 1], n_frames=5), 2)
    noise = rng.normal(scale=1e-10, size=cut.rotations.shape)
    skewed = cut.replace(rotations=cut.rotations + noise)  # rotations a file rounded to 10 digits
    reference, compiled = both(lambda m, b: join_edit(m, 2, backend=b), skewed)
    assert_same(reference.motion, compiled.motion)
    rotations = compiled.motion.rotations[:, 2]
    assert np.abs(np.einsum("fab,fac->fbc", rotations, rotations) - np.eye(3)).max() < 1e-13


def test_split_all_then_join_all_of_a_real_file_agree_with_the_numpy_path_and_give_it_back():
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 60))
    everything = split_all_edit(motion).motion
    reference, compiled = both(lambda m, b: join_all_edit(m, backend=b), everything)
    assert_same(reference.motion, compiled.motion)
    assert_carried(everything, compiled)
    np.testing.assert_array_equal(compiled.motion.offsets, motion.offsets)
    np.testing.assert_array_equal(compiled.motion.translations, motion.translations)
    forearm = motion.joint_index("RightForeArm")
    cut = split_edit(motion, forearm).motion
    reference, compiled = both(lambda m, b: join_edit(m, forearm, backend=b), cut)
    assert_same(reference.motion, compiled.motion)
    np.testing.assert_array_equal(compiled.motion.translations, motion.translations)


def test_threads_give_the_same_bits(rng):
    frames = 2 * MIN_FRAMES_PER_THREAD + 5
    motion = split(random_motion(rng, [-1, 0, 1, 1, 3, 0, 5], n_frames=frames, translation_joints=(4,)), 3)
    for operation in (
        lambda m, t: shift_root_edit(m, 4, threads=t),
        lambda m, t: split_edit(m, 5, threads=t),
        lambda m, t: join_edit(m, 3, threads=t),
        lambda m, t: join_all_edit(split_all_edit(m).motion, threads=t),
    ):
        one, two = operation(motion, 1).motion, operation(motion, 2).motion
        np.testing.assert_array_equal(one.rotations, two.rotations)
        np.testing.assert_array_equal(one.translations, two.translations)
        np.testing.assert_array_equal(one.offsets, two.offsets)


def test_a_thousand_shifts_back_and_forth_stay_orthonormal_and_in_place(rng):
    motion = random_motion(rng, [-1, 0, 1, 2, 1, 0], n_frames=4, translation_joints=(3,))
    positions = forward_kinematics(motion)[0]
    shifted = motion
    for _ in range(500):
        shifted = shift_root(shift_root(shifted, 3), 0)
    gram = np.einsum("fjab,fjac->fjbc", shifted.rotations, shifted.rotations)
    assert np.abs(gram - np.eye(3)).max() < 1e-12
    assert np.abs(forward_kinematics(shifted)[0] - positions).max() <= 1e-11 * motion.size
