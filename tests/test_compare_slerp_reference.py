"""B between its frames, against scipy: every rotation slerped by ``scipy.spatial.transform``
(quaternions, one sample at a time) and the angle to A taken as the magnitude of the relative
rotation (``2 arctan2(|q_v|, |q_w|)``), an independent computation accurate at every angle.

The rotations are made to reach the hard cases of the vectorised path: steps between B's
frames of 0, 1e-9 rad, around the 60-degree switch to the far path and up to 180 - 1e-6
degrees; angles between A and B of 1e-8 rad and of 180 degrees minus 1e-7 rad (where the
chord's arcsin would lose digits); NaN frames on either side; A's frames outside B's time
range on both ends; two frame rates, so that the fractional frames vary. Resampling is
checked with both interpolators, the numpy reference and the compiled kernel.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from gmr_studio.core.compare import compare_tracks
from gmr_studio.core.compare.tracks import Track
from gmr_studio.core.jointmap import match_joints
from gmr_studio.core.kinematics.engine import have_numba
from gmr_studio.core.timebase.sampling import interpolate_rotations as resample_rotations

N_B, N_A, RATE_A, RATE_B, OFFSET = 60, 100, 40.0, 30.0, -0.3  # A's frame i is B's 0.75 i - 9
NEAR_PI_STEPS = [*np.radians([180.0 - 1e-4, 179.0, 150.0, 120.0, 90.0]), np.pi - 1e-6, np.pi - 1e-3]


def _about(axes: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Rotation matrices (K, 3, 3) by angles (K,) about axes (K, 3) (normalised here)."""
    axes = axes / np.linalg.norm(axes, axis=-1, keepdims=True)
    return Rotation.from_rotvec(axes * np.asarray(angles)[:, None]).as_matrix()


def _b_rotations(rng: np.random.Generator) -> np.ndarray:
    """(N_B, 8, 3, 3) world rotations of B, one kind of step per joint."""
    start = Rotation.random(8, random_state=rng).as_matrix()
    steps = np.empty((N_B - 1, 8))
    steps[:, 0] = rng.uniform(0.0, np.pi, N_B - 1)  # anything
    steps[:, 1] = rng.uniform(0.0, np.pi, N_B - 1)
    steps[:, 2] = rng.uniform(0.01, 0.1, N_B - 1)  # a motion sampled finely
    steps[:, 3] = rng.uniform(0.01, 0.1, N_B - 1)
    steps[:, 4] = np.where(np.arange(N_B - 1) % 2, 1e-9, 0.0)  # still and nearly still
    steps[:, 5] = np.resize(NEAR_PI_STEPS, N_B - 1)  # towards 180 degrees
    steps[:, 6] = np.resize(np.radians([59.999999, 60.0, 60.000001, 45.0, 75.0]), N_B - 1)  # the switch
    steps[:, 7] = rng.uniform(0.0, 0.5, N_B - 1)
    out = np.empty((N_B, 8, 3, 3))
    out[0] = start
    for f in range(1, N_B):
        turn = _about(rng.normal(size=(8, 3)), steps[f - 1])
        out[f] = turn @ out[f - 1]  # a step of exactly that angle, about a world axis
    out[10] = np.nan  # a gap in every joint
    out[20, 2] = np.nan  # a gap in one
    return out


def _scipy_b(b: np.ndarray, at: np.ndarray) -> np.ndarray:
    """(F, J, 3, 3): B at fractional frames, scipy's Slerp sample by sample (NaN outside or
    next to a gap); a whole frame (within 1e-6) is that frame."""
    out = np.full((len(at), b.shape[1], 3, 3), np.nan)
    for row, u in enumerate(at):
        if not 0.0 <= u <= N_B - 1:
            continue
        if abs(u - np.rint(u)) <= 1e-6:
            out[row] = b[int(np.rint(u))]
            continue
        low = min(int(np.floor(u)), N_B - 2)
        for j in range(b.shape[1]):
            pair = b[low : low + 2, j]
            if np.isnan(pair).any():
                continue
            out[row, j] = Slerp([0.0, 1.0], Rotation.from_matrix(pair))([u - low]).as_matrix()[0]
    return out


def _scipy_angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(F, J) degrees between rotations (F, J, 3, 3), NaN where either is NaN."""
    out = np.full(a.shape[:2], np.nan)
    present = ~(np.isnan(a).any(axis=(-1, -2)) | np.isnan(b).any(axis=(-1, -2)))
    relative = Rotation.from_matrix(a[present]).inv() * Rotation.from_matrix(b[present])
    out[present] = np.degrees(relative.magnitude())
    return out


@pytest.fixture(scope="module")
def case():
    """Tracks A (N_A frames at RATE_A) and B (N_B frames at RATE_B) and B slerped by scipy."""
    rng = np.random.default_rng(11)
    b = _b_rotations(rng)
    at = (np.arange(N_A) / RATE_A + OFFSET) * RATE_B
    reference_b = _scipy_b(b, at)
    # A: B slerped, turned by a known angle about a random axis per (frame, joint)
    offsets = np.tile(np.array([0.0, 1e-8, 0.3, 1e-3, np.pi - 1e-7, 2.0, np.pi - 1e-4, 1e-6]), (N_A, 1))
    offsets[:, 0] = rng.uniform(0.0, np.pi, N_A)  # random A against random B
    turn = _about(rng.normal(size=(N_A * 8, 3)), offsets.ravel()).reshape(N_A, 8, 3, 3)
    anywhere = Rotation.random(N_A * 8, random_state=rng).as_matrix().reshape(N_A, 8, 3, 3)
    a = np.where(np.isnan(reference_b), anywhere, reference_b @ turn)
    a[5, 3] = np.nan  # a gap in A
    names = tuple(f"j{j}" for j in range(8))
    positions_a = rng.normal(size=(N_A, 8, 3))
    positions_b = rng.normal(size=(N_B, 8, 3))
    has = np.ones(8, dtype=bool)
    track_a = Track(names, positions_a, a, has, RATE_A)
    track_b = Track(names, positions_b, b, has, RATE_B)
    return track_a, track_b, at, reference_b


def test_the_cases_are_reached(case):
    """The fixture really holds the hard cases (else the test below proves less)."""
    a, b, at, reference_b = case
    assert (at < 0).any() and (at > N_B - 1).any() and (at == np.rint(at)).any() and (at != np.rint(at)).any()
    angles = _scipy_angles(a.rotations, reference_b)
    assert np.nanmin(angles) < 1e-6 and np.nanmax(angles) > 180.0 - 1e-5
    steps = _scipy_angles(b.rotations[:-1], b.rotations[1:])
    assert np.nanmax(steps) > 180.0 - 1e-3 and np.nanmin(steps[:, 4]) == 0.0
    assert np.isnan(angles).any()


@pytest.mark.parametrize("align", ["none", "rigid"])
def test_interpolated_rotation_errors_equal_scipy(case, align):
    a, b, _at, reference_b = case
    result = compare_tracks(a, b, match_joints(a.names, b.names), align=align, offset=OFFSET * RATE_A)
    assert result.alignment.offset_seconds == pytest.approx(OFFSET)
    expected = _scipy_angles(a.rotations, result.alignment.fit.rotation @ reference_b)
    assert np.array_equal(np.isnan(result.rotation_error), np.isnan(expected))
    assert np.nanmax(np.abs(result.rotation_error - expected)) <= 1e-9


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_resampled_rotations_equal_scipy(case, backend):
    """Both interpolators: the numpy reference and the compiled kernel."""
    if backend == "numba" and not have_numba():
        pytest.skip("numba is not installed")
    _a, b, at, reference_b = case
    got = resample_rotations(b.rotations, at, backend=backend)
    assert np.array_equal(np.isnan(got), np.isnan(reference_b))
    assert np.nanmax(np.abs(got - reference_b)) <= 1e-12
    # orthonormal to rounding, also after steps towards 180 degrees
    product = np.einsum("fjki,fjkl->fjil", got, got)
    assert np.nanmax(np.abs(product - np.eye(3))) <= 1e-14
