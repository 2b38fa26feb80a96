"""The refinement (core/markers/refine.py) on a built skeleton: the seed's residuals, fixed
joints, markers refitted to the skeleton, the motions refused, the defaults, tiny rotations;
the walks up the skeleton (joints listed root last, a fixed root), Gauss-Newton's speed and
LAPACK held to one thread while it runs."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.refine import (
    marker_places,
    one_blas_thread,
    refine_joints,
    refine_motion,
    rotation_from_vector,
)
from gmr_studio.core.rotations.euler import nearest_rotation
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


def test_by_default_the_refinement_brings_the_markers_back_and_its_result_is_frozen():
    motion, seed, targets, bones, offsets = seeded()
    result = refine_motion(seed, targets, bones, offsets)
    assert np.nanmax(result.residuals) < 1e-6 * np.nanmax(result.residuals_before)
    assert np.nanmax(refine_joints(motion, targets).residuals) < 1e-6
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


def reversed_joints(motion):
    """The same motion with its joints listed the other way round (the root last, every parent
    after its children), and the index map old -> new (J,)."""
    order = np.arange(motion.n_joints)[::-1]  # new joint i is old joint order[i]
    new_index = np.argsort(order)

    def reindex(parents):
        return None if parents is None else np.where(parents[order] < 0, -1, new_index[parents[order]])

    return dataclasses.replace(
        motion,
        names=tuple(motion.names[i] for i in order),
        parents=reindex(motion.parents),
        soft_parents=reindex(motion.soft_parents),
        offsets=motion.offsets[order],
        link_offsets=None if motion.link_offsets is None else motion.link_offsets[order],
        rotation_orders=tuple(motion.rotation_orders[i] for i in order),
        has_translation=motion.has_translation[order],
        rotations=motion.rotations[:, order],
        translations=motion.translations[:, order],
    ), new_index


def test_the_refinement_does_not_depend_on_the_order_the_joints_are_listed_in():
    # markers on a few bones only and two joints fixed: joints without a free rotation in the
    # walks up the skeleton; listed root last, the root is no longer index 0 and parents follow
    # their children
    motion, seed, targets, _, _ = seeded()
    bones = np.array([3, 5, 9, 14, 15, 19, 12])
    fixed = np.array([2, 11])
    reordered, new_index = reversed_joints(seed)
    assert reordered.roots[0] == seed.n_joints - 1
    result = refine_motion(seed, targets[:, bones], bones, motion.offsets[bones], iterations=3, fixed=tuple(fixed))
    other = refine_motion(
        reordered, targets[:, bones], new_index[bones], motion.offsets[bones], iterations=3,
        fixed=tuple(new_index[fixed]),
    )  # fmt: skip
    assert np.nanmax(result.residuals) < 0.2 * np.nanmax(result.residuals_before)
    np.testing.assert_allclose(other.residuals, result.residuals, atol=1e-8)
    np.testing.assert_allclose(other.motion.rotations[:, new_index], result.motion.rotations, atol=1e-8)


def test_a_fixed_root_keeps_its_rotation_while_the_joints_below_it_fit_the_markers():
    motion, seed, targets, _, _ = seeded()
    bones = np.array([3, 5, 9, 14, 15, 19, 12])  # none on the root's own bone
    result = refine_motion(seed, targets[:, bones], bones, motion.offsets[bones], iterations=8, fixed=(0,))
    np.testing.assert_array_equal(result.motion.rotations[:, 0], seed.rotations[:, 0])
    assert np.nanmax(result.residuals_before) > 10.0
    assert np.nanmax(result.residuals) < 1e-6


def test_six_iterations_bring_a_pose_turned_by_about_three_degrees_back_to_rounding():
    # Levenberg-Marquardt from lambda 1e-3, lowered 0.3-fold at each step kept: Gauss-Newton's
    # quadratic convergence (a start or a factor ten times too large stalls it at 1e-3)
    _, seed, targets, bones, offsets = seeded()
    result = refine_motion(seed, targets, bones, offsets, iterations=6)
    assert np.nanmax(result.residuals_before) > 100.0
    assert np.nanmax(result.residuals) < 1e-8 * np.nanmax(result.residuals_before)


def numpy_openblas():
    """The thread-count setter and getter of the OpenBLAS numpy bundles, opened here with
    ctypes, or None (a numpy built against another BLAS)."""
    import ctypes

    for path in sorted((Path(np.__file__).resolve().parent.parent / "numpy.libs").glob("*openblas*.so*")):
        library = ctypes.CDLL(str(path))
        for name in ("scipy_openblas_%s_num_threads64_", "openblas_%s_num_threads64_", "openblas_%s_num_threads"):
            if hasattr(library, name % "set") and hasattr(library, name % "get"):
                return getattr(library, name % "set"), getattr(library, name % "get")
    return None


def test_one_blas_thread_sets_numpys_openblas_to_one_thread_and_restores_it():
    functions = numpy_openblas()
    if functions is None:
        pytest.skip("this numpy bundles no OpenBLAS (the helper then does nothing)")
    setter, getter = functions
    before = getter()
    setter(2)
    try:
        start = getter()
        with one_blas_thread():
            assert getter() == 1
        assert getter() == start
        with pytest.raises(RuntimeError), one_blas_thread():
            assert getter() == 1
            raise RuntimeError("inside the block")
        assert getter() == start
    finally:
        setter(before)
