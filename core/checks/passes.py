"""Per-frame statistics several checks read, each one pass over the motion.

- :func:`second_differences`: each joint's middle deviation ``|P_f - (P_{f-1} + P_{f+1}) / 2|``
  and the products of consecutive middles (pops and jitter, :mod:`core.checks.spikes`);
- :func:`largest_steps`: the largest squared step of any joint from frame to frame (frozen
  and duplicate frames, :mod:`core.checks.frames`);
- :func:`step_cosines`: the cosine of the angle of ``R_f^T R_{f+1}`` of every joint (flips,
  :mod:`core.checks.joints`).

With numba installed each is a compiled kernel (:mod:`core.checks._kernels`) that writes only
its result; without it (or with ``backend='numpy'``) numpy computes the same (the reference;
the two agree to rounding, tested).
"""

from __future__ import annotations

import os

import numpy as np

try:  # the compiled backend is optional, as for the FK engine
    if os.environ.get("GMR_DISABLE_NUMBA") == "1":
        raise ImportError("disabled by GMR_DISABLE_NUMBA=1")
    from gmr_studio.core.checks import _kernels
except ImportError:  # pragma: no cover - depends on the environment
    _kernels = None


def _compiled(backend: str, array: np.ndarray) -> bool:
    if backend not in ("auto", "numba", "numpy"):
        raise ValueError(f"unknown backend {backend!r}: expected 'auto', 'numba' or 'numpy'")
    if backend == "numba" and _kernels is None:
        raise RuntimeError("the numba backend is not available: install the 'fast' extra (numba)")
    return backend != "numpy" and _kernels is not None and array.dtype == np.float64


def middles(positions: np.ndarray) -> np.ndarray:
    """(F-2, J, 3): ``P_f - (P_{f-1} + P_{f+1}) / 2`` for frames 1..F-2 of positions (F, J, 3)."""
    out = np.add(positions[:-2], positions[2:])
    out *= -0.5
    out += positions[1:-1]
    return out


def second_differences(positions: np.ndarray, *, backend: str = "auto") -> tuple[np.ndarray, np.ndarray]:
    """(deviations (F-2, J), products (F-3, J)) of positions (F, J, 3), F >= 2: the length of
    each middle and the dot product of the middles of frames f and f+1."""
    n_frames, n_joints = positions.shape[:2]
    if _compiled(backend, positions):
        deviations = np.empty((max(n_frames - 2, 0), n_joints))
        products = np.empty((max(n_frames - 3, 0), n_joints))
        _kernels.second_differences(np.ascontiguousarray(positions), deviations, products)
        return deviations, products
    m = middles(positions)
    return np.sqrt(np.einsum("fja,fja->fj", m, m)), np.einsum("fja,fja->fj", m[:-1], m[1:])


def largest_steps(positions: np.ndarray, joints: np.ndarray | None = None, *, backend: str = "auto") -> np.ndarray:
    """(F-1,): the largest squared step of the ``joints`` (None: all) from frame f to f+1 of
    positions (F, J, 3); NaN steps are left out, NaN where every one is."""
    if _compiled(backend, positions):
        every = np.arange(positions.shape[1]) if joints is None else np.asarray(joints, dtype=np.int64)
        out = np.empty(max(positions.shape[0] - 1, 0))
        _kernels.largest_steps(np.ascontiguousarray(positions), every, out)
        return out
    picked = positions if joints is None else positions[:, joints]
    steps = picked[1:] - picked[:-1]
    return np.fmax.reduce(np.einsum("fja,fja->fj", steps, steps), axis=1)


def step_cosines(rotations: np.ndarray, joints: np.ndarray | None = None, *, backend: str = "auto") -> np.ndarray:
    """(F-1, K): the cosine of the angle between consecutive rotations (F, J, 3, 3) of the
    ``joints`` (K,) (None: all), ``(trace(R_f^T R_{f+1}) - 1) / 2`` clipped to [-1, 1]."""
    every = np.arange(rotations.shape[1]) if joints is None else np.asarray(joints, dtype=np.int64)
    if _compiled(backend, rotations):
        out = np.empty((max(rotations.shape[0] - 1, 0), every.size))
        _kernels.step_cosines(np.ascontiguousarray(rotations), every, out)
        return out
    picked = rotations[:, every]
    trace = np.einsum("fkab,fkab->fk", picked[1:], picked[:-1])
    return np.clip(0.5 * (trace - 1.0), -1.0, 1.0)


def step_angles(rotations: np.ndarray, joints: np.ndarray | None = None, *, backend: str = "auto") -> np.ndarray:
    """(F-1, K): the angles in degrees of :func:`step_cosines`."""
    return np.degrees(np.arccos(step_cosines(rotations, joints, backend=backend)))
