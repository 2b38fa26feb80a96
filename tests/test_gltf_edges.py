"""The glTF writer's bookkeeping (core/formats/gltf.py): the buffer's layout, the time accessor's
bounds, names, a motion without frames, refusals, the summary and the quaternions of half turns."""

from __future__ import annotations

import numpy as np
import pygltflib as gl
import pytest

from gmr_studio.core.formats.gltf import SCENE_ROOT, build_gltf, export_gltf
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import rotation_about_axis
from gmr_studio.core.rotations.quaternions import quaternion_from_matrix
from tests.conftest import random_motion
from tests.test_gltf import accessor_array, check_round_trip, load_gltf, matrix_from_quaternion

_BYTES = {gl.FLOAT: 4, gl.UNSIGNED_SHORT: 2, gl.UNSIGNED_INT: 4}
_WIDTH = {gl.SCALAR: 1, gl.VEC3: 3, gl.VEC4: 4, gl.MAT4: 16}


def test_the_buffer_holds_every_accessor_aligned_and_the_times_bounded(tmp_path, rng):
    motion = random_motion(rng, [-1, 0, 1, 0], n_frames=7).replace(frame_time=0.25)
    gltf, blob, summary = build_gltf(motion, metres_per_unit=1.0)
    end = 0
    for accessor in gltf.accessors:
        view = gltf.bufferViews[accessor.bufferView]
        assert view.byteOffset % 4 == 0 and view.byteOffset >= end  # in order, 4-byte aligned
        assert view.byteLength == accessor.count * _WIDTH[accessor.type] * _BYTES[accessor.componentType]
        end = view.byteOffset + view.byteLength
    assert gltf.buffers[0].byteLength == len(blob) and len(blob) % 4 == 0 and len(blob) - end < 4
    animation = gltf.animations[0]
    times = gltf.accessors[animation.samplers[0].input]
    assert times.min == [0.0] and times.max == [1.5] and times.type == gl.SCALAR  # 6 frames of 0.25 s
    assert accessor_array(gltf, blob, animation.samplers[0].input).tolist() == [0.25 * f for f in range(7)]
    assert all(sampler.interpolation == "LINEAR" for sampler in animation.samplers)
    assert summary.n_frames == 7 and summary.skinned and summary.n_nodes == len(gltf.nodes)
    assert gltf.asset.generator == "GMR Studio" and gltf.asset.version == "2.0"
    assert gltf.asset.extras == {
        "convention": motion.convention,  # read back as the same convention (glTF in)
        "metres_per_unit": 1.0,  # the unit the lengths were in: the source unit of a read back
        "source_unit": "m",
        "units": "lengths times 1 (metres per unit, given)",
        "up_axis": "Y up as in the source",
    }


def test_a_joint_named_like_the_scene_root_keeps_its_name(tmp_path, rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=3)
    motion = motion.replace(names=[SCENE_ROOT, f"{SCENE_ROOT}2", "hand"])
    gltf, _, _ = build_gltf(motion, skin=False, metres_per_unit=1.0)
    names = [node.name for node in gltf.nodes]
    assert names[:3] == [SCENE_ROOT, f"{SCENE_ROOT}2", "hand"] and names[3] == f"{SCENE_ROOT}3"
    assert gltf.nodes[3].children == [0] and gltf.scenes[0].nodes == [3]


def test_a_motion_without_frames_is_a_still_skeleton(tmp_path, rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=2)
    empty = motion.replace(rotations=motion.rotations[:0], translations=motion.translations[:0])
    result = export_gltf(empty, tmp_path / "still.glb", metres_per_unit=1.0)
    gltf, _ = load_gltf(tmp_path / "still.glb")
    assert gltf.animations == [] and gltf.meshes == [] and not result.skinned and result.n_frames == 0
    assert all(node.translation is None and node.rotation is None for node in gltf.nodes)
    assert [node.name for node in gltf.nodes] == [*motion.names, SCENE_ROOT]


def test_refusals(tmp_path, rng):
    motion = random_motion(rng, [-1, 0], n_frames=2)
    with pytest.raises(ValueError, match=r"a glTF file ends in \.glb or \.gltf, not '\.fbx'"):
        export_gltf(motion, tmp_path / "walk.fbx")
    for factor in (0.0, -1.0, np.inf, np.nan):
        with pytest.raises(ValueError, match="metres per unit must be a positive number"):
            export_gltf(motion, tmp_path / "walk.glb", metres_per_unit=factor)
    assert not (tmp_path / "walk.glb").exists()
    assert export_gltf(motion, tmp_path / "WALK.GLB", metres_per_unit=2.0).path == str(tmp_path / "WALK.GLB")
    check_round_trip(motion, tmp_path / "walk.gltf", metres_per_unit=2.0)  # JSON with a data URI


def test_quaternions_of_half_turns_and_their_sign():
    angles = np.array([np.pi, np.pi - 1e-7, 2.5, -np.pi + 1e-3])
    for axis in "XYZ":
        matrices = rotation_about_axis(axis, angles)
        q = quaternion_from_matrix(matrices, scalar_last=True)
        np.testing.assert_allclose(matrix_from_quaternion(q), matrices, rtol=0, atol=1e-14)
        np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, rtol=0, atol=1e-15)
        assert (q[:, 3] >= 0).all()
        k = "XYZ".index(axis)
        np.testing.assert_allclose(np.abs(q[:, k]), np.abs(np.sin(angles / 2)), rtol=0, atol=1e-12)
    tilted = rotation_about_axis("X", np.array([0.7])) @ rotation_about_axis("Z", np.array([np.pi]))
    np.testing.assert_allclose(
        matrix_from_quaternion(quaternion_from_matrix(tilted, scalar_last=True)), tilted, atol=1e-14
    )


def test_a_post_rotation_motion_round_trips_too(tmp_path, rng):
    motion = random_motion(rng, [-1, 0, 1, 1], n_frames=5, convention="post")
    assert isinstance(motion, Motion)
    check_round_trip(motion, tmp_path / "post.glb", metres_per_unit=0.5)
