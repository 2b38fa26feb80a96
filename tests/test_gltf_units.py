"""The glTF writer's units, static pose, bounds and options (core/formats/gltf.py)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.world import scale_lengths
from gmr_studio.core.formats.gltf import build_gltf, export_gltf, infer_metres_per_unit
from tests.conftest import random_motion


@pytest.mark.parametrize(("metres", "unit"), [(1.0, "m"), (0.01, "cm"), (0.001, "mm"), (0.0254, "in")])
def test_the_unit_inferred_makes_a_standing_adult(rng, metres, unit):
    motion = random_motion(rng, [-1, 0, 1, 2], n_frames=2)
    sized = scale_lengths(motion, 1.7 / metres / motion.size)  # 1.7 m in that unit
    factor, note = infer_metres_per_unit(sized)
    assert factor == metres and note.startswith(f"lengths taken as {unit} (")


def test_the_static_pose_is_the_first_frame_and_only_times_and_vertices_are_bounded(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=4)
    gltf, blob, _ = build_gltf(motion, metres_per_unit=1.0)
    animation = gltf.animations[0]
    from tests.test_gltf import accessor_array

    for channel in animation.channels:
        keys = accessor_array(gltf, blob, animation.samplers[channel.sampler].output)
        node = gltf.nodes[channel.target.node]
        static = node.rotation if channel.target.path == "rotation" else node.translation
        np.testing.assert_array_equal(np.float32(static), keys[0])  # frame 0, not another
    bounded = [i for i, accessor in enumerate(gltf.accessors) if accessor.min is not None]
    vertices = [mesh.primitives[0].attributes.POSITION for mesh in gltf.meshes]
    assert bounded == sorted([animation.samplers[0].input, *vertices])


def test_options_are_keywords(tmp_path, rng):
    motion = random_motion(rng, [-1, 0], n_frames=2)
    with pytest.raises(TypeError):
        export_gltf(motion, tmp_path / "a.glb", False)
    assert not export_gltf(motion, tmp_path / "a.glb", skin=False, metres_per_unit=1.0).skinned
