"""Why the paper's closed form stays above 15 mm on CMU 01_01's ASF (issue 22), and the fix.

The paper's closed form puts the root at the waist markers' root virtual marker and hangs
every joint from it; the AMC (Vicon's fixed-length fit to all the markers) lowers its root as
the leg lengthens. Placing the root by the least-squares translation of all the joints given
the closed form's rotations (``root_at="fit"``, the default: core/markers/root_fit.py) takes
most of that error out. These tests pin the measurements docs/markers.md ("Accuracy") and
docs/markersets.md ("Figures") give for it.
"""

from __future__ import annotations

import functools

import numpy as np

from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import markers_to_motion, read_markers
from gmr_studio.core.markers.refine import refine_joints
from tests.conftest import shared_path

MM_PER_ASF_UNIT = 25.4 / 0.45
EVALUATION = slice(1100, None)  # the shipped map was calibrated on 0:1100


@functools.cache
def _closed_form(root_at: str, skeleton_file: str = "01.asf"):
    markers = read_markers(shared_path("cmu/subject01/01_01.c3d"))
    skeleton = load_gmr(shared_path("cmu/subject01/" + skeleton_file))
    if skeleton_file.endswith(".asf"):
        truth = world_positions(load_gmr(shared_path("cmu/subject01/01_01.amc")))[EVALUATION]
    else:  # the BVH's frame 0 is an added T-pose
        truth = world_positions(skeleton)[1:][EVALUATION]
    result = markers_to_motion(markers, skeleton, "cmu", frames=EVALUATION, root_at=root_at)
    return result, world_positions(result.motion), truth, skeleton.names


def _mpjpe(positions, truth) -> float:
    return float(np.linalg.norm(positions - truth, axis=2).mean() * MM_PER_ASF_UNIT)


def test_with_the_true_root_position_the_papers_closed_form_is_near_10_mm():
    _, positions, truth, _ = _closed_form("pelvis")
    moved = positions + (truth[:, :1] - positions[:, :1])  # the same poses, the AMC's root position
    assert 16.5 < _mpjpe(positions, truth) < 18.0  # measured 17.2
    assert _mpjpe(moved, truth) < 11.0  # measured 10.1: the root's 13.4 mm is the closed form's share


def _root_error_in_pelvis(root_at: str) -> tuple[np.ndarray, list[float]]:
    """(F, 3) the root's error in the pelvis's axes (mm; ASF: y up) and its correlation with
    the hip-knee-ankle length the markers measure, left and right."""
    result, positions, truth, names = _closed_form(root_at)
    error = (positions[:, 0] - truth[:, 0]) * MM_PER_ASF_UNIT
    in_pelvis = np.einsum("fba,fb->fa", result.motion.rotations[:, 0], error)
    measured = result.measured * MM_PER_ASF_UNIT
    correlations = []
    for hip, knee, ankle in (("lfemur", "ltibia", "lfoot"), ("rfemur", "rtibia", "rfoot")):
        h, k, a = (names.index(n) for n in (hip, knee, ankle))
        leg = np.linalg.norm(measured[:, h] - measured[:, k], axis=1) + np.linalg.norm(
            measured[:, k] - measured[:, a], axis=1
        )
        seen = np.isfinite(leg)
        correlations.append(float(np.corrcoef(in_pelvis[seen, 1], leg[seen])[0, 1]))
    return in_pelvis, correlations


def test_the_papers_root_error_is_vertical_in_the_pelvis_and_follows_the_leg_length():
    in_pelvis, correlations = _root_error_in_pelvis("pelvis")
    spread = in_pelvis.std(axis=0)
    assert spread[1] > 12.0 and spread[0] < 3.0 and spread[2] < 4.0  # measured 14.3 against 1.3, 2.8
    assert min(correlations) > 0.7  # measured 0.79 and 0.80


def test_the_fitted_root_meets_the_goal_on_the_asf():
    _, positions, truth, _ = _closed_form("fit")
    assert 11.0 < _mpjpe(positions, truth) <= 14.0  # measured 13.1 (goal <= 15; 17.2 at X1)
    root = np.linalg.norm(positions[:, 0] - truth[:, 0], axis=1).mean() * MM_PER_ASF_UNIT
    assert root < 9.5  # measured 8.3 (13.4 at X1)
    in_pelvis, _ = _root_error_in_pelvis("fit")
    assert in_pelvis.std(axis=0)[1] < 10.5  # measured 9.1 (14.3 at X1)


def test_the_fitted_root_on_the_bvh_and_after_refinement():
    # the BVH lacks the map's thorax bone: its neck and arms stay out of the root's fit
    result, positions, truth, _ = _closed_form("fit", "01_01.bvh")
    _, at_x1, _, _ = _closed_form("pelvis", "01_01.bvh")
    assert _mpjpe(positions, truth) < 13.0 < _mpjpe(at_x1, truth)  # measured 11.8 and 16.9
    refined = refine_joints(result.motion, result.refine_targets(), weights=result.weights)
    assert _mpjpe(world_positions(refined.motion), truth) < 13.0  # measured 11.8 (15.3 seeded at X1)
    asf, _, asf_truth, _ = _closed_form("fit")
    refined = refine_joints(asf.motion, asf.refine_targets(), weights=asf.weights)
    assert _mpjpe(world_positions(refined.motion), asf_truth) <= 15.0  # measured 14.6, either seed
