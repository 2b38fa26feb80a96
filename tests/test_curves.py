"""Curves of joints over time against independent computations on real files."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.analysis.curves import (
    QUANTITIES,
    gap_spans,
    joint_curves,
    local_translations,
    world_acceleration,
    world_speed,
)
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from gmr_studio.core.rotations.continuity import continuous_quaternions
from gmr_studio.core.rotations.quaternions import (
    matrix_from_quaternion,
    quaternion_from_matrix,
    slerp,
)
from tests.conftest import random_motion, shared_path


def bvh_channels(path) -> dict[str, tuple[list[str], np.ndarray]]:
    """An independent reading of a BVH file's channels: joint -> (channel names, (F, n) values)."""
    lines = path.read_text().splitlines()
    joints: list[tuple[str, list[str]]] = []
    name = None
    for number, line in enumerate(lines):
        words = line.split()
        if words and words[0] in ("ROOT", "JOINT"):
            name = words[1]
        elif words and words[0] == "CHANNELS":
            joints.append((name, words[2:]))
        elif words and words[0] == "Frame" and words[1] == "Time:":
            data = np.array([[float(v) for v in row.split()] for row in lines[number + 1 :] if row.strip()])
            break
    out, column = {}, 0
    for joint, channels in joints:
        out[joint] = (channels, data[:, column : column + len(channels)])
        column += len(channels)
    assert column == data.shape[1]
    return out


def test_euler_curves_of_a_bvh_equal_its_channels_up_to_unwrapping():
    path = shared_path("cmu/subject01/01_01.bvh")
    motion = read_motion(path)
    channels = bvh_channels(path)
    worst = 0.0
    for joint, (names, values) in channels.items():
        rotation_columns = [i for i, c in enumerate(names) if c.endswith("rotation")]
        curves = joint_curves(motion, joint, "euler")  # the alias of channels
        assert curves.columns == tuple(f"{joint}.channels.{names[i]}" for i in rotation_columns)
        difference = curves.values - values[:, rotation_columns]
        turns = np.rint(difference / 360.0)
        worst = max(worst, float(np.abs(difference - 360.0 * turns).max()))
        # unwrapped: no jump of more than 180 degrees between frames
        assert np.abs(np.diff(curves.values, axis=0)).max() < 180.0
    assert worst < 1e-12  # measured 8.5e-14 degrees (the file is read as written)


@pytest.mark.parametrize("noise", [0.3, 3.0])
def test_the_channels_curves_of_a_motion_are_what_its_bvh_file_says(tmp_path, rng, noise):
    """Noisy rotations (a random walk of steps up to ``noise`` radians, passing 90 degrees of
    middle angle now and then): the ``channels`` curves of a motion made in memory equal,
    frame for frame, the channels the BVH writer saves for that motion (one continuity rule)."""
    from gmr_studio.core.formats import write_motion

    steps = Rotation.from_rotvec(rng.normal(scale=noise / 2, size=(200, 3))).as_matrix()
    walk = np.empty_like(steps)
    walk[0] = steps[0]
    for f in range(1, len(steps)):
        walk[f] = walk[f - 1] @ steps[f]
    motion = random_motion(rng, [-1, 0, 1], n_frames=200, convention="post")
    rotations = np.array(motion.rotations)
    rotations[:, 1] = walk
    motion = motion.replace(rotations=rotations)
    path = tmp_path / "noisy.bvh"
    write_motion(motion, path)
    written = bvh_channels(path)
    for j, name in enumerate(motion.names):
        if name not in written or not motion.rotation_orders[j]:
            continue
        names, values = written[name]
        rotation_columns = [i for i, c in enumerate(names) if c.endswith("rotation")]
        curves = joint_curves(motion, name, "channels")
        np.testing.assert_allclose(curves.values, values[:, rotation_columns], rtol=0, atol=1e-9)


def test_world_curve_equals_reference_forward_kinematics(rng):
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    reference, _ = reference_forward_kinematics(motion)
    for joint in rng.choice(motion.n_joints, size=6, replace=False):
        curves = joint_curves(motion, int(joint), "world")
        assert curves.columns == tuple(f"{motion.names[joint]}.world.{a}" for a in "xyz")
        np.testing.assert_allclose(curves.values, reference[:, joint], rtol=0, atol=1e-12 * motion.size)


def test_speed_and_acceleration_are_finite_differences_of_world_positions():
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    reference, _ = reference_forward_kinematics(motion)
    j = motion.joint_index("LeftFoot")
    p, dt = reference[:, j], motion.frame_time
    velocity = (p[2:] - p[:-2]) / (2 * dt)
    speed = joint_curves(motion, j, "speed").values[:, 0]
    np.testing.assert_allclose(speed[1:-1], np.linalg.norm(velocity, axis=1), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(speed[0], np.linalg.norm(p[1] - p[0]) / dt, rtol=1e-9)
    acceleration = joint_curves(motion, j, "acceleration").values[:, 0]
    v = np.gradient(p, dt, axis=0)
    middle = (v[3:-1] - v[1:-3]) / (2 * dt)
    np.testing.assert_allclose(acceleration[2:-2], np.linalg.norm(middle, axis=1), rtol=1e-9, atol=1e-6)
    assert world_speed(p[:1], dt).tolist() == [0.0]
    assert world_acceleration(p[:1], dt).tolist() == [0.0]


def test_local_translations_both_ways_and_rotation_angle(rng):
    motion = random_motion(rng, [-1, 0, 1, 1, 3], n_frames=20)
    for j in range(motion.n_joints):
        pre = joint_curves(motion, j, "local-pre").values
        post = joint_curves(motion, j, "local-post").values
        np.testing.assert_array_equal(post, motion.translations[:, j])
        if motion.parents[j] < 0:
            np.testing.assert_array_equal(pre, post)
        else:
            expected = Rotation.from_matrix(np.array(motion.rotations[:, j])).apply(np.array(motion.translations[:, j]))
            np.testing.assert_allclose(pre, expected, atol=1e-13)
        angle = joint_curves(motion, j, "angle").values[:, 0]
        np.testing.assert_allclose(
            angle, np.degrees(Rotation.from_matrix(np.array(motion.rotations[:, j])).magnitude()), atol=1e-9
        )
    bvh = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    gmr = load_gmr(shared_path("cmu/subject01/01_01.bvh"))
    for j in (0, 3, 6):  # root, LeftLeg, an end site: the same as on the converted motion
        for composition in ("pre", "post"):
            np.testing.assert_array_equal(
                local_translations(bvh, j, composition), local_translations(gmr, j, composition)
            )


def test_quaternion_curves_are_continuous_and_match_scipy(rng):
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh"))  # the GMR rotation, either convention
    curves = joint_curves(motion, "LeftUpLeg", "quaternion")
    q = curves.values
    assert curves.columns[0] == "LeftUpLeg.quaternion.w"
    xyzw = Rotation.from_matrix(np.array(motion.rotations[:, motion.joint_index("LeftUpLeg")])).as_quat()
    expected = xyzw[:, [3, 0, 1, 2]]
    same_sign = np.sign(np.sum(q * expected, axis=1))[:, None]
    np.testing.assert_allclose(q, expected * same_sign, atol=1e-12)
    assert np.all(np.sum(q[1:] * q[:-1], axis=1) > 0)


def test_quaternions_round_trip_and_slerp_against_scipy(rng):
    matrices = Rotation.random(500, random_state=7).as_matrix()
    q = quaternion_from_matrix(matrices)
    assert np.all(q[:, 0] >= 0)
    np.testing.assert_allclose(matrix_from_quaternion(q), matrices, atol=1e-14)
    half_turns = Rotation.from_rotvec(
        np.pi * rng.normal(size=(50, 3)) / np.linalg.norm(rng.normal(size=(50, 3)))
    ).as_matrix()
    np.testing.assert_allclose(matrix_from_quaternion(quaternion_from_matrix(half_turns)), half_turns, atol=1e-14)
    from scipy.spatial.transform import Slerp

    fraction = rng.uniform(size=499)
    mine = matrix_from_quaternion(slerp(q[:-1], q[1:], fraction))
    for i in range(0, 499, 37):
        oracle = Slerp([0, 1], Rotation.from_matrix(matrices[i : i + 2]))([fraction[i]]).as_matrix()[0]
        np.testing.assert_allclose(mine[i], oracle, atol=1e-12)
    flipped = continuous_quaternions(np.stack([q[0], -q[0], q[0]]))
    np.testing.assert_array_equal(flipped, np.stack([q[0], q[0], q[0]]))


def test_gap_spans_and_refusals():
    positions = np.zeros((10, 3))
    positions[[0, 3, 4, 9], 1] = np.nan
    np.testing.assert_array_equal(gap_spans(positions), [[0, 1], [3, 5], [9, 10]])
    motion = random_motion(np.random.default_rng(1), [-1, 0])
    with pytest.raises(OperationError, match="unknown quantity"):
        joint_curves(motion, 0, "jerk")
    with pytest.raises(OperationError, match="unknown joint"):
        joint_curves(motion, "nobody", "euler")
    assert len(QUANTITIES) == 9
