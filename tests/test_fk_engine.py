"""The FK engine against the reference, a per-frame 4x4 loop, and itself across backends."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gmr_studio.core.edits.operations import shift_root, split
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.kinematics import euler_matrices
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics, reference_forward_kinematics
from tests.conftest import random_motion, shared_files
from tests.test_kinematics import per_frame_fk

BACKENDS = ["numpy", pytest.param("numba", marks=pytest.mark.skipif(not fk_engine.have_numba(), reason="no numba"))]
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def forests(draw, max_joints=40, frame_counts=None):
    """A random forest (parents in any index order), random rotations, some moving joints."""
    n = draw(st.integers(1, max_joints))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    convention = draw(st.sampled_from(["pre", "post"]))
    branching = draw(st.floats(0.0, 1.0))
    parents = [-1]
    for j in range(1, n):
        if rng.random() < draw(st.sampled_from([0.0, 0.05, 0.5])):
            parents.append(-1)
        else:
            parents.append(int(rng.integers(0, j)) if rng.random() < branching else j - 1)
    relabel = rng.permutation(n)  # parents need not come before children in index order
    inverse = np.argsort(relabel)
    shuffled = [-1 if parents[inverse[k]] < 0 else int(relabel[parents[inverse[k]]]) for k in range(n)]
    moving = tuple(int(j) for j in rng.choice(n, size=min(n, 2), replace=False))
    frames = draw(st.integers(1, 5) if frame_counts is None else frame_counts)
    return random_motion(rng, shuffled, n_frames=frames, convention=convention, translation_joints=moving)


@SETTINGS
@given(motion=forests())
def test_engine_matches_reference_and_per_frame_loop(motion):
    expected_positions, expected_rotations = per_frame_fk(motion)
    reference_positions, reference_rotations = reference_forward_kinematics(motion)
    tolerance = 1e-12 * max(1.0, np.abs(expected_positions).max())
    for backend in ("numpy", "numba") if fk_engine.have_numba() else ("numpy",):
        positions, rotations = fk_engine.forward_kinematics(motion, backend=backend)
        np.testing.assert_allclose(positions, expected_positions, rtol=0, atol=tolerance)
        np.testing.assert_allclose(rotations, expected_rotations, rtol=0, atol=1e-12)
        np.testing.assert_allclose(positions, reference_positions, rtol=0, atol=tolerance)
        np.testing.assert_allclose(rotations, reference_rotations, rtol=0, atol=1e-12)
        # positions do not depend on whether rotations were asked for
        alone, none = fk_engine.forward_kinematics(motion, with_rotations=False, backend=backend)
        assert none is None
        np.testing.assert_array_equal(alone, positions)


@pytest.mark.skipif(not fk_engine.have_numba(), reason="numba is not installed: only one backend")
@SETTINGS
@given(motion=forests())
def test_backends_are_bitwise_identical(motion):
    for with_rotations in (False, True):
        fast = fk_engine.forward_kinematics(motion, with_rotations=with_rotations, backend="numba")
        plain = fk_engine.forward_kinematics(motion, with_rotations=with_rotations, backend="numpy")
        np.testing.assert_array_equal(fast[0], plain[0])
        if with_rotations:
            np.testing.assert_array_equal(fast[1], plain[1])


@pytest.mark.skipif(not fk_engine.have_numba(), reason="numba is not installed: only one backend")
@SETTINGS
@given(motion=forests(frame_counts=st.sampled_from([0, 1, 2, 9, 64])), data=st.data())
def test_positions_alone_are_the_bits_of_the_numpy_backend_and_of_the_full_fk(motion, data):
    # the compiled kernel computes positions alone and positions with world rotations by
    # two different walks: both give the numpy backend's bits, whatever the frame count
    if motion.convention == "pre":  # a root anywhere: the walk no longer in memory order
        motion = shift_root(motion, data.draw(st.integers(0, motion.n_joints - 1)))
    alone = fk_engine.world_positions(motion, backend="numba")
    np.testing.assert_array_equal(alone, fk_engine.world_positions(motion, backend="numpy"))
    np.testing.assert_array_equal(alone, fk_engine.forward_kinematics(motion, backend="numba")[0])
    assert alone.shape == (motion.n_frames, motion.n_joints, 3)


@pytest.mark.skipif(not fk_engine.have_numba(), reason="numba is not installed: only one backend")
@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_real_files_give_the_numpy_backends_bits(path):
    post = read_bvh(path).frame_slice(slice(0, 300))
    gmr = pre_from_post(post)
    forest = split(shift_root(gmr, int(np.argmax(gmr.depths))), gmr.n_joints // 2)
    for motion in (post, gmr, forest):
        for with_rotations in (False, True):
            fast = fk_engine.forward_kinematics(motion, with_rotations=with_rotations, backend="numba")
            plain = fk_engine.forward_kinematics(motion, with_rotations=with_rotations, backend="numpy")
            np.testing.assert_array_equal(fast[0], plain[0])
            if with_rotations:
                np.testing.assert_array_equal(fast[1], plain[1])


@SETTINGS
@given(motion=forests())
def test_positions_from_euler_angles_match(motion):
    angles = fk_engine.euler_angles(motion)
    expected = fk_engine.world_positions(motion)
    tolerance = 1e-11 * max(1.0, np.abs(expected).max())
    for backend in ("numpy", "numba") if fk_engine.have_numba() else ("numpy",):
        positions = fk_engine.positions_from_euler(motion, angles, backend=backend)
        np.testing.assert_allclose(positions, expected, rtol=0, atol=tolerance)


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
@pytest.mark.parametrize("backend", BACKENDS)
def test_real_files_in_both_conventions_and_as_forests(path, backend):
    post = read_bvh(path)
    gmr = pre_from_post(post)
    # joints picked by structure, not by name (the files name them LeftHand, LeftWrist,
    # mixamorig:LeftHand...): the root moves to the deepest joint, then two others split off
    deepest = int(np.argmax(gmr.depths))
    others = [j for j in (gmr.n_joints // 3, 2 * gmr.n_joints // 3) if j != deepest]
    forest = shift_root(gmr, deepest)
    for joint in others:
        forest = split(forest, joint)
    assert len(forest.roots) == 1 + len(others)
    # measured over the shared files: positions 8.0e-16 of the size, rotations 6.7e-16,
    # positions from Euler angles 5.4e-16 of the size (the bounds were 1e-12, 1e-12, 1e-11)
    for motion in (post, gmr, forest):
        expected_positions, expected_rotations = reference_forward_kinematics(motion)
        positions, rotations = fk_engine.forward_kinematics(motion, backend=backend)
        assert np.abs(positions - expected_positions).max() <= 5e-15 * motion.size
        assert np.abs(rotations - expected_rotations).max() <= 4e-15
    angles = fk_engine.euler_angles(post)
    from_euler = fk_engine.positions_from_euler(post, angles, backend=backend)
    assert np.abs(from_euler - reference_forward_kinematics(post)[0]).max() <= 4e-15 * post.size


def test_hand_computed_two_joint_forest():
    # root 0 at (1, 2, 3) turned 90 degrees about z, child 1 one unit along x; root 2 alone
    rz = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    motion = random_motion(np.random.default_rng(0), [-1, 0, -1], n_frames=1)
    motion = motion.replace(
        rotations=np.stack([rz, np.eye(3), rz])[None],
        translations=np.array([[[1.0, 2, 3], [1, 0, 0], [7, 8, 9]]]),
        offsets=np.array([[1.0, 2, 3], [1, 0, 0], [7, 8, 9]]),
        has_translation=np.array([True, False, True]),
    )
    positions, rotations = fk_engine.forward_kinematics(motion)
    np.testing.assert_array_equal(positions[0], [[1, 2, 3], [1, 3, 3], [7, 8, 9]])
    np.testing.assert_array_equal(rotations[0, 1], rz)


@pytest.mark.parametrize("convention", ["pre", "post"])
def test_the_public_entry_point_matches_the_per_joint_reference(rng, convention):
    # kinematics.forward_kinematics is the engine: check it against the independent
    # per-joint reference and the per-frame 4x4 loop, not against the engine again
    motion = shift_root(random_motion(rng, [-1, 0, 1, 0, -1, 4, 1], n_frames=7, convention="pre"), 2)
    if convention == "post":
        motion = random_motion(rng, [-1, 0, 1, 0, -1, 4, 1], n_frames=7, convention="post", translation_joints=(3,))
    positions, rotations = forward_kinematics(motion)
    reference_positions, reference_rotations = reference_forward_kinematics(motion)
    loop_positions, loop_rotations = per_frame_fk(motion)
    tolerance = 4e-15 * max(1.0, np.abs(reference_positions).max())
    for expected, rotation in ((reference_positions, reference_rotations), (loop_positions, loop_rotations)):
        np.testing.assert_allclose(positions, expected, rtol=0, atol=tolerance)
        np.testing.assert_allclose(rotations, rotation, rtol=0, atol=4e-15)


def test_strided_and_empty_inputs(rng):
    motion = random_motion(rng, [-1, 0, 1, 1, 0], n_frames=9)
    every_other = motion.frame_slice(slice(None, None, 2))
    np.testing.assert_allclose(
        fk_engine.world_positions(every_other), reference_forward_kinematics(motion)[0][::2], rtol=0, atol=1e-12
    )
    empty = motion.frame_slice(slice(0, 0))
    positions, rotations = fk_engine.forward_kinematics(empty)
    assert positions.shape == (0, 5, 3) and rotations.shape == (0, 5, 3, 3)
    assert fk_engine.positions_from_euler(empty, np.zeros((0, 5, 3))).shape == (0, 5, 3)


def test_many_frames_span_several_numpy_blocks(rng):
    motion = random_motion(rng, [-1, 0, 1, 2, 1, -1, 5], n_frames=fk_engine.NUMPY_CHUNK_FRAMES + 37)
    positions, rotations = fk_engine.forward_kinematics(motion, backend="numpy")
    expected_positions, expected_rotations = reference_forward_kinematics(motion)
    np.testing.assert_allclose(positions, expected_positions, rtol=0, atol=1e-12 * 100)
    np.testing.assert_allclose(rotations, expected_rotations, rtol=0, atol=1e-12)


def test_bad_arguments(rng):
    motion = random_motion(rng, [-1, 0], n_frames=2)
    with pytest.raises(ValueError, match="unknown backend"):
        fk_engine.forward_kinematics(motion, backend="fortran")
    with pytest.raises(ValueError, match="angles must have shape"):
        fk_engine.positions_from_euler(motion, np.zeros((2, 3, 3)))


@pytest.mark.skipif(not fk_engine.have_numba(), reason="numba is not installed: the readers use numpy")
def test_compiled_degree_conversion_matches_numpy(rng):
    from gmr_studio.core.rotations.euler import matrix_from_euler

    frames = 2 * fk_engine.MIN_FRAMES_PER_THREAD + 50  # enough for two threads
    values = rng.uniform(-400, 400, size=(frames, 12))
    groups = [
        ("ZYX", [0, 3], np.array([[0, 1, 2], [5, 6, 7]])),
        ("XZ", [1], np.array([[3, 4]])),
        ("Y", [4], np.array([[8]])),
        ("YXZ", [2], np.array([[9, 10, 11]])),
    ]
    out = np.full((frames, 7, 3, 3), 7.0)
    assert euler_matrices.degrees_to_matrices_compiled(values, groups, out, 10, frames, identities=[6])
    assert (out[:10] == 7.0).all() and (out[:, 5] == 7.0).all()  # only the frames and joints asked for
    for order, joints, cols in groups:
        expected = matrix_from_euler(np.radians(values[10:, cols]), order)
        np.testing.assert_allclose(out[10:, joints], expected, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(out[10:, 6], np.broadcast_to(np.eye(3), (frames - 10, 3, 3)))
    many = np.full_like(out, 7.0)
    assert euler_matrices.degrees_to_matrices_compiled(values, groups, many, 10, frames, identities=[6], threads=2)
    np.testing.assert_array_equal(many, out)  # threads change nothing


@pytest.mark.skipif(not fk_engine.have_numba(), reason="numba is not installed: the readers use numpy")
@pytest.mark.parametrize("scale", [np.pi / 180.0, 1.0], ids=["degrees", "radians"])
def test_compiled_conversion_about_axes_matches_numpy(rng, scale):
    """C R C^T of Euler angles (an AMC bone's rotation about its ASF axes), every order and
    joints of one or two angles: the kernel gives numpy's numbers to rounding."""
    from gmr_studio.core.formats.amc import conjugate
    from gmr_studio.core.rotations.euler import EULER_ORDERS, matrix_from_euler

    orders = [*EULER_ORDERS, "XZ", "Y"]
    frames = 2 * fk_engine.MIN_FRAMES_PER_THREAD + 50  # enough for two threads
    values = rng.uniform(-400, 400, size=(frames, 3 * len(orders))) * (np.pi / 180.0 / scale)
    # each joint's angles in its own columns, read last to first (as the AMC reader does)
    groups = [(order, [j], np.array([3 * j + np.arange(len(order))[::-1]])) for j, order in enumerate(orders)]
    axes = matrix_from_euler(rng.uniform(-np.pi, np.pi, size=(len(orders) + 2, 3)), "XYZ")
    out = np.full((frames, len(orders) + 2, 3, 3), 7.0)
    identity = len(orders)
    assert euler_matrices.conjugated_matrices_compiled(values, groups, axes, out, scale=scale, identities=[identity])
    for order, (j,), cols in groups:
        expected = conjugate(axes[j], matrix_from_euler(values[:, cols[0]] * scale, order))
        np.testing.assert_allclose(out[:, j], expected, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(out[:, identity], np.broadcast_to(np.eye(3), (frames, 3, 3)))
    assert (out[:, -1] == 7.0).all()  # only the joints asked for
    many = np.full_like(out, 7.0)
    assert euler_matrices.conjugated_matrices_compiled(
        values, groups, axes, many, scale=scale, identities=[identity], threads=2
    )
    np.testing.assert_array_equal(many, out)  # threads change nothing
    assert not euler_matrices.conjugated_matrices_compiled(values, groups, axes, many, scale=scale, backend="numpy")


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_forest_of_roots_is_its_data(rng, backend):
    motion = random_motion(rng, [-1, -1, -1, -1], n_frames=6)
    positions, rotations = fk_engine.forward_kinematics(motion, backend=backend)
    np.testing.assert_array_equal(positions, motion.translations)
    np.testing.assert_array_equal(rotations, motion.rotations)
    from_euler = fk_engine.positions_from_euler(motion, np.full((6, 4, 3), np.nan), backend=backend)
    np.testing.assert_array_equal(from_euler, motion.translations)  # no angle is read
    np.testing.assert_allclose(positions, reference_forward_kinematics(motion)[0], rtol=0, atol=0)


@pytest.mark.parametrize("threads", [2, 3, None])
def test_threads_give_the_same_bits(threads, rng):
    from gmr_studio.core.kinematics.engine import MIN_FRAMES_PER_THREAD

    motion = shift_root(random_motion(rng, [-1, 0, 1, 1, 3, 0, 5], n_frames=2 * MIN_FRAMES_PER_THREAD + 7), 4)
    for with_rotations in (True, False):
        one = fk_engine.forward_kinematics(motion, with_rotations=with_rotations, threads=1)
        many = fk_engine.forward_kinematics(motion, with_rotations=with_rotations, threads=threads)
        np.testing.assert_array_equal(one[0], many[0])
        if with_rotations:
            np.testing.assert_array_equal(one[1], many[1])


@pytest.mark.parametrize("threads", [1, 2])
def test_gathering_joints_picks_the_same_numbers_as_numpy(threads, rng):
    from gmr_studio.core.kinematics.engine import MIN_FRAMES_PER_THREAD

    frames = 2 * MIN_FRAMES_PER_THREAD + 3
    joints = np.array([4, 0, 0, 2])  # any order, repeats allowed
    for shape in ((frames, 5, 3), (frames, 5, 3, 3), (0, 5, 3, 3)):
        array = rng.normal(size=shape)
        np.testing.assert_array_equal(fk_engine.gather_joints(array, joints, threads=threads), array[:, joints])
    assert fk_engine.gather_joints(np.zeros((4, 5, 3)), np.zeros(0, np.int64)).shape == (4, 0, 3)
