"""Shift root, split and join (paper 4.1) on real files and small hand-made forests."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from tests.conftest import random_motion, shared_files, shared_path


def assert_same_positions(a, b, relative=1e-9):
    error = np.abs(world_positions(a) - world_positions(b)).max()
    assert error <= relative * a.size, error


@pytest.fixture(scope="module")
def cmu():
    return pre_from_post(read_bvh(shared_path("cmu/subject01/01_01.bvh")))


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_shift_root_to_every_joint_keeps_positions(path):
    gmr = pre_from_post(read_bvh(path))
    positions, world = forward_kinematics(gmr)
    for j in range(gmr.n_joints):
        shifted = shift_root(gmr, j)
        assert shifted.parents[j] == -1 and len(shifted.roots) == 1
        new_positions, new_world = forward_kinematics(shifted)
        assert np.abs(new_positions - positions).max() <= 1e-9 * gmr.size
        off_path = sorted(set(range(gmr.n_joints)) - set(gmr.path_from_root(j)))
        np.testing.assert_allclose(new_world[:, off_path], world[:, off_path], atol=1e-9)
        shifted.check_invariants()


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_split_then_join_of_every_joint_restores_offsets_and_rotations(path):
    gmr = pre_from_post(read_bvh(path))
    positions, world = forward_kinematics(gmr)
    for j in np.flatnonzero(gmr.parents >= 0):
        parted = split(gmr, j)
        assert parted.parents[j] == -1 and parted.soft_parents[j] == gmr.parents[j]
        split_positions, split_world = forward_kinematics(parted)
        assert np.abs(split_positions - positions).max() <= 1e-9 * gmr.size
        np.testing.assert_allclose(split_world, world, atol=1e-12)  # split keeps world rotations
        joined = join(parted, j)
        assert list(joined.parents) == list(gmr.parents) and joined.soft_parents[j] == -1
        assert not joined.has_translation[j]
        np.testing.assert_allclose(joined.offsets, gmr.offsets, atol=1e-9 * gmr.size)
        np.testing.assert_allclose(joined.rotations, gmr.rotations, atol=1e-9)
        joined.check_invariants()


def test_shift_root_by_the_paper_on_two_joints(rng):
    gmr = random_motion(rng, [-1, 0, 0, 1], n_frames=2)
    r0, r1 = gmr.rotations[:, 0], gmr.rotations[:, 1]
    shifted = shift_root(gmr, 1)
    t = np.swapaxes
    np.testing.assert_allclose(shifted.translations[:, 1], world_positions(gmr)[:, 1], atol=1e-12)  # G'
    np.testing.assert_allclose(shifted.rotations[:, 1], r0)  # R'_1 = R_0
    np.testing.assert_allclose(shifted.rotations[:, 0], r1)  # R'_0 = R_1
    np.testing.assert_allclose(shifted.translations[:, 0], -gmr.translations[:, 1])  # t'_0 = -t_1
    np.testing.assert_allclose(shifted.rotations[:, 2], t(r1, -1, -2) @ gmr.rotations[:, 2], atol=1e-15)
    np.testing.assert_allclose(shifted.rotations[:, 3], r1 @ gmr.rotations[:, 3], atol=1e-15)
    assert shifted.rotation_orders[:2] == gmr.rotation_orders[1::-1]


def test_shift_root_there_and_back_restores_the_motion(cmu):
    back = shift_root(shift_root(cmu, "LeftToeBase_End"), "Hips")
    np.testing.assert_allclose(back.rotations, cmu.rotations, atol=1e-12)
    np.testing.assert_allclose(back.offsets, cmu.offsets, atol=1e-12)
    assert list(back.parents) == list(cmu.parents) and back.rotation_orders == cmu.rotation_orders


def test_shift_root_to_the_root_changes_nothing(cmu):
    assert shift_root(cmu, "Hips") is cmu


def test_split_all_is_fully_translational_and_join_all_restores(cmu):
    everything = split_all(cmu)
    positions = world_positions(cmu)
    assert len(everything.roots) == cmu.n_joints and everything.has_translation.all()
    np.testing.assert_array_equal(everything.translations, positions)  # positions are the data
    restored = join_all(everything)
    assert list(restored.parents) == list(cmu.parents) and (restored.soft_parents == -1).all()
    np.testing.assert_allclose(restored.offsets, cmu.offsets, atol=1e-9 * cmu.size)
    assert not restored.has_translation[1:].any()
    assert_same_positions(restored, cmu)


def test_join_of_a_stretching_bone_keeps_translation_channels(cmu):
    parted = split(cmu, "LeftForeArm")
    j = parted.joint_index("LeftForeArm")
    translations = parted.translations.copy()
    translations[:, j, 1] += np.linspace(0, 2, cmu.n_frames)  # the forearm drifts up over time
    stretched = parted.replace(translations=translations)
    joined = join(stretched, j)
    assert joined.has_translation[j] and joined.parents[j] == cmu.joint_index("LeftArm")
    assert_same_positions(joined, stretched)
    joined.check_invariants()


def test_refusals_name_the_problem_and_change_nothing(cmu):
    before = cmu.rotations.copy()
    cases = [
        (lambda: join(cmu, "Hips"), "last root"),
        (lambda: join(cmu, "LeftArm"), "not a root"),
        (lambda: split(cmu, "Hips"), "already a root"),
        (lambda: shift_root(cmu, "Tail"), "unknown joint 'Tail'"),
        (lambda: split(cmu, 99), "out of range"),
        (lambda: join(split(split(cmu, "LeftArm"), "RightArm"), "Hips"), "no soft link"),
    ]
    for call, message in cases:
        with pytest.raises(OperationError, match=message):
            call()
    np.testing.assert_array_equal(cmu.rotations, before)
    with pytest.raises(ValueError):
        cmu.rotations[0, 0, 0, 0] = 1.0  # motions are immutable


def test_operations_need_a_gmr_motion(rng):
    post = random_motion(rng, [-1, 0], convention="post")
    with pytest.raises(OperationError, match="pre-rotation"):
        shift_root(post, 1)


def test_split_root_shifted_away_then_split_again_still_joins_back(rng):
    gmr = random_motion(rng, [-1, 0, 1, 2, 3, 4], n_frames=3)
    step = split(gmr, 2)  # tree {2..5}, soft link 2 -> 1
    step = shift_root(step, 4)  # 2 keeps its link, dormant
    step = split(step, 3)  # cuts 3-2 (2 is below 3 now): the link goes on 3's side
    assert len(step.roots) == 3
    assert_same_positions(step, gmr)
    restored = join_all(step)
    assert len(restored.roots) == 1
    edges = {frozenset((j, int(p))) for j, p in enumerate(restored.parents) if p >= 0}
    assert edges == {frozenset((j, j - 1)) for j in range(1, 6)}
    assert_same_positions(restored, gmr)


def test_join_all_on_a_forest_without_links_changes_nothing(rng):
    forest = random_motion(rng, [-1, 0, -1, 2], n_frames=2)
    assert join_all(forest) is forest
