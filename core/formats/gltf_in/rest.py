"""The rest pose of a glTF skeleton, and motions this project exported in pre-rotation.

**Bind pose as rest pose.** A motion's rest pose has every rotation the identity; a glTF
skeleton's rest is its bind pose, given by the skin's inverse bind matrices (the joint's
world transform at bind is their inverse). Tools that build bones along the limbs
(Blender's armatures) give each joint a rest orientation there, so its world rotation is
the motion's times that orientation: ``W_gltf = W B``. :func:`turn_to_bind` takes it out,
``W = W_gltf B^T``: local rotations become ``B_p R B_j^T`` and translations ``B_p t``
(positions unchanged). Joints without an inverse bind matrix (nodes between two joints,
every node of a file without skin) keep their frames, as the specification's identity
default for a missing matrix says.

**Pre-rotation exports.** This project writes a GMR motion's joint ``j`` as a node with
``[R_j, R_j t_j]`` and says ``"convention": "pre"`` in ``asset.extras``;
:func:`pre_from_export` reads it back as pre-rotation: ``t_j = R_j^T t'_j``, static where it
varies by float32 rounding only (below :data:`STATIC_FLOAT32`, relative).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.formats.gltf_in.container import GltfDocument
from gmr_studio.core.rotations.blocks import sandwiched, turned_vectors
from gmr_studio.core.rotations.euler import nearest_rotation

#: a translation of a pre-rotation export varying less than this (relative to its length)
#: over the frames is float32 rounding of a static offset
STATIC_FLOAT32 = 1e-6


def bind_rotations(doc: GltfDocument, skin: int | None, joints: list[int]) -> tuple[np.ndarray, int]:
    """Each joint's rest orientation (J, 3, 3): from the skin's inverse bind matrices, else
    the identity; and how many came from the skin."""
    bind = np.broadcast_to(np.eye(3), (len(joints), 3, 3)).copy()
    if skin is None:
        return bind, 0
    spec = doc.item("skins", skin, "--skin")
    if spec.get("inverseBindMatrices") is None:
        return bind, 0
    matrices = doc.accessor(spec["inverseBindMatrices"], f"skin {skin} inverseBindMatrices")
    listed = spec["joints"]
    if matrices.shape != (len(listed), 16):
        raise doc.error(f"skin {skin}: {len(listed)} joints need as many MAT4 inverse bind matrices")
    linear = matrices.reshape(-1, 4, 4).transpose(0, 2, 1)[:, :3, :3]  # column-major
    index = {node: j for j, node in enumerate(joints)}
    rows = [(index[node], k) for k, node in enumerate(listed) if node in index]
    ours, theirs = (np.array(side, dtype=np.int64) for side in zip(*rows))
    bind[ours] = np.swapaxes(nearest_rotation(linear[theirs]), -1, -2)  # the inverse's rotation
    return bind, len(rows)


def bind_turns(bind: np.ndarray, parents: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(``B_p`` (J, 3, 3), the parent's rest orientation or the identity for a root;
    ``B_j^T`` (J, 3, 3)): what each joint's rotation is turned by on the left and the right
    (and its translation on the left) to take the rest orientations ``bind`` (J, 3, 3) out;
    None when they are all the identity (to 1e-12)."""
    if np.abs(bind - np.eye(3)).max(initial=0.0) <= 1e-12:
        return None
    above = np.where((parents >= 0)[:, None, None], bind[np.maximum(parents, 0)], np.eye(3))
    return above, np.swapaxes(bind, -1, -2)


def turn_to_bind(
    bind: np.ndarray,
    parents: np.ndarray,
    rotations: np.ndarray,
    translations: np.ndarray,
    offsets: np.ndarray,
    moving: np.ndarray,
    *,
    overwrite: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local rotations (F, J, 3, 3), translations (F, J, 3) and offsets (J, 3) with the
    joints' rest orientations ``bind`` (J, 3, 3) taken out (module docstring); the joints
    not ``moving`` (J,) keep their translations equal to their offsets. Unchanged when every
    orientation is the identity (to 1e-12, as this project's exports bind). ``overwrite``:
    the rotations and translations given are the caller's own and may be written over."""
    turns = bind_turns(bind, parents)
    if turns is None:
        return rotations, translations, offsets
    above, below = turns
    turned = sandwiched(above, rotations, below, overwrite=overwrite)
    offsets = (above @ offsets[..., None])[..., 0]
    translations = turned_vectors(above, translations, overwrite=overwrite)
    translations[:, ~moving] = offsets[~moving]
    return turned, translations, offsets


def pre_from_export(
    rotations: np.ndarray, translations: np.ndarray, offsets: np.ndarray, parents: np.ndarray, moving: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pre-rotation translations (F, J, 3), offsets (J, 3) and moving (J,) of a motion this
    project exported from GMR and that was read as post-rotation (module docstring)."""
    children = parents >= 0
    local = (np.swapaxes(rotations, -1, -2) @ translations[..., None])[..., 0]  # R^T t', every joint
    local[:, ~children] = translations[:, ~children]
    mean = local.mean(axis=0)
    spread = np.abs(local - mean).max(axis=(0, 2), initial=0.0)
    static = children & (spread <= STATIC_FLOAT32 * np.maximum(np.abs(local).max(axis=(0, 2), initial=0.0), 1e-300))
    moving = moving & ~children | children & ~static
    offsets = np.where(children[:, None], np.where(static[:, None], mean, local[0] if len(local) else offsets), offsets)
    local[:, static] = offsets[static]
    return local, offsets, moving
