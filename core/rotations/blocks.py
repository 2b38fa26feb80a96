"""A motion's rotation block (F, J, 3, 3) times constant matrices per joint, fast.

Changing the joints' frames (``L_j R C_j`` for every frame: the rest orientations a
reader takes out, a turn of the world) with numpy's ``@`` costs one small product per
frame and joint. Written as one linear map of the nine entries per joint,
``vec(L R C) = (L kron C^T) vec(R)``, it becomes a few matrix products per
:data:`CHUNK_FRAMES` frames, each a size the cache holds (one call per joint and chunk,
not per frame), equal to the products to rounding.
"""

from __future__ import annotations

import numpy as np

#: frames multiplied at a time (a few hundred kB per chunk: the temporaries stay in cache)
CHUNK_FRAMES = 256


def sandwiched(left: np.ndarray, block: np.ndarray, right: np.ndarray, *, overwrite: bool = False) -> np.ndarray:
    """``left[j] @ block[f, j] @ right[j]`` (F, J, 3, 3) for a block (F, J, 3, 3) and
    constant matrices ``left`` and ``right`` (J or 1, 3, 3); ``overwrite``: written into
    ``block`` itself when it is a contiguous float64 array (no new memory)."""
    frames, joints = block.shape[:2]
    left, right = (np.broadcast_to(np.asarray(m, dtype=np.float64), (joints, 3, 3)) for m in (left, right))
    maps = np.einsum("jab,jcd->jadbc", left, right).reshape(joints, 9, 9)  # (L R C)_ad = L_ab R_bc C_cd
    flat = np.ascontiguousarray(block, dtype=np.float64).reshape(frames, joints, 9)
    return _mapped(flat, maps, flat if overwrite and _writable(block) else None).reshape(frames, joints, 3, 3)


def turned_vectors(matrices: np.ndarray, vectors: np.ndarray, *, overwrite: bool = False) -> np.ndarray:
    """``matrices[j] @ vectors[f, j]`` (F, J, 3) for vectors (F, J, 3) and constant
    matrices (J or 1, 3, 3); ``overwrite`` as for :func:`sandwiched`."""
    joints = vectors.shape[1]
    matrices = np.broadcast_to(np.asarray(matrices, dtype=np.float64), (joints, 3, 3))
    values = np.ascontiguousarray(vectors, dtype=np.float64)
    return _mapped(values, matrices, values if overwrite and _writable(vectors) else None)


def _writable(array: np.ndarray) -> bool:
    """Whether the contiguous float64 view taken of ``array`` is ``array``'s own memory."""
    return array.dtype == np.float64 and array.flags.c_contiguous and array.flags.writeable


def _mapped(values: np.ndarray, maps: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``maps[j] @ values[f, j]`` (F, J, n) for values (F, J, n) and maps (J, n, n), into
    ``out`` (which may be ``values``: each chunk is read before it is written)."""
    out = np.empty_like(values) if out is None else out
    transposed = np.ascontiguousarray(np.swapaxes(maps, 1, 2))
    for start in range(0, len(values), CHUNK_FRAMES):
        part = slice(start, start + CHUNK_FRAMES)
        np.matmul(values[part].transpose(1, 0, 2), transposed, out=out[part].transpose(1, 0, 2))
    return out
