"""The node tree of a glTF file and which of its nodes make the skeleton.

- :func:`node_parents`: each node's parent, checked (indices in range, one parent each,
  no cycles).
- :func:`static_trs`: each node's own translation, rotation (quaternion ``x, y, z, w``)
  and scale, a ``matrix`` decomposed into them (glTF's ``T R S``, column-major); a matrix
  that shears (or collapses an axis) is no ``T R S`` and is refused, as the specification
  requires node matrices to be decomposable.
- :func:`skeleton_nodes`: the joints (a skin's joints and the nodes between them) in
  depth-first order, and the nodes above them (the armature) whose transform the roots
  take on. Without a skin, a VRM animation's humanoid bones (``.vrma``), else every node
  of the scene, are the joints.
- :func:`choose`: a skin or an animation by name or index.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.formats.gltf_in.container import GltfDocument
from gmr_studio.core.rotations.quaternions import quaternion_from_matrix

#: largest |U^T U - I| of a node matrix's columns scaled to unit length U (float32 files
#: round a rotation times a scale to about 1e-7; a shear of 1e-5 radians is refused)
SHEAR_TOLERANCE = 1e-5


def node_parents(doc: GltfDocument) -> np.ndarray:
    """(N,) int64 parent node of each node, -1 for a top node."""
    nodes = doc.items("nodes")
    parents = np.full(len(nodes), -1, np.int64)
    for index, node in enumerate(nodes):
        children = node.get("children", [])
        if not isinstance(children, list):
            raise doc.error(f"node {index}: 'children' must be an array of node indices")
        for child in children:
            doc.item("nodes", child, f"node {index} children")
            if parents[child] >= 0 or child == index:
                raise doc.error(f"node {child} has two parents ({parents[child]} and {index}) or is its own child")
            parents[child] = index
    for start in range(len(nodes)):
        node, steps = start, 0
        while parents[node] >= 0:
            node, steps = int(parents[node]), steps + 1
            if steps > len(nodes):
                raise doc.error(f"the node tree has a cycle through node {start}")
    return parents


def static_trs(doc: GltfDocument) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each node's translation (N, 3), rotation (N, 4, ``x, y, z, w``) and scale (N, 3)."""
    nodes = doc.items("nodes")
    translation = np.zeros((len(nodes), 3))
    rotation = np.zeros((len(nodes), 4))
    scale = np.ones((len(nodes), 3))
    for index, node in enumerate(nodes):
        where = f"node {index}"
        if "matrix" in node:
            matrix = doc.numbers(node, "matrix", 16, [], where).reshape(4, 4).T  # column-major
            if np.abs(matrix[3] - [0, 0, 0, 1]).max() > 1e-6:
                raise doc.error(f"{where}: its matrix is not an affine transform (last row {matrix[3].tolist()})")
            linear = matrix[:3, :3]
            lengths = np.linalg.norm(linear, axis=0)
            if not (lengths > 0).all():
                raise doc.error(f"{where}: its matrix collapses an axis (scale 0)")
            unit = linear / lengths  # a rotation, or a mirror, for a T R S matrix
            shear = float(np.abs(unit.T @ unit - np.eye(3)).max())
            if not shear <= SHEAR_TOLERANCE:
                raise doc.error(
                    f"{where}: its matrix shears (its columns' cosines differ from the identity's by {shear:.3g}), "
                    "so it is no translation, rotation and scale (T R S), as glTF requires of a node matrix"
                )
            if np.linalg.det(unit) < 0:  # not det(linear): tiny scales underflow it to -0.0
                lengths[0] = -lengths[0]  # a mirror: the TRS the specification asks for has one negative scale
            translation[index] = matrix[:3, 3]
            rotation[index] = np.roll(quaternion_from_matrix(linear / lengths), -1)
            scale[index] = lengths
            continue
        translation[index] = doc.numbers(node, "translation", 3, [0, 0, 0], where)
        quaternion = doc.numbers(node, "rotation", 4, [0, 0, 0, 1], where)
        norm = np.linalg.norm(quaternion)
        rotation[index] = quaternion / norm if norm > 0 else [0, 0, 0, 1]
        scale[index] = doc.numbers(node, "scale", 3, [1, 1, 1], where)
    return translation, rotation, scale


def choose(doc: GltfDocument, key: str, wanted: str | int | None, option: str) -> tuple[int | None, str]:
    """(index, note) of the skin or animation ``wanted`` (a name or an index; None: the
    first); (None, "") when the file has none."""
    items = doc.items(key)
    what = key[:-1]
    if not items:
        if wanted is not None:
            raise doc.error(f"{option} {wanted}: the file has no {key}")
        return None, ""
    names = [str(item.get("name", "")) for item in items]
    if wanted is None:
        index = 0
    elif isinstance(wanted, int) or str(wanted).isdigit():
        index = int(wanted)
        if not 0 <= index < len(items):
            raise doc.error(f"{option} {wanted}: the file has {len(items)} {key} (0..{len(items) - 1})")
    elif str(wanted) in names:
        index = names.index(str(wanted))
    else:
        raise doc.error(f"{option} {wanted!r}: no {what} of that name (the file has {', '.join(map(repr, names))})")
    label = f"{what} {index}" + (f" '{names[index]}'" if names[index] else "")
    others = f" of {len(items)} ({option} to choose)" if len(items) > 1 else ""
    return index, label + others


def scene_roots(doc: GltfDocument, parents: np.ndarray) -> list[int]:
    """The top nodes of the file's scene (``scene``, else the first), or every top node."""
    scenes = doc.items("scenes")
    if not scenes:
        return [int(n) for n in np.flatnonzero(parents < 0)]
    scene = doc.item("scenes", doc.json.get("scene", 0), "scene")
    roots = scene.get("nodes", [])
    if not isinstance(roots, list):
        raise doc.error("scene: 'nodes' must be an array of node indices")
    for node in roots:
        doc.item("nodes", node, "scene nodes")
        if parents[node] >= 0:
            raise doc.error(f"scene: node {node} is listed as a scene root but has a parent")
    return [int(n) for n in roots]


def _depth_first(doc: GltfDocument, tops: list[int]) -> list[int]:
    nodes = doc.items("nodes")
    order: list[int] = []
    stack = list(reversed(tops))
    while stack:
        node = stack.pop()
        order.append(node)
        stack.extend(reversed(nodes[node].get("children", [])))
    return order


def skeleton_nodes(doc: GltfDocument, parents: np.ndarray, skin: int | None) -> tuple[list[int], list[int]]:
    """The joints' node indices (depth-first, parents first) and the nodes above the
    topmost joints (the armature), for a skin; without one, a VRM animation's humanoid
    bones (:func:`vrm_humanoid_nodes`), else the whole scene."""
    if skin is None:
        humanoid = vrm_humanoid_nodes(doc)
        if humanoid:
            return _joints_of(doc, parents, humanoid)
        joints = _depth_first(doc, scene_roots(doc, parents))
        if not joints:
            raise doc.error("the file has no skin and its scene has no nodes")
        return joints, []
    spec = doc.item("skins", skin, "skin")
    listed = spec.get("joints")
    if not isinstance(listed, list) or not listed:
        raise doc.error(f"skin {skin}: 'joints' must be a non-empty array of node indices")
    return _joints_of(doc, parents, listed, f"skin {skin} joints")


def vrm_humanoid_nodes(doc: GltfDocument) -> list[int]:
    """The nodes of a VRM animation's humanoid bones (``.vrma``: the extension
    ``VRMC_vrm_animation``, ``humanoid.humanBones.<bone>.node``), in the file's order; empty
    for other files. Its expression and lookAt nodes are not bones."""
    extension = doc.json.get("extensions", {})
    vrma = extension.get("VRMC_vrm_animation") if isinstance(extension, dict) else None
    humanoid = vrma.get("humanoid") if isinstance(vrma, dict) else None
    bones = humanoid.get("humanBones") if isinstance(humanoid, dict) else None
    if not isinstance(bones, dict):
        return []
    nodes = [bone.get("node") for bone in bones.values() if isinstance(bone, dict)]
    for node in nodes:
        doc.item("nodes", node, "VRMC_vrm_animation humanBones")
    return list(dict.fromkeys(nodes))


def _joints_of(
    doc: GltfDocument, parents: np.ndarray, listed: list, where: str = "VRMC_vrm_animation humanBones"
) -> tuple[list[int], list[int]]:
    """The listed nodes and the nodes between them (depth first), and the nodes above."""
    for node in listed:
        doc.item("nodes", node, where)
    members = set(listed)
    for node in listed:  # the nodes between two joints are joints too
        path, up = [], int(parents[node])
        while up >= 0 and up not in members:
            path.append(up)
            up = int(parents[up])
        if up >= 0:
            members.update(path)
    above = set()
    for node in members:
        up = int(parents[node])
        while up >= 0 and up not in members:
            above.add(up)
            up = int(parents[up])
    tops = [n for n in members if parents[n] < 0 or parents[n] in above]
    order = [n for n in _depth_first(doc, sorted(tops)) if n in members]
    return order, sorted(above)
