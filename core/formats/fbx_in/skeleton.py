"""From the FBX nodes' local transforms to a post-rotation motion, and the file's facts.

:func:`motion_from_nodes` takes what :mod:`.worker` evaluated (each node's translation,
rotation matrix and scale per frame: FBX's whole transform stack composed into one
``T R S``) and builds the motion exactly as the glTF reader builds one from node ``T R S``
(:mod:`core.formats.gltf_in.pose`): a joint's rotation is its node's, its translation the
node's carried through the scales above, the nodes above the skeleton (the armature)
applied to the roots, uniform scale folded into the lengths and non-uniform scale named in
a warning note. Every joint's position is ufbx's to rounding.

:func:`file_facts` is the one place where the file's units and axes become the motion's.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.formats.fbx_in.worker import EULER_ORDERS
from gmr_studio.core.formats.gltf_in.pose import NodePose, skeleton_pose
from gmr_studio.core.formats.gltf_in.reader import scale_notes, valid_joint_names
from gmr_studio.core.motion import Motion

#: the length units ``units:`` comments name, in metres (core/compare/tracks.py reads them)
NAMED_UNITS = {"mm": 0.001, "cm": 0.01, "m": 1.0, "in": 0.0254, "ft": 0.3048}
#: a file's metres per unit within this (relative) of a named unit is that unit
UNIT_TOLERANCE = 1e-6
#: ufbx coordinate axis codes (``ufbx.CoordinateAxis``) -> names
AXES = {0: "+x", 1: "-x", 2: "+y", 3: "-y", 4: "+z", 5: "-z", 6: "unknown"}


def file_facts(unit_meters: float, axes: list[int]) -> tuple[float, list[str]]:
    """(factor the lengths are multiplied by, comment lines) for a file whose unit is
    ``unit_meters`` metres and whose axes are ``axes`` (right, up, front as ufbx codes).

    A named unit is kept (``units: cm``); any other is converted to metres. The up axis is
    the file's when it is +Y or +Z (``up axis: y|z``); another is named in a note and the
    motion is left as the file has it (read as Y up).
    """
    lines = []
    factor = 1.0
    name = next(
        (n for n, m in NAMED_UNITS.items() if abs(unit_meters - m) <= UNIT_TOLERANCE * m),
        None,
    )
    if name is None:
        if np.isfinite(unit_meters) and unit_meters > 0:
            factor, name = float(unit_meters), "m"
            lines.append(f"lengths converted to metres from the file's unit of {unit_meters:.9g} m")
        else:
            name = "cm"
            lines.append(f"the file's unit ({unit_meters}) is not a length: read as cm, FBX's default")
    lines.insert(0, f"units: {name}")
    right, up, front = (AXES.get(int(a), "unknown") for a in axes)
    if up in ("+y", "+z"):
        lines.append(f"up axis: {up[1]}")
    else:
        lines.append(f"WARNING the file's up axis is {up}: read as it is, as if Y were up")
    lines.append(f"axes: right {right}, up {up}, front {front} (the file's)")
    return factor, lines


def motion_from_nodes(meta: dict, trs: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]) -> Motion:
    """The motion of the worker's output: ``meta`` (its JSON) and per node index its
    translation (F|1, 3), rotation (F|1, 3, 3) and scale (F|1, 3)."""
    joints, above = list(meta["joints"]), list(meta["above"])
    parents = np.asarray(meta["parents"], dtype=np.int64)
    n_frames = int(meta["frames"])
    frames = max(len(trs[node][1]) for node in joints)
    block = np.empty((frames, len(joints), 3, 3))
    for k, node in enumerate(joints):
        block[:, k] = trs[node][1]
    poses = {node: NodePose(trs[node][0], block[:, k], trs[node][2]) for k, node in enumerate(joints)}
    poses.update({node: NodePose(*trs[node]) for node in above})
    rotations, translations, moving = skeleton_pose(poses, parents, joints, n_frames, block)
    offsets = translations[0].copy()
    index = {node: j for j, node in enumerate(joints)}
    motion_parents = np.array([index.get(int(parents[node]), -1) for node in joints], dtype=np.int64)
    names, renamed = valid_joint_names([meta["names"][node] for node in joints], joints)
    factor, facts = file_facts(meta["unit_meters"], meta["axes"])
    labels = {node: repr(meta["names"][node]) for node in joints + above}
    motion = Motion(
        names=names,
        parents=motion_parents,
        offsets=offsets * factor,
        rotation_orders=tuple(EULER_ORDERS.get(meta["orders"][node], "ZYX") for node in joints),
        has_translation=moving,
        rotations=rotations,
        translations=translations * factor if factor != 1.0 else translations,
        frame_time=1.0 / meta["frame_rate"],
        convention="post",
        comments=tuple(
            line
            for line in [
                content_line(meta),
                *facts,
                take_line(meta),
                f"skeleton: {meta['selection']}",
                *armature_lines(meta, above, joints, parents, index),
                *left_out_lines(meta),
                *inherit_lines(meta, joints, poses),
                *scale_notes(labels, poses),
                *renamed,
            ]
            if line
        ),
    )
    return motion


def content_line(meta: dict) -> str:
    kind = "ASCII" if meta["ascii"] else "binary"
    creator = f", written by {meta['creator']}" if meta.get("creator") else ""
    return f"FBX {meta['version']} {kind}{creator}"


def take_line(meta: dict) -> str:
    stacks = meta["stacks"]
    if meta["take"] is None:
        return "no animation stack (take): the nodes' pose, one frame"
    stack = stacks[meta["take"]]
    others = f" of {len(stacks)} (--animation to choose)" if len(stacks) > 1 else ""
    layers = stack["layers"]
    blended = f", {len(layers)} layers blended" if len(layers) > 1 else ""
    return (
        f"take {meta['take']} '{stack['name']}'{others}: {stack['begin']:.6g} to {stack['end']:.6g} s at the "
        f"file's {meta['frame_rate']:.8g} Hz, {meta['frames']} frames{blended}"
    )


def armature_lines(meta: dict, above: list[int], joints: list[int], parents: np.ndarray, index: dict) -> list[str]:
    if not above:
        return []
    roots = [meta["names"][n] for n in joints if int(parents[n]) not in index]
    return [
        f"armature: the transform of {', '.join(repr(meta['names'][n]) for n in above)} above the skeleton "
        f"applied to its roots ({', '.join(roots)})"
    ]


def left_out_lines(meta: dict) -> list[str]:
    """What the file holds that is not the skeleton's motion."""
    parts = [counted(meta[key], key) for key in ("meshes", "cameras", "lights") if meta[key]]
    return [f"left out: {', '.join(parts)} (their nodes' transforms only are read)"] if parts else []


def counted(count: int, plural: str) -> str:
    """``1 mesh``, ``2 meshes``, ``1 camera``..."""
    single = plural[:-2] if plural.endswith("shes") else plural[:-1]
    return f"{count} {plural if count != 1 else single}"


def inherit_lines(meta: dict, joints: list[int], poses: dict[int, NodePose]) -> list[str]:
    """A warning for joints that inherit their parent's scale in FBX's other ways, where
    the parent's scale is not one (positions below differ from FBX's then)."""
    parents = meta["parents"]
    odd = [
        meta["names"][n]
        for n in joints
        if meta["inherit"][n] != 0
        and parents[n] >= 0
        and parents[n] in poses
        and np.abs(poses[parents[n]].scale - 1).max() > 1e-9
    ]
    if not odd:
        return []
    return [f"WARNING {', '.join(odd)} ignore their parent's scale in FBX; read as if they inherited it"]
