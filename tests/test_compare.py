"""The comparison core (core/compare/): real CMU files, edits, known transforms, clocks, gaps."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.compare import compare_motions, compare_tracks, fit_alignment, track_of_points
from gmr_studio.core.compare.offset import find_offset
from gmr_studio.core.compare.tracks import Track
from gmr_studio.core.edits.operations import join_all, shift_root, split, split_all
from gmr_studio.core.edits.world import change_up_axis, scale_lengths
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.jointmap import match_joints
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.rotations.euler import matrix_from_euler, rotation_about_axis, rotation_angle
from gmr_studio.core.space.units import UNITS
from tests.conftest import shared_path

THORAX = 2.06488  # the bone the cgspeed BVH dropped (test_jointmap.py)


@pytest.fixture(scope="module")
def cmu():
    return read_motion(shared_path("cmu/subject01/01_01.bvh")), read_motion(shared_path("cmu/subject01/01_01.amc"))


@pytest.fixture(scope="module")
def walk():
    return load_gmr(shared_path("cmu/subject01/01_01.bvh"))


def test_bvh_against_its_amc_through_the_cmu_map(cmu):
    bvh, amc = cmu
    result = compare_motions(bvh, amc, joint_map="cmu", offset="auto", label_a="01_01.bvh", label_b="01_01.amc")
    # the BVH's frame 0 is an added T-pose: AMC frame f is BVH frame f + 1
    assert result.alignment.offset_frames == -1 and result.alignment.offset_found
    assert result.n_pairs == 28 and result.unmatched_b == ["thorax", "lwrist", "rwrist"]
    assert np.isnan(result.position_error[0]).all() and np.isfinite(result.position_error[1:]).all()
    error = dict(zip(result.names_a, result.position.per_joint_max))
    assert max(error[n] for n in ("Hips", "LeftUpLeg", "LeftLeg", "RightFoot", "Spine", "Spine1")) < 1.5e-4
    assert abs(error["Head"] - THORAX) < 1e-4 and abs(error["LeftHand"] - THORAX) < 1e-4
    assert result.position.max_joint in {"LFingers", "LFingers_End", "LThumb_End"} and result.position.max < 3.81
    # the same frames through the explicit offset; rotations agree to a fraction of a degree
    given = compare_motions(bvh, amc, joint_map="cmu", offset=-1)
    np.testing.assert_array_equal(given.position_error, result.position_error)
    assert np.nanmax(result.rotation_error) < 0.25
    assert np.isnan(result.rotation_error[:, result.names_a.index("Hips")]).all()  # a root has no bone
    document = result.to_json()
    assert document["units"] == "file units" and document["frames"] == bvh.n_frames
    assert document["max"]["joint"] == result.position.max_joint and len(document["joints"]) == 28
    assert document["alignment"]["offset_frames"] == -1 and document["alignment"]["kind"] == "none"


def test_summary_against_an_independent_computation(cmu):
    bvh, amc = cmu
    result = compare_motions(bvh, amc, joint_map="cmu", offset=-1)
    errors = result.position_error
    summary = result.position
    assert summary.mean == pytest.approx(np.nanmean(errors), rel=1e-12)
    assert summary.median == pytest.approx(np.nanmedian(errors), rel=1e-12)
    assert summary.p95 == pytest.approx(np.nanpercentile(errors, 95), rel=1e-12)
    frame, joint = np.unravel_index(np.nanargmax(errors), errors.shape)
    assert summary.max == np.nanmax(errors) and summary.max_frame == result.frames[frame]
    assert summary.max_joint == result.names_a[joint]
    np.testing.assert_allclose(summary.per_frame[1:], errors[1:].mean(axis=1), rtol=1e-12)
    assert np.isnan(summary.per_frame[0]) and summary.count == errors[1:].size
    # positions of the result are the files' own, frame for frame
    positions_a = forward_kinematics(bvh, with_rotations=False)[0][:, result.index_a]
    positions_b = forward_kinematics(amc, with_rotations=False)[0][:, result.index_b]
    # (FK in GMR's convention: the same points to rounding)
    np.testing.assert_allclose(result.positions_a, positions_a, rtol=0, atol=1e-13 * bvh.size)
    np.testing.assert_allclose(result.positions_b[1:], positions_b[: bvh.n_frames - 1], rtol=0, atol=1e-13 * bvh.size)


@pytest.mark.parametrize(
    "edit",
    [
        lambda m: shift_root(m, "LeftFoot"),
        lambda m: split(m, "Spine1"),
        lambda m: join_all(split_all(m)),
        lambda m: shift_root(split(m, "LeftArm"), "Head"),
    ],
    ids=["shift-root", "split", "split-all-join-all", "split-then-shift"],
)
def test_a_motion_against_itself_after_edits_is_zero(walk, edit):
    edited = edit(walk)
    result = compare_motions(walk, edited, align="none")
    assert result.n_pairs == walk.n_joints and not result.unmatched_a
    assert result.position.max <= 1e-9 * walk.size
    rigid = compare_motions(walk, edited, align="similarity")
    assert rigid.position.max <= 1e-9 * walk.size and abs(rigid.alignment.fit.scale - 1) < 1e-12


def test_ten_degrees_on_one_joint_stays_in_its_subtree_and_frames(walk):
    joint = walk.joint_index("LeftForeArm")
    frames = np.arange(100, 160)
    rotations = walk.rotations.copy()
    rotations[frames, joint] = rotations[frames, joint] @ rotation_about_axis("Z", np.radians(10.0))
    changed = walk.replace(rotations=rotations)
    result = compare_motions(walk, changed)
    subtree = np.isin(result.index_a, walk.subtree(joint))
    in_frames = np.isin(result.frames, frames)
    moved = result.position_error > 1e-9 * walk.size
    # in GMR a joint's rotation turns the bone ending at it: the joint itself moves too
    assert moved[np.ix_(in_frames, subtree)].all() and not moved[~in_frames].any() and not moved[:, ~subtree].any()
    turned = result.rotation_error
    np.testing.assert_allclose(turned[np.ix_(in_frames, subtree)], 10.0, atol=1e-9)
    outside = np.concatenate([turned[~in_frames].ravel(), turned[:, ~subtree].ravel()])
    assert np.nanmax(outside) < 1e-9
    worst = result.position
    assert worst.max_joint in {walk.names[j] for j in walk.subtree(joint)} and 100 <= worst.max_frame < 160


def test_rigid_and_similarity_alignments_recover_a_known_transform(walk):
    turn = matrix_from_euler(np.radians([[20.0, -35.0, 50.0]]), "ZYX")[0]
    shift, factor = np.array([3.0, -7.0, 11.0]), 2.5
    # B = the same motion turned, moved and scaled as a whole: every world point p -> s Q^T (p - shift)
    rotations = walk.rotations.copy()
    root = walk.roots[0]
    rotations[:, root] = turn.T @ rotations[:, root]
    translations = walk.translations.copy()
    translations[:, root] = (translations[:, root] - shift) @ turn
    moved = scale_lengths(walk.replace(rotations=rotations, translations=translations), factor)
    # a figure tilted this much could be lying on its back: the file says it is Y up
    moved = moved.replace(facts=FileFacts(up_axis="y"))
    plain = compare_motions(walk, moved, align="none")
    assert plain.position.mean > walk.size / 10
    rigid = compare_motions(walk, moved, align="rigid")
    assert rigid.position.mean > 1e-3 * walk.size  # rigid cannot undo a scale
    similar = compare_motions(walk, moved, align="similarity")
    assert similar.position.max < 1e-9 * walk.size
    assert np.nanmax(similar.rotation_error) < 1e-6
    alignment = similar.alignment
    np.testing.assert_allclose(alignment.fit.rotation, turn, atol=1e-12)
    assert alignment.fit.scale == pytest.approx(1 / factor, rel=1e-12)
    np.testing.assert_allclose(alignment.fit.translation, shift, atol=1e-9 * walk.size)
    assert alignment.rms_after < 1e-9 * walk.size < alignment.rms_before
    assert similar.to_json()["alignment"]["scale"] == pytest.approx(1 / factor)


def test_fit_alignment_against_scipy_and_its_refusals(rng):
    from scipy.spatial.transform import Rotation

    b = rng.normal(size=(50, 4, 3))
    truth = Rotation.random(random_state=1).as_matrix()
    a = 1.7 * b @ truth.T + [1.0, 2.0, 3.0] + rng.normal(scale=1e-3, size=b.shape)
    rotation, _translation, scale = fit_alignment(a, b, "similarity")
    expected, _ = Rotation.align_vectors((a - a.mean((0, 1))).reshape(-1, 3), (b - b.mean((0, 1))).reshape(-1, 3))
    np.testing.assert_allclose(rotation, expected.as_matrix(), atol=1e-9)
    assert abs(scale - 1.7) < 2e-5  # measured 6.0e-6 (noise of 1e-3 on 600 points)
    assert rotation_angle(rotation.T @ truth) < 1.5e-4  # measured 4.8e-5 radians
    b_with_gap = b.copy()
    b_with_gap[3:9, 2] = np.nan
    again = fit_alignment(a, b_with_gap, "rigid")[0]
    # the points missing on either side are left out: scipy on the rows kept gives the same turn
    kept_a, kept_b = a.reshape(-1, 3), b_with_gap.reshape(-1, 3)
    kept = np.isfinite(kept_b).all(axis=1)
    kept_a, kept_b = kept_a[kept], kept_b[kept]
    alone, _ = Rotation.align_vectors(kept_a - kept_a.mean(0), kept_b - kept_b.mean(0))
    np.testing.assert_allclose(again, alone.as_matrix(), atol=1e-9)
    assert rotation_angle(again.T @ truth) < 1.5e-4  # measured 5.4e-5 radians
    with pytest.raises(ValueError, match="at least 3"):
        fit_alignment(a[:1, :2], b[:1, :2], "rigid")
    with pytest.raises(ValueError, match="alignment must be one of"):
        fit_alignment(a, b, "affine")


def _moving_points(rate: float, seconds: float, start: float = 0.0) -> np.ndarray:
    """Two points moving linearly in time (linear interpolation is exact on them)."""
    t = start + np.arange(round(seconds * rate)) / rate
    return np.stack([np.stack([t, 2 * t, -t], 1), np.stack([1 - t, 3 * t, 0.5 + 0 * t], 1)], axis=1)


def test_one_clock_by_time_not_by_index():
    a = track_of_points(["p", "q"], _moving_points(30.0, 4.0), 30.0)
    b = track_of_points(["p", "q"], _moving_points(47.0, 3.0, start=0.5), 47.0)
    match = match_joints(a.names, b.names)
    # B starts 0.5 s later: A's time t is B's time t - 0.5, an offset of -15 of A's frames
    result = compare_tracks(a, b, match, offset=-15)
    inside = (result.times >= 0.5) & (result.times <= 0.5 + 140 / 47)
    assert np.isnan(result.position_error[~inside]).all()
    assert np.nanmax(result.position_error) < 1e-12 and np.isfinite(result.position_error[inside]).all()
    assert result.alignment.offset_seconds == pytest.approx(-0.5)
    assert result.rotation_error is None and result.to_json()["mpjpe"] < 1e-12


def test_rotations_interpolate_along_the_geodesic():
    """A joint turning at constant speed about a fixed axis, sampled at 10 and 25 Hz: the 10 Hz
    side resampled at 25 Hz has the same rotations."""

    def spinning(rate: float) -> Track:
        t = np.arange(int(2 * rate) + 1) / rate
        world = matrix_from_euler(np.stack([0.9 * t, 0 * t, 0 * t], 1), "ZYX")[:, None]
        return Track(("j",), np.zeros((len(t), 1, 3)), world, np.array([True]), rate)

    result = compare_tracks(spinning(25.0), spinning(10.0), match_joints(["j"], ["j"]))
    assert result.n_frames == 51 and np.nanmax(result.rotation_error) < 1e-9


def test_find_offset_on_the_real_walk(walk):
    positions = forward_kinematics(walk, with_rotations=False)[0][:, 0]
    lag, _ = find_offset(positions[:200], positions[37:], walk.frame_rate, walk.frame_rate)
    assert lag == -37
    # at another rate too: B at half the rate, 20 of A's frames later
    lag, _ = find_offset(positions[40:], positions[::2], walk.frame_rate, walk.frame_rate / 2)
    assert lag == 40


def test_gaps_are_nan_and_left_out(walk):
    positions = forward_kinematics(walk, with_rotations=False)[0]
    a = track_of_points(walk.names, positions, walk.frame_rate)
    holes = positions.copy()
    holes[10:20, 3] = np.nan
    result = compare_tracks(
        a, track_of_points(walk.names, holes, walk.frame_rate), match_joints(walk.names, walk.names)
    )
    assert np.isnan(result.position_error[10:20, 3]).all()
    assert np.isfinite(result.position_error).sum() == result.position.count == positions[..., 0].size - 10
    assert result.position.max == 0.0
    # a planted error, compared from a non-zero first frame: frames are A's numbers, not rows
    holes[250, 5] += [0.0, 0.5, 0.0]
    holes[120, 5] += [0.0, 0.2, 0.0]
    b = track_of_points(walk.names, holes, walk.frame_rate)
    late = compare_tracks(a, b, match_joints(walk.names, walk.names), frames=(100, 400), offset=0)
    assert late.position.per_joint_max_frame[5] == 250 and late.position.per_joint_max[5] == pytest.approx(0.5)
    assert late.position.max_frame == 250 and late.position.max_joint == walk.names[5]
    assert late.position.per_joint_max_frame[3] == 100 and late.position.per_joint_max[3] == 0.0  # no error: first


def test_units_and_up_axis_from_what_the_files_state(walk):
    z_up_mm = change_up_axis(scale_lengths(walk, 10.0), "z").replace(facts=FileFacts(unit=UNITS["mm"], up_axis="z"))
    a = walk.replace(facts=FileFacts(unit=UNITS["cm"]))
    result = compare_motions(a, z_up_mm)
    assert result.position.max < 1e-9 * walk.size and np.nanmax(result.rotation_error) < 1e-6
    assert result.alignment.space.scale == pytest.approx(0.1) and result.units == "cm"
    assert any("B turned from z up" in note for note in result.alignment.notes)
    # nothing stated: the caller says it
    bare = z_up_mm.replace(facts=FileFacts())
    assert compare_motions(walk, bare).position.mean > 1.0
    told = compare_motions(walk, bare, scale=0.1, up_b="z")
    assert told.position.max < 1e-9 * walk.size
    assert any("given" in note for note in told.alignment.notes)


def test_refusals(walk):
    other = walk.replace(names=[f"x{i}" for i in range(walk.n_joints)])
    with pytest.raises(ValueError, match="no joints matched"):
        compare_motions(walk, other)
    with pytest.raises(ValueError, match="no frames to compare"):
        compare_motions(walk, walk, frames=(5, 5))
    with pytest.raises(ValueError, match="frames must be within"):
        compare_motions(walk, walk, frames=np.array([0, walk.n_frames]))
    with pytest.raises(ValueError, match="'auto'"):
        compare_motions(walk, walk, offset="later")
    part = compare_motions(walk, walk, frames=(10, 20))
    assert part.frames.tolist() == list(range(10, 20)) and part.row_of_frame(12) == 2 and part.row_of_frame(3) is None


def test_quantiles_are_numpys_to_the_bit():
    """The summaries' median and p95 (a partition per index and a minimum) are np.quantile's."""
    from gmr_studio.core.compare.result import quantiles

    rng = np.random.default_rng(5)
    for trial in range(400):
        n = int(rng.integers(1, 40)) if trial % 2 else int(rng.integers(40, 3000))
        values = rng.random(n) if trial % 3 else rng.integers(0, 4, n).astype(float)  # ties too
        for q in [(0.5, 0.95), (0.0, 1.0), (0.25,), (0.5, 0.5000001, 0.99)]:
            assert np.array_equal(np.array(quantiles(values, q)), np.quantile(values, q))
            copy = values.copy()
            assert np.array_equal(np.array(quantiles(copy, q, overwrite=True)), np.quantile(values, q))
