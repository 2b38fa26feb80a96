"""The comparison engine (core/compare/engine.py) against a sample-by-sample reference: B put on
A's clock (whole and fractional frames, out of its range), in A's space (units, up axis, a
fitted alignment), errors per frame and joint against loops and scipy, in blocks, the frames
asked for, the offset, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from gmr_studio.core.compare import compare_motions, compare_tracks, engine, fit_alignment
from gmr_studio.core.compare.engine import angle_between
from gmr_studio.core.compare.tracks import Track
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.jointmap import JointMatch, match_joints
from gmr_studio.core.space.units import unit_named

NAMES_A = ("hips", "spine", "head", "arm", "hand", "leg")
#: B's joints in another order, one of A's missing and one of its own
NAMES_B = ("leg", "tail", "hand", "head", "spine", "hips")


def make_tracks(n_a: int, n_b: int, *, rate_b: float = 30.0, seed: int = 0, **b_fields) -> tuple[Track, Track]:
    """Random tracks A (n_a frames at 30 Hz) and B (n_b frames at ``rate_b``): positions about
    a metre apart, rotations anywhere (angles between them from 0 to 180 degrees); one joint
    of A and one of B without an orientation."""
    rng = np.random.default_rng(seed)
    has_a = np.ones(len(NAMES_A), dtype=bool)
    has_a[NAMES_A.index("arm")] = False
    has_b = np.ones(len(NAMES_B), dtype=bool)
    has_b[NAMES_B.index("hand")] = False

    def rotations(n_frames: int, n_joints: int) -> np.ndarray:
        return Rotation.random(n_frames * n_joints, random_state=rng).as_matrix().reshape(n_frames, n_joints, 3, 3)

    a = Track(NAMES_A, rng.normal(size=(n_a, 6, 3)), rotations(n_a, 6), has_a, 30.0, label="a.bvh")
    b = Track(NAMES_B, rng.normal(size=(n_b, 6, 3)), rotations(n_b, 6), has_b, rate_b, label="b.bvh", **b_fields)
    return a, b


def b_at(values: np.ndarray, at: np.ndarray, *, rotations: bool) -> np.ndarray:
    """B's values (N, J, ...) at its fractional frames ``at`` (F,), one sample at a time: its
    frame where ``u`` is whole (within 1e-6), else linear (positions) or scipy's Slerp
    (rotations); NaN outside [0, N - 1]."""
    n = len(values)
    out = np.full((len(at), *values.shape[1:]), np.nan)
    for row, u in enumerate(at):
        if not -1e-6 <= u <= n - 1 + 1e-6:
            continue
        if abs(u - np.rint(u)) <= 1e-6:
            out[row] = values[int(np.rint(u))]
            continue
        low = min(max(int(np.floor(u)), 0), n - 2)
        weight = min(max(u - low, 0.0), 1.0)
        for j in range(values.shape[1]):
            if rotations:
                out[row, j] = Slerp([0.0, 1.0], Rotation.from_matrix(values[low : low + 2, j]))([weight]).as_matrix()[0]
            else:
                out[row, j] = (1.0 - weight) * values[low, j] + weight * values[low + 1, j]
    return out


def reference(a: Track, b: Track, rows: np.ndarray, result) -> tuple[np.ndarray, ...]:
    """(B before the fit (F, J, 3), B aligned (F, J, 3), position errors (F, J), rotation
    errors (F, J) in degrees) from loops and scipy, with the comparison's own clock offset
    and alignment."""
    alignment = result.alignment
    ia = [NAMES_A.index(n) for n in result.names_a]
    ib = [NAMES_B.index(n) for n in result.names_b]
    at = (rows + alignment.offset_frames) / a.frame_rate * b.frame_rate
    positions_b = b_at(b.positions[:, ib], at, rotations=False)
    pre_fit = alignment.space.scale * positions_b @ alignment.space.rotation.T
    aligned = alignment.apply(positions_b)
    position_error = np.linalg.norm(a.positions[rows][:, ia] - aligned, axis=-1)
    turned_b = alignment.apply_rotations(b_at(b.rotations[:, ib], at, rotations=True))
    rotation_error = np.full(position_error.shape, np.nan)
    for f in range(len(rows)):
        for k in range(len(ia)):
            if a.has_rotation[ia[k]] and b.has_rotation[ib[k]] and np.isfinite(turned_b[f, k]).all():
                relative = Rotation.from_matrix(a.rotations[rows[f], ia[k]]).inv() * Rotation.from_matrix(
                    turned_b[f, k]
                )
                rotation_error[f, k] = np.degrees(relative.magnitude())
    return pre_fit, aligned, position_error, rotation_error


def rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values[np.isfinite(values)] ** 2)))


def check_against_reference(a: Track, b: Track, rows: np.ndarray, result) -> None:
    pre_fit, aligned, position_error, rotation_error = reference(a, b, rows, result)
    np.testing.assert_array_equal(result.frames, rows)
    np.testing.assert_array_equal(result.times, rows / a.frame_rate)
    assert result.names_a == ("hips", "spine", "head", "hand", "leg")  # A's order, arm unmatched
    assert result.names_b == result.names_a
    assert list(result.unmatched_a) == ["arm"] and list(result.unmatched_b) == ["tail"]
    np.testing.assert_array_equal(result.positions_a, a.positions[rows][:, [0, 1, 2, 4, 5]])
    np.testing.assert_array_equal(np.isnan(result.position_error), np.isnan(position_error))
    np.testing.assert_allclose(result.position_error, position_error, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result.positions_b, aligned, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(np.isnan(result.rotation_error), np.isnan(rotation_error))
    np.testing.assert_allclose(result.rotation_error, rotation_error, rtol=0, atol=1e-9)
    assert result.alignment.rms_after == pytest.approx(rms(position_error), rel=1e-12)
    before = np.linalg.norm(a.positions[rows][:, [0, 1, 2, 4, 5]] - pre_fit, axis=-1)
    assert result.alignment.rms_before == pytest.approx(rms(before), rel=1e-12)
    # the cases below reach what they are meant to: both paths of the angle (90 degrees), gaps
    finite = rotation_error[np.isfinite(rotation_error)]
    assert finite.min() < 90.0 < finite.max()
    assert np.isnan(rotation_error[:, result.names_a.index("hand")]).all()  # B's hand has no orientation
    assert np.isnan(position_error).any() and np.isfinite(position_error).any()


CASES = {
    # whole frames of B, nothing turned (B's rotations taken as they are)
    "whole": dict(offset=3.0),
    # whole frames, B in metres and z up, A in centimetres and y up: B turned and scaled
    "whole-turned": dict(offset=-2.0, b_fields=dict(unit=unit_named("m"), up="z"), a_units="cm"),
    "whole-rigid": dict(offset=4.0, align="rigid"),
    # a scale given, the up axes alike: B scaled only (by 2, a scale of 1 leaves B as it is)
    "whole-scaled": dict(offset=0.0, scale=2.0),
    # fractional frames of B (component-major path), nothing turned, then turned and fitted
    "between": dict(offset=2.5),
    "between-similarity": dict(offset=-1.25, align="similarity", b_fields=dict(up="z")),
    # another rate: every third frame of A on a whole frame of B, the others between
    "rates": dict(offset=8.0, rate_b=20.0, align="rigid"),
}


@pytest.mark.parametrize("blocks", ["default", "small"])
@pytest.mark.parametrize("case", list(CASES))
def test_errors_equal_a_sample_by_sample_reference(case, blocks, monkeypatch):
    spec = CASES[case]
    if blocks == "small":  # several blocks and chunks, the last one short
        monkeypatch.setattr(engine, "ROTATION_BLOCK", 7)
        monkeypatch.setattr(engine, "ROTATION_BLOCK_INTERPOLATED", 5)
        monkeypatch.setattr(engine, "PRODUCT_CHUNK", 11)
    a, b = make_tracks(40, 30, rate_b=spec.get("rate_b", 30.0), seed=len(case), **spec.get("b_fields", {}))
    if "a_units" in spec:
        unit = None if spec["a_units"] is None else unit_named(spec["a_units"])
        a = Track(a.names, a.positions, a.rotations, a.has_rotation, a.frame_rate, unit=unit)
    frames = np.array([39, 3, 0, 17, 3, 25, 38, 9, 1, 30, 31, 32, 33, 34, 35, 36, 37, 12])  # unsorted, repeated
    result = compare_tracks(
        a,
        b,
        match_joints(a.names, b.names),
        frames=frames,
        offset=spec["offset"],
        align=spec.get("align", "none"),
        scale=spec.get("scale"),
    )
    rows = np.unique(frames)
    assert result.alignment.offset_frames == spec["offset"] and not result.alignment.offset_found
    assert result.alignment.offset_seconds == spec["offset"] / 30.0
    assert result.alignment.space.scale == (100.0 if "a_units" in spec else spec.get("scale", 1.0))
    check_against_reference(a, b, rows, result)


def test_the_fit_is_over_every_frame_where_b_is_and_only_those():
    # B covers A's frames 5 to 34 (offset -5 and 30 frames): the fit is the one over those
    # rows, noisy, so that a frame more or less moves it
    rng = np.random.default_rng(5)
    a, b = make_tracks(45, 30, seed=9)
    turn = Rotation.from_euler("xyz", [20.0, -35.0, 50.0], degrees=True).as_matrix()
    shifted = np.full((45, 5, 3), np.nan)
    shifted[5:35] = 0.5 * b.positions[:, [NAMES_B.index(n) for n in NAMES_A if n in NAMES_B]] @ turn.T
    noisy = shifted + rng.normal(scale=0.05, size=shifted.shape) + np.array([1.0, -2.0, 0.5])
    a = Track(NAMES_A[:3] + NAMES_A[4:], noisy, None, np.zeros(5, dtype=bool), 30.0)
    for kind in ("rigid", "similarity"):
        result = compare_tracks(a, b, match_joints(a.names, b.names), offset=-5.0, align=kind)
        assert result.rotation_error is None
        assert np.isnan(result.position_error[:5]).all() and np.isnan(result.position_error[35:]).all()
        present = slice(5, 35)
        index_b = [NAMES_B.index(n) for n in a.names]
        expected = fit_alignment(a.positions[present], b.positions[:, index_b], kind)
        np.testing.assert_allclose(result.alignment.fit.rotation, expected[0], atol=1e-12)
        np.testing.assert_allclose(result.alignment.fit.translation, expected[1], atol=1e-12)
        assert result.alignment.fit.scale == pytest.approx(expected[2], rel=1e-12)
        assert result.alignment.rms_after < result.alignment.rms_before
        np.testing.assert_allclose(np.linalg.det(result.alignment.fit.rotation), 1.0)
        if kind == "similarity":
            assert result.alignment.fit.scale == pytest.approx(0.5, rel=0.02) and result.alignment.rms_after < 0.1


def test_the_frames_asked_for():
    a, b = make_tracks(12, 12)
    match = match_joints(a.names, b.names)

    def rows(frames):
        return compare_tracks(a, b, match, frames=frames, offset=0.0).frames.tolist()

    assert rows(None) == list(range(12))
    assert rows((2, 5)) == [2, 3, 4] and rows((None, 3)) == [0, 1, 2] and rows((9, None)) == [9, 10, 11]
    assert rows(slice(1, None, 4)) == [1, 5, 9] and rows(slice(-2, None)) == [10, 11]
    assert rows([11, 0, 11]) == [0, 11] and rows(np.array([5])) == [5]
    for outside in ([-1, 3], [3, 12], [12]):
        with pytest.raises(ValueError, match=r"within 0\.\.11"):
            rows(outside)
    for empty in ((5, 5), slice(20, None), [], np.array([], dtype=int)):
        with pytest.raises(ValueError, match="no frames to compare: A has 12 frames"):
            rows(empty)


def test_the_offset_given_found_or_refused():
    a, b = make_tracks(80, 80, seed=3)
    index_b = [NAMES_B.index(n) for n in NAMES_A if n in NAMES_B]
    # A's frame f is B's frame f + 6 on the joints both have (B's random walk, smooth enough to find)
    walk = np.cumsum(np.random.default_rng(4).normal(scale=0.1, size=(86, 6, 3)), axis=0)
    b = Track(NAMES_B, walk[:80], b.rotations, b.has_rotation, 30.0)
    positions_a = np.full((80, 6, 3), np.nan)
    positions_a[:, [0, 1, 2, 4, 5]] = walk[6:86][:, index_b]
    positions_a[:, 3] = 0.0
    a = Track(NAMES_A, positions_a, None, a.has_rotation, 30.0)
    match = match_joints(a.names, b.names)
    found = compare_tracks(a, b, match, offset="auto")
    assert found.alignment.offset_found and found.alignment.offset_search is not None
    assert found.alignment.offset_frames == pytest.approx(6.0, abs=1e-6)
    assert found.alignment.offset_seconds == pytest.approx(6.0 / 30.0, abs=1e-6)
    given = compare_tracks(a, b, match, offset=6)
    assert not given.alignment.offset_found and given.alignment.offset_search is None
    assert np.nanmax(given.position_error[:74]) == 0.0 and np.isnan(given.position_error[74:]).all()
    for wrong in ("later", "Auto"):
        with pytest.raises(ValueError, match="a number of frames or 'auto'"):
            compare_tracks(a, b, match, offset=wrong)
    for wrong in (np.nan, np.inf, -np.inf):
        with pytest.raises(ValueError, match="finite number of frames"):
            compare_tracks(a, b, match, offset=wrong)


def test_the_refusals_and_the_rate_note():
    a, b = make_tracks(10, 10)
    # four names of each side, no more
    with pytest.raises(ValueError, match=r"A has hips, spine, head, arm\.\.\.; B has x1, x2, x3, x4\.\.\.\)$"):
        compare_tracks(a, b, JointMatch((), list(NAMES_A), [f"x{k}" for k in range(1, 7)]), offset=0.0)
    with pytest.raises(ValueError, match="alignment must be one of none, rigid, similarity, not 'affine'"):
        compare_tracks(a, b, match_joints(a.names, b.names), offset=0.0, align="affine")
    near = Track(b.names, b.positions, b.rotations, b.has_rotation, 30.0 * (1 + 5e-6))
    result = compare_tracks(a, near, match_joints(a.names, b.names), offset=1.0)
    assert any("frame rates 30 and 30.00015 Hz taken as equal" in note for note in result.alignment.notes)
    exact = compare_tracks(a, b, match_joints(a.names, b.names), offset=1.0)
    np.testing.assert_array_equal(result.position_error, exact.position_error)  # B on whole frames
    assert not any("taken as equal" in note for note in exact.alignment.notes)
    assert exact.alignment.notes == tuple(note for note in result.alignment.notes if "taken as equal" not in note)


def test_motions_compared_through_their_tracks():
    walk = load_gmr(demo_folder() / MOTION_FILE).frame_slice(slice(0, 40))
    first = walk.names[int(walk.roots[0])]
    other = walk.names[-1]
    pair = JointMatch(((walk.names.index(other), walk.names.index(other)),), [], [])
    chosen = compare_motions(walk, walk, match=pair, joint_map={first: first}, offset=0.0, label_a="x", label_b="y")
    assert chosen.names_a == (other,) and chosen.label_a == "x" and chosen.label_b == "y"
    assert np.nanmax(chosen.rotation_error) < 1e-6 and np.nanmax(chosen.position_error) == 0.0
    plain = compare_motions(walk, walk, with_rotations=False, offset=0.0)
    assert plain.rotation_error is None and plain.names_a == walk.names


@pytest.mark.parametrize("degrees", [0.0, 1e-7, 0.5, 60.0, 90.0, 120.0, 179.0, 180.0 - 1e-6, 180.0])
def test_the_angle_between_two_rotations_at_every_angle(degrees):
    rng = np.random.default_rng(int(degrees * 10) % 1000)
    first = Rotation.random(6, random_state=rng)
    axes = rng.normal(size=(6, 3))
    turn = Rotation.from_rotvec(np.radians(degrees) * axes / np.linalg.norm(axes, axis=1, keepdims=True))
    second = first * turn
    got = angle_between(first.as_matrix().reshape(-1, 9), second.as_matrix().reshape(-1, 9))
    np.testing.assert_allclose(np.degrees(got), degrees, rtol=0, atol=1e-9)


@pytest.mark.parametrize("offset", [-1e-6, 1e-6])
def test_a_frame_within_the_tolerance_of_bs_range_counts_for_the_fit(offset):
    # at 1 Hz B's frame of A's row r is r + offset: with -1e-6 row 0 falls exactly the
    # tolerance before B's first frame, with +1e-6 row 11 exactly after its last; both are
    # sampled (B at its end), and the fit is over rows 0 to 11, those two included
    rng = np.random.default_rng(8)
    b = Track(("p", "q", "r"), rng.normal(size=(12, 3, 3)), None, np.zeros(3, dtype=bool), 1.0)
    a = Track(
        b.names,
        np.concatenate([b.positions, np.zeros((8, 3, 3))]) + 0.1 * rng.normal(size=(20, 3, 3)),
        None,
        b.has_rotation,
        1.0,
    )
    result = compare_tracks(a, b, match_joints(a.names, b.names), offset=offset, align="rigid")
    assert np.isfinite(result.position_error[:12]).all() and np.isnan(result.position_error[12:]).all()
    at = np.arange(12) + offset
    assert at[0 if offset < 0 else -1] == (-1e-6 if offset < 0 else 11 + 1e-6)
    expected = fit_alignment(a.positions[:12], b_at(b.positions, at, rotations=False), "rigid")
    np.testing.assert_allclose(result.alignment.fit.rotation, expected[0], atol=1e-12)
    np.testing.assert_allclose(result.alignment.fit.translation, expected[1], atol=1e-12)


@pytest.mark.parametrize("align", ["none", "rigid"])
def test_the_tracks_compared_are_left_as_they_were(align):
    # B's joints all matched in order on its whole frames: its rows are read as views
    a, b = make_tracks(30, 30, seed=2)
    b = Track(NAMES_A, b.positions, b.rotations, a.has_rotation, 30.0)
    before = [x.copy() for x in (a.positions, a.rotations, b.positions, b.rotations)]
    first = compare_tracks(a, b, match_joints(a.names, b.names), offset=0.0, align=align)
    for array, kept in zip((a.positions, a.rotations, b.positions, b.rotations), before):
        np.testing.assert_array_equal(array, kept)
    again = compare_tracks(a, b, match_joints(a.names, b.names), offset=0.0, align=align)
    np.testing.assert_array_equal(again.rotation_error, first.rotation_error)
    np.testing.assert_array_equal(again.position_error, first.position_error)


def test_the_options_are_keywords():
    a, b = make_tracks(5, 5)
    with pytest.raises(TypeError):
        compare_tracks(a, b, match_joints(a.names, b.names), None, 0.0)
    walk = load_gmr(demo_folder() / MOTION_FILE).frame_slice(slice(0, 5))
    with pytest.raises(TypeError):
        compare_motions(walk, walk, None)
