"""glTF 2.0 export (``.glb`` binary or ``.gltf`` with the buffer embedded): the skeleton as
a node hierarchy with one animation, written through pygltflib.

- Nodes: one per joint, named as the joint, under one scene root node (``World``, or a
  numbered variant if a joint has that name); each tree of the forest (split roots
  included) is a child of it. Joint ``j`` is node ``j``.
- Animation ``motion``: for every joint a translation and a rotation channel (LINEAR,
  float32, quaternions ``x, y, z, w``) sampled at the frame times ``f * frame_time``. A
  node's local transform is the joint's: ``[R_j, R_j t_j]`` in GMR's pre-rotation
  convention, ``[R_j, t_j]`` in post-rotation (BVH), ``[R_r, t_r]`` for a root, so glTF's
  node composition gives FK's world transforms. The nodes' static TRS is frame 0.
- Units: glTF lengths are metres. ``metres_per_unit`` scales every length; by default it
  is the unit the motion's comments state (``units: m``: a glTF read back), else inferred
  from the skeleton's size (:func:`infer_metres_per_unit`). The factor used and
  the up-axis conversion are stated in ``asset.extras``, with the motion's convention
  (``"pre"`` or ``"post"``: which frame a node's rotation is, for reading it back).
- Up axis: glTF is Y-up. A motion whose comments say ``up axis: z`` is turned with
  :func:`core.conversions.change_up_axis` (``(x, y, z) -> (x, z, -y)``).
- ``skin=True`` adds a mesh of one capsule per bone, rigidly skinned to the joints
  (:mod:`core.formats.gltf_mesh`), for viewers that show only meshes.

Every world position of the written file at frame ``f`` is ``s Q P_j(f)`` with ``s`` the
scale, ``Q`` the up-axis rotation and ``P`` the project's FK (to float32 precision).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pygltflib as gl

from gmr_studio.core.atomic import atomic_write_bytes, atomic_write_text
from gmr_studio.core.conversions import change_up_axis, scale_lengths, up_axis_of
from gmr_studio.core.motion import Motion

#: name of the node above every tree (numbered if a joint has it already)
SCENE_ROOT = "World"
#: lengths of the units motion files use, in metres, for :func:`infer_metres_per_unit`
KNOWN_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "CMU (in / 0.45)": 0.0254 / 0.45}
#: the skeleton size (metres) the inference aims at: a standing adult
TYPICAL_SIZE_METRES = 1.7

_FLOAT = gl.FLOAT
_ARRAY_BUFFER = gl.ARRAY_BUFFER


@dataclasses.dataclass(frozen=True)
class GltfExport:
    """What :func:`export_gltf` wrote: the file, the scale, the up conversion, the counts."""

    path: str
    metres_per_unit: float
    unit_note: str
    up_note: str
    n_nodes: int
    n_frames: int
    skinned: bool


def infer_metres_per_unit(motion: Motion) -> tuple[float, str]:
    """(metres per unit, why): the known unit (:data:`KNOWN_UNITS`) that makes the skeleton's
    size closest, in ratio, to :data:`TYPICAL_SIZE_METRES`."""
    size = motion.size
    name, factor = min(KNOWN_UNITS.items(), key=lambda item: abs(np.log(size * item[1] / TYPICAL_SIZE_METRES)))
    return factor, f"lengths taken as {name} (size {size:.4g} units = {size * factor:.3g} m), times {factor:.6g}"


def quaternions_from_matrices(matrices: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(x, y, z, w)`` of rotation matrices: (..., 3, 3) -> (..., 4).

    Shepperd's method (the largest of the four squared components is computed directly),
    vectorised; ``w >= 0``.
    """
    m = np.asarray(matrices, dtype=np.float64)
    m00, m11, m22 = m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]
    trace = m00 + m11 + m22
    # squared components times 4: w, x, y, z
    candidates = np.stack([1 + trace, 1 + m00 - m11 - m22, 1 - m00 + m11 - m22, 1 - m00 - m11 + m22], axis=-1)
    best = np.argmax(candidates, axis=-1)
    big = 2.0 * np.sqrt(np.take_along_axis(candidates, best[..., None], -1)[..., 0])  # at least 1: they sum to 4
    zy, yz = m[..., 2, 1], m[..., 1, 2]
    xz, zx = m[..., 0, 2], m[..., 2, 0]
    yx, xy = m[..., 1, 0], m[..., 0, 1]
    options = np.stack(
        [
            np.stack([(zy - yz) / big, (xz - zx) / big, (yx - xy) / big, big / 4], -1),
            np.stack([big / 4, (xy + yx) / big, (xz + zx) / big, (zy - yz) / big], -1),
            np.stack([(xy + yx) / big, big / 4, (yz + zy) / big, (xz - zx) / big], -1),
            np.stack([(xz + zx) / big, (yz + zy) / big, big / 4, (yx - xy) / big], -1),
        ],
        axis=-2,
    )
    quat = np.take_along_axis(options, best[..., None, None], -2)[..., 0, :]
    quat *= np.where(quat[..., 3:] < 0, -1.0, 1.0)
    return quat / np.linalg.norm(quat, axis=-1, keepdims=True)


def continuous_quaternions(quat: np.ndarray) -> np.ndarray:
    """Flip signs along the frames so consecutive quaternions are in one hemisphere (glTF
    interpolates linearly between them): (F, J, 4) -> (F, J, 4)."""
    flips = np.einsum("fjq,fjq->fj", quat[1:], quat[:-1]) < 0
    sign = np.ones(quat.shape[:2])
    sign[1:] = np.where(np.cumsum(flips, axis=0) % 2 == 1, -1.0, 1.0)
    return quat * sign[..., None]


def local_transforms(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """Node translations (F, J, 3) and rotations (F, J, 4, quaternion ``x, y, z, w``) whose
    glTF composition (parent world times ``T(t) R(q)``) is the motion's FK."""
    if motion.convention == "pre":
        translations = np.einsum("fjab,fjb->fja", motion.rotations, motion.translations)
        roots = motion.roots
        translations[:, roots] = motion.translations[:, roots]
    else:
        translations = np.array(motion.translations)
    return translations, continuous_quaternions(quaternions_from_matrices(motion.rotations))


class BufferBuilder:
    """Accumulates accessors over one binary buffer (one buffer view per accessor)."""

    def __init__(self, gltf: gl.GLTF2) -> None:
        self.gltf = gltf
        self.chunks: list[bytes] = []
        self.length = 0

    def add(self, data: np.ndarray, kind: str, *, target: int | None = None, bounds: bool = False) -> int:
        """Append ``data`` (rows of ``kind``: SCALAR, VEC3, VEC4, MAT4; uint16 and uint32 stay
        integers, anything else is written as float32) and return its accessor's index."""
        integer = {np.dtype(np.uint16): gl.UNSIGNED_SHORT, np.dtype(np.uint32): gl.UNSIGNED_INT}
        component = integer.get(data.dtype, _FLOAT)
        data = np.ascontiguousarray(data, dtype=data.dtype if component != _FLOAT else np.float32)
        blob = data.tobytes()
        self.gltf.bufferViews.append(
            gl.BufferView(buffer=0, byteOffset=self.length, byteLength=len(blob), target=target)
        )
        rows = data.reshape(data.shape[0], -1)
        accessor = gl.Accessor(
            bufferView=len(self.gltf.bufferViews) - 1,
            componentType=component,
            count=data.shape[0],
            type=kind,
            min=rows.min(axis=0).tolist() if bounds else None,
            max=rows.max(axis=0).tolist() if bounds else None,
        )
        self.gltf.accessors.append(accessor)
        padded = blob + b"\0" * (-len(blob) % 4)
        self.chunks.append(padded)
        self.length += len(padded)
        return len(self.gltf.accessors) - 1

    def finish(self) -> bytes:
        blob = b"".join(self.chunks)
        self.gltf.buffers = [gl.Buffer(byteLength=len(blob))]
        return blob


def _unique_name(base: str, taken: set[str]) -> str:
    name, n = base, 2
    while name in taken:
        name, n = f"{base}{n}", n + 1
    return name


def _stated_units(motion: Motion) -> tuple[str, float] | None:
    """The length unit the motion's comments state (``units: m``, as the glTF reader
    writes) and its metres, else None (then the unit is inferred)."""
    from gmr_studio.core.compare.tracks import UNIT_SCALE, units_of

    unit = units_of(motion)
    return (unit, UNIT_SCALE[unit]) if unit else None


def prepared_for_gltf(motion: Motion, metres_per_unit: float | None = None) -> tuple[Motion, float, str, str]:
    """The motion turned Y-up and scaled to metres, with the factor and notes on both."""
    source_up = up_axis_of(motion)
    up_note = "Y up as in the source" if source_up == "y" else "turned from Z up to Y up: (x, y, z) -> (x, z, -y)"
    turned = change_up_axis(motion, "y", source_up)
    stated = _stated_units(motion)
    if metres_per_unit is None and stated is not None:
        metres_per_unit = stated[1]
        unit_note = f"lengths in {stated[0]} as the motion states, times {metres_per_unit:.6g}"
    elif metres_per_unit is None:
        metres_per_unit, unit_note = infer_metres_per_unit(turned)
    else:
        unit_note = f"lengths times {metres_per_unit:.6g} (metres per unit, given)"
    if not np.isfinite(metres_per_unit) or metres_per_unit <= 0:
        raise ValueError(f"metres per unit must be a positive number, not {metres_per_unit}")
    return scale_lengths(turned, metres_per_unit), float(metres_per_unit), unit_note, up_note


def build_gltf(
    motion: Motion, *, skin: bool = True, metres_per_unit: float | None = None
) -> tuple[gl.GLTF2, bytes, GltfExport]:
    """The glTF document, its binary buffer and a summary (path left empty)."""
    from gmr_studio.core.formats.gltf_mesh import add_capsule_skin

    scene_motion, factor, unit_note, up_note = prepared_for_gltf(motion, metres_per_unit)
    translations, rotations = local_transforms(scene_motion)
    n_frames, n_joints = scene_motion.n_frames, scene_motion.n_joints
    gltf = gl.GLTF2(
        asset=gl.Asset(
            generator="GMR Studio",
            version="2.0",
            extras={
                "metres_per_unit": factor,
                "units": unit_note,
                "up_axis": up_note,
                "convention": scene_motion.convention,
            },
        )
    )
    buffers = BufferBuilder(gltf)
    for j, name in enumerate(scene_motion.names):
        node = gl.Node(name=name, children=list(scene_motion.children[j]) or [])
        if n_frames:
            node.translation = translations[0, j].tolist()
            node.rotation = rotations[0, j].tolist()
        gltf.nodes.append(node)
    root_name = _unique_name(SCENE_ROOT, set(scene_motion.names))
    gltf.nodes.append(gl.Node(name=root_name, children=[int(r) for r in scene_motion.roots]))
    scene_nodes = [n_joints]
    if n_frames:
        times = buffers.add(np.arange(n_frames) * scene_motion.frame_time, gl.SCALAR, bounds=True)
        samplers, channels = [], []
        for j in range(n_joints):
            for path, values, kind in (
                ("translation", translations[:, j], gl.VEC3),
                ("rotation", rotations[:, j], gl.VEC4),
            ):
                samplers.append(
                    gl.AnimationSampler(input=times, output=buffers.add(values, kind), interpolation="LINEAR")
                )
                channels.append(
                    gl.AnimationChannel(sampler=len(samplers) - 1, target=gl.AnimationChannelTarget(node=j, path=path))
                )
        gltf.animations.append(gl.Animation(name="motion", samplers=samplers, channels=channels))
    mesh_node = add_capsule_skin(gltf, buffers, scene_motion, skeleton_root=n_joints) if skin and n_frames else None
    if mesh_node is not None:
        scene_nodes.append(mesh_node)
    gltf.scenes.append(gl.Scene(name="motion", nodes=scene_nodes))
    gltf.scene = 0
    blob = buffers.finish()
    summary = GltfExport("", factor, unit_note, up_note, len(gltf.nodes), n_frames, mesh_node is not None)
    return gltf, blob, summary


def export_gltf(
    motion: Motion, path: str | Path, *, skin: bool = True, metres_per_unit: float | None = None
) -> GltfExport:
    """Write ``motion`` (either convention) as glTF 2.0, atomically: ``.glb`` binary, or
    ``.gltf`` JSON with the buffer embedded as a data URI. See the module docstring."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".glb", ".gltf"):
        raise ValueError(f"a glTF file ends in .glb or .gltf, not {path.suffix!r}")
    gltf, blob, summary = build_gltf(motion, skin=skin, metres_per_unit=metres_per_unit)
    gltf.set_binary_blob(blob)
    if suffix == ".glb":
        atomic_write_bytes(path, b"".join(gltf.save_to_bytes()))
    else:
        gltf.convert_buffers(gl.BufferFormat.DATAURI)
        atomic_write_text(path, gltf.gltf_to_json())
    return dataclasses.replace(summary, path=str(path))
