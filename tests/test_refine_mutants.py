"""The refinement (core/markers/refine.py) on a built skeleton: the seed's residuals, fixed
joints, markers refitted to the skeleton (the mutation run's first blind spots,
docs/reliability.md)."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.kinematics import forward_kinematics, world_positions
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.refine import marker_places, refine_joints, refine_motion
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
