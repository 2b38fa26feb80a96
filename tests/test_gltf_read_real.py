"""Other tools' glTF files (../shared/data/gltf): every skin and animation reads, and every
joint is where the file's own nodes put it.

The check is independent of the reader: pygltflib (or plain JSON and base64 for the files
pygltflib cannot open) gives the document, numpy decodes the float accessors, and each node's
world matrix is composed as the specification (and so the reference viewers) does:
``parent_world @ T @ R @ S`` (or the node's ``matrix``), in 4x4 homogeneous matrices, at
times where every channel has a key (its key value, no interpolation). The joints' world
positions (translation column) must match the motion's forward kinematics to 1e-9 of the
size (both are computed in float64 from the same float32 data).
"""

from __future__ import annotations

import base64
import json
import urllib.parse
from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest

from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.gltf_in import gltf_contents
from gmr_studio.core.kinematics.fk import reference_forward_kinematics
from tests.conftest import DATA, shared_path
from tests.test_gltf import matrix_from_quaternion

FILES = [
    "gltf/bevy_Fox.glb",
    "gltf/bevy_SimpleSkin.gltf",
    "gltf/rgl2gltf_RiggedSimple.glb",
    "gltf/lab0_CesiumMan.glb",
    "gltf/mjolnir-zig_CesiumMan.glb",
    "gltf/mjolnir-zig_RiggedSimple.glb",
    "gltf/mediaplusarchi_RobotExpressive.glb",
    "gltf/blenderio_03_skinned_cylinder/03_skinned_cylinder.gltf",
    "gltf/blenderio_03_all_animations/03_all_animations.gltf",
]
#: our FK against the independent walk, relative to the size: float32 precision. Measured:
#: 1e-15 where the keys fall on the frames; 8e-8 for mjolnir-zig_RiggedSimple, whose STEP and
#: LINEAR channels have key times a float32 rounding apart (frames sit on one of them)
RELATIVE_TOLERANCE = 2e-7
_WIDTH = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def load_document(path: Path) -> tuple[dict, list[bytes]]:
    """The JSON and the buffers' bytes."""
    if path.suffix == ".glb":
        gltf = gl.GLTF2().load_binary(str(path))
        return json.loads(gltf.gltf_to_json()), [gltf.binary_blob()]
    document = json.loads(path.read_text())
    buffers = []
    for buffer in document["buffers"]:
        uri = buffer["uri"]
        if uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            buffers.append((path.parent / urllib.parse.unquote(uri)).read_bytes())
    return document, buffers


def floats(document: dict, buffers: list[bytes], index: int) -> np.ndarray:
    """A float accessor without stride or sparse values: (count, width)."""
    accessor = document["accessors"][index]
    assert accessor["componentType"] == gl.FLOAT and "sparse" not in accessor
    view = document["bufferViews"][accessor["bufferView"]]
    width = _WIDTH[accessor["type"]]
    assert view.get("byteStride", 4 * width) == 4 * width
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    data = np.frombuffer(buffers[view["buffer"]], "<f4", accessor["count"] * width, start)
    return data.reshape(accessor["count"], width).astype(np.float64)


def local_matrix(node: dict, animated: dict[str, np.ndarray]) -> np.ndarray:
    """The node's 4x4 local transform ``T R S`` (or its matrix)."""
    if "matrix" in node and not animated:
        return np.asarray(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = animated.get("translation", node.get("translation", [0, 0, 0]))
    q = np.asarray(animated.get("rotation", node.get("rotation", [0, 0, 0, 1])), dtype=np.float64)
    s = animated.get("scale", node.get("scale", [1, 1, 1]))
    matrix = np.eye(4)
    matrix[:3, :3] = matrix_from_quaternion(q / np.linalg.norm(q)) * np.asarray(s, dtype=np.float64)
    matrix[:3, 3] = t
    return matrix


def world_positions_at_keys(path: Path, animation: int | None) -> tuple[np.ndarray, dict[int, np.ndarray], list]:
    """Key times where every channel of the animation has a key (or none: before its first
    or after its last), each node's world position at them: (K,), node -> (K, 3), and the
    nodes (JSON)."""
    document, buffers = load_document(path)
    channels = []
    if animation is not None:
        spec = document["animations"][animation]
        for channel in spec["channels"]:
            target = channel["target"]
            if target.get("path") not in ("translation", "rotation", "scale") or "node" not in target:
                continue
            sampler = spec["samplers"][channel["sampler"]]
            times = floats(document, buffers, sampler["input"])[:, 0]
            values = floats(document, buffers, sampler["output"])
            if sampler.get("interpolation") == "CUBICSPLINE":
                values = values.reshape(times.size, 3, -1)[:, 1]  # the key's value, between its tangents
            channels.append((target["node"], target["path"], times, values))
    all_times = np.unique(np.concatenate([c[2] for c in channels])) if channels else np.zeros(1)
    usable = []
    for t in all_times:
        keys = []
        for node, kind, times, values in channels:
            k = int(np.argmin(np.abs(times - t)))
            if abs(times[k] - t) < 1e-7 or t < times[0] or t > times[-1]:
                keys.append(((node, kind), values[k]))
            else:
                break
        else:
            usable.append((t, keys))
    nodes = document["nodes"]
    children = {c for n in nodes for c in n.get("children", [])}
    roots = [i for i in range(len(nodes)) if i not in children]
    out: dict[int, list] = {}
    for _, keys in usable:
        animated: dict[int, dict[str, np.ndarray]] = {}
        for (node, kind), value in keys:
            animated.setdefault(node, {})[kind] = value
        stack = [(r, np.eye(4)) for r in roots]
        while stack:
            index, parent = stack.pop()
            world = parent @ local_matrix(nodes[index], animated.get(index, {}))
            out.setdefault(index, []).append(world[:3, 3])
            stack.extend((c, world) for c in nodes[index].get("children", []))
    return np.array([t for t, _ in usable]), {node: np.array(v) for node, v in out.items()}, nodes


def node_of(name: str, nodes: list, joint_names: tuple[str, ...], skin: list[int]) -> int:
    """The node a joint name came from: the node of that name (of several, the one in the
    skin whose renamed form ``<name>_<node>`` is not a joint), or ``<name>_<node>``, or
    ``node<node>``."""
    named = [i for i, node in enumerate(nodes) if node.get("name") == name and f"{name}_{i}" not in joint_names]
    named = [i for i in named if i in skin] if len(named) > 1 else named
    if len(named) == 1:
        return named[0]
    stem, _, number = name.rpartition("_") if "_" in name else ("", "", name.removeprefix("node"))
    assert number.isdigit() and nodes[int(number)].get("name", "") == stem, name
    return int(number)


def cases() -> list[tuple[str, int | None]]:
    """(file, animation index) for every animation of every file (None: no animation)."""
    out = []
    for relative in FILES:
        path = DATA / relative
        count = len(gltf_contents(path)["animations"]) if path.exists() else 1
        out += [(relative, a) for a in range(count)] or [(relative, None)]
    return out


@pytest.mark.parametrize(("relative", "animation"), cases())
def test_joints_where_the_files_nodes_put_them(relative, animation):
    path = shared_path(relative)
    motion = read_motion(path, animation=animation) if animation is not None else read_motion(path)
    motion.check_invariants()
    times, expected, nodes = world_positions_at_keys(path, animation)
    skin = load_document(path)[0].get("skins", [{"joints": []}])[0]["joints"]
    start = min(times) if animation is not None else 0.0
    frames = np.round((times - start) / motion.frame_time).astype(np.int64)
    on_frames = np.abs(start + frames * motion.frame_time - times) < 1e-6  # keys on the motion's frames
    assert on_frames.sum() >= 2 or motion.n_frames == 1
    times, frames = times[on_frames], frames[on_frames]
    expected = {name: value[on_frames] for name, value in expected.items()}
    positions = reference_forward_kinematics(motion.frame_slice(frames), with_rotations=False)[0]
    worst = 0.0
    for j, name in enumerate(motion.names):
        worst = max(worst, float(np.abs(positions[:, j] - expected[node_of(name, nodes, motion.names, skin)]).max()))
    print(f"{relative} animation {animation}: {motion.n_joints} joints, {times.size} key times, "
          f"worst {worst / motion.size:.1e} of the size")  # fmt: skip
    assert worst <= RELATIVE_TOLERANCE * motion.size


def test_every_skin_reads_the_same_joints():
    path = shared_path("gltf/mediaplusarchi_RobotExpressive.glb")
    first, second = read_motion(path, skin=0), read_motion(path, skin="1")
    assert first.names == second.names and first.n_joints == 43
    np.testing.assert_array_equal(first.translations, second.translations)
    assert "skin 1 of 2" in second.comments[0]


def test_animation_by_name_and_notes():
    path = shared_path("gltf/bevy_Fox.glb")
    walk = read_motion(path, animation="Walk")
    assert walk.comments[0].endswith("animation 1 'Walk' of 3 (--animation to choose)")
    assert (walk.facts.unit.name, walk.facts.up_axis) == ("m", "y")
    assert any(c.startswith("armature: the transform of 'root'") for c in walk.comments)
    robot = read_motion(shared_path("gltf/mediaplusarchi_RobotExpressive.glb"))
    assert "uniform scale folded into the offsets: 'RobotArmature' (100)" in robot.comments
    assert any(c.startswith("WARNING non-uniform scale") and "'UpperLeg.L'" in c for c in robot.comments)


def test_cubic_spline_between_keys_follows_hermite():
    """03_all_animations: the Sphere's translation is CUBICSPLINE with 3 keys at 1 s; at
    2 Hz, the frames between keys are the specification's Hermite polynomial."""
    path = shared_path("gltf/blenderio_03_all_animations/03_all_animations.gltf")
    motion = read_motion(path, animation="SphereAction", frame_rate=4)
    document, buffers = load_document(path)
    sampler = document["animations"][0]["samplers"][0]
    times = floats(document, buffers, sampler["input"])[:, 0]
    a, v, b = np.moveaxis(floats(document, buffers, sampler["output"]).reshape(times.size, 3, 3), 1, 0)
    s, d = 0.25, times[1] - times[0]
    hermite = (
        (2 * s**3 - 3 * s**2 + 1) * v[0]
        + (s**3 - 2 * s**2 + s) * d * b[0]
        + (-2 * s**3 + 3 * s**2) * v[1]
        + (s**3 - s**2) * d * a[1]
    )
    sphere = motion.names.index("Sphere")
    assert motion.frame_time == 0.25
    np.testing.assert_allclose(motion.translations[1, sphere], hermite, atol=1e-12)
    np.testing.assert_allclose(motion.translations[4, sphere], v[1], atol=1e-12)
