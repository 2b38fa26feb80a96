"""glTF export: read back with pygltflib, every node's world position at every frame is the
project's FK (turned Y-up, in metres) to float32 precision; structure, names, skin."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.edits.operations import split
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.gltf import export_gltf, infer_metres_per_unit
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.rotations.quaternions import quaternion_from_matrix
from gmr_studio.core.space.up_axis import Y_TO_Z
from tests.conftest import random_motion, shared_path

#: measured worst error of the read-back positions, relative to the size: 1.9e-7 (CMU
#: 01_01, 2752 frames) and below 2e-7 on the random forests; float32 has a 6e-8 epsilon
RELATIVE_TOLERANCE = 5e-7

_COMPONENTS = {gl.FLOAT: np.float32, gl.UNSIGNED_SHORT: np.uint16, gl.UNSIGNED_INT: np.uint32}
_WIDTH = {gl.SCALAR: 1, gl.VEC3: 3, gl.VEC4: 4, gl.MAT4: 16}


def accessor_array(gltf: gl.GLTF2, blob: bytes, index: int) -> np.ndarray:
    """The data of one accessor: (count, width) or (count,) for scalars."""
    accessor = gltf.accessors[index]
    view = gltf.bufferViews[accessor.bufferView]
    dtype = np.dtype(_COMPONENTS[accessor.componentType])
    width = _WIDTH[accessor.type]
    start = (view.byteOffset or 0) + (accessor.byteOffset or 0)
    data = np.frombuffer(blob, dtype=dtype, count=accessor.count * width, offset=start)
    return data.reshape(accessor.count, width) if width > 1 else data


def load_gltf(path: Path) -> tuple[gl.GLTF2, bytes]:
    gltf = gl.GLTF2().load(str(path))
    if path.suffix == ".gltf":
        gltf.convert_buffers(gl.BufferFormat.BINARYBLOB)
    return gltf, gltf.binary_blob()


def matrix_from_quaternion(q: np.ndarray) -> np.ndarray:
    """(..., 4) x, y, z, w -> (..., 3, 3): the textbook formula (independent of the exporter)."""
    x, y, z, w = np.moveaxis(q.astype(np.float64), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def node_world_positions(gltf: gl.GLTF2, blob: bytes) -> dict[str, np.ndarray]:
    """Each named node's world position (F, 3) at every keyframe of animation 0, composing
    the nodes' animated TRS from the scene's roots down (glTF's rule: parent world times
    T R S of the node)."""
    animation = gltf.animations[0]
    times = accessor_array(gltf, blob, animation.samplers[0].input)
    n_frames = times.size
    animated: dict[tuple[int, str], np.ndarray] = {}
    for channel in animation.channels:
        sampler = animation.samplers[channel.sampler]
        assert np.array_equal(accessor_array(gltf, blob, sampler.input), times)
        animated[channel.target.node, channel.target.path] = accessor_array(gltf, blob, sampler.output)
    out: dict[str, np.ndarray] = {}

    def visit(index: int, rotation: np.ndarray, position: np.ndarray) -> None:
        node = gltf.nodes[index]
        t = animated.get((index, "translation"), np.broadcast_to(node.translation or [0, 0, 0], (n_frames, 3)))
        q = animated.get((index, "rotation"), np.broadcast_to(node.rotation or [0, 0, 0, 1], (n_frames, 4)))
        assert node.scale in (None, [1, 1, 1]) and node.matrix in (None, list(np.eye(4).ravel()))
        position = position + np.einsum("fab,fb->fa", rotation, t.astype(np.float64))
        rotation = rotation @ matrix_from_quaternion(q)
        out[node.name] = position
        for child in node.children or []:
            visit(child, rotation, position)

    for root in gltf.scenes[gltf.scene].nodes:
        visit(root, np.broadcast_to(np.eye(3), (n_frames, 3, 3)), np.zeros((n_frames, 3)))
    return out


def expected_positions(motion, up: str, metres_per_unit: float) -> np.ndarray:
    """FK of the motion, turned to Y up and scaled: (F, J, 3)."""
    positions = reference_forward_kinematics(motion, with_rotations=False)[0]
    if up == "z":
        positions = positions @ Y_TO_Z  # Y_TO_Z.T maps Z up to Y up: p -> Q^T p
    return positions * metres_per_unit


def check_round_trip(motion, path: Path, up: str = "y", **options) -> float:
    """Export, read back, compare every node's positions; return the worst relative error.
    The motion's file facts state ``up`` (a random forest's figure shows no up axis)."""
    motion = motion.replace(facts=motion.facts.replace(up_axis=up))
    result = export_gltf(motion, path, **options)
    gltf, blob = load_gltf(path)
    read = node_world_positions(gltf, blob)
    expected = expected_positions(motion, up, result.metres_per_unit)
    got = np.stack([read[name] for name in motion.names], axis=1)
    size = motion.size * result.metres_per_unit
    error = float(np.abs(got - expected).max()) / size
    assert error <= RELATIVE_TOLERANCE, error
    times = accessor_array(gltf, blob, gltf.animations[0].samplers[0].input)
    np.testing.assert_allclose(times, np.arange(motion.n_frames) * motion.frame_time, rtol=1e-6)
    return error


@pytest.mark.parametrize("convention", ["pre", "post"])
@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_random_forest_round_trip(tmp_path, rng, convention, suffix):
    parents = [-1, 0, 1, 1, 3, -1, 5, 6, 0]
    motion = random_motion(rng, parents, n_frames=40, convention=convention, translation_joints=(4,))
    check_round_trip(motion, tmp_path / f"m{suffix}", metres_per_unit=0.37)


def test_split_roots_are_their_own_trees(tmp_path):
    motion = pre_from_post(read_motion(shared_path("cmu/subject01/01_01.bvh"))).frame_slice(slice(0, 200))
    motion = split(split(motion, "LeftUpLeg"), "RightArm")
    check_round_trip(motion, tmp_path / "split.glb")
    gltf, _ = load_gltf(tmp_path / "split.glb")
    root = gltf.nodes[gltf.scenes[0].nodes[0]]
    assert root.name == "World"
    assert sorted(gltf.nodes[c].name for c in root.children) == sorted(motion.names[r] for r in motion.roots)
    assert len(motion.roots) == 3


def test_real_file_round_trip_and_names(tmp_path):
    motion = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    error = check_round_trip(motion, tmp_path / "walk.glb")
    print(f"01_01.bvh -> glb: worst position error {error:.2e} of the size")
    gltf, _ = load_gltf(tmp_path / "walk.glb")
    assert [n.name for n in gltf.nodes[: motion.n_joints]] == list(motion.names)
    assert gltf.asset.extras["metres_per_unit"] == pytest.approx(0.0254 / 0.45)
    assert len(gltf.animations) == 1
    assert len(gltf.animations[0].channels) == 2 * motion.n_joints


def test_z_up_motion_is_turned_y_up(tmp_path, rng):
    motion = random_motion(rng, [-1, 0, 1, 2], n_frames=10)
    z_up = motion.replace(facts=FileFacts(up_axis="z"))
    check_round_trip(z_up, tmp_path / "z.glb", up="z", metres_per_unit=1.0)
    gltf, _ = load_gltf(tmp_path / "z.glb")
    assert "Z up" in gltf.asset.extras["up_axis"]


def test_skin_follows_the_nodes(tmp_path, rng):
    """Skinned capsule vertices, moved by glTF's skinning rule (joint world times inverse
    bind), stay at a fixed place in their joint's frame: the capsule of a bone spans it."""
    motion = random_motion(rng, [-1, 0, 1, 1], n_frames=5, convention="post").replace(facts=FileFacts(up_axis="y"))
    export_gltf(motion, tmp_path / "s.glb", metres_per_unit=1.0)
    gltf, blob = load_gltf(tmp_path / "s.glb")
    (skin,) = gltf.skins
    primitive = gltf.meshes[0].primitives[0]
    vertices = accessor_array(gltf, blob, primitive.attributes.POSITION).astype(np.float64)
    joints = accessor_array(gltf, blob, primitive.attributes.JOINTS_0)[:, 0]
    weights = accessor_array(gltf, blob, primitive.attributes.WEIGHTS_0)
    assert np.array_equal(weights[:, 0], np.ones(len(vertices)))
    inverse_bind = accessor_array(gltf, blob, skin.inverseBindMatrices).reshape(-1, 4, 4).transpose(0, 2, 1)
    positions, world = reference_forward_kinematics(motion)
    homogeneous = np.concatenate([vertices, np.ones((len(vertices), 1))], axis=1)
    in_joint = np.einsum("vab,vb->va", inverse_bind[joints], homogeneous)[:, :3]
    bones = [(motion.parents[c], c) for c in (1, 2, 3)]  # post: a bone turns with its parent
    for f in (0, 4):  # every skinned vertex lies on a capsule around a bone of its joint
        moved = np.einsum("vab,vb->va", world[f, joints], in_joint) + positions[f, joints]
        distance = np.full(len(moved), np.inf)
        for parent, child in bones:
            mine = joints == parent
            seg_a, seg_b = positions[f, parent], positions[f, child]
            d = seg_b - seg_a
            s = np.clip((moved[mine] - seg_a) @ d / (d @ d), 0, 1)
            along = np.linalg.norm(moved[mine] - (seg_a + s[:, None] * d), axis=1)
            distance[mine] = np.minimum(distance[mine], along / np.linalg.norm(d))
        assert np.isin(joints, [p for p, _ in bones]).all()
        assert distance.max() <= 0.12 + 1e-6  # the capsule radius: at most 12% of the bone length
        assert distance.min() > 1e-3  # a capsule, not a line


def test_unit_inference():
    motion = read_motion(shared_path("cmu/subject01/01_01.bvh"))
    factor, note = infer_metres_per_unit(motion)
    assert factor == pytest.approx(0.0254 / 0.45) and "in / 0.45" in note


def test_quaternions_match_matrices(rng):
    from scipy.spatial.transform import Rotation

    matrices = Rotation.random(500, random_state=3).as_matrix()
    matrices[:4] = [np.eye(3), np.diag([1, -1, -1]), np.diag([-1, 1, -1]), np.diag([-1, -1, 1])]
    q = quaternion_from_matrix(matrices, scalar_last=True)
    np.testing.assert_allclose(matrix_from_quaternion(q), matrices, atol=1e-14)


def test_cli_convert_to_glb(tmp_path, capsys):
    source = shared_path("cmu/subject01/01_01.bvh")
    out = tmp_path / "walk.glb"
    assert main(["convert", str(source), str(out), "--metres-per-unit", "0.1"]) == 0
    gltf, _ = load_gltf(out)
    assert gltf.asset.extras["metres_per_unit"] == 0.1
    assert "glTF" in capsys.readouterr().out


def test_a_single_joint_has_no_mesh(tmp_path, rng):
    motion = random_motion(rng, [-1], n_frames=4)
    result = export_gltf(motion, tmp_path / "one.glb", metres_per_unit=1.0)
    assert not result.skinned
    check_round_trip(motion, tmp_path / "one.glb", metres_per_unit=1.0)
    gltf, _ = load_gltf(tmp_path / "one.glb")
    assert gltf.meshes == [] and gltf.skins == [] and len(gltf.nodes) == 2
