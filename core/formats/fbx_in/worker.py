"""The child process of :func:`core.formats.fbx_in.read_fbx`: ufbx loads one FBX file and
evaluates the transforms of its skeleton's nodes at every frame of one take.

``python .../fbx_in/worker.py FILE|- OPTIONS_JSON`` (run by its path: it imports only numpy,
ufbx and two numpy modules of the core, not the package of every format) writes an .npz
archive to stdout (``meta``: JSON; per node ``t<k>``, ``r<k>``, ``s<k>``: its local
translation (F|1, 3), rotation matrix (F|1, 3, 3) and scale (F|1, 3), a leading 1 where
the value does not change), or its error to stderr with exit status :data:`REJECTED`.

**Why a child process.** The ``ufbx`` Python bindings (0.0.5) hand out their cached element
objects (nodes, takes, curves) without counting the reference they return: the second time
a program asks for the same node, it may get freed memory, and the scene frees its elements
again at exit (the crash at interpreter exit seen on long takes). :func:`owned` adds the
missing count to every element this module receives, and the child leaves with
``os._exit`` once its output is written, so the scene is never freed twice; a file that
still crashes ufbx takes only the child down, and the reader reports it as a bad file.

**The transform stack.** FBX composes a node's local transform as
``T Roff Rp Rpre R Rpost^-1 Rp^-1 Soff Sp S Sp^-1``: a translation, the rotation
``Q = Rpre R Rpost^-1`` and the scale ``S``, with the pivots and offsets folded into the
translation ``T + Roff + Rp + Q (Sp + Soff - Rp - S Sp)``. Where every animated channel of
a node has a key on every frame of the take (as exported takes and baked motion capture
do), the values are the keys themselves, read in bulk, and the stack is composed here with
numpy (:func:`composed_trs`); this is checked against ufbx's own evaluation at the first,
middle and last frames (:data:`AGREEMENT`), and any other node (keys between frames, cubic
curves sampled between keys, several layers, animated pivots) is evaluated by ufbx, frame
by frame. Either way the result is ufbx's local transform of the node (``ufbx_transform``).
"""

from __future__ import annotations

import ctypes
import io
import json
import os
import sys

import numpy as np

#: exit status when the file was refused (the message is on stderr)
REJECTED = 3
#: FBX time ticks per second (FBX 7; older files say theirs in the header)
KTIME_SECOND = 46_186_158_000
#: a key within this fraction of a frame of a frame's time is on it
ON_FRAME = 1e-4
#: largest difference, relative to the transform's size, between the numpy composition and
#: ufbx's evaluation at the frames checked (float64 rounding is 1e-15)
AGREEMENT = 1e-9
#: the most frames x nodes a take may be evaluated to (the reader's MAX_SAMPLES)
MAX_SAMPLES = 20_000_000
#: ufbx rotation order (``ufbx.RotationOrder``) -> the project's intrinsic order
#: (core/rotations/euler.py: read left to right). FBX ``XYZ`` turns about X first: ``Rz Ry Rx``.
EULER_ORDERS = {0: "ZYX", 1: "YZX", 2: "XZY", 3: "ZXY", 4: "YXZ", 5: "XYZ"}
TRANSFORM_PROPS = ("Lcl Translation", "Lcl Rotation", "Lcl Scaling")
#: animated properties besides the three above that move a node (pivots, offsets, order)
STACK_PROPS = (
    "PreRotation",
    "PostRotation",
    "RotationPivot",
    "RotationOffset",
    "ScalingPivot",
    "ScalingOffset",
    "RotationOrder",
    "InheritType",
)


class RefusedError(ValueError):
    """A reason of the project's own for refusing the file."""


def owned(element):
    """``element`` with the reference count the bindings forgot (module docstring)."""
    if element is not None:
        ctypes.pythonapi.Py_IncRef(ctypes.py_object(element))
    return element


def elements(items) -> list:
    """Every element of a ufbx element list, each owned."""
    return [owned(items[i]) for i in range(len(items))]


def vector(value) -> np.ndarray:
    return np.array([value[0], value[1], value[2]], dtype=np.float64)


def prop_vector(node, name: str, default: float = 0.0) -> np.ndarray:
    """A node's static vector property (3,), ``default`` in each component if absent."""
    prop = node.props.find_prop(name)
    return np.full(3, default) if prop is None else vector(prop.value_vec4)


#: every scene loaded, kept until the process ends: a scene freed while the elements
#: taken from it live on is the crash the module docstring tells of
_SCENES: list = []


# --------------------------------------------------------------------------- the scene
def load(source: str | bytes):
    """The scene of a file (a path, or its bytes), kept for the life of the process."""
    import ufbx

    try:
        if isinstance(source, bytes):
            scene = ufbx.load_memory(source, retain_dom=True)
        else:
            scene = ufbx.load_file(source, retain_dom=True)
    except ufbx.UfbxError as exc:
        raise RefusedError(describe_error(exc)) from None
    _SCENES.append(scene)
    return scene


def describe_error(exc: Exception) -> str:
    """ufbx's error as a sentence: its kind and description."""
    kind = type(exc).__name__.removesuffix("Error")
    words = "".join(f" {c.lower()}" if c.isupper() else c for c in kind).strip()
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    known = {
        "unrecognized file format": "not an FBX file (ufbx does not recognise its format)",
        "truncated file": "the file is truncated (it ends inside its data)",
        "empty file": "the file is empty",
        "unsupported version": f"this FBX version is not supported ({text})",
    }
    return known.get(words, f"ufbx cannot read the file: {words}" + (f" ({text})" if text else ""))


def scene_facts(scene) -> dict:
    """Units, axes, frame rate, what the file holds besides its skeleton, and its takes."""
    settings = scene.settings
    axes = settings.axes
    stacks = []
    for stack in elements(scene.anim_stacks):
        layers = elements(stack.layers)
        stacks.append(
            {
                "name": stack.name,
                "begin": float(stack.time_begin),
                "end": float(stack.time_end),
                "layers": [layer.name for layer in layers],
            }
        )
    metadata = scene.metadata
    return {
        "unit_meters": float(settings.unit_meters),
        "axes": [int(axes.right), int(axes.up), int(axes.front)],
        "frame_rate": float(settings.frames_per_second),
        "version": int(metadata.version),
        "ascii": bool(metadata.ascii),
        "creator": str(metadata.creator),
        "meshes": len(scene.meshes),
        "cameras": len(scene.cameras),
        "lights": len(scene.lights),
        "stacks": stacks,
    }


def node_table(scene) -> tuple[list, dict]:
    """The scene's nodes without its root (list, parents first as ufbx orders them) and a
    JSON-ready table: names, parents (-1 below the scene root), attribute types, inherit
    modes, rotation orders."""
    nodes = [node for node in elements(scene.nodes) if not node.is_root]
    index = {node.element_id: k for k, node in enumerate(nodes)}
    parents = []
    for node in nodes:
        parent = owned(node.parent)
        parents.append(index.get(parent.element_id, -1) if parent is not None else -1)
    return nodes, {
        "names": [node.name for node in nodes],
        "parents": parents,
        "types": [int(node.attrib_type) for node in nodes],
        "inherit": [int(node.inherit_mode) for node in nodes],
        "orders": [int(node.rotation_order) for node in nodes],
    }


def choose_stack(scene, facts: dict, wanted) -> int | None:
    """The index of the take asked for (name or index; None: the first); None when the file
    has no take."""
    stacks = facts["stacks"]
    if not stacks:
        if wanted is not None:
            raise RefusedError(f"--animation {wanted}: the file has no animation stacks (takes)")
        return None
    if wanted is None:
        return 0
    names = [s["name"] for s in stacks]
    if str(wanted) in names:
        return names.index(str(wanted))
    if str(wanted).isdigit():
        index = int(wanted)
        if index < len(stacks):
            return index
        raise RefusedError(f"--animation {wanted}: the file has {len(stacks)} takes (0..{len(stacks) - 1})")
    raise RefusedError(f"--animation {wanted!r}: no take of that name (the file has {', '.join(map(repr, names))})")


def frame_times(stack: dict, rate: float) -> np.ndarray:
    """(F,) seconds: the take's span at the file's frame rate, both ends included."""
    if not np.isfinite(rate) or rate <= 0:
        raise RefusedError(f"the file's frame rate is {rate}: expected a positive number")
    span = max(stack["end"] - stack["begin"], 0.0)
    count = int(np.floor(span * rate + ON_FRAME)) + 1
    return stack["begin"] + np.arange(count) / rate


# ------------------------------------------------------------------ skeleton selection
def skeleton(table: dict, animated: set[int]) -> tuple[list[int], list[int], str]:
    """(joints, nodes above them, how they were chosen): the bones, the nodes between
    them, and the nodes above the top bones that are animated (a root null carrying the
    motion) with everything between them and the bones; the other nodes above are the
    armature. Without bones, every node is a joint (node animation)."""
    parents, types = table["parents"], table["types"]
    bones = [k for k, kind in enumerate(types) if kind == 5]
    if not bones:
        order = list(range(len(parents)))
        if not order:
            raise RefusedError("the file has no nodes")
        return order, [], "no bones: every node is a joint (node animation)"
    members = set(bones)
    for node in bones:  # nodes between two bones, and animated nodes above them
        path, up = [], parents[node]
        while up >= 0:
            path.append(up)
            if up in members or up in animated:
                members.update(path)
                path = []
            up = parents[up]
    above = set()
    for node in members:
        up = parents[node]
        while up >= 0 and up not in members:
            above.add(up)
            up = parents[up]
    joints = [k for k in range(len(parents)) if k in members]  # ufbx lists parents first
    return joints, sorted(above), f"{len(bones)} bones"


# ---------------------------------------------------------------------- evaluation
def animated_nodes(scene, stack) -> tuple[dict[int, dict[str, object]], set[int]]:
    """Per node element id: its animated transform properties (name -> ufbx AnimValue) in
    the take's single layer; and the element ids of nodes with other animated properties
    that move them (pivots, offsets) or animated in a take of several layers."""
    layers = elements(stack.layers)
    values: dict[int, dict[str, object]] = {}
    other: set[int] = set()
    for layer in layers:
        for prop in elements(layer.anim_props):
            element = owned(prop.element)
            name = prop.prop_name
            if name in TRANSFORM_PROPS or name in STACK_PROPS:
                values.setdefault(element.element_id, {})[name] = owned(prop.anim_value)
                if name in STACK_PROPS or len(layers) > 1:
                    other.add(element.element_id)
    return values, other


def curves_of(value) -> list:
    """The three component curves of an animated value (None where a component has none),
    each owned: the bindings' tuple holds them without counting (module docstring)."""
    return [owned(curve) for curve in value.curves]


def curve_keys(curve) -> tuple[np.ndarray, np.ndarray] | None:
    """(seconds (K,), values (K,)) of one component's curve, read in bulk from the file's
    own arrays; None when the component has no curve."""
    if curve is None:
        return None
    dom = curve.dom_node
    if dom is None:
        raise LookupError("no curve data")
    times = _dom_array(dom, "KeyTime")
    values = _dom_array(dom, "KeyValueFloat")
    if times is None or values is None or times.shape != values.shape:
        raise LookupError("curve arrays missing")
    return times.astype(np.float64) / KTIME_SECOND, values.astype(np.float64)


_DOM_DTYPES = {3: "<i4", 4: "<i8", 5: "<f4", 6: "<f8"}


def _dom_array(dom, name: str) -> np.ndarray | None:
    node = dom.find(name)
    if node is None or len(node.values) != 1:
        return None
    value = node.values[0]
    dtype = _DOM_DTYPES.get(int(value.type))
    if dtype is None:
        return None
    return np.frombuffer(value.value_blob, dtype=dtype)


def on_frames(keys: tuple[np.ndarray, np.ndarray], times: np.ndarray, rate: float) -> np.ndarray | None:
    """The curve's value at every frame (F,) when it is constant or has a key on every
    frame, else None."""
    seconds, values = keys
    if values.size == 0:
        return None
    if np.all(values == values[0]):
        return np.full(times.size, values[0])
    position = (seconds - times[0]) * rate
    index = np.round(position)
    on = np.abs(position - index) <= ON_FRAME
    index = index[on].astype(np.int64)
    inside = (index >= 0) & (index < times.size)
    index, kept = index[inside], values[on][inside]
    if index.size < times.size:
        return None
    out = np.full(times.size, np.nan)
    out[index] = kept
    return out if np.isfinite(out).all() else None


def euler_matrices(degrees: np.ndarray, order: int) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of FBX Euler angles (..., 3) in degrees, x y z."""
    from gmr_studio.core.rotations.euler import matrix_from_euler

    intrinsic = EULER_ORDERS[order]
    columns = ["XYZ".index(axis) for axis in intrinsic]
    return matrix_from_euler(np.radians(degrees[..., columns]), intrinsic)


def composed_trs(node, channels: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local translation (F|1, 3), rotation matrix (F|1, 3, 3) and scale (F|1, 3) of a node
    from its Lcl values (``channels``: name -> (F|1, 3)) and its static pivots, offsets and
    pre/post rotations (module docstring); the products with identities and zeros (most
    nodes have no pivots, many no pre-rotation) are left out."""
    translation = channels["Lcl Translation"]
    turn = euler_matrices(channels["Lcl Rotation"], int(node.rotation_order))
    scale = channels["Lcl Scaling"]
    pre, post = prop_vector(node, "PreRotation"), prop_vector(node, "PostRotation")
    if pre.any():
        turn = euler_matrices(pre, 0) @ turn
    if post.any():
        turn = turn @ euler_matrices(post, 0).T
    pivot, offset = prop_vector(node, "RotationPivot"), prop_vector(node, "RotationOffset")
    scale_pivot, scale_offset = prop_vector(node, "ScalingPivot"), prop_vector(node, "ScalingOffset")
    if pivot.any() or offset.any() or scale_pivot.any() or scale_offset.any():
        inner = scale_pivot + scale_offset - pivot - scale * scale_pivot
        translation = translation + offset + pivot + (turn @ inner[..., None])[..., 0]
    return translation, turn, scale


def fast_trs(node, props: dict, times: np.ndarray, rate: float):
    """The node's local TRS over the frames by :func:`composed_trs`, or None where its
    curves do not fall on the frames (or cannot be read in bulk)."""
    channels = {}
    for name in TRANSFORM_PROPS:
        default = prop_vector(node, name, 1.0 if name == "Lcl Scaling" else 0.0)
        value = props.get(name)
        if value is None:
            channels[name] = default[None]
            continue
        columns = []
        for component, curve in enumerate(curves_of(value)):
            try:
                keys = curve_keys(curve)
            except LookupError:
                return None
            if keys is None:
                columns.append(np.full(times.size, default[component]))
                continue
            sampled = on_frames(keys, times, rate)
            if sampled is None:
                return None
            columns.append(sampled)
        channels[name] = np.stack(columns, axis=1)
    frames = max(len(c) for c in channels.values())
    channels = {k: (v if len(v) == frames else np.repeat(v, frames, axis=0)) for k, v in channels.items()}
    return composed_trs(node, channels)


def ufbx_trs(node, anim, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The node's local TRS at each time as ufbx evaluates it: (F, 3), (F, 3, 3), (F, 3)."""
    from gmr_studio.core.rotations.quaternions import matrix_from_quaternion

    translation = np.empty((times.size, 3))
    quaternion = np.empty((times.size, 4))
    scale = np.empty((times.size, 3))
    for f, time in enumerate(times.tolist()):
        transform = node.evaluate_transform(anim, time)
        translation[f] = transform[0]
        quaternion[f] = transform[1]
        scale[f] = transform[2]
    return translation, matrix_from_quaternion(quaternion, scalar_last=True), scale


def agrees(a: tuple, b: tuple) -> bool:
    """Two TRS at the same frames agree to :data:`AGREEMENT` of their size."""
    size = max(1.0, float(np.abs(a[0]).max()), float(np.abs(b[0]).max()))
    return (
        float(np.abs(a[0] - b[0]).max()) <= AGREEMENT * size
        and float(np.abs(a[1] - b[1]).max()) <= AGREEMENT
        and float(np.abs(a[2] - b[2]).max()) <= AGREEMENT * max(1.0, float(np.abs(a[2]).max()))
    )


def evaluate(scene, stack, nodes: list, wanted: list[int], times: np.ndarray, rate: float) -> tuple[dict, int]:
    """Per wanted node (index into ``nodes``): its TRS over the frames, a leading 1 where it
    is static; and how many nodes ufbx evaluated frame by frame."""
    out = {}
    by_frame = 0
    if stack is None:
        anim = scene.anim
        values, other = {}, set()
    else:
        anim = stack.anim
        values, other = animated_nodes(scene, stack)
    probe = np.array(sorted({0, times.size // 2, times.size - 1}))
    for k in wanted:
        node = nodes[k]
        props = values.get(node.element_id)
        if props is None:  # not animated in this take: its static transform
            out[k] = ufbx_trs(node, anim, times[:1])
            continue
        trs = None
        if node.element_id not in other and int(node.rotation_order) in EULER_ORDERS:
            trs = fast_trs(node, props, times, rate)
            if trs is not None:
                check = ufbx_trs(node, anim, times[probe])
                picked = tuple(part[probe] if len(part) > 1 else np.repeat(part, probe.size, 0) for part in trs)
                if not agrees(picked, check):
                    trs = None
        if trs is None:
            by_frame += 1
            trs = ufbx_trs(node, anim, times)
        out[k] = tuple(_squeeze(part) for part in trs)
    return out, by_frame


def _squeeze(part: np.ndarray) -> np.ndarray:
    """A leading 1 when every frame holds the same value."""
    if len(part) > 1 and np.array_equal(part, np.broadcast_to(part[:1], part.shape)):
        return np.ascontiguousarray(part[:1])
    return np.ascontiguousarray(part)


# ---------------------------------------------------------------------------- entry
def extract(scene, animation=None) -> tuple[dict, dict]:
    """Everything the reader needs from one scene: ``meta`` (JSON-ready) and per node
    index its TRS arrays (module docstring)."""
    facts = scene_facts(scene)
    nodes, table = node_table(scene)
    chosen = choose_stack(scene, facts, animation)
    stack = elements(scene.anim_stacks)[chosen] if chosen is not None else None
    values, _ = animated_nodes(scene, stack) if stack is not None else ({}, set())
    animated = {k for k, node in enumerate(nodes) if node.element_id in values}
    joints, above, how = skeleton(table, animated)
    times = np.zeros(1) if stack is None else frame_times(facts["stacks"][chosen], facts["frame_rate"])
    wanted = sorted(set(joints) | set(above))
    if times.size * len(wanted) > MAX_SAMPLES:
        raise RefusedError(f"{times.size} frames of {len(wanted)} nodes is more than this reader holds")
    trs, by_frame = evaluate(scene, stack, nodes, wanted, times, facts["frame_rate"])
    bind = bind_pose(scene, nodes, joints)
    meta = {
        **facts,
        **table,
        "take": chosen,
        "joints": joints,
        "above": above,
        "selection": how,
        "frames": int(times.size),
        "evaluated_by_frame": by_frame,
        "bind": bind,
    }
    return meta, trs


def bind_pose(scene, nodes: list, joints: list[int]) -> dict:
    """``{"source": ..., "linear": {node index (text): (3, 3) nested lists}}``: the world
    linear part of each joint in the file's first bind pose; without one, in the nodes'
    static pose (their transforms without animation: a Blender armature's rest)."""
    index = {node.element_id: k for k, node in enumerate(nodes)}
    wanted = set(joints)
    listed = _listed_bind_pose(scene, index, wanted)
    if listed:
        return {"source": "the file's bind pose", "linear": listed}
    static = {}
    for k in joints:
        columns = nodes[k].node_to_world
        static[str(k)] = [[float(columns[c][r]) for c in range(3)] for r in range(3)]
    return {"source": "the nodes' static pose (the file has no bind pose)", "linear": static}


def _listed_bind_pose(scene, index: dict, wanted: set[int]) -> dict:
    for pose in elements(scene.poses):
        if not pose.is_bind_pose:
            continue
        out = {}
        poses = pose.bone_poses
        for i in range(len(poses)):
            bone = poses[i]
            node = owned(bone.bone_node)
            k = index.get(node.element_id) if node is not None else None
            if k in wanted:
                columns = bone.bone_to_world
                out[str(k)] = [[float(columns[c][r]) for c in range(3)] for r in range(3)]
        return out
    return {}


def contents(scene) -> dict:
    """What ``gmr info`` lists (see :func:`.reader.fbx_contents`)."""
    facts = scene_facts(scene)
    _, table = node_table(scene)
    takes = [{"index": k, **stack} for k, stack in enumerate(facts.pop("stacks"))]
    return {**facts, "takes": takes, "nodes": len(table["names"]), "bones": table["types"].count(5)}


def main(argv: list[str]) -> None:
    """``FILE|- OPTIONS_JSON``: ``-`` reads the file's bytes from stdin; options ``mode``
    (``motion`` or ``contents``) and ``animation``."""
    source, options = argv[0], json.loads(argv[1]) if len(argv) > 1 else {}
    try:
        scene = load(source if source != "-" else sys.stdin.buffer.read())
        if options.get("mode") == "contents":
            output = json.dumps(contents(scene)).encode("utf-8")
        else:
            meta, trs = extract(scene, options.get("animation"))
            arrays = {"meta": np.array(json.dumps(meta))}
            for k, (t, r, s) in trs.items():
                arrays[f"t{k}"], arrays[f"r{k}"], arrays[f"s{k}"] = t, r, s
            buffer = io.BytesIO()
            np.savez(buffer, **arrays)
            output = buffer.getvalue()
    except RefusedError as exc:
        sys.stderr.write(f"{exc}\n")
        sys.stderr.flush()
        os._exit(REJECTED)
    sys.stdout.buffer.write(output)
    sys.stdout.flush()
    os._exit(0)  # never free the scene (module docstring)


if __name__ == "__main__":
    main(sys.argv[1:])
