"""glTF rotation keyframes are continuous (issue 24): a viewer interpolates linearly between
consecutive quaternions, so each must lie in the previous one's hemisphere, even through
turns past 180 degrees where the ``w >= 0`` form flips sign."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.formats.gltf import export_gltf
from gmr_studio.core.rotations.euler import rotation_about_axis, rotation_angle
from tests.conftest import random_motion
from tests.test_gltf import accessor_array, load_gltf, matrix_from_quaternion

STEP_DEGREES = 12.0


def test_rotation_keyframes_stay_in_one_hemisphere_through_two_full_turns(tmp_path, rng):
    # planted bug: quaternions written in the w >= 0 form frame by frame (sign flips at 180 deg)
    n_frames = 61  # 0 .. 720 degrees
    motion = random_motion(rng, [-1, 0, 1], n_frames=n_frames, convention="post")
    turns = rotation_about_axis("Y", np.radians(STEP_DEGREES * np.arange(n_frames)))  # (F, 3, 3)
    rotations = motion.rotations.copy()
    rotations[:, 0] = turns
    rotations[:, 1] = np.swapaxes(turns, -1, -2) @ rotations[:, 1]  # the other way, on top of its own
    motion = motion.replace(rotations=rotations)
    export_gltf(motion, tmp_path / "turn.glb")
    gltf, blob = load_gltf(tmp_path / "turn.glb")
    animation = gltf.animations[0]
    checked = 0
    for channel in animation.channels:
        if channel.target.path != "rotation":
            continue
        q = accessor_array(gltf, blob, animation.samplers[channel.sampler].output).astype(np.float64)
        assert q.shape == (n_frames, 4)
        dots = np.einsum("fq,fq->f", q[1:], q[:-1])
        assert (dots > 0).all(), (gltf.nodes[channel.target.node].name, np.flatnonzero(dots <= 0))
        # what a viewer draws halfway between keyframes (normalised lerp) is halfway in angle
        middle = q[1:] + q[:-1]
        middle /= np.linalg.norm(middle, axis=-1, keepdims=True)
        before, halfway = matrix_from_quaternion(q[:-1]), matrix_from_quaternion(middle)
        step = rotation_angle(np.swapaxes(before, -1, -2) @ matrix_from_quaternion(q[1:]))
        half = rotation_angle(np.swapaxes(before, -1, -2) @ halfway)
        np.testing.assert_allclose(half, step / 2, atol=1e-5)
        checked += 1
    assert checked >= 2
    w = [
        accessor_array(gltf, blob, animation.samplers[c.sampler].output)[:, 3]
        for c in animation.channels
        if c.target.path == "rotation" and gltf.nodes[c.target.node].name == motion.names[0]
    ]
    assert len(w) == 1 and (w[0] < 0).any()  # the root's keys do pass to the negative-w side
