"""The vectorised comparison against a straightforward one, in every mode of the benchmark.

The reference below samples B with plain matrix products (``R_0 expm(w log(R_0^T R_1))`` by
Rodrigues), turns B's rotations with ``M W N`` products and measures the angle from the
full matrix difference: what :mod:`core.compare` computed before it was vectorised. The
fitted alignment is taken from the result (its fit is tested in test_compare.py), so the
errors must agree to rounding: 1e-12 of the size for positions, 1e-12 degrees for angles.
"""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.benchmark.compare_speed import perturbed
from gmr_studio.core.compare import compare_tracks, track_of_motion
from gmr_studio.core.formats import read_motion
from gmr_studio.core.jointmap import match_joints
from tests.conftest import shared_path

MODES = [
    ("none", 0.0),
    ("rigid", 0.0),
    ("similarity", 0.0),
    ("rigid", "auto"),
    ("none", 0.5),
    ("similarity", -3.25),
    ("rigid", 2.7),
]


@pytest.fixture(scope="module")
def tracks():
    a = read_motion(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 1500))
    b = perturbed(a.frame_slice(slice(20, 1500)), seed=3)  # B starts 20 frames later
    return track_of_motion(a), track_of_motion(b), match_joints(a.names, b.names)


def reference_rotations(rotations: np.ndarray, at: np.ndarray) -> np.ndarray:
    """(N, J, 3, 3) at fractional frames (F,): matrix products, one frame at a time."""
    n = rotations.shape[0]
    out = np.full((len(at), *rotations.shape[1:]), np.nan)
    for row, u in enumerate(at):
        if u < -1e-6 or u > n - 1 + 1e-6:
            continue
        low = min(max(int(np.floor(u)), 0), max(n - 2, 0))
        weight = min(max(u - low, 0.0), 1.0)
        if abs(u - round(u)) <= 1e-6:
            out[row] = rotations[min(max(round(u), 0), n - 1)]
            continue
        for j in range(rotations.shape[1]):
            r0, r1 = rotations[low, j], rotations[low + 1, j]
            relative = r0.T @ r1
            axis = np.array(
                [relative[2, 1] - relative[1, 2], relative[0, 2] - relative[2, 0], relative[1, 0] - relative[0, 1]]
            )
            sin = 0.5 * np.linalg.norm(axis)
            angle = np.arctan2(sin, 0.5 * (np.trace(relative) - 1.0))
            unit = axis / (2.0 * sin) if sin > 1e-12 else np.zeros(3)
            k = np.array([[0.0, -unit[2], unit[1]], [unit[2], 0.0, -unit[0]], [-unit[1], unit[0], 0.0]])
            part = weight * angle
            out[row, j] = r0 @ (np.eye(3) + np.sin(part) * k + (1.0 - np.cos(part)) * k @ k)
    return out


def reference_positions(positions: np.ndarray, at: np.ndarray) -> np.ndarray:
    n = positions.shape[0]
    out = np.full((len(at), *positions.shape[1:]), np.nan)
    for row, u in enumerate(at):
        if -1e-6 <= u <= n - 1 + 1e-6:
            low = min(max(int(np.floor(u)), 0), max(n - 2, 0))
            weight = min(max(u - low, 0.0), 1.0)
            out[row] = positions[low] * (1.0 - weight) + positions[min(low + 1, n - 1)] * weight
    return out


@pytest.mark.parametrize(("align", "offset"), MODES)
def test_vectorised_comparison_equals_the_straightforward_one(tracks, align, offset):
    a, b, match = tracks
    result = compare_tracks(a, b, match, align=align, offset=offset)
    fit = result.alignment.fit
    at = (np.arange(a.n_frames) / a.frame_rate + result.alignment.offset_seconds) * b.frame_rate
    positions_b = reference_positions(b.positions, at)
    moved = fit.scale * positions_b @ fit.rotation.T + fit.translation
    position_error = np.linalg.norm(a.positions - moved, axis=-1)
    turned = fit.rotation @ reference_rotations(b.rotations, at)
    difference = (a.rotations - turned).reshape(len(at), -1, 9)
    chord = np.linalg.norm(difference, axis=-1)
    rotation_error = np.degrees(2.0 * np.arcsin(np.minimum(chord / (2.0 * np.sqrt(2.0)), 1.0)))
    rotation_error[:, ~a.has_rotation] = np.nan

    assert np.array_equal(np.isnan(result.position_error), np.isnan(position_error))
    assert np.nanmax(np.abs(result.position_error - position_error)) <= 1e-12 * a.size
    assert np.array_equal(np.isnan(result.rotation_error), np.isnan(rotation_error))
    gap = np.abs(result.rotation_error - rotation_error)
    # the chord's arcsin is ill-conditioned towards 180 degrees (both sides use it): 1e-12
    # below 150 degrees, where it amplifies rounding at most 4-fold, the rest to 1e-10
    assert np.nanmax(np.where(rotation_error < 150.0, gap, 0.0)) <= 1e-12
    assert np.nanmax(gap) <= 1e-10
    assert np.nanmax(rotation_error) > 1.0  # B really differs (about 2 degrees per joint)
    if offset == "auto":
        assert result.alignment.offset_frames == -20  # B is A from frame 20 on: A frame 20 is B frame 0
    assert result.position.mean == pytest.approx(np.nanmean(position_error), rel=1e-12)
