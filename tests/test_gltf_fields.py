"""Fields a glTF validator reads (core/formats/gltf.py): the scene and buffer indices, the scene
root's name, continuity of a one-joint motion, the summary frozen."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.formats.gltf import SCENE_ROOT, build_gltf
from gmr_studio.core.rotations.euler import rotation_about_axis
from tests.conftest import random_motion


def test_indices_point_at_the_scene_and_buffer_written(rng):
    gltf, _, summary = build_gltf(random_motion(rng, [-1, 0, 1], n_frames=3), metres_per_unit=1.0)
    assert gltf.scene == 0 and len(gltf.scenes) == 1 and len(gltf.buffers) == 1
    assert {view.buffer for view in gltf.bufferViews} == {0}
    with pytest.raises(dataclasses.FrozenInstanceError):
        summary.n_frames = 0
    with pytest.raises(TypeError):
        build_gltf(random_motion(rng, [-1, 0], n_frames=2), False)  # options by name only


def test_the_scene_root_takes_the_next_free_number(rng):
    motion = random_motion(rng, [-1, 0], n_frames=2).replace(names=[SCENE_ROOT, "hand"])
    gltf, _, _ = build_gltf(motion, skin=False, metres_per_unit=1.0)
    assert [node.name for node in gltf.nodes] == [SCENE_ROOT, "hand", f"{SCENE_ROOT}2"]


def test_a_single_joint_turning_twice_has_continuous_keys(rng):
    motion = random_motion(rng, [-1], n_frames=61, convention="post")
    turns = rotation_about_axis("Y", np.radians(12.0 * np.arange(61)))
    gltf, blob, _ = build_gltf(motion.replace(rotations=turns[:, None]), metres_per_unit=1.0)
    from tests.test_gltf import accessor_array

    animation = gltf.animations[0]
    (rotation,) = [c for c in animation.channels if c.target.path == "rotation"]
    q = accessor_array(gltf, blob, animation.samplers[rotation.sampler].output).astype(np.float64)
    assert (np.einsum("fq,fq->f", q[1:], q[:-1]) > 0).all()


def test_two_frames_across_a_half_turn_stay_continuous(rng):
    motion = random_motion(rng, [-1], n_frames=2, convention="post")
    turns = rotation_about_axis("Y", np.radians([170.0, 190.0]))  # w changes sign between them
    gltf, blob, _ = build_gltf(motion.replace(rotations=turns[:, None]), metres_per_unit=1.0)
    from tests.test_gltf import accessor_array

    animation = gltf.animations[0]
    (rotation,) = [c for c in animation.channels if c.target.path == "rotation"]
    q = accessor_array(gltf, blob, animation.samplers[rotation.sampler].output).astype(np.float64)
    assert q[0] @ q[1] > 0


def test_buffer_views_after_two_byte_data_stay_aligned():
    import pygltflib as gl

    from gmr_studio.core.formats.gltf import BufferBuilder

    builder = BufferBuilder(gl.GLTF2())
    builder.add(np.arange(3, dtype=np.uint16), gl.SCALAR)  # 6 bytes: padded to 8
    builder.add(np.zeros((1, 3)), gl.VEC3, target=gl.ARRAY_BUFFER, bounds=True)
    blob = builder.finish()
    assert [view.byteOffset for view in builder.gltf.bufferViews] == [0, 8] and len(blob) == 20
    with pytest.raises(TypeError):
        builder.add(np.zeros((1, 3)), gl.VEC3, gl.ARRAY_BUFFER)  # target and bounds by name only


def test_the_unit_note_gives_the_size_in_metres(rng):
    from gmr_studio.core.edits.world import scale_lengths
    from gmr_studio.core.formats.gltf import infer_metres_per_unit

    motion = random_motion(rng, [-1, 0, 1], n_frames=2)
    sized = scale_lengths(motion, 170.0 / motion.size)  # 170 cm
    factor, note = infer_metres_per_unit(sized)
    assert factor == 0.01 and "(size 170 units = 1.7 m)" in note
