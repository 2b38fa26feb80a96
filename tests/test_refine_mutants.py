"""The refinement (core/markers/refine.py) on a built skeleton: the seed's residuals, fixed
joints, markers refitted to the skeleton, the motions refused, the defaults, tiny rotations
(the mutation run's first blind spots, docs/reliability.md)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics import forward_kinematics, world_positions
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.refine import marker_places, refine_joints, refine_motion, rotation_from_vector
from gmr_studio.core.rotations import nearest_rotation
from tests.test_markers_build import generated_markers


def seeded():
    markers, _ = generated_markers("plug-in-gait-full", seed=3)
    motion = markers_to_built_motion(markers).result.motion
    rng = np.random.default_rng(1)
    noisy = motion.rotations @ nearest_rotation(np.eye(3) + rng.normal(scale=0.05, size=motion.rotations.shape))
    bones = np.arange(motion.n_joints)
    offsets = np.where((bones == motion.roots[0])[:, None], 0.0, motion.offsets)
    return motion, motion.replace(rotations=noisy), world_positions(motion), bones, offsets


def test_residuals_before_are_the_seeds():
    _, seed, targets, bones, offsets = seeded()
    result = refine_motion(seed, targets, bones, offsets, iterations=2)
    expected = np.linalg.norm(marker_places(seed, bones, offsets) - targets, axis=2)
    np.testing.assert_allclose(result.residuals_before, expected, atol=1e-12)
    assert result.iterations == 2


def test_fixed_joints_keep_their_local_rotations():
    _, seed, targets, bones, offsets = seeded()
    fixed = (3, 7)
    result = refine_motion(seed, targets, bones, offsets, iterations=5, fixed=fixed)
    np.testing.assert_array_equal(result.motion.rotations[:, list(fixed)], seed.rotations[:, list(fixed)])
    moved = [j for j in range(seed.n_joints) if j not in fixed and j != seed.roots[0]]
    assert np.abs(result.motion.rotations[:, moved] - seed.rotations[:, moved]).max() > 1e-3


def test_joint_centres_displaced_on_their_bones_are_refitted_only_when_asked():
    motion, _, _, _, _ = seeded()
    # every measured centre 10 units along its own bone's frame x: a constant local offset
    world, rotations = forward_kinematics(motion)
    shifted = world + np.einsum("fjab,b->fja", rotations, [10.0, 0.0, 0.0])
    fitted = refine_joints(motion, shifted, iterations=5, fitted=True)
    assert np.nanmax(fitted.residuals) < 1e-6
    plain = refine_joints(motion, shifted, iterations=5)
    assert np.nanmax(plain.residuals) > 1.0


def test_only_a_gmr_motion_with_one_root_and_one_translated_joint_is_refined():
    motion, _, targets, bones, offsets = seeded()
    with pytest.raises(OperationError, match="one root and no other translated joint"):
        refine_motion(motion.replace(convention="post"), targets, bones, offsets)
    translated = motion.has_translation.copy()
    translated[1] = True
    with pytest.raises(OperationError, match="one root and no other translated joint"):
        refine_motion(motion.replace(has_translation=translated), targets, bones, offsets)


def test_five_iterations_by_default_and_the_result_frozen():
    motion, seed, targets, bones, offsets = seeded()
    result = refine_motion(seed, targets, bones, offsets)
    assert result.iterations == 5 and refine_joints(motion, targets).iterations == 5
    assert result == result and result != dataclasses.replace(result)
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.iterations = 1  # type: ignore[misc]


def test_rotation_from_vector_is_exact_at_zero_and_follows_tiny_angles():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(rotation_from_vector(np.zeros((2, 3))), np.broadcast_to(np.eye(3), (2, 3, 3)))
        v = np.array([[3e-9, -4e-9, 5e-9], [1e-7, 2e-7, -2e-7]])  # below and above the series' 1e-8
        got = rotation_from_vector(v)
    expected = Rotation.from_rotvec(v).as_matrix()
    off = ~np.eye(3, dtype=bool)
    # below it, the series: its first-order terms to 1e-12 relative (above it the closed form's
    # 1 - cos loses digits to cancellation: absolute agreement only)
    np.testing.assert_allclose(got[0, off], expected[0, off], rtol=1e-12)
    np.testing.assert_allclose(got, expected, atol=1e-15)


def test_a_missing_marker_is_as_if_it_were_not_there():
    """Frames are refined each on its own: a frame missing a marker comes out as that frame
    refined without the marker."""
    _, seed, targets, bones, offsets = seeded()
    gappy = targets.copy()
    gappy[2, 5] = np.nan
    together = refine_motion(seed, gappy, bones, offsets, iterations=3)
    keep = np.delete(np.arange(len(bones)), 5)
    alone = refine_motion(seed.frame_slice(slice(2, 3)), targets[2:3, keep], bones[keep], offsets[keep], iterations=3)
    np.testing.assert_allclose(together.motion.rotations[2], alone.motion.rotations[0], atol=1e-12)
    np.testing.assert_allclose(together.motion.translations[2], alone.motion.translations[0], atol=1e-12)
