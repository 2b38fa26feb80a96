"""The closed form's root placed by least squares (core/markers/root_fit.py), and the paper's.

``root_at="fit"`` keeps the closed form's rotations and translates the root so that the
weighted squared distances of the joints to their virtual markers are least; ``"pelvis"``
stands it at the pelvis root virtual marker X1, as the paper does. Both are exact on markers
generated from a known skeleton.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import markers_to_motion
from gmr_studio.core.markers.refine import refine_joints
from gmr_studio.core.markers.root_fit import hanging_from_root, root_translations
from gmr_studio.core.markers.solve import solve_positions
from gmr_studio.core.markers.targets import below_missing_bones
from gmr_studio.core.model.motion import Motion, build_translations
from tests.conftest import shared_path
from tests.test_markers_solve import assert_exact, joint_markers


@functools.cache
def walk(frames: int = 60):
    truth = load_gmr(shared_path("cmu/subject02/02_01.amc")).frame_slice(slice(0, frames))
    return truth, load_gmr(shared_path("cmu/subject02/02.asf"))


def noisy(truth, scale: float = 0.4, seed: int = 3) -> np.ndarray:
    """(F, J, 3) the joints of ``truth`` with Gaussian noise (skeleton units, ~2 cm)."""
    positions = world_positions(truth)
    return positions + np.random.default_rng(seed).normal(scale=scale, size=positions.shape)


@pytest.mark.parametrize("root_at", ["fit", "pelvis"])
@pytest.mark.parametrize("refine", [False, True])
def test_exact_case_both_ways_with_and_without_refinement(root_at, refine):
    truth, skeleton = walk()
    result = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth, root_at=root_at)
    motion = result.motion
    if refine:
        motion = refine_joints(motion, result.refine_targets(), weights=result.weights).motion
    assert_exact(motion, truth)


def test_the_fitted_root_is_the_least_squares_translation():
    # noisy joints: the weighted mean of the residuals is zero in every frame, and moving the
    # root by d adds exactly W |d|^2 to the weighted sum of squares (W the sum of the weights)
    truth, skeleton = walk()
    measured = noisy(truth)
    weights = np.random.default_rng(4).uniform(0.2, 3.0, truth.n_joints)
    result = solve_positions(measured, skeleton, ("root", "lhipjoint", "rhipjoint"), weights=weights)
    residual = measured - world_positions(result.motion)
    mean = np.einsum("j,fja->fa", weights, residual) / weights.sum()
    assert np.abs(mean).max() < 1e-12
    d = np.array([0.3, -0.2, 0.5])
    cost = np.einsum("j,fj->f", weights, (residual**2).sum(axis=2))
    moved = np.einsum("j,fj->f", weights, ((residual - d) ** 2).sum(axis=2))
    np.testing.assert_allclose(moved - cost, weights.sum() * d @ d, rtol=1e-9)


def test_the_fit_keeps_the_rotations_and_the_paper_keeps_x1():
    truth, skeleton = walk()
    measured = noisy(truth)
    triple = ("root", "lhipjoint", "rhipjoint")
    fitted = solve_positions(measured, skeleton, triple)
    paper = solve_positions(measured, skeleton, triple, root_at="pelvis")
    np.testing.assert_array_equal(fitted.motion.rotations, paper.motion.rotations)
    np.testing.assert_array_equal(paper.motion.translations[:, 0], measured[:, 0])
    shift = fitted.motion.translations[:, 0] - paper.motion.translations[:, 0]
    np.testing.assert_allclose(world_positions(fitted.motion), world_positions(paper.motion) + shift[:, None])
    assert np.linalg.norm(shift, axis=1).min() > 1e-3  # noise of 0.4 moves it


def test_a_split_root_is_not_moved_and_its_tree_is_left_out():
    # lfemur holds its measured position: its leg neither moves with the root nor pulls it
    truth, skeleton = walk()
    measured = noisy(truth)
    result = solve_positions(measured, skeleton, ("root", "lhipjoint", "rhipjoint"), roots=["lfemur"])
    motion = result.motion
    lfemur = motion.joint_index("lfemur")
    np.testing.assert_array_equal(motion.translations[:, lfemur], measured[:, lfemur])
    have = np.isfinite(measured).all(axis=2)
    follows = hanging_from_root(skeleton, 0, {lfemur}, have)
    leg = [skeleton.joint_index(n) for n in ("lfemur", "ltibia", "lfoot", "ltoes")]
    assert not follows[:, leg].any() and follows[:, skeleton.joint_index("rfemur")].all()
    residual = np.where(follows[..., None], measured - world_positions(motion), 0.0)
    assert np.abs(residual.sum(axis=1)).max() < 1e-12


def test_a_frame_without_joints_keeps_its_root():
    positions = np.zeros((2, 3, 3))
    measured = np.ones((2, 3, 3))
    measured[1] = np.nan
    shift = root_translations(positions, measured, np.ones((2, 3), bool))
    np.testing.assert_array_equal(shift, [[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]])


def test_joints_below_a_bone_the_skeleton_lacks():
    # CMU's BVH shape: the map starts the neck and the arms at a thorax the skeleton has no
    # joint for; the legs at Hips, where the zero-length LHipJoint (never measured) sits
    bvh = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(1, 4))
    measured = world_positions(bvh)
    for dummy in ("LHipJoint", "RHipJoint", "LowerBack", "Neck", "LeftShoulder", "RightShoulder"):
        measured[:, bvh.joint_index(dummy)] = np.nan
    starts = np.full_like(measured, np.nan)
    for j in range(1, bvh.n_joints):
        starts[:, j] = measured[:, bvh.parents[j]]
    for leg, hip in (("LeftUpLeg", "LHipJoint"), ("RightUpLeg", "RHipJoint"), ("Spine", "LowerBack")):
        assert np.linalg.norm(bvh.offsets[bvh.joint_index(hip)]) == 0
        starts[:, bvh.joint_index(leg)] = measured[:, 0]
    thorax = measured[:, bvh.joint_index("Spine1")] + [0.0, 1.0, 0.0]
    for joint in ("Neck1", "LeftArm", "RightArm"):
        starts[:, bvh.joint_index(joint)] = thorax
    below = {bvh.names[j] for j in np.flatnonzero(below_missing_bones(measured, starts, bvh))}
    assert {"Neck1", "Head", "LeftArm", "RightHand", "LFingers", "RThumb_End"} <= below
    assert not below & {"Hips", "LeftUpLeg", "RightFoot", "Spine", "Spine1", "LeftToeBase_End"}
    assert not below_missing_bones(measured, np.full_like(measured, np.nan), bvh).any()  # no [bones]


def test_gmr_markers_root_at_on_a_built_skeleton(tmp_path, capsys):
    # without --skeleton the built skeleton keeps the pelvis markers' root unless asked to fit it
    source = shared_path("c3d/c3dorg_s03_gait-pig.c3d")
    outputs = {}
    for option in ((), ("--root-at", "pelvis"), ("--root-at", "fit")):
        out = tmp_path / f"{'-'.join(option) or 'default'}.gmr"
        assert main(["markers", str(source), "-o", str(out), *option]) == 0
        outputs[option[1:] or ("default",)] = load_gmr(out)
    capsys.readouterr()
    default, paper, fitted = outputs[("default",)], outputs[("pelvis",)], outputs[("fit",)]
    np.testing.assert_array_equal(default.translations, paper.translations)
    np.testing.assert_allclose(fitted.rotations, paper.rotations, atol=1e-12)
    shift = np.linalg.norm(fitted.translations[:, 0] - paper.translations[:, 0], axis=1)
    assert 0.1 < np.median(shift) < 20.0  # mm: the bones' spread (up to 12 mm on this take)


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
