"""The glTF reader on files built for each feature: every joint where glTF's node rule
(``parent_world @ T R S``, walked here with 4x4 matrices) puts it; samplers as the
specification defines them; notes that say what was done; one-line errors for bad files."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.gltf_in import read_gltf
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from tests.gltf_builder import GltfBuilder, glb_bytes, quaternion
from tests.test_gltf_read_real import local_matrix

TOLERANCE = 1e-12


def f32(values) -> np.ndarray:
    """Values as the file stores them (float32), back in float64."""
    return np.asarray(values, dtype=np.float64).astype(np.float32).astype(np.float64)


def walk(nodes: list[dict], values: dict[int, dict[str, np.ndarray]]) -> dict[int, np.ndarray]:
    """World position of every node, with ``values`` overriding their TRS."""
    children = {c for n in nodes for c in n.get("children", [])}
    out, stack = {}, [(i, np.eye(4)) for i in range(len(nodes)) if i not in children]
    while stack:
        index, parent = stack.pop()
        world = parent @ local_matrix(nodes[index], values.get(index, {}))
        out[index] = world[:3, 3]
        stack.extend((c, world) for c in nodes[index].get("children", []))
    return out


def arm(builder: GltfBuilder, armature: dict | None = None) -> list[int]:
    """Armature node 0 above joints 1 (root), 3 (under the non-joint node 2) and 4."""
    builder.node(name="Armature", children=[1], **(armature or {}))
    builder.node(name="hips", translation=[0, 1, 0], children=[2])
    builder.node(name="between", translation=[0.5, 0, 0], rotation=list(quaternion([0, 0, 1], 30)), children=[3])
    builder.node(name="knee", translation=[0, -0.5, 0], children=[4])
    builder.node(name="foot", translation=[0, -0.4, 0.1])
    builder.doc["skins"] = [{"name": "body", "joints": [1, 3, 4]}]
    builder.doc["scenes"] = [{"nodes": [0]}]
    return [1, 2, 3, 4]


def check_positions(motion, nodes, frames_values: list[dict], joints: list[int]) -> float:
    positions = reference_forward_kinematics(motion, with_rotations=False)[0]
    worst = 0.0
    for f, values in enumerate(frames_values):
        expected = walk(nodes, values)
        for j, node in enumerate(joints):
            worst = max(worst, float(np.abs(positions[f, j] - expected[node]).max()))
    return worst


@pytest.mark.parametrize("mode", ["glb", "embedded", "external"])
def test_containers_armature_and_the_nodes_between_joints(tmp_path, mode):
    builder = GltfBuilder()
    joints = arm(builder, {"rotation": list(quaternion([1, 0, 0], -90)), "scale": [2, 2, 2], "translation": [1, 2, 3]})
    times = np.array([0.0, 0.5, 1.0])
    turns = f32([quaternion([0, 1, 0], a) for a in (0, 40, -70)])
    moves = f32([[0, 1, 0], [0.2, 1.1, 0], [0.4, 0.9, 0.3]])
    builder.animation([(1, "rotation", times, turns, "LINEAR"), (1, "translation", times, moves, "LINEAR")], "walk")
    path = builder.save(tmp_path / ("m.glb" if mode == "glb" else "m.gltf"), mode)
    motion = read_motion(path)
    assert motion.names == ("hips", "between", "knee", "foot") and list(motion.parents) == [-1, 0, 1, 2]
    assert motion.n_frames == 3 and motion.frame_time == pytest.approx(0.5)
    values = [{1: {"rotation": turns[f], "translation": moves[f]}} for f in range(3)]
    assert check_positions(motion, builder.doc["nodes"], values, joints) <= TOLERANCE
    assert "armature: the transform of 'Armature' above the skeleton applied to its roots (hips)" in motion.comments
    assert "uniform scale folded into the offsets: 'Armature' (2)" in motion.comments
    assert motion.comments[0] == f"glTF {path.name}: skin 0 'body', animation 0 'walk'"
    assert motion.has_translation.tolist() == [True, False, False, False]  # only the root moves
    np.testing.assert_allclose(motion.offsets[2], [0, -1, 0], atol=1e-15)  # 0.5 times the armature's 2


def test_linear_rotation_is_slerp_and_step_holds(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root", children=[1])
    builder.node(name="tip", translation=[1, 0, 0])
    turns = np.array([quaternion([0, 0, 1], 0), quaternion([0, 0, 1], 120)])
    builder.animation([(0, "rotation", [0.0, 1.0], turns, "LINEAR")], "slerp")
    builder.animation([(0, "translation", [0.0, 1.0], [[0, 0, 0], [0, 5, 0]], "STEP")], "step")
    path = builder.save(tmp_path / "s.glb")
    slerped = read_motion(path, animation="slerp", frame_rate=4)
    assert slerped.n_frames == 5 and "sampled at 4 Hz (--frame-rate)" in slerped.comments
    tip = reference_forward_kinematics(slerped, with_rotations=False)[0][:, 1]
    angles = np.degrees(np.arctan2(tip[:, 1], tip[:, 0]))
    np.testing.assert_allclose(angles, [0, 30, 60, 90, 120], atol=1e-9)  # constant speed: slerp, not lerp
    stepped = read_motion(path, animation=1, frame_rate=4)
    np.testing.assert_array_equal(stepped.translations[:, 0, 1], [0, 0, 0, 0, 5])


def test_normalised_integer_quaternions_and_sparse_accessors(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root", children=[1])
    builder.node(name="tip", translation=[1, 0, 0])
    q = np.array([quaternion([0, 0, 1], 0), quaternion([0, 0, 1], 90), quaternion([1, 1, 0], 45)])
    stored = np.round(q * 32767).astype(np.int16)
    times = builder.accessor(np.array([[0.0], [1.0], [2.0]]))
    rotations = builder.accessor(stored, "<i2", normalized=True)
    sparse = {
        "count": 1,
        "indices": {"bufferView": builder.view(np.array([2], "<u2").tobytes()), "componentType": 5123},
        "values": {"bufferView": builder.view(np.array([[0.0, 3.0, 0.0]], "<f4").tobytes())},
    }
    builder.doc["accessors"].append({"componentType": 5126, "count": 3, "type": "VEC3", "sparse": sparse})
    translations = len(builder.doc["accessors"]) - 1
    builder.doc["animations"] = [
        {
            "samplers": [{"input": times, "output": rotations}, {"input": times, "output": translations}],
            "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "rotation"}},
                {"sampler": 1, "target": {"node": 0, "path": "translation"}},
            ],
        }
    ]
    motion = read_gltf(builder.save(tmp_path / "n.gltf", "embedded"))
    decoded = np.maximum(stored / 32767.0, -1.0)
    values = [{0: {"rotation": decoded[f], "translation": [0, 3 * (f == 2), 0]}} for f in range(3)]
    assert check_positions(motion, builder.doc["nodes"], values, [0, 1]) <= TOLERANCE
    np.testing.assert_array_equal(motion.translations[:, 0], [[0, 0, 0], [0, 0, 0], [0, 3, 0]])


def test_non_uniform_and_animated_scale_are_named_and_positions_exact(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root", children=[1], rotation=list(quaternion([0, 0, 1], 20)))
    builder.node(name="stretched", translation=[1, 0, 0], scale=[1, 3, 1], children=[2])
    builder.node(name="elbow", translation=[0, 1, 0], children=[3])
    builder.node(name="hand", translation=[0.3, 0.2, 0.1])
    turns = f32([quaternion([1, 0, 1], a) for a in (0, 50)])
    grow = np.array([[1.0, 1, 1], [2.0, 2, 2]])
    builder.animation([(1, "rotation", [0.0, 1.0], turns, "LINEAR"), (2, "scale", [0.0, 1.0], grow, "LINEAR")])
    motion = read_gltf(builder.save(tmp_path / "scale.glb"))
    values = [{1: {"rotation": turns[f]}, 2: {"scale": grow[f]}} for f in range(2)]
    assert check_positions(motion, builder.doc["nodes"], values, [0, 1, 2, 3]) <= TOLERANCE
    warning = next(c for c in motion.comments if c.startswith("WARNING non-uniform scale"))
    assert "'stretched' (axes up to 3:1)" in warning and "'elbow'" not in warning
    assert "animated uniform scale folded into per-frame translations: 'elbow' (1 to 2)" in motion.comments
    motion.check_invariants()


def test_matrix_nodes_equal_their_trs(tmp_path):
    q, t, s = quaternion([1, 2, 3], 70), [0.1, 0.2, 0.3], 1.5
    local = local_matrix({"translation": t, "rotation": list(q), "scale": [s, s, s]}, {})
    by_matrix, by_trs = GltfBuilder(), GltfBuilder()
    by_matrix.node(name="a", matrix=local.T.ravel().tolist(), children=[1])
    by_trs.node(name="a", translation=t, rotation=list(q), scale=[s, s, s], children=[1])
    for builder in (by_matrix, by_trs):
        builder.node(name="b", translation=[0, 1, 0])
    one, two = (read_gltf(b.save(tmp_path / f"{i}.glb")) for i, b in enumerate((by_matrix, by_trs)))
    assert one.n_frames == 1 and "a single key: one frame, 30 Hz" in one.comments
    first, second = (reference_forward_kinematics(m, with_rotations=False)[0] for m in (one, two))
    np.testing.assert_allclose(first, second, atol=1e-15)
    np.testing.assert_allclose(first[0, 1], walk(by_trs.doc["nodes"], {})[1], atol=1e-15)


def test_clock_regular_irregular_and_asked(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root")
    regular = np.arange(6) / 60
    builder.animation([(0, "translation", regular, np.arange(18).reshape(6, 3), "LINEAR")], "regular")
    builder.animation([(0, "translation", [0.0, 0.1, 0.35], np.zeros((3, 3)), "LINEAR")], "irregular")
    path = builder.save(tmp_path / "c.glb")
    motion = read_gltf(path)
    assert motion.n_frames == 6 and motion.frame_rate == pytest.approx(60)
    np.testing.assert_array_equal(motion.translations[:, 0], np.arange(18).reshape(6, 3))  # exactly the keys
    odd = read_gltf(path, animation="irregular")
    assert "keys at irregular times: sampled at 30 Hz (--frame-rate to choose)" in odd.comments
    assert odd.n_frames == 12 and odd.frame_time == pytest.approx(1 / 30)  # 0 .. 0.35 s, last frame at or after it


def test_choosing_skins_and_animations(tmp_path, capsys):
    builder = GltfBuilder()
    arm(builder)
    builder.doc["skins"].append({"name": "feet", "joints": [4]})
    builder.animation([(3, "rotation", [0.0, 1.0], [quaternion([1, 0, 0], a) for a in (0, 10)], "LINEAR")], "a")
    builder.animation([(3, "rotation", [0.0, 2.0], [quaternion([1, 0, 0], a) for a in (0, 90)], "LINEAR")], "b")
    path = builder.save(tmp_path / "two.glb")
    assert read_gltf(path, skin="feet").names == ("foot",)
    assert read_gltf(path, skin=1).comments[0].startswith("glTF two.glb: skin 1 'feet' of 2 (--skin to choose)")
    assert read_gltf(path, animation="b").n_frames == 2
    with pytest.raises(MotionFileError, match="--animation 'c': no animation of that name"):
        read_gltf(path, animation="c")
    with pytest.raises(MotionFileError, match="--skin 2: the file has 2 skins"):
        read_gltf(path, skin=2)
    assert main(["info", str(path), "--animation", "b", "--skin", "body"]) == 0
    out = capsys.readouterr().out
    assert "skin:       1 'feet', 1 joints (--skin)" in out and "animation:  1 'b', 1 channels, LINEAR" in out
    assert main(["info", str(path), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert [a["name"] for a in document["gltf"]["animations"]] == ["a", "b"] and document["format"] == "glTF 2.0 binary"


def test_without_a_skin_every_node_is_a_joint(tmp_path):
    builder = GltfBuilder()
    arm(builder)
    del builder.doc["skins"]
    motion = read_gltf(builder.save(tmp_path / "plain.glb"))
    assert motion.names == ("Armature", "hips", "between", "knee", "foot")
    assert motion.comments[0] == "glTF plain.glb: no skin: every node is a joint"


def test_a_repeated_node_name_takes_the_nodes_index(tmp_path):
    """The nodes are listed out of depth-first order, so a repeat's node index differs from
    its place among the joints and from a count of repeats: ``Bone_5`` is node 5."""
    builder = GltfBuilder()
    layout = [
        ("Root", [6]),
        ("Head", [4]),
        ("Tail", []),
        ("Neck", [5]),
        ("Bone", []),
        ("Bone", [1]),
        ("Bone", [3]),
    ]
    for k, (name, children) in enumerate(layout):
        builder.node(name=name, translation=[0.1 * k, 0.2, 0.05 * k], children=children)
    motion = read_gltf(builder.save(tmp_path / "repeats.glb"))
    nodes = [0, 6, 3, 5, 1, 4, 2]  # depth first from the scene's roots 0 and 2
    assert motion.names == ("Root", "Bone", "Neck", "Bone_5", "Head", "Bone_4", "Tail")
    assert check_positions(motion, builder.doc["nodes"], [{}], nodes) < TOLERANCE


# ------------------------------------------------------------------------ bad files
def _valid() -> GltfBuilder:
    builder = GltfBuilder()
    builder.node(name="root", children=[1])
    builder.node(name="tip", translation=[1, 0, 0])
    builder.animation([(0, "rotation", [0.0, 1.0], [quaternion([0, 0, 1], a) for a in (0, 90)], "LINEAR")])
    return builder


def _edit(change):
    def make(tmp_path):
        builder = _valid()
        change(builder.doc)
        return builder.save(tmp_path / "bad.glb")

    return make


def _truncated(tmp_path):
    data = _valid().save(tmp_path / "whole.glb").read_bytes()
    (tmp_path / "bad.glb").write_bytes(data[: len(data) - 10])
    return tmp_path / "bad.glb"


def _chunk_too_long(tmp_path):
    data = bytearray(_valid().save(tmp_path / "whole.glb").read_bytes())
    json_length = int.from_bytes(data[12:16], "little")
    data[20 + json_length : 24 + json_length] = (10**6).to_bytes(4, "little")  # the BIN chunk's length
    (tmp_path / "bad.glb").write_bytes(bytes(data))
    return tmp_path / "bad.glb"


def _external(uri):
    def make(tmp_path):
        builder = _valid()
        builder.save(tmp_path / "bad.gltf", "external")
        doc = json.loads((tmp_path / "bad.gltf").read_text())
        doc["buffers"][0]["uri"] = uri
        (tmp_path / "bad.gltf").write_text(json.dumps(doc))
        return tmp_path / "bad.gltf"

    return make


def _raw(data: bytes, name: str = "bad.glb"):
    def make(tmp_path):
        (tmp_path / name).write_bytes(data)
        return tmp_path / name

    return make


def _set(path: list, value):
    def change(doc):
        target = doc
        for key in path[:-1]:
            target = target[key]
        target[path[-1]] = value

    return change


BAD = {
    "truncated file": (_truncated, "the header says"),
    "chunk beyond the end": (_chunk_too_long, "beyond the file's end"),
    "accessor beyond its view": (
        _edit(_set(["accessors", 1, "count"], 40)),
        "need 640 bytes but its bufferView has",
    ),
    "view beyond its buffer": (_edit(_set(["bufferViews", 1, "byteLength"], 4000)), "lie outside its buffer"),
    "huge count": (_edit(_set(["accessors", 0, "count"], 2**40)), "beyond the 50000000 elements"),
    "node cycle": (_edit(_set(["nodes", 1, "children"], [0])), "the node tree has a cycle through node 0"),
    "two parents": (_edit(lambda d: d["nodes"].append({"children": [1]})), "node 1 has two parents (0 and 2)"),
    "cycle of one parent each": (
        _edit(lambda d: d["nodes"].extend([{"children": [3]}, {"children": [2]}])),
        "the node tree has a cycle",
    ),
    "child out of range": (_edit(_set(["nodes", 0, "children"], [7])), "nodes index 7 out of range"),
    "buffer longer than the chunk": (_edit(lambda d: None), None),
    "missing external buffer": (_external("gone.bin"), "its file 'gone.bin' is missing beside the glTF"),
    "absolute buffer path": (_external("/etc/passwd"), "is not a path relative to the file"),
    "remote buffer": (_external("http://example.com/x.bin"), "is not a path relative to the file"),
    "bad base64": (_external("data:application/octet-stream;base64,@@@"), "not valid base64"),
    "decreasing times": (_edit(lambda d: None), None),
    "outputs short": (_edit(_set(["accessors", 1, "type"], "VEC3")), "outputs of 4 components"),
    "sampler out of range": (_edit(_set(["animations", 0, "channels", 0, "sampler"], 5)), "sampler 5 out of range"),
    "bad interpolation": (_edit(_set(["animations", 0, "samplers", 0, "interpolation"], "CUBIC")), "interpolation"),
    "not JSON": (_raw(b'{"asset": {', "bad.gltf"), "not valid JSON"),
    "glTF 1": (_raw(b'{"asset": {"version": "1.0"}}', "bad.gltf"), "only glTF 2.x"),
    "not a glb": (_raw(b"PK\x03\x04" + b"\0" * 40), "not a binary glTF file"),
    "tiny": (_raw(b"glTF"), "this has 4 bytes"),
    "zero quaternion": (_edit(lambda d: d["accessors"][1].pop("bufferView")), "rotation key 0 is not a quaternion"),
    "compressed buffers": (
        _edit(_set(["extensionsRequired"], ["EXT_meshopt_compression"])),
        "requires EXT_meshopt_compression, which this reader does not decode",
    ),
    "skin joint out of range": (_edit(_set(["skins"], [{"joints": [9]}])), "skin 0 joints: nodes index 9"),
    "frames beyond reason": (_edit(lambda d: None), None),
}


def _longer_buffer(tmp_path):
    builder = _valid()
    builder.save(tmp_path / "whole.glb")
    doc = json.loads(json.dumps(builder.doc))
    doc["buffers"] = [{"byteLength": len(builder.blob) + 1000}]
    (tmp_path / "bad.glb").write_bytes(glb_bytes(doc, bytes(builder.blob)))
    return tmp_path / "bad.glb"


def _decreasing(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root")
    builder.animation([(0, "translation", [0.0, 2.0, 1.0], np.zeros((3, 3)), "LINEAR")])
    return builder.save(tmp_path / "bad.glb")


def _endless(tmp_path):
    builder = GltfBuilder()
    builder.node(name="root")
    builder.animation([(0, "translation", [0.0, 0.5, 1e7], np.zeros((3, 3)), "LINEAR")])
    return builder.save(tmp_path / "bad.glb")


BAD["buffer longer than the chunk"] = (_longer_buffer, "bytes but claims byteLength")
BAD["decreasing times"] = (_decreasing, "key times must not decrease (key 2)")
BAD["frames beyond reason"] = (_endless, "more than 2000000")


@pytest.mark.parametrize("case", list(BAD))
def test_bad_files_raise_one_clear_error(tmp_path, capsys, case):
    make, expected = BAD[case]
    path = make(tmp_path)
    with pytest.raises(MotionFileError) as caught:
        read_motion(path)
    assert expected in caught.value.message and caught.value.path == str(path)
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err and expected in err
