"""Why the paper's closed form stays above 15 mm on CMU 01_01's ASF (issue 22): the root.

The closed form puts the root at the waist markers' root virtual marker and hangs every joint
from it; the AMC (Vicon's fixed-length fit to all the markers) lowers its root as the leg
lengthens. These tests pin the measurements docs/markers.md ("Accuracy") and
docs/markersets.md ("Figures") give for it.
"""

from __future__ import annotations

import functools

import numpy as np

from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics import world_positions
from gmr_studio.core.markers import markers_to_motion, read_markers
from tests.conftest import shared_path

MM_PER_ASF_UNIT = 25.4 / 0.45
EVALUATION = slice(1100, None)  # the shipped map was calibrated on 0:1100


@functools.cache
def _closed_form():
    markers = read_markers(shared_path("cmu/subject01/01_01.c3d"))
    skeleton = load_gmr(shared_path("cmu/subject01/01.asf"))
    truth = world_positions(load_gmr(shared_path("cmu/subject01/01_01.amc")))[EVALUATION]
    result = markers_to_motion(markers, skeleton, "cmu", frames=EVALUATION)
    return result, world_positions(result.motion), truth, skeleton.names


def test_with_the_true_root_position_the_closed_form_is_near_10_mm():
    _, positions, truth, _ = _closed_form()
    error = np.linalg.norm(positions - truth, axis=2).mean() * MM_PER_ASF_UNIT
    moved = positions + (truth[:, :1] - positions[:, :1])  # the same poses, the AMC's root position
    with_root = np.linalg.norm(moved - truth, axis=2).mean() * MM_PER_ASF_UNIT
    assert 16.5 < error < 18.0  # measured 17.2
    assert with_root < 11.0  # measured 10.1: the root's 13.4 mm is the closed form's share


def test_the_root_error_is_vertical_in_the_pelvis_and_follows_the_leg_length():
    result, positions, truth, names = _closed_form()
    error = (positions[:, 0] - truth[:, 0]) * MM_PER_ASF_UNIT
    in_pelvis = np.einsum("fba,fb->fa", result.motion.rotations[:, 0], error)  # ASF: y up
    spread = in_pelvis.std(axis=0)
    assert spread[1] > 12.0 and spread[0] < 3.0 and spread[2] < 4.0  # measured 14.3 against 1.3, 2.8
    measured = result.measured * MM_PER_ASF_UNIT
    for hip, knee, ankle in (("lfemur", "ltibia", "lfoot"), ("rfemur", "rtibia", "rfoot")):
        h, k, a = (names.index(n) for n in (hip, knee, ankle))
        leg = np.linalg.norm(measured[:, h] - measured[:, k], axis=1) + np.linalg.norm(
            measured[:, k] - measured[:, a], axis=1
        )
        seen = np.isfinite(leg)
        assert np.corrcoef(in_pelvis[seen, 1], leg[seen])[0, 1] > 0.7  # measured 0.79 and 0.80
