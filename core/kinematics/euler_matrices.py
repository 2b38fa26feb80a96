"""Euler angles of every frame to rotation matrices in one compiled pass: the file readers'
conversion (BVH and FBX channels in degrees; AMC bones about their ASF axes).

Each function fills an output the caller allocated, on ``threads`` threads (blocks of
frames, :func:`core.kinematics.engine.in_blocks`; any number gives the same numbers), and
returns False, doing nothing, when the compiled kernels of :mod:`core.kinematics._kernels`
are not to be used; the caller then takes its numpy path
(:func:`core.rotations.euler.matrix_from_euler`), the reference.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.compiled import Backend, chosen_kernels, optional_kernels
from gmr_studio.core.kinematics.engine import euler_codes, in_blocks

_kernels = optional_kernels("gmr_studio.core.kinematics._kernels")


def degrees_to_matrices_compiled(
    values: np.ndarray,
    groups: list[tuple[str, list[int], np.ndarray]],
    out: np.ndarray,
    start: int,
    stop: int,
    *,
    identities: list[int] | tuple[int, ...] = (),
    threads: int | None = 1,
) -> bool:
    """Fill ``out[start:stop, joints]`` (F, J, 3, 3) from Euler angles in degrees, the
    channel columns of each (order, joints, (n, len(order)) columns) group of ``values``
    (F, V), and ``out[start:stop, identities]`` with the identity; the file readers'
    conversion, on ``threads`` threads (None: one per core; the same numbers). Returns
    False (doing nothing) without numba. ``values`` is read in its own memory layout (a
    block of channels (V, F) transposed is not copied).

    The same operations as ``matrix_from_euler(np.radians(...))``; sin and cos come from
    the C library rather than numpy's own, so results may differ in the last bit. One pass
    per frame in compiled code instead of a dozen numpy temporaries: this keeps BVH parsing
    near the speed of reading the numbers alone.
    """
    if _kernels is None:
        return False
    joints, columns, codes = _euler_columns(groups)
    arguments = (
        np.asarray(values, dtype=np.float64),
        joints,
        columns,
        codes,
        np.asarray(identities, dtype=np.int64).reshape(-1),
    )

    def block(frames: slice) -> None:
        _kernels.matrices_from_degrees(*arguments, start + frames.start, start + frames.stop, out)

    if joints.size or len(identities):
        in_blocks(block, stop - start, threads)
    return True


def conjugated_matrices_compiled(
    values: np.ndarray,
    groups: list[tuple[str, list[int], np.ndarray]],
    axes: np.ndarray,
    out: np.ndarray,
    *,
    scale: float,
    identities: list[int] | tuple[int, ...] = (),
    threads: int | None = 1,
    backend: Backend = "auto",
) -> bool:
    """Fill ``out`` (F, J, 3, 3) with ``C R C^T`` of every joint of the groups, ``R`` the
    rotation of the Euler angles ``values[:, columns] * scale`` (``groups`` and ``values``
    as in :func:`degrees_to_matrices_compiled`, ``scale`` radians per unit of ``values``)
    and ``C = axes[joint]`` (axes (J, 3, 3)), and ``out[:, identities]`` with the identity;
    on ``threads`` threads (None: one per core; the same numbers). Returns False (doing
    nothing) when ``backend`` chooses the numpy path (:func:`core.compiled.chosen_kernels`).

    The AMC reader's conversion (a bone's rotation about its ASF axes): the operations of
    :func:`core.rotations.euler.matrix_from_euler` then ``C (R C^T)``, one rotation at a
    time in compiled code, with no array of the take's size but ``out``. sin and cos come
    from the C library, and the products are summed in a fixed order where numpy's matrix
    product may use fused multiply-adds: results may differ from numpy's in the last bits.
    """
    kernels = chosen_kernels(backend, _kernels)
    if kernels is None:
        return False
    joints, columns, codes = _euler_columns(groups)
    arguments = (
        np.ascontiguousarray(values, dtype=np.float64),
        float(scale),
        joints,
        columns,
        codes,
        np.ascontiguousarray(np.asarray(axes, dtype=np.float64)[joints]).reshape(-1, 3, 3),
        np.asarray(identities, dtype=np.int64).reshape(-1),
    )

    def block(frames: slice) -> None:
        kernels.conjugated_from_angles(*arguments, frames.start, frames.stop, out)

    if joints.size or len(identities):
        in_blocks(block, out.shape[0], threads)
    return True


def _euler_columns(groups: list[tuple[str, list[int], np.ndarray]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernels' view of (order, joints, columns) groups: joints (M,) int64, their
    angles' columns (M, 3) int64 (-1 for a missing angle), their order codes (M, 4)."""
    joints, columns, orders = [], [], []
    for order, members, cols in groups:
        for joint, joint_cols in zip(members, np.asarray(cols).reshape(len(members), -1)):
            joints.append(joint)
            columns.append(list(joint_cols) + [-1] * (3 - len(joint_cols)))
            orders.append(order)
    return (
        np.asarray(joints, dtype=np.int64).reshape(-1),
        np.asarray(columns, dtype=np.int64).reshape(-1, 3),
        euler_codes(tuple(orders)).reshape(-1, 4),
    )
