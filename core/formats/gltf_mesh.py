"""A skinned mesh of bone capsules for glTF export, so that viewers that show only meshes
show the skeleton.

One capsule per bone (a joint with a parent, at a distance above 1e-6 of the size), each
vertex weighted 1 to the node that carries the bone rigidly: in GMR's pre-rotation
convention the bone ending at joint ``j`` turns with ``j`` (its local segment runs from
``-t_j`` to the node's origin), in post-rotation (BVH) it turns with the parent ``p``
(from ``p``'s origin to ``t_j``). The bind pose is the motion's rest pose (every rotation
the identity): vertices are placed with the nodes' rest world transforms, and each inverse
bind matrix is the inverse of that, so a reader that takes the bind pose as the rest pose
(:mod:`core.formats.gltf_in`) gets the motion's own joint frames back.
Capsule radius: 12% of the bone's length, at most 4% of the skeleton's size.
"""

from __future__ import annotations

import numpy as np
import pygltflib as gl

from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion

#: segments around a capsule and rings per hemisphere
AROUND, RINGS = 8, 3
RADIUS_OF_LENGTH, RADIUS_OF_SIZE = 0.12, 0.04


def unit_capsule() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Template capsule along +Z: sphere directions (V, 3), 0/1 per vertex for the bottom or
    top hemisphere (V,), and triangles (T, 3) with outward (counter-clockwise) winding."""
    angles = np.linspace(0, 2 * np.pi, AROUND, endpoint=False)
    latitudes = np.concatenate(
        [np.linspace(-np.pi / 2, 0, RINGS + 1)[1:], np.linspace(0, np.pi / 2, RINGS + 1)[:-1]]
    )  # bottom rings (excluding the pole) up to the equator, then the top's equator to below its pole
    ring_dirs = np.stack(
        [
            np.cos(latitudes)[:, None] * np.cos(angles),
            np.cos(latitudes)[:, None] * np.sin(angles),
            np.broadcast_to(np.sin(latitudes)[:, None], (latitudes.size, AROUND)),
        ],
        axis=-1,
    ).reshape(-1, 3)
    directions = np.concatenate([[[0.0, 0.0, -1.0]], ring_dirs, [[0.0, 0.0, 1.0]]])
    top = np.concatenate([[0], np.repeat([0] * RINGS + [1] * RINGS, AROUND), [1]])
    n_rings = latitudes.size
    faces = []
    first, last = 1, 1 + (n_rings - 1) * AROUND
    for k in range(AROUND):
        nxt = (k + 1) % AROUND
        faces.append([0, first + nxt, first + k])
        faces.append([len(directions) - 1, last + k, last + nxt])
    for ring in range(n_rings - 1):
        a, b = 1 + ring * AROUND, 1 + (ring + 1) * AROUND
        for k in range(AROUND):
            nxt = (k + 1) % AROUND
            faces.append([a + k, a + nxt, b + nxt])
            faces.append([a + k, b + nxt, b + k])
    return directions, top.astype(np.float64), np.asarray(faces, dtype=np.int64)


def _frames_from_z(directions: np.ndarray) -> np.ndarray:
    """Rotations (B, 3, 3) taking +Z to each unit direction (B, 3)."""
    helper = np.where(np.abs(directions[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    x = np.cross(helper, directions)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    y = np.cross(directions, x)
    return np.stack([x, y, directions], axis=-1)


def capsule_bones(motion: Motion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each drawn bone: the node carrying it (B,), and its ends (B, 3) each, in that
    node's local frame."""
    children = np.flatnonzero(motion.parents >= 0)
    offsets = motion.offsets[children]
    long_enough = np.linalg.norm(offsets, axis=1) > 1e-6 * motion.size
    children, offsets = children[long_enough], offsets[long_enough]
    if motion.convention == "pre":
        return children, -offsets, np.zeros_like(offsets)
    return motion.parents[children], np.zeros_like(offsets), offsets


def add_capsule_skin(gltf: gl.GLTF2, buffers, motion: Motion, *, skeleton_root: int) -> int | None:
    """Add the capsule mesh, its skin over nodes ``0..J-1`` and a node holding both to
    ``gltf`` (``buffers``: the exporter's BufferBuilder); return that node's index, or None
    (nothing added) when the skeleton has no bone to draw."""
    nodes, starts, ends = capsule_bones(motion)
    if nodes.size == 0:
        return None
    positions, world = forward_kinematics(motion.rest_pose())
    positions, world = positions[0], world[0]
    directions, top, faces = unit_capsule()
    axis = ends - starts
    length = np.linalg.norm(axis, axis=1)
    radius = np.minimum(RADIUS_OF_LENGTH * length, RADIUS_OF_SIZE * motion.size)
    frames = _frames_from_z(axis / length[:, None])  # (B, 3, 3)
    local_dirs = np.einsum("bij,vj->bvi", frames, directions)  # (B, V, 3)
    local = starts[:, None] + radius[:, None, None] * local_dirs + top[None, :, None] * axis[:, None]
    bind_rot, bind_pos = world[nodes], positions[nodes]
    vertices = np.einsum("bij,bvj->bvi", bind_rot, local) + bind_pos[:, None]
    normals = np.einsum("bij,bvj->bvi", bind_rot, local_dirs)
    n_bones, n_verts = vertices.shape[:2]
    indices = (faces[None] + n_verts * np.arange(n_bones)[:, None, None]).reshape(-1)
    joints = np.zeros((n_bones * n_verts, 4), np.uint16)
    joints[:, 0] = np.repeat(nodes, n_verts)
    weights = np.zeros((n_bones * n_verts, 4))
    weights[:, 0] = 1.0
    inverse_bind = np.zeros((motion.n_joints, 4, 4))
    inverse_bind[:, :3, :3] = np.swapaxes(world, -1, -2)
    inverse_bind[:, :3, 3] = -np.einsum("jba,jb->ja", world, positions)
    inverse_bind[:, 3, 3] = 1.0
    attributes = gl.Attributes(
        POSITION=buffers.add(vertices.reshape(-1, 3), gl.VEC3, target=gl.ARRAY_BUFFER, bounds=True),
        NORMAL=buffers.add(normals.reshape(-1, 3), gl.VEC3, target=gl.ARRAY_BUFFER),
        JOINTS_0=buffers.add(joints, gl.VEC4, target=gl.ARRAY_BUFFER),
        WEIGHTS_0=buffers.add(weights, gl.VEC4, target=gl.ARRAY_BUFFER),
    )
    index_accessor = buffers.add(
        indices.astype(np.uint16 if n_bones * n_verts < 65536 else np.uint32),
        gl.SCALAR,
        target=gl.ELEMENT_ARRAY_BUFFER,
    )
    gltf.materials.append(
        gl.Material(
            name="bone",
            pbrMetallicRoughness=gl.PbrMetallicRoughness(baseColorFactor=[0.8, 0.8, 0.75, 1.0], roughnessFactor=0.7),
            doubleSided=True,
        )
    )
    gltf.meshes.append(
        gl.Mesh(name="bones", primitives=[gl.Primitive(attributes=attributes, indices=index_accessor, material=0)])
    )
    # glTF stores matrices column-major
    matrices = buffers.add(np.swapaxes(inverse_bind, -1, -2).reshape(-1, 16), gl.MAT4)
    gltf.skins.append(
        gl.Skin(
            name="skeleton", joints=list(range(motion.n_joints)), inverseBindMatrices=matrices, skeleton=skeleton_root
        )
    )
    gltf.nodes.append(gl.Node(name="bones", mesh=len(gltf.meshes) - 1, skin=len(gltf.skins) - 1))
    return len(gltf.nodes) - 1
