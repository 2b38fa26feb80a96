"""The comparison in less common conditions: a comparison that does not start at frame 0, a
mirrored target, errors with gaps, summaries read twice, an audit path that loses joints. Each
test names the planted bug it catches."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.compare import audit, compare_motions, fit_alignment
from gmr_studio.core.compare.audit import AuditPath, audit_motion
from gmr_studio.core.compare.result import quantiles, summarize
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions


def demo_walk():
    return load_gmr(demo_folder() / MOTION_FILE)


def bumped(motion, frame: int, joint: int, by: float):
    """``motion`` with ``joint``'s translation moved by ``by`` (along x) at one frame."""
    translations = motion.translations.copy()
    translations[frame, joint, 0] += by
    return motion.replace(translations=translations)


def test_worst_frame_is_as_frame_number_when_the_comparison_starts_at_frame_100():
    # planted bug: the row of the compared window reported instead of A's frame number
    walk = demo_walk()
    assert walk.n_frames > 400
    root = int(walk.roots[0])
    other = bumped(walk, 300, root, 0.1 * walk.size)  # every joint moves at frame 300 only
    result = compare_motions(walk, other, frames=(100, 400))
    assert result.frames[0] == 100 and result.frames[-1] == 399
    assert result.position.max_frame == 300
    np.testing.assert_array_equal(result.position.per_joint_max_frame, 300)
    document = result.to_json()
    assert document["max"]["frame"] == 300 and document["first_frame"] == 100
    assert {joint["max_frame"] for joint in document["joints"]} == {300}
    assert result.row_of_frame(300) == 200


def test_summary_worst_frames_are_the_frame_numbers_given():
    errors = np.array([[0.0, 5.0], [3.0, 1.0], [1.0, np.nan]])
    summary = summarize(errors, np.array([7, 11, 40]), ("a", "b"))
    np.testing.assert_array_equal(summary.per_joint_max_frame, [11, 7])
    assert summary.max_frame == 7 and summary.max_joint == "b"


def test_compared_counts_only_the_samples_present_on_both_sides():
    # planted bug: ``compared`` counts the NaN samples (gaps, B out of its range) too
    walk = demo_walk()
    shorter = walk.frame_slice(slice(0, walk.n_frames - 30))  # B ends 30 frames before A
    result = compare_motions(walk, shorter)
    n_joints = walk.n_joints
    assert np.isnan(result.position_error[-30:]).all() and np.isfinite(result.position_error[:-30]).all()
    assert result.position.count == (walk.n_frames - 30) * n_joints
    assert result.to_json()["compared"] == (walk.n_frames - 30) * n_joints
    errors = np.array([[1.0, np.nan], [np.nan, np.nan], [2.0, 4.0]])
    assert summarize(errors, np.arange(3), ("a", "b")).count == 3


@pytest.mark.parametrize("gaps", [False, True])
def test_reading_the_summary_leaves_the_errors_in_place(gaps):
    # planted bug: the quantiles partition the caller's array (reordering the errors in place)
    rng = np.random.default_rng(3)
    errors = rng.random((50, 4))
    if gaps:
        errors[::7, 1] = np.nan
    before = errors.copy()
    summary = summarize(errors, np.arange(50), ("a", "b", "c", "d"))
    np.testing.assert_array_equal(errors, before)
    present = before[np.isfinite(before)]
    assert summary.median == np.quantile(present, 0.5) and summary.p95 == np.quantile(present, 0.95)
    values = rng.random(101)
    kept = values.copy()
    assert quantiles(values, (0.5, 0.95)) == tuple(np.quantile(kept, (0.5, 0.95)))
    np.testing.assert_array_equal(values, kept)


def test_a_rigid_fit_onto_a_mirrored_walk_is_a_rotation_not_a_reflection():
    # planted bug: the reflection fix of the SVD fit removed (det(R) = -1 on a mirror image)
    walk = demo_walk()
    a = world_positions(walk)[::10]
    b = a * np.array([-1.0, 1.0, 1.0]) + np.array([3.0, 0.0, -2.0])  # a mirror image, moved
    rotation, translation, scale = fit_alignment(a, b, "rigid")
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-12) and scale == 1.0
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-12)
    # the best proper rotation, found independently (scipy's Kabsch, which keeps det = +1)
    flat_a, flat_b = a.reshape(-1, 3), b.reshape(-1, 3)
    centred_a, centred_b = flat_a - flat_a.mean(axis=0), flat_b - flat_b.mean(axis=0)
    expected, _ = Rotation.align_vectors(centred_a, centred_b)
    np.testing.assert_allclose(rotation, expected.as_matrix(), atol=1e-9)
    np.testing.assert_allclose(translation, flat_a.mean(axis=0) - rotation @ flat_b.mean(axis=0), atol=1e-9)


def test_an_audit_path_that_loses_a_joint_fails(monkeypatch):
    # planted bug: ``ok`` ignores the lost joints (only the error of the joints kept is checked)
    walk = demo_walk()
    leaf = next(j for j in range(walk.n_joints) if not walk.children[j])
    renamed = list(walk.names)
    renamed[leaf] = walk.names[leaf] + " renamed"

    def trips(motion, source=None, every=5):
        return [("keeps every joint", 1e-12, lambda m: m), ("loses one", 1e-12, lambda m: m.replace(names=renamed))]

    monkeypatch.setattr(audit, "round_trips", trips)
    kept, lost = audit_motion(walk)
    assert kept.ok and kept.lost_joints == () and kept.max_error == 0.0
    assert lost.max_error == 0.0 and lost.lost_joints == (walk.names[leaf],)  # the others did not move
    assert not lost.ok and lost.to_json()["ok"] is False
    assert not AuditPath("p", 0.0, 0.0, 1e-9, "Hips", 0, lost_joints=("Head",)).ok
    assert AuditPath("p", 0.0, 0.0, 1e-9, "Hips", 0).ok
