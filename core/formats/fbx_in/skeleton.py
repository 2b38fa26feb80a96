"""From the FBX nodes' local transforms to a post-rotation motion, and the file's facts.

:func:`motion_from_nodes` takes what :mod:`.worker` sent, each node's translation, rotation
matrix and scale per frame (:mod:`.poses`: FBX's whole transform stack composed into one
``T R S``; :mod:`.compiled_pose` does it all in compiled passes where it can), and builds
the motion exactly as the glTF reader builds one from node ``T R S``
(:mod:`core.formats.gltf_in.pose`): a joint's rotation is its node's, its translation the
node's carried through the scales above, the nodes above the skeleton (the armature)
applied to the roots, uniform scale folded into the lengths and non-uniform scale named in
a warning note. Every joint's position is ufbx's to rounding.

:func:`file_facts` is the one place where the file's units and axes become the motion's.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.compiled import Backend
from gmr_studio.core.edits.world import scale_lengths, turned_world
from gmr_studio.core.formats.fbx_in.compiled_pose import compiled_skeleton
from gmr_studio.core.formats.fbx_in.poses import channel_arrays, node_poses
from gmr_studio.core.formats.gltf_in.pose import NodePose, skeleton_pose
from gmr_studio.core.formats.gltf_in.reader import bind_note, scale_notes, valid_joint_names
from gmr_studio.core.formats.gltf_in.rest import turn_to_bind
from gmr_studio.core.kinematics.fbx_stack import EULER_ORDERS
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import nearest_rotation
from gmr_studio.core.space.units import LIKELY_UNITS, UNITS, unit_of_length

#: ufbx coordinate axis codes (``ufbx.CoordinateAxis``) -> names
AXES = {0: "+x", 1: "-x", 2: "+y", 3: "-y", 4: "+z", 5: "-z", 6: "unknown"}
AXIS_VECTORS = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0), "+z": (0, 0, 1), "-z": (0, 0, -1)}
#: the project's axes (right, up, front) for each up axis: what files are turned to
CANONICAL = {"y": ("+x", "+y", "+z"), "z": ("+x", "+z", "-y")}


def file_facts(unit_meters: float, axes: list[int]) -> tuple[float, np.ndarray, FileFacts, list[str]]:
    """(factor the lengths are multiplied by, (3, 3) turn of the world, the motion's file
    facts, note lines) for a file whose unit is ``unit_meters`` metres and whose axes are
    ``axes`` (right, up, front as ufbx codes).

    A unit of the registry (:mod:`core.space.units`: m, cm, mm, in, ft, CMU's) is kept; the
    lengths of any other are multiplied by the factor, to metres (the facts' unit is the
    file's, which :func:`core.edits.world.scale_lengths` then makes metres). The world is
    turned from the file's axes to the project's (:data:`CANONICAL`: Y up with right +X and
    front +Z, FBX's default; Z up with right +X and front -Y, as 3ds Max and Blender), so that
    an FBX compares with a BVH or GMR without flags; files already so are unchanged.
    """
    lines = []
    factor = 1.0
    if np.isfinite(unit_meters) and unit_meters > 0:
        unit = unit_of_length(float(unit_meters))
        if unit not in LIKELY_UNITS:  # the motion is scaled to metres: this unit times the factor
            factor = float(unit_meters)
            lines.append(f"lengths converted to metres from the file's unit of {unit_meters:.9g} m")
    else:
        unit = UNITS["cm"]
        lines.append(f"the file's unit ({unit_meters}) is not a length: read as cm, FBX's default")
    names = [AXES.get(int(a), "unknown") for a in axes]
    if "unknown" in names or len({n[1] for n in names}) != 3:
        lines.append(f"WARNING the file's axes ({', '.join(names)}) are not three axes: read as Y up")
        return factor, np.eye(3), FileFacts(unit=unit, up_axis="y"), lines
    up = "z" if names[1][1] == "z" else "y"
    file_frame = np.array([AXIS_VECTORS[n] for n in names], dtype=np.float64).T
    turn = np.array([AXIS_VECTORS[n] for n in CANONICAL[up]], dtype=np.float64).T @ file_frame.T
    stated = f"right {names[0]}, up {names[1]}, front {names[2]}"
    if np.array_equal(turn, np.eye(3)):
        lines.append(f"axes: {stated} (the file's)")
    else:
        right, up_axis, front = CANONICAL[up]
        lines.append(f"axes: turned from the file's ({stated}) to right {right}, up {up_axis}, front {front}")
    return factor, turn, FileFacts(unit=unit, up_axis=up), lines


def motion_from_nodes(meta: dict, arrays: dict[str, np.ndarray], *, backend: Backend = "auto") -> Motion:
    """The motion of the worker's output: ``meta`` (its JSON) and the arrays it names; the
    skeleton composed in compiled code or by numpy (``backend``, :mod:`.compiled_pose`)."""
    joints, above = list(meta["joints"]), list(meta["above"])
    parents = np.asarray(meta["parents"], dtype=np.int64)
    n_frames = int(meta["frames"])
    index = {node: j for j, node in enumerate(joints)}
    motion_parents = np.array([index.get(int(parents[node]), -1) for node in joints], dtype=np.int64)
    bind, from_pose = bind_rotations(meta, joints)
    source = meta.get("bind", {}).get("source", "")
    arrays = channel_arrays(meta, arrays)
    composed = compiled_skeleton(meta, arrays, parents, bind, backend)  # the rest orientations taken out
    if composed is not None:
        poses, rotations, translations, moving = composed
        offsets = translations[0].copy()
    else:
        poses, block = node_poses(meta, arrays)
        rotations, translations, moving = skeleton_pose(poses, parents, joints, n_frames, block)
        offsets = translations[0].copy()
        turned = turn_to_bind(bind, motion_parents, rotations, translations, offsets, moving, overwrite=True)  # ours
        rotations, translations, offsets = turned
    names, renamed = valid_joint_names([meta["names"][node] for node in joints], joints)
    factor, turn, facts, notes = file_facts(meta["unit_meters"], meta["axes"])
    labels = {node: repr(meta["names"][node]) for node in joints + above}
    motion = Motion(
        names=names,
        parents=motion_parents,
        offsets=offsets,
        rotation_orders=tuple(EULER_ORDERS.get(meta["orders"][node], "ZYX") for node in joints),
        has_translation=moving,
        rotations=rotations,
        translations=translations,
        frame_time=1.0 / meta["frame_rate"],
        convention="post",
        comments=tuple(
            line
            for line in [
                content_line(meta),
                *notes,
                take_line(meta),
                f"skeleton: {meta['selection']}",
                *armature_lines(meta, above, joints, parents, index),
                bind_note(bind, from_pose, source),
                *left_out_lines(meta),
                *inherit_lines(meta, joints, poses),
                *scale_notes(labels, poses),
                *renamed,
            ]
            if line
        ),
        facts=facts,
    )
    return scale_lengths(turned_world(motion, turn), factor)


def bind_rotations(meta: dict, joints: list[int]) -> tuple[np.ndarray, int]:
    """Each joint's rest orientation (J, 3, 3): its world rotation in the file's bind pose
    (or static pose, :func:`.worker.bind_pose`), else the identity; and how many were
    given. Tools that build bones along the limbs (Blender's armatures, 3ds Max) give each
    joint such an orientation: taking it out (:func:`core.formats.gltf_in.rest.turn_to_bind`,
    as for glTF's skins) makes the joints' rotations the motion's own, as a BVH of the same
    capture has them."""
    bind = np.broadcast_to(np.eye(3), (len(joints), 3, 3)).copy()
    given = meta.get("bind", {}).get("linear", {})
    rows = [(j, np.asarray(given[str(node)], dtype=np.float64)) for j, node in enumerate(joints) if str(node) in given]
    if not rows:
        return bind, 0
    ours = np.array([j for j, _ in rows])
    linear = np.stack([matrix for _, matrix in rows])
    usable = np.abs(np.linalg.det(linear)) > 1e-12
    bind[ours[usable]] = nearest_rotation(linear[usable])
    return bind, int(usable.sum())


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
