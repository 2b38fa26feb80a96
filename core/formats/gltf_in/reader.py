"""glTF 2.0 in: a skin's joints and their node animation as a post-rotation motion.

``read_gltf(path, animation=None, skin=None, frame_rate=None)``:

- the joints are the skin's (``skin``: name or index, default the first) and the nodes
  between them, depth first; without a skin, every node of the scene. The nodes above the
  topmost joints (an armature) are applied to the roots, and a note says so.
- the animation (``animation``: name or index, default the first) is sampled at
  ``frame_rate``, by default at the keys' own spacing when it is regular, else 30 Hz
  (:mod:`.sampling`); without an animation the motion is the nodes' pose, one frame.
- node transforms become joint rotations and translations as :mod:`.pose` says; uniform
  scale folds into lengths, non-uniform or animated scale is named in the notes.
- units metres and Y up (the specification's): the motion's file facts say so, so ``gmr
  compare`` and ``--up`` know. A file this project wrote also records the unit of its source
  (``asset.extras``), which becomes the facts' ``source_unit``: a BVH written from it is in
  that unit again, and ``gmr compare`` uses it when the other side states no units.

Every note is a line of :attr:`Motion.comments`. Errors: :class:`~core.errors.MotionFileError`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError, read_input
from gmr_studio.core.formats.gltf_in.container import GltfDocument, open_gltf
from gmr_studio.core.formats.gltf_in.pose import NodePose, node_poses, skeleton_pose
from gmr_studio.core.formats.gltf_in.rest import bind_rotations, pre_from_export, turn_to_bind
from gmr_studio.core.formats.gltf_in.sampling import INTERPOLATIONS, Sampler, frame_times, sample, segments
from gmr_studio.core.formats.gltf_in.scene import (
    choose,
    node_parents,
    skeleton_nodes,
    static_trs,
    vrm_humanoid_nodes,
)
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import rotation_angle
from gmr_studio.core.space.units import UNITS, Unit, unit_of_length

#: rotation channel order given to every joint (what a BVH written from it uses)
ROTATION_ORDER = "ZYX"
PATHS = {"translation": 3, "rotation": 4, "scale": 3}
#: scales closer than this (relative) to uniform, or to 1, are float32 rounding: not reported
SCALE_NOTE_TOLERANCE = 1e-5
#: a rotation key shorter than this has no direction (normalised int8 keys are at least 1/127)
MIN_QUATERNION_LENGTH = 1e-3
#: the most joint samples (frames times joints) a file may be sampled to (~2 GB of motion)
MAX_SAMPLES = 20_000_000


def read_gltf(
    path: str | Path,
    *,
    animation: str | int | None = None,
    skin: str | int | None = None,
    frame_rate: float | None = None,
    data: bytes | None = None,
) -> Motion:
    """Read a ``.glb``/``.gltf`` file as a post-rotation motion (see the module docstring)."""
    doc = open_gltf(path, read_input(path, data))
    try:
        return _read(doc, animation, skin, frame_rate)
    except ValueError as exc:  # limits of the sampling and of the motion model
        raise MotionFileError(path, str(exc)) from None


def _read(doc: GltfDocument, animation, skin, frame_rate) -> Motion:
    parents = node_parents(doc)
    skin_index, skin_note = choose(doc, "skins", skin, "--skin")
    joints, above = skeleton_nodes(doc, parents, skin_index)
    needed = set(joints) | set(above)
    anim_index, anim_note = choose(doc, "animations", animation, "--animation")
    samplers, ignored = _channels(doc, anim_index, needed) if anim_index is not None else ({}, [])
    distinct = {id(s.times): s.times for s in samplers.values()}  # samplers often share their key times
    clock = frame_times(list(distinct.values()), frame_rate)
    located = {key: segments(times, clock.times) for key, times in distinct.items()}
    n_frames = clock.times.size
    if n_frames * len(joints) > MAX_SAMPLES:
        raise doc.error(f"{n_frames} frames of {len(joints)} joints is more than this reader holds: use --frame-rate")
    translation, rotation, scale = static_trs(doc)
    static = {node: (translation[node][None], rotation[node][None], scale[node][None]) for node in needed}
    animated = {  # keys as stored where frames fall on them (pose.py works on them in float64)
        node: [
            sample(s, clock.times, name == "rotation", located[id(s.times)])
            if (s := samplers.get((node, name)))
            else value
            for name, value in zip(PATHS, static[node])
        ]
        for node in needed
    }
    for trs in animated.values():  # scales also feed the notes, which work in their own type
        trs[2] = trs[2].astype(np.float64, copy=False)
    rest, rest_block = _poses(joints, above, static)
    poses, block = _poses(joints, above, animated)
    index = {node: j for j, node in enumerate(joints)}
    motion_parents = np.array([index.get(int(parents[node]), -1) for node in joints], dtype=np.int64)
    offsets = skeleton_pose(rest, parents, joints, 1, rest_block)[1][0]
    rotations, translations, moving = skeleton_pose(poses, parents, joints, n_frames, block)
    offsets[~moving] = translations[0, ~moving]  # constant over the animation: that value, not the rest's
    bind, from_skin = bind_rotations(doc, skin_index, joints)
    turned = turn_to_bind(bind, motion_parents, rotations, translations, offsets, moving, overwrite=True)  # ours
    rotations, translations, offsets = turned
    convention, pre_note = "post", ""
    if _extras(doc).get("convention") == "pre" and str(doc.json["asset"].get("generator", "")).startswith("GMR"):
        translations, offsets, moving = pre_from_export(rotations, translations, offsets, motion_parents, moving)
        convention, pre_note = "pre", "written by GMR Studio from a pre-rotation (GMR) motion: read as one"
    names, renamed = _joint_names(doc, joints)
    comments = [
        f"glTF {doc.path.name}: " + ", ".join(filter(None, [skin_note or _no_skin_note(doc), anim_note])),
        clock.note,
        *_armature_notes(doc, above, joints, parents, index),
        bind_note(bind, from_skin),
        pre_note,
        *_scale_notes(doc, poses, needed),
        *ignored,
        *renamed,
    ]
    return Motion(
        names=names,
        parents=motion_parents,
        offsets=offsets,
        rotation_orders=(ROTATION_ORDER,) * len(joints),
        has_translation=moving,
        rotations=rotations,
        translations=translations,
        frame_time=clock.frame_time,
        convention=convention,
        comments=tuple(c for c in comments if c),
        facts=FileFacts(unit=UNITS["m"], up_axis="y", source_unit=_source_unit(doc)),
    )


def _poses(joints: list[int], above: list[int], trs: dict[int, list[np.ndarray]]) -> tuple[dict, np.ndarray]:
    """Node poses of the joints (their rotations one block, returned) and of the nodes above."""
    poses, block = node_poses(joints, *(list(column) for column in zip(*(trs[n] for n in joints))))
    if above:
        poses.update(node_poses(above, *(list(column) for column in zip(*(trs[n] for n in above))))[0])
    return poses, block


def _channels(doc: GltfDocument, index: int, needed: set[int]) -> tuple[dict[tuple[int, str], Sampler], list[str]]:
    """The animation's samplers of the skeleton's nodes, by (node, path), and notes on the
    channels left out."""
    spec = doc.item("animations", index, "--animation")
    channels, sampler_specs = spec.get("channels"), spec.get("samplers")
    if not isinstance(channels, list) or not isinstance(sampler_specs, list):
        raise doc.error(f"animation {index}: 'channels' and 'samplers' must be arrays")
    out: dict[tuple[int, str], Sampler] = {}
    outside, other_paths = 0, set()
    ordered: set[int] = set()  # the key times found in order (samplers share them)
    for c, channel in enumerate(channels):
        at = f"animation {index} channel {c}"
        target = channel.get("target") if isinstance(channel, dict) else None
        if not isinstance(target, dict):
            raise doc.error(f"{at}: needs a 'target'")
        node, path = target.get("node"), target.get("path")
        if not isinstance(path, str) or path not in PATHS:
            other_paths.add(str(path))
            continue
        if node is None:
            continue
        doc.item("nodes", node, at)
        if node not in needed:
            outside += 1
            continue
        s = channel.get("sampler")
        if not isinstance(s, int) or isinstance(s, bool) or not 0 <= s < len(sampler_specs):
            raise doc.error(f"{at}: sampler {s!r} out of range (the animation has {len(sampler_specs)})")
        out[node, path] = _sampler(doc, sampler_specs[s], PATHS[path], f"{at} sampler {s}", ordered)
    notes = []
    if outside:
        notes.append(f"{outside} channels of nodes outside the skeleton (meshes, cameras) left out")
    if other_paths:
        notes.append(f"channels of {', '.join(sorted(other_paths))} (not a joint's transform) left out")
    return out, notes


def _sampler(doc: GltfDocument, spec: object, width: int, at: str, ordered: set[int]) -> Sampler:
    """The sampler of ``spec``; ``ordered``: the ids of the key-time arrays (one per
    accessor: :meth:`GltfDocument.key_times`) already found in order, which it adds to."""
    if not isinstance(spec, dict):
        raise doc.error(f"{at}: must be an object")
    interpolation = spec.get("interpolation", "LINEAR")
    if interpolation not in INTERPOLATIONS:
        raise doc.error(f"{at}: interpolation {interpolation!r} is not one of {', '.join(INTERPOLATIONS)}")
    times = doc.key_times(spec.get("input"), f"{at} input")
    values = doc.key_values(spec.get("output"), f"{at} output")
    if id(times) not in ordered:
        if (np.diff(times) < 0).any():
            raise doc.error(f"{at}: key times must not decrease (key {int(np.argmax(np.diff(times) < 0)) + 1})")
        ordered.add(id(times))
    expected = times.size * (3 if interpolation == "CUBICSPLINE" else 1)
    if values.shape != (expected, width):
        raise doc.error(
            f"{at}: {times.size} {interpolation} keys need {expected} outputs of {width} components, "
            f"not {values.shape[0]} of {values.shape[1]}"
        )
    if width == 4:  # rotations: every key a quaternion that has a direction
        keys = values.reshape(times.size, 3, 4)[:, 1] if interpolation == "CUBICSPLINE" else values
        short = _short_quaternions(keys)
        if short.size:
            k = int(short[0])
            raise doc.error(f"{at}: rotation key {k} is not a quaternion (length {np.linalg.norm(keys[k]):.3g})")
    return Sampler(times, values, interpolation)


def _short_quaternions(keys: np.ndarray) -> np.ndarray:
    """Indices (in order) of the quaternions (K, 4) shorter than
    :data:`MIN_QUATERNION_LENGTH`, their lengths taken in float64. Only a quaternion whose
    every component is that small can be one, so only those are measured: one cheap
    comparison a component, in the keys' own type, for the rest."""
    limit = keys.dtype.type(MIN_QUATERNION_LENGTH)
    if limit < MIN_QUATERNION_LENGTH:  # rounded down to the keys' type: the next one up, so none is missed
        limit = np.nextafter(limit, keys.dtype.type(np.inf))
    small = np.abs(keys[:, 0]) < limit
    for component in range(1, 4):
        small &= np.abs(keys[:, component]) < limit
    candidates = np.flatnonzero(small)
    near = keys[candidates].astype(np.float64)
    return candidates[np.einsum("kq,kq->k", near, near) < MIN_QUATERNION_LENGTH**2]


def _joint_names(doc: GltfDocument, joints: list[int]) -> tuple[list[str], list[str]]:
    nodes = doc.items("nodes")
    return valid_joint_names([nodes[node].get("name") for node in joints], joints)


def valid_joint_names(raw: list[object], keys: list[int]) -> tuple[list[str], list[str]]:
    """Node names (``raw``, one per joint) made valid joint names (spaces collapsed, braces
    and control characters replaced, ``node<key>`` for none, ``_<key>`` added to repeats),
    and a note on the changes; ``keys`` are the nodes' indices in their file."""
    names, taken, changed = [], set(), 0
    for name, node in zip(raw, keys):
        text = " ".join(str(name).split()) if isinstance(name, str) else ""
        text = "".join(ch if ch.isprintable() and ch not in "{}" else "_" for ch in text) or f"node{node}"
        if text in taken:
            text = f"{text}_{node}"
        changed += text != name
        taken.add(text)
        names.append(text)
    return names, ([f"{changed} node names made valid joint names (unnamed: node<index>)"] if changed else [])


def _no_skin_note(doc: GltfDocument) -> str:
    if vrm_humanoid_nodes(doc):
        return "VRM animation: its humanoid bones are the joints (expression and lookAt nodes left out)"
    return "no skin: every node is a joint"


def _extras(doc: GltfDocument) -> dict:
    extras = doc.json["asset"].get("extras")
    return extras if isinstance(extras, dict) else {}


def bind_note(bind: np.ndarray, from_pose: int, source: str = "the skin's bind pose") -> str:
    """The note on the rest orientation taken out of the joints' frames (``bind`` (J, 3, 3),
    from ``source``), empty when none was."""
    angles = np.degrees(rotation_angle(bind))
    if not from_pose or angles.max() < 1e-6:
        return ""
    return (
        f"rest pose: {source}; the rest orientation of its joints (up to {angles.max():.4g} deg, "
        f"{int((angles > 1e-6).sum())} joints) taken out of their frames"
    )


def _source_unit(doc: GltfDocument) -> Unit | None:
    """The unit of the motion a glTF written by this project came from (its metres per unit
    in ``asset.extras``; metres: None), else None."""
    extras = _extras(doc)
    factor = extras.get("metres_per_unit")
    if not isinstance(factor, (int, float)) or isinstance(factor, bool) or not np.isfinite(factor) or factor <= 0:
        return None
    name = extras.get("source_unit")
    unit = unit_of_length(float(factor), name if isinstance(name, str) and name else None)
    return None if unit.name == "m" else unit


def _node_label(doc: GltfDocument, node: int) -> str:
    name = doc.items("nodes")[node].get("name")
    return f"'{name}'" if isinstance(name, str) and name else f"node {node}"


def _armature_notes(doc: GltfDocument, above: list[int], joints, parents, index) -> list[str]:
    if not above:
        return []
    roots = [doc.items("nodes")[n].get("name", f"node {n}") for n in joints if int(parents[n]) not in index]
    return [
        f"armature: the transform of {', '.join(_node_label(doc, n) for n in above)} above the skeleton "
        f"applied to its roots ({', '.join(map(str, roots))})"
    ]


def _scale_notes(doc: GltfDocument, poses: dict[int, NodePose], needed: set[int]) -> list[str]:
    return scale_notes({node: _node_label(doc, node) for node in needed}, poses)


def scale_notes(labels: dict[int, str], poses: dict[int, NodePose]) -> list[str]:
    """Notes naming every node (``labels``: node -> how to name it) whose scale is not one:
    folded (uniform), animated, or not uniform (which neither BVH nor GMR carries)."""
    folded, animated, skewed = [], [], []
    for node in sorted(labels):
        scale = poses[node].scale
        label = labels[node]
        size = np.abs(scale)
        widest = np.maximum(np.maximum(size[:, 0], size[:, 1]), size[:, 2])  # per frame (elementwise: fast)
        narrowest = np.minimum(np.minimum(size[:, 0], size[:, 1]), size[:, 2])
        ratio = float((widest / np.maximum(narrowest, 1e-300)).max())
        if ratio > 1 + SCALE_NOTE_TOLERANCE or (scale <= 0).any():
            skewed.append(f"{label} (axes up to {ratio:.6g}:1{', mirrored' if (scale < 0).any() else ''})")
        elif np.ptp(scale[:, 0]) > SCALE_NOTE_TOLERANCE * abs(scale[0, 0]):
            animated.append(f"{label} ({scale[:, 0].min():.6g} to {scale[:, 0].max():.6g})")
        elif abs(scale[0, 0] - 1) > SCALE_NOTE_TOLERANCE:
            folded.append(f"{label} ({scale[0, 0]:.6g})")
    notes = []
    if folded:
        notes.append(f"uniform scale folded into the offsets: {', '.join(folded)}")
    if animated:
        notes.append(f"animated uniform scale folded into per-frame translations: {', '.join(animated)}")
    if skewed:
        notes.append(
            f"WARNING non-uniform scale, which BVH and GMR cannot carry, on {', '.join(skewed)}: joint positions "
            "are kept exactly; the rotations below it leave the scaling out"
        )
    return notes
