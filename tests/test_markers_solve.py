"""Markers to GMR: the exact case (joint positions as markers), twists, roots, gaps,
degenerate input, and the real CMU markers against the AMC."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gmr_studio.core.edits.operations import shift_root, split
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from gmr_studio.core.markers import MarkerSet, load_marker_map, markers_to_motion, read_markers, recover_pelvis
from gmr_studio.core.markers.solve import FROM_REFERENCE, HELD, MEASURED, solve_positions
from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.euler import matrix_from_euler, rotation_angle
from tests.conftest import shared_path

CMU01 = "cmu/subject01/"
CMU02 = "cmu/subject02/"


@functools.cache
def cmu_motion(relative: str) -> Motion:
    return load_gmr(shared_path(relative))


def joint_markers(motion: Motion, units: str = "mm") -> MarkerSet:
    """The exact case: one marker per joint, at the joint (skeleton units and axes)."""
    return MarkerSet(
        labels=motion.names, positions=world_positions(motion), rate=motion.frame_rate, units=units, source="fk"
    )


def angle_errors(result_motion: Motion, truth: Motion) -> np.ndarray:
    return rotation_angle(np.swapaxes(result_motion.rotations, -1, -2) @ truth.rotations)


def assert_exact(result_motion: Motion, truth: Motion, angles: bool = True) -> None:
    error = np.abs(world_positions(result_motion) - world_positions(truth)).max()
    assert error <= 1e-9 * truth.size
    if angles:
        assert angle_errors(result_motion, truth).max() <= 1e-6


@pytest.mark.parametrize("amc", [CMU01 + "01_01.amc", CMU02 + "02_01.amc"])
def test_exact_case_on_cmu_amc(amc):
    truth = cmu_motion(amc)
    skeleton = load_gmr(shared_path(amc).parent / ("01.asf" if "01_01" in amc else "02.asf"))
    result = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth)
    assert_exact(result.motion, truth)
    assert result.frame_valid.all() and result.reasons == ()
    np.testing.assert_array_equal(result.matches, np.arange(truth.n_frames))  # each frame matches itself
    assert list(result.motion.roots) == [0] and result.motion.names == skeleton.names
    # without a reference the positions are still exact (the twist only turns bones about themselves)
    free = markers_to_motion(joint_markers(truth), skeleton, "joints")
    assert_exact(free.motion, truth, angles=False)
    assert (free.sources[:, 1:] == MEASURED).all()


def test_exact_case_on_a_bvh_skeleton_with_dummies_and_end_sites():
    truth = load_gmr(shared_path(CMU01 + "01_01.bvh")).frame_slice(slice(0, 300))
    result = markers_to_motion(joint_markers(truth), truth, "joints", reference=truth)
    assert_exact(result.motion, truth)
    # the zero-offset dummies (LHipJoint...) have no bone direction: their rotation is the reference's
    dummy = truth.joint_index("LHipJoint")
    assert (result.sources[:, dummy] == FROM_REFERENCE).all()


@st.composite
def skeletons(draw):
    n_joints = draw(st.integers(3, 12))
    parents = [-1, 0, 0] + [draw(st.integers(0, j - 1)) for j in range(3, n_joints)]
    n_frames = draw(st.integers(1, 6))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    offsets = rng.normal(size=(n_joints, 3))
    zero = [j for j in range(3, n_joints) if draw(st.booleans()) and rng.random() < 0.3]
    offsets[zero] = 0.0
    orders = [str(rng.choice(["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"])) for _ in range(n_joints)]
    rotations = np.stack(
        [matrix_from_euler(rng.uniform(-np.pi, np.pi, (n_frames, 3)), orders[j]) for j in range(n_joints)], axis=1
    )
    flags = np.zeros(n_joints, bool)
    flags[0] = True
    return Motion(
        names=[f"j{j}" for j in range(n_joints)],
        parents=parents,
        offsets=offsets,
        rotation_orders=orders,
        has_translation=flags,
        rotations=rotations,
        translations=build_translations(n_frames, offsets, {0: rng.normal(size=(n_frames, 3)) * 3}),
        frame_time=1 / 30,
    )


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(skeletons())
def test_exact_case_on_generated_skeletons(motion):
    positions = world_positions(motion)
    result = solve_positions(positions, motion, ("j0", "j1", "j2"), reference=motion)
    assert_exact(result.motion, motion)
    free = solve_positions(positions, motion, ("j0", "j1", "j2"))
    assert_exact(free.motion, motion, angles=False)
    paper = solve_positions(positions, motion, ("j0", "j1", "j2"), reference=motion, root_at="pelvis")
    assert_exact(paper.motion, motion)


def test_twist_from_the_same_trial_with_one_second_excluded():
    truth = cmu_motion(CMU02 + "02_01.amc")
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    result = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth, exclude_within=1.0)
    times = np.arange(truth.n_frames) * truth.frame_time
    matched = result.matches >= 0
    assert matched.all()
    assert np.all(np.abs(times - times[result.matches]) > 1.0)
    assert_exact(result.motion, truth, angles=False)  # positions never depend on the twist
    errors = np.degrees(angle_errors(result.motion, truth)[:, 1:])
    assert np.median(errors) < 2.0 and errors.max() < 45.0  # measured: 0.8 and 22 degrees


def test_named_roots_hold_their_measured_positions():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 60))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    markers = joint_markers(truth)
    result = markers_to_motion(markers, skeleton, "joints", reference=truth, roots=["lfemur", "rhumerus"])
    motion = result.motion
    for name, parent in (("lfemur", "lhipjoint"), ("rhumerus", "rclavicle")):
        j = motion.joint_index(name)
        assert motion.parents[j] == -1 and motion.soft_parents[j] == motion.joint_index(parent)
        assert motion.has_translation[j]
        np.testing.assert_allclose(motion.translations[:, j], markers.positions[:, j], atol=1e-12)
    assert sorted(motion.names[r] for r in motion.roots) == ["lfemur", "rhumerus", "root"]
    assert_exact(motion, truth, angles=False)
    motion.check_invariants()


def test_named_roots_on_a_skeleton_with_soft_links_split_like_the_operation():
    # the tree of lwrist holds its soft link at lwrist, inside the subtree of lradius: the
    # new link must go on the cut's other side, as core.edits.operations.split puts it
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 30))
    skeleton = shift_root(split(load_gmr(shared_path(CMU02 + "02.asf")), "lhumerus"), "lwrist")
    result = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth, roots=["lradius"])
    expected = split(skeleton, "lradius")
    np.testing.assert_array_equal(result.motion.parents, expected.parents)
    np.testing.assert_array_equal(result.motion.soft_parents, expected.soft_parents)
    result.motion.check_invariants()
    np.testing.assert_allclose(world_positions(result.motion), world_positions(truth), atol=1e-9 * truth.size)


def test_bad_frames_are_flagged_and_leave_good_frames_alone():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 80))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    clean = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth)
    positions = joint_markers(truth).positions.copy()
    root, lhip, rhip = (truth.joint_index(n) for n in ("root", "lhipjoint", "rhipjoint"))
    positions[10:13] = np.nan  # all-NaN frames
    positions[30, lhip] = positions[30, root]  # coincident pelvis markers
    positions[40, rhip] = 2 * positions[40, root] - positions[40, lhip]  # collinear
    positions[50:53, truth.joint_index("ltibia")] = np.nan  # a limb gap
    markers = MarkerSet(labels=truth.names, positions=positions, rate=truth.frame_rate, units="mm")
    result = markers_to_motion(markers, skeleton, "joints", reference=truth)
    bad = [10, 11, 12, 30, 40]
    assert list(np.flatnonzero(~result.frame_valid)) == bad
    text = " | ".join(result.reasons)
    assert "pelvis marker root missing in frames 10-12" in text
    assert "coincide in frames 30" in text and "collinear in frames 40" in text
    assert "frames 10-12, 30, 40 copy the nearest frame with a usable pelvis" in text
    motion = result.motion
    assert np.isfinite(motion.rotations).all() and np.isfinite(motion.translations).all()
    np.testing.assert_array_equal(
        motion.rotations[10:13], np.broadcast_to(motion.rotations[9], (3, *motion.rotations.shape[1:]))
    )
    good = np.setdiff1d(np.arange(80), [*bad, 50, 51, 52])
    np.testing.assert_array_equal(motion.rotations[good], clean.motion.rotations[good])
    np.testing.assert_array_equal(motion.translations[good], clean.motion.translations[good])
    # the limb gap: ltibia takes the matched reference rotation, its children go on measured
    assert (result.sources[50:53, truth.joint_index("ltibia")] == FROM_REFERENCE).all()
    assert (result.sources[50:53, truth.joint_index("lfoot")] == MEASURED).all()


def test_long_gaps_and_a_long_stretch_without_markers_leave_good_frames_alone():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 300))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    clean = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth)
    positions = joint_markers(truth).positions.copy()
    positions[60:180] = np.nan  # every marker gone for a second (120 fps)
    knee = truth.joint_index("ltibia")
    positions[190:290, knee] = np.nan  # one marker gone for most of a second
    markers = MarkerSet(labels=truth.names, positions=positions, rate=truth.frame_rate, units="mm")
    result = markers_to_motion(markers, skeleton, "joints", reference=truth)
    assert list(np.flatnonzero(~result.frame_valid)) == list(range(60, 180))
    assert "frames 60-179 copy the nearest frame with a usable pelvis" in " | ".join(result.reasons)
    motion = result.motion
    assert np.isfinite(motion.rotations).all() and np.isfinite(motion.translations).all()
    good = np.r_[0:60, 180:190, 290:300]
    np.testing.assert_array_equal(motion.rotations[good], clean.motion.rotations[good])
    np.testing.assert_array_equal(motion.translations[good], clean.motion.translations[good])
    # inside the long limb gap only the knee's rotation is borrowed (here the exact one); the
    # rest stays measured: the same rotations, to rounding below the knee (its frame moved)
    assert (result.sources[190:290, knee] == FROM_REFERENCE).all()
    others = np.setdiff1d(np.arange(truth.n_joints), [knee])
    assert (result.sources[190:290][:, others] == clean.sources[190:290][:, others]).all()
    np.testing.assert_allclose(motion.rotations[190:290], clean.motion.rotations[190:290], rtol=0, atol=1e-12)


def test_without_reference_a_limb_gap_holds_the_last_rotation():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 30))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    positions = joint_markers(truth).positions.copy()
    knee = truth.joint_index("lfemur")
    positions[5:9, knee] = np.nan
    markers = MarkerSet(labels=truth.names, positions=positions, rate=truth.frame_rate, units="mm")
    result = markers_to_motion(markers, skeleton, "joints")
    assert (result.sources[5:9, knee] == HELD).all()
    np.testing.assert_array_equal(
        result.motion.rotations[5:9, knee], np.broadcast_to(result.motion.rotations[4, knee], (4, 3, 3))
    )


def test_one_frame_and_nothing_usable():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(100, 101))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    markers = joint_markers(truth)
    assert_exact(markers_to_motion(markers, skeleton, "joints", reference=truth).motion, truth)
    alone = markers_to_motion(markers, skeleton, "joints", reference=truth, exclude_within=1.0)
    assert alone.matches[0] == -1 and "no reference frame could be matched in frames 0" in alone.reasons[0]
    assert_exact(alone.motion, truth, angles=False)
    empty = markers.replace(positions=np.full_like(markers.positions, np.nan))
    with pytest.raises(OperationError, match="no frame has a usable pelvis: pelvis marker root missing"):
        markers_to_motion(empty, skeleton, "joints")
    with pytest.raises(OperationError, match="there are no marker frames"):
        markers_to_motion(markers, skeleton, "joints", frames=slice(5, 9))


def test_wrong_reference_and_pelvis_that_is_not_the_root():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 5))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    other = load_gmr(shared_path(CMU01 + "01_01.bvh")).frame_slice(slice(0, 5))
    with pytest.raises(OperationError, match="the reference motion is not of the skeleton: it lacks the joints root"):
        markers_to_motion(joint_markers(truth), skeleton, "joints", reference=other)
    with pytest.raises(OperationError, match="the pelvis root 'lfemur' is not a root"):
        solve_positions(world_positions(truth), skeleton, ("lfemur", "ltibia", "lfoot"))
    # markers of another set than the map's: said as such, not as gaps in the pelvis (issue 22)
    expected = r"of no known set, not map plug-in-gait \(missing: LASI, RASI, LPSI, RPSI\)"
    with pytest.raises(OperationError, match=expected):
        markers_to_motion(joint_markers(truth), skeleton, load_marker_map("plug-in-gait"))


def test_recover_pelvis_on_joint_markers_is_the_root_rotation():
    truth = cmu_motion(CMU02 + "02_01.amc")
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    frames = recover_pelvis(joint_markers(truth), "joints", skeleton=skeleton)
    assert frames.valid.all() and frames.labels == ("root", "lhipjoint", "rhipjoint")
    # lhipjoint and rhipjoint have no dof in the ASF: the triple is rigid with the root
    np.testing.assert_allclose(frames.rotations, truth.rotations[:, 0], atol=1e-12)
    np.testing.assert_allclose(frames.origins, truth.translations[:, 0], atol=1e-12)
    assert frames.residuals.max() < 1e-9


@functools.cache
def cmu_real():
    markers = read_markers(shared_path(CMU01 + "01_01.c3d"))
    skeleton = load_gmr(shared_path(CMU01 + "01.asf"))
    return markers, skeleton, cmu_motion(CMU01 + "01_01.amc")


def test_real_cmu_markers_against_the_amc():
    """The shipped map was calibrated on frames 0:1100; the error is measured on the rest."""
    markers, skeleton, truth = cmu_real()
    result = markers_to_motion(markers, skeleton, "cmu", frames=slice(1100, None))
    error_mm = np.linalg.norm(world_positions(result.motion) - world_positions(truth)[1100:], axis=2) * (25.4 / 0.45)
    per_joint = error_mm.mean(axis=0)
    assert per_joint.mean() < 15.0 and per_joint.max() < 22.0  # measured: 13.1 overall, 19.8 worst (was 30, 40)
    assert result.frame_valid.all()
    pelvis = recover_pelvis(markers, "cmu")
    assert pelvis.valid.all()  # at 944, where LBWT and RBWT were not seen, the lab's gap filling
    measured = recover_pelvis(markers.without_computed(), "cmu")
    assert list(np.flatnonzero(~measured.valid)) == [944]  # the cameras' samples only
    assert "pelvis marker root missing in frames 944" in measured.reasons[0]
    # one rigid cluster places all three virtual markers: the Procrustes fits three of its real
    # markers instead, whose residual varies (tests/test_markers_pelvis_fit.py checks its values)
    assert pelvis.fit_labels == ("LFWT", "RFWT", "LBWT") and np.nanstd(pelvis.residuals) > 0.5
    np.testing.assert_allclose(np.linalg.det(pelvis.rotations), 1.0)
    # in the file's axes (Z up): the home pelvis is the skeleton's rest pose, so the
    # recovered rotation agrees with the AMC root rotation seen through the alignment
    alignment = load_marker_map("cmu").alignment
    in_skeleton = alignment.change_frames(pelvis.rotations[pelvis.valid])
    angle = rotation_angle(np.swapaxes(in_skeleton, -1, -2) @ truth.rotations[pelvis.valid, 0])
    assert np.degrees(np.median(angle)) < 5.0


def test_forward_kinematics_of_the_result_is_the_chain():
    truth = cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 10))
    skeleton = load_gmr(shared_path(CMU02 + "02.asf"))
    result = markers_to_motion(joint_markers(truth), skeleton, "joints", reference=truth)
    errors = result.position_errors()
    assert np.nanmax(errors) < 1e-9 * truth.size
    positions, _ = forward_kinematics(result.motion)
    assert positions.shape == (10, truth.n_joints, 3)


def test_refinement_keeps_the_exact_case():
    # the joints' own positions as markers: the closed form is exact, and the refinement
    # (towards the same markers) leaves it so, on the ASF and on the BVH skeleton
    from gmr_studio.core.markers.refine import refine_joints

    for truth in (
        cmu_motion(CMU02 + "02_01.amc").frame_slice(slice(0, 40)),
        cmu_motion(CMU01 + "01_01.bvh").frame_slice(slice(0, 40)),
    ):
        result = markers_to_motion(joint_markers(truth), truth, "joints", reference=truth)
        refined = refine_joints(result.motion, result.refine_targets(), weights=result.weights)
        error = np.abs(world_positions(refined.motion) - world_positions(truth)).max()
        assert error <= 1e-9 * truth.size
        assert np.nanmax(refined.residuals) <= 1e-9 * truth.size
