"""The child process of :func:`core.formats.fbx_in.read_fbx`: ufbx loads one FBX file, and
this module works out how each node of its skeleton moves over one take.

``python .../fbx_in/worker.py FILE OPTIONS_JSON`` (run by its path: it imports only numpy,
ufbx and four numpy modules of the core, not the package of every format) writes its
result to the file named by the option ``output`` (:mod:`core.array_transfer`: raw
arrays, read by the parent in one go) and closes its stderr, or writes its error to stderr
and exits with status :data:`REJECTED`. The result's ``meta`` (JSON) has, per node index,
what the parent composes the node's local transform from (``nodes``):

- ``channels``: its nine Lcl channels (translation, rotation in degrees, scale; x y z), each
  a number or the name of an array (F,) of the file's key values as ufbx holds them (a row
  of one block, :data:`CHANNEL_BLOCK`, whose rows ``channel_rows`` names), its rotation
  order and its static pre/post rotations, pivots and offsets;
- ``evaluated`` or ``static``: ufbx's local transform, arrays ``t<k>`` (F|1, 3), ``q<k>``
  (F|1, 4, x y z w) and ``s<k>`` (F|1, 3), a leading 1 where the value does not change.

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
translation ``T + Roff + Rp + Q (Sp + Soff - Rp - S Sp)``
(:mod:`core.kinematics.fbx_stack`). Where every animated
channel of a node has a key on every frame of the take (as exported takes and baked motion
capture do), its values are the keys themselves, read in bulk from the file's arrays, and
the node is sent as ``channels``: composed here at the first, middle and last frames and
checked against ufbx's own evaluation there (:data:`AGREEMENT`), the parent composes the
rest. Any other node (keys between frames, cubic curves sampled between keys, several
layers blended, animated pivots, a rotation order that is not Euler) is evaluated by ufbx,
frame by frame. Either way the result is ufbx's local transform of the node.
"""

from __future__ import annotations

import ctypes
import json
import os
import sys

import numpy as np

from gmr_studio.core.kinematics.fbx_stack import EULER_ORDERS, STATIC_STACK, stack_rotation, stack_translation

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
TRANSFORM_PROPS = ("Lcl Translation", "Lcl Rotation", "Lcl Scaling")
#: animated properties besides the three above that move a node (pivots, offsets, order)
STACK_PROPS = (*STATIC_STACK, "RotationOrder", "InheritType")
#: the array (C, F) float64 whose rows are the channel arrays, named in ``channel_rows``:
#: written row by row as the file holds them, handed over as one block
CHANNEL_BLOCK = "channels"


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
    """The scene of a file (a path, or its bytes), kept for the life of the process. The
    format is recognised by the content, whatever the file's name (as for bytes)."""
    import ufbx

    try:
        if isinstance(source, bytes):
            scene = ufbx.load_memory(source, retain_dom=True)
        else:
            scene = ufbx.load_file(source, retain_dom=True, no_format_from_extension=True)
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


def static_stack(node) -> dict[str, np.ndarray]:
    """A node's static pre/post rotations, pivots and offsets (name -> (3,))."""
    return {name: prop_vector(node, name) for name in STATIC_STACK}


# ----------------------------------------------------------------------- the channels
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


_DOM_DTYPES = {3: "<i4", 4: "<i8", 5: "<f4", 6: "<f8"}


def _dom_blob(dom, name: str) -> tuple[bytes | memoryview, str] | None:
    """The bytes and dtype of one of a curve's arrays in the file (``KeyTime``...): a
    float64 array as a view of ufbx's own memory where the bindings lend one (kept as
    long as the scene, :data:`_SCENES`), else a copy."""
    node = dom.find(name)
    if node is None or len(node.values) != 1:
        return None
    value = node.values[0]
    dtype = _DOM_DTYPES.get(int(value.type))
    if dtype == "<f8" and sys.byteorder == "little":
        lent = memoryview(node.as_real_list())
        if lent.format == "d" and lent.nbytes == 8 * node.array_size():
            return lent, dtype
    return None if dtype is None else (value.value_blob, dtype)


class KeyFrames:
    """Which keys of a curve fall on which frames of the take, worked out once per distinct
    ``KeyTime`` array (the curves of an exported take share one)."""

    def __init__(self, times: np.ndarray, rate: float) -> None:
        self.times, self.rate = times, rate
        self.seen: list[tuple[bytes, str, object]] = []

    def __call__(self, ticks: bytes, dtype: str):
        """``slice``: key ``f`` is on frame ``f``, one per frame; ``(keys (K,), frames (K,))``:
        the keys on frames and their frames, every frame having one; None: some frame has
        none."""
        for blob, kind, found in self.seen:
            if kind == dtype and blob == ticks:
                return found
        found = self._work_out(np.frombuffer(ticks, dtype))
        self.seen.append((ticks, dtype, found))
        return found

    def _work_out(self, ticks: np.ndarray):
        count = self.times.size
        position = (ticks.astype(np.float64) / KTIME_SECOND - self.times[0]) * self.rate
        index = np.round(position)
        keys = np.flatnonzero((np.abs(position - index) <= ON_FRAME) & (index >= 0) & (index < count))
        frames = index[keys].astype(np.int64)
        covered = np.zeros(count, bool)
        covered[frames] = True
        if not covered.all():
            return None
        if keys.size == count and keys[-1] == count - 1 and np.array_equal(frames, keys):
            return slice(0, count)
        return keys, frames


def curve_on_frames(curve, key_frames: KeyFrames) -> float | np.ndarray | None:
    """One component's value at every frame: a number when its keys all hold one value, an
    array (F,) of the file's own values (its dtype) when it has a key on every frame; None
    otherwise (or when its arrays cannot be read in bulk)."""
    dom = curve.dom_node
    ticks = _dom_blob(dom, "KeyTime") if dom is not None else None
    values = _dom_blob(dom, "KeyValueFloat") if dom is not None else None
    if ticks is None or values is None:
        return None
    ticks_blob, values_array = ticks[0], np.frombuffer(*values)
    if values_array.size == 0 or len(ticks_blob) // np.dtype(ticks[1]).itemsize != values_array.size:
        return None
    if np.all(values_array == values_array[0]):
        return float(values_array[0])
    found = key_frames(*ticks)
    if found is None:
        return None
    if isinstance(found, slice):
        return values_array
    keys, frames = found
    out = np.empty(key_frames.times.size, values_array.dtype)
    out[frames] = values_array[keys]
    return out


def node_channels(node, props: dict, key_frames: KeyFrames) -> list | None:
    """The node's nine Lcl channels (translation, rotation in degrees, scale; x y z each) at
    every frame, each a number or an array (F,) (:func:`curve_on_frames`); None when one of
    them does not fall on the frames."""
    channels = []
    for name in TRANSFORM_PROPS:
        static = prop_vector(node, name, 1.0 if name == "Lcl Scaling" else 0.0)
        value = props.get(name)
        curves = curves_of(value) if value is not None else [None] * 3
        for component, curve in enumerate(curves):
            if curve is None:
                channels.append(float(static[component]))
                continue
            sampled = curve_on_frames(curve, key_frames)
            if sampled is None:
                return None
            channels.append(sampled)
    return channels


def channels_at(channels: list, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lcl translation, rotation (degrees) and scale (P, 3) of the channels at some frames."""
    block = np.stack([c[frames].astype(np.float64) if np.ndim(c) else np.full(frames.shape, c) for c in channels], 1)
    return block[:, 0:3], block[:, 3:6], block[:, 6:9]


def composed_at(channels: list, order: int, stack: dict, frames: np.ndarray) -> tuple:
    """The node's local TRS (P, 3), (P, 3, 3), (P, 3) at some frames, composed from its channels."""
    translation, degrees, scale = channels_at(channels, frames)
    turn = stack_rotation(degrees, order, stack["PreRotation"], stack["PostRotation"])
    return stack_translation(translation, turn, scale, stack), turn, scale


# --------------------------------------------------------------------- evaluation
def ufbx_trs(node, anim, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The node's local TRS at each time as ufbx evaluates it: translation (F, 3),
    quaternion (F, 4, x y z w), scale (F, 3)."""
    translation = np.empty((times.size, 3))
    quaternion = np.empty((times.size, 4))
    scale = np.empty((times.size, 3))
    for f, time in enumerate(times.tolist()):
        transform = node.evaluate_transform(anim, time)
        translation[f] = transform[0]
        quaternion[f] = transform[1]
        scale[f] = transform[2]
    return translation, quaternion, scale


def agrees(a: tuple, b: tuple) -> bool:
    """Two TRS (rotations as matrices) at the same frames agree to :data:`AGREEMENT` of
    their size."""
    size = max(1.0, float(np.abs(a[0]).max()), float(np.abs(b[0]).max()))
    return (
        float(np.abs(a[0] - b[0]).max()) <= AGREEMENT * size
        and float(np.abs(a[1] - b[1]).max()) <= AGREEMENT
        and float(np.abs(a[2] - b[2]).max()) <= AGREEMENT * max(1.0, float(np.abs(a[2]).max()))
    )


def evaluate(
    scene, stack, nodes: list, wanted: list[int], times: np.ndarray, rate: float
) -> tuple[dict, dict, list[str]]:
    """Per wanted node (index into ``nodes``), what the parent needs to pose it (JSON-ready,
    module docstring), the arrays named there, and the names of the channel arrays in the
    order of the rows of :data:`CHANNEL_BLOCK` (which holds them, as float64)."""
    from gmr_studio.core.rotations.quaternions import matrix_from_quaternion

    specs, arrays = {}, {}
    rows, row_names = [], []
    if stack is None:
        anim = scene.anim
        values, other = {}, set()
    else:
        anim = stack.anim
        values, other = animated_nodes(scene, stack)
    probe = np.array(sorted({0, times.size // 2, times.size - 1}))
    key_frames = KeyFrames(times, rate)
    for k in wanted:
        node = nodes[k]
        props = values.get(node.element_id)
        order = int(node.rotation_order)
        channels = None
        if props is not None and node.element_id not in other and order in EULER_ORDERS:
            channels = node_channels(node, props, key_frames)
        if channels is not None:
            stack_props = static_stack(node)
            translation, quaternion, scale = ufbx_trs(node, anim, times[probe])
            check = translation, matrix_from_quaternion(quaternion, scalar_last=True), scale
            if not agrees(composed_at(channels, order, stack_props, probe), check):
                channels = None
        if channels is not None:
            names = []
            for c, channel in enumerate(channels):
                if isinstance(channel, np.ndarray):
                    rows.append(channel.astype(np.float64, copy=False))
                    names.append(f"c{k}.{c}")
                    row_names.append(names[-1])
                else:
                    names.append(channel)
            stack_lists = {name: vector.tolist() for name, vector in stack_props.items()}
            specs[str(k)] = {"kind": "channels", "order": order, "stack": stack_lists, "channels": names}
            continue
        # not animated in this take (its static transform), or evaluated by ufbx frame by frame
        trs = ufbx_trs(node, anim, times if props is not None else times[:1])
        for part, array in zip("tqs", trs):
            arrays[f"{part}{k}"] = _squeeze(array)
        specs[str(k)] = {"kind": "evaluated" if props is not None else "static"}
    arrays[CHANNEL_BLOCK] = rows
    return specs, arrays, row_names


def _squeeze(part: np.ndarray) -> np.ndarray:
    """A leading 1 when every frame holds the same value."""
    if len(part) > 1 and np.array_equal(part, np.broadcast_to(part[:1], part.shape)):
        return np.ascontiguousarray(part[:1])
    return np.ascontiguousarray(part)


# ---------------------------------------------------------------------------- entry
def extract(scene, animation=None) -> tuple[dict, dict]:
    """Everything the reader needs from one scene: ``meta`` (JSON-ready) and the arrays it
    names (module docstring)."""
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
    specs, arrays, row_names = evaluate(scene, stack, nodes, wanted, times, facts["frame_rate"])
    bind = bind_pose(scene, nodes, joints)
    meta = {
        **facts,
        **table,
        "take": chosen,
        "joints": joints,
        "above": above,
        "selection": how,
        "frames": int(times.size),
        "nodes": specs,
        "channel_rows": row_names,
        "bind": bind,
    }
    return meta, arrays


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
    """``FILE OPTIONS_JSON``: options ``mode`` (``motion`` or ``contents``), ``animation``
    and ``output`` (the file to write; stderr is closed once it is there)."""
    from gmr_studio.core.array_transfer import write_arrays

    source, options = argv[0], json.loads(argv[1]) if len(argv) > 1 else {}
    try:
        scene = load(source)
        if options.get("mode") == "contents":
            header, arrays = {"contents": contents(scene)}, {}
        else:
            meta, arrays = extract(scene, options.get("animation"))
            header = {"meta": meta}
    except RefusedError as exc:
        sys.stderr.write(f"{exc}\n")
        sys.stderr.flush()
        os._exit(REJECTED)
    partial = f"{options['output']}.part"
    write_arrays(partial, header, arrays)
    os.replace(partial, options["output"])  # whole, or not there
    os.close(2)  # done: the parent reads the result while this process releases its memory
    os._exit(0)  # never free the scene (module docstring)


if __name__ == "__main__":
    main(sys.argv[1:])
