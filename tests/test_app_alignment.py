"""Marker alignment (pure numpy): up axis, similarity fit, unit and heading heuristics."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.demo import demo_markers, demo_motion
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers.alignment import (
    MarkerAlignment,
    auto_alignment,
    markers_on_motion_frames,
    similarity_fit,
)
from gmr_studio.core.markers.markerset import Y_UP_TO_Z_UP
from gmr_studio.core.rotations.euler import axis_permutations, rotation_about_axis
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.space.up_axis import detect_up_axis


def turn(axis: int, degrees: float) -> np.ndarray:
    """(3, 3) rotation by ``degrees`` about coordinate axis 0, 1 or 2 (core.rotations.euler)."""
    return rotation_about_axis("XYZ"[axis], np.radians(degrees))


@pytest.fixture(scope="module")
def walk():
    motion = demo_motion()
    return motion, world_positions(motion), demo_markers(motion)


def test_up_axis_of_y_up_and_z_up_figures(walk):
    _, positions, markers = walk
    assert detect_up_axis(positions) == "y"
    assert detect_up_axis(markers.positions) == "z"  # the demo markers are Z up, with gaps


def test_axis_rotations_are_the_24_proper_permutations():
    rotations = axis_permutations()
    assert len(rotations) == 24
    assert len({tuple(r.ravel()) for r in rotations}) == 24
    for r in rotations:
        np.testing.assert_allclose(r @ r.T, np.eye(3))
        assert np.linalg.det(r) == pytest.approx(1)


def test_similarity_fit_recovers_a_known_transform(rng):
    source = rng.normal(size=(50, 3))
    rotation = Rotation.random(random_state=3).as_matrix()
    target = 2.5 * source @ rotation.T + np.array([1.0, -2.0, 3.0])
    fitted, scale, offset, rms = similarity_fit(source, target)
    np.testing.assert_allclose(fitted, rotation, atol=1e-12)
    assert scale == pytest.approx(2.5) and rms < 1e-12
    np.testing.assert_allclose(offset, [1, -2, 3], atol=1e-12)


def test_markers_named_like_joints_are_fitted_exactly(walk):
    motion, positions, markers = walk
    alignment = auto_alignment(markers.positions, markers.labels, positions, motion.names, markers.units)
    assert "31 markers named like joints" in alignment.method
    assert alignment.transform.scale == pytest.approx(0.1, rel=1e-4)  # mm -> cm
    np.testing.assert_allclose(alignment.transform.rotation, Y_UP_TO_Z_UP.T, atol=1e-4)
    moved = alignment.apply(markers.positions[:, : motion.n_joints])
    assert np.nanmax(np.linalg.norm(moved - positions, axis=-1)) < 0.5  # noise is 0.5 mm


def test_without_names_units_up_axis_and_heading_are_found(walk):
    motion, positions, markers = walk
    anonymous = tuple(f"M{i}" for i in range(markers.n_markers))
    alignment = auto_alignment(markers.positions, anonymous, positions, motion.names, markers.units)
    assert alignment.transform.scale == pytest.approx(0.1)  # snapped to mm -> cm
    np.testing.assert_allclose(alignment.transform.rotation, Y_UP_TO_Z_UP.T)
    moved = alignment.apply(markers.positions[:, : motion.n_joints])
    error = np.nanmean(np.linalg.norm(moved - positions, axis=-1))
    assert error < 0.05 * motion.size  # only the centroid offset of the surface markers remains


def test_a_figure_of_one_point_gets_the_markers_unit_and_a_usable_alignment(walk):
    """One tree of a forest exported alone may be a single joint: it has no height to scale
    the markers by, so the markers keep their unit (mm to the BVH's unknown unit: x1) and
    are laid on the joint's path."""
    _, positions, markers = walk
    joint = positions[:, 3:4]  # (F, 1, 3) one joint's path
    anonymous = tuple(f"M{i}" for i in range(markers.n_markers))
    alignment = auto_alignment(markers.positions, anonymous, joint, ("lfemur",), markers.units)
    assert alignment.transform.scale == 1.0 and np.isfinite(alignment.transform.translation).all()
    centre = np.nanmean(alignment.apply(markers.positions[: len(joint)]), axis=1)  # (F, 3) the markers' centroid
    np.testing.assert_allclose(centre.mean(axis=0), joint[:, 0].mean(axis=0), atol=1e-9 * np.ptp(joint))


def test_a_turned_lab_is_turned_back(walk):
    motion, positions, markers = walk
    turned = markers.transformed(turn(2, 90.0))  # the lab's heading differs by 90 degrees
    anonymous = tuple(f"M{i}" for i in range(markers.n_markers))
    alignment = auto_alignment(turned.positions, anonymous, positions, motion.names, "mm")
    moved = alignment.apply(turned.positions[:, : motion.n_joints])
    assert np.nanmean(np.linalg.norm(moved - positions, axis=-1)) < 0.05 * motion.size


def test_apply_keeps_gaps_and_frame_shift():
    alignment = MarkerAlignment(transform=Similarity(turn(1, 90), 2.0, np.array([1.0, 0, 0])))
    np.testing.assert_allclose(alignment.apply(np.array([1.0, 0, 0])), [1, 0, -2], atol=1e-12)
    assert np.isnan(alignment.apply(np.array([np.nan, np.nan, np.nan]))).all()
    positions = np.arange(4 * 1 * 3, dtype=float).reshape(4, 1, 3)
    shifted = markers_on_motion_frames(positions, 5, 1)
    np.testing.assert_array_equal(shifted[:3], positions[1:])
    assert np.isnan(shifted[3:]).all()


def test_cmu_c3d_markers_land_on_the_bvh_skeleton():
    """The CMU C3D (mm, Z up) onto the cgspeed BVH (CMU units, Y up, an added first frame):
    PROVENANCE.md says (x, y, z)_c3d = 56.444 * (z, x, y)_amc, and LANK stays 47 mm from the ankle."""
    from gmr_studio.core.formats import load_gmr
    from gmr_studio.core.markers import read_markers
    from tests.conftest import shared_path

    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    markers = read_markers(shared_path("cmu/subject01/01_01.c3d"))
    positions = world_positions(motion)
    alignment = auto_alignment(markers.positions, markers.labels, positions, motion.names, markers.units)
    np.testing.assert_array_equal(alignment.transform.rotation, [[0, 1, 0], [0, 0, 1], [1, 0, 0]])
    assert alignment.transform.scale == pytest.approx(0.45 / 25.4)  # mm -> CMU length units
    assert alignment.frame_offset == -1  # the BVH's frame 0 is an added T-pose
    on_frames = alignment.apply(markers_on_motion_frames(markers.positions, motion.n_frames, alignment.frame_offset))
    ankle = positions[:, motion.joint_index("LeftFoot")]
    distance = np.linalg.norm(on_frames[:, markers.labels.index("LANK")] - ankle, axis=1) * 25.4 / 0.45
    assert 30 < np.nanmean(distance) < 75 and np.nanstd(distance) < 5  # millimetres
