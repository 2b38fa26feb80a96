"""The sample grid and the one interpolator: values of one clock at the times of another.

Every feature that puts data on another clock calls these: resampling a motion (the clip
edit, ``gmr edit --rate``), ``gmr dataset --rate``, markers resampled to a motion's rate,
comparisons (B on A's frames) and their offset search.

- **The grid** (:func:`resample_grid`): a clock at ``rate`` Hz laid over ``n_frames`` frames
  of ``frame_time`` s: its frame ``k`` at ``k / rate`` s is the source's fractional frame
  ``k / (rate * frame_time)``, up to the source's last frame give or take the rounding of a
  printed frame time (:func:`core.timebase.clock.frames_within`). A fractional frame within
  :data:`WHOLE_FRAME_TOLERANCE` of a whole one is that frame. A rate that divides the
  source's to within the rounding of its printed frame time (60 Hz of a 0.0083333 s take:
  2.000008 source frames a frame) takes every n-th source frame: ``k n`` exactly, not a
  fraction drifting off the frames by the printed digits' rounding
  (:func:`core.timebase.clock.frames_per_frame`).
- **The interpolator**: positions (any values) linearly (:func:`interpolate`), rotations
  along the geodesic between the two neighbouring frames (:func:`interpolate_rotations`:
  quaternion slerp, computed on the matrices). Where a sample falls on a source frame, the
  frame is taken as it is (bit for bit); outside the source's range, and next to its gaps
  (NaN), the samples are NaN. With numba installed both run as compiled kernels
  (:mod:`core.timebase._kernels`), one pass over the samples: the linear one with the numpy
  path's very operations, the rotations in agreement with the numpy path
  (:func:`slerp_component_major`, the reference) to rounding.
"""

from __future__ import annotations

from types import ModuleType

import numpy as np

from gmr_studio.core.compiled import chosen_kernels, optional_kernels
from gmr_studio.core.timebase.clock import frames_per_frame, frames_within


def compiled_kernels() -> ModuleType | None:
    """:mod:`core.timebase._kernels`, or None without numba (:func:`core.compiled.optional_kernels`)."""
    return optional_kernels("gmr_studio.core.timebase._kernels")


#: a fractional frame this close to a whole number is that frame (rounding of ``k / rate``)
WHOLE_FRAME_TOLERANCE = 1e-6
#: frames per block of :func:`interpolate_rotations` (component-major temporaries in the cache)
ROTATION_BLOCK = 512
#: values per chunk of the linear interpolation of :func:`interpolate` (a buffer in the cache)
RESAMPLE_CHUNK = 65536
#: the two other axes of each axis, in cyclic order (cross products by components)
_NEXT = ((1, 2), (2, 0), (0, 1))


def resample_grid(n_frames: int, frame_time: float, rate: float) -> np.ndarray:
    """The frames of a clock at ``rate`` Hz over ``n_frames`` frames of ``frame_time`` s, in
    source frames: (K,) float64 (module docstring); whole where within the tolerance, never
    past the last source frame. ValueError for a rate that is not a positive number."""
    if not np.isfinite(rate) or rate <= 0:
        raise ValueError(f"the frame rate must be a positive number, not {rate}")
    if n_frames <= 0:
        return np.zeros(0)
    count = frames_within(n_frames, frame_time, rate)
    every = frames_per_frame(frame_time, rate)
    if every is not None:
        return every * np.arange(min(count, (n_frames - 1) // every + 1), dtype=np.float64)
    at = np.arange(count) / (rate * frame_time)
    nearest = np.rint(at)
    return np.minimum(np.where(np.abs(at - nearest) <= WHOLE_FRAME_TOLERANCE, nearest, at), n_frames - 1)


def take(values: np.ndarray, rows: np.ndarray, columns: np.ndarray | None = None) -> np.ndarray:
    """``values[rows][:, columns]`` (rows (F,), columns (J,) or None for all), copying as
    little as possible: a run of consecutive rows is a view, all columns in order are not
    taken again."""
    if len(rows) and rows[-1] - rows[0] == len(rows) - 1 and (len(rows) < 2 or bool(np.all(np.diff(rows) == 1))):
        picked = values[rows[0] : rows[-1] + 1]
    else:
        picked = values[rows]
    if columns is None or (len(columns) == values.shape[1] and bool(np.all(columns == np.arange(len(columns))))):
        return picked
    return np.take(picked, columns, axis=1)


def interpolate(values: np.ndarray, at: np.ndarray, columns: np.ndarray | None = None) -> np.ndarray:
    """``values`` (N, ...) of B sampled at fractional frames ``at`` (F,) -> (F, ...), linear.

    ``columns``: only these indices of axis 1 (then (F, len(columns), ...)). NaN outside
    ``[0, N - 1]``; a NaN neighbour makes the sample NaN. Samples inside B's range that
    follow one another (``at`` increasing) are read from views of B, not gathered.
    """
    n = values.shape[0]
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n - 1 + WHOLE_FRAME_TOLERANCE)
    if inside.all():
        return _resample_inside(values, at, columns)
    shape = (len(at), *values.shape[1:]) if columns is None else (len(at), len(columns), *values.shape[2:])
    where = np.flatnonzero(inside)
    if where.size and where[-1] - where[0] == where.size - 1:  # one run of samples
        out = np.empty(shape)
        out[: where[0]] = np.nan
        out[where[-1] + 1 :] = np.nan
        _resample_inside(values, at[where[0] : where[-1] + 1], columns, out=out[where[0] : where[-1] + 1])
        return out
    out = np.full(shape, np.nan)
    if where.size:
        out[inside] = _resample_inside(values, at[inside], columns)
    return out


def _resample_inside(
    values: np.ndarray, at: np.ndarray, columns: np.ndarray | None, out: np.ndarray | None = None
) -> np.ndarray:
    """:func:`interpolate` for ``at`` (F,) within B's range, into ``out`` if given (else a view
    of ``values`` where B's frames are taken as they are)."""
    n = values.shape[0]
    nearest = np.rint(at)
    if np.all(np.abs(at - nearest) <= WHOLE_FRAME_TOLERANCE):
        picked = take(values, np.clip(nearest.astype(np.int64), 0, n - 1), columns)
        if out is None:
            return picked
        np.copyto(out, picked)
        return out
    low, high, weight = neighbours(at, n)
    kernels = compiled_kernels()
    compiled = kernels is not None and columns is None and values.dtype == np.float64 and values.ndim > 1
    if compiled and (out is None or out.flags.c_contiguous):
        if out is None:
            out = np.empty((len(at), *values.shape[1:]))
        rows = np.ascontiguousarray(values).reshape(n, -1)
        flat_out = out.reshape(len(at), -1)  # out is C-contiguous: a view
        kernels.lerp_rows(rows, low, high, weight, flat_out)
        return out
    first, second = take(values, low, columns), take(values, high, columns)
    if out is None:
        out = np.empty(first.shape)
    # (F, everything else): the weight (F, 1) broadcast along rows, not along a short last
    # axis; in chunks of rows so that the product with the second frame reuses one buffer
    size = int(np.prod(first.shape[1:]))
    flat_out, flat_first, flat_second = (x.reshape(len(at), size) for x in (out, first, second))
    weight = weight[:, None]
    rows = max(1, RESAMPLE_CHUNK // max(flat_out.shape[1], 1))
    buffer = np.empty((min(rows, len(at)), flat_out.shape[1]))
    for start in range(0, len(at), rows):
        chunk = slice(start, start + rows)
        part = buffer[: len(flat_out[chunk])]
        # a + (b - a) w: exact where the two frames agree (a joint that does not move) and at w = 0
        np.subtract(flat_second[chunk], flat_first[chunk], out=part)
        part *= weight[chunk]
        np.add(flat_first[chunk], part, out=flat_out[chunk])
    return out


def neighbours(at: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The source frames around fractional frames ``at`` (F,) of ``n`` frames and the weight
    of the second: (low (F,) int64, high (F,) int64, weight (F,) in [0, 1]). A whole frame
    (within :data:`WHOLE_FRAME_TOLERANCE`) is its own two neighbours with weight 0, so that
    it is taken exactly as it is."""
    nearest = np.rint(at)
    whole = np.abs(at - nearest) <= WHOLE_FRAME_TOLERANCE
    between = np.clip(np.floor(at).astype(np.int64), 0, max(n - 2, 0))
    low = np.where(whole, np.clip(nearest, 0, n - 1).astype(np.int64), between)
    high = np.where(whole, low, np.minimum(between + 1, n - 1))
    weight = np.where(whole, 0.0, np.clip(at - between, 0.0, 1.0))
    return low, high, weight


def interpolate_rotations(
    rotations: np.ndarray, at: np.ndarray, columns: np.ndarray | None = None, *, backend: str = "auto"
) -> np.ndarray:
    """Rotations (N, J, 3, 3) at fractional frames (F,) -> (F, J, 3, 3), along the geodesic.

    ``backend``: 'numba' (the compiled kernel, one pass over the samples), 'numpy'
    (:func:`rotations_component_major` in blocks of :data:`ROTATION_BLOCK` frames, put back
    in row-major order), or 'auto' (numba when installed); the same rotations to rounding.
    NaN outside B's range.
    """
    if whole_frames(at):
        return interpolate(rotations, at, columns)
    kernels = chosen_kernels(backend, compiled_kernels())
    if kernels is not None and rotations.shape[0] and rotations.dtype == np.float64:
        return _slerp_compiled(rotations, at, columns)
    n_columns = rotations.shape[1] if columns is None else len(columns)
    out = np.empty((len(at), n_columns, 3, 3))
    for start in range(0, len(at), ROTATION_BLOCK):
        block = slice(start, start + ROTATION_BLOCK)
        major = rotations_component_major(rotations, at[block], columns)
        out[block] = np.moveaxis(major.reshape(9, -1, n_columns), 0, -1).reshape(-1, n_columns, 3, 3)
    return out


def _slerp_compiled(rotations: np.ndarray, at: np.ndarray, columns: np.ndarray | None) -> np.ndarray:
    """:func:`interpolate_rotations` by the compiled kernel (B has frames)."""
    n = rotations.shape[0]
    low, high, weight = neighbours(at, n)
    joints = np.arange(rotations.shape[1]) if columns is None else np.asarray(columns, dtype=np.int64)
    out = np.empty((len(at), joints.size, 3, 3))
    compiled_kernels().slerp_rows(np.ascontiguousarray(rotations), low, high, weight, joints, out)
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n - 1 + WHOLE_FRAME_TOLERANCE)
    if not inside.all():
        out[~inside] = np.nan
    return out


def whole_frames(at: np.ndarray) -> bool:
    """True when every fractional frame of ``at`` (F,) is a whole one (B taken as it is)."""
    return bool(np.all(np.abs(at - np.rint(at)) <= WHOLE_FRAME_TOLERANCE))


def rotations_component_major(rotations: np.ndarray, at: np.ndarray, columns: np.ndarray | None = None) -> np.ndarray:
    """Rotations (N, J, 3, 3) at fractional frames (F,) -> component-major (3, 3, F * J).

    ``out[r, c, f * J + j]`` is entry (r, c) of joint j's rotation at ``at[f]``, along the
    geodesic between B's two neighbouring frames (:func:`slerp_component_major`). B's frames
    in range are put in component-major order once each (one transposing copy), so that all
    the arithmetic runs along the samples. NaN outside B's range.
    """
    n = rotations.shape[0]
    n_columns = rotations.shape[1] if columns is None else len(columns)
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n - 1 + WHOLE_FRAME_TOLERANCE)
    whole = whole_frames(at)
    if whole:
        low = high = np.clip(np.rint(at).astype(np.int64), 0, n - 1)
    else:
        low, high, weight = neighbours(at, n)
    first, last = (int(low.min()), int(high.max())) if len(at) else (0, -1)
    span = take(rotations, np.arange(first, last + 1), columns).reshape(-1, 9)
    major = np.ascontiguousarray(span.T).reshape(9, -1, n_columns)  # (9, frames of B, J)
    r0 = _frames_of_major(major, low - first).reshape(3, 3, -1)
    if whole:
        out = r0
    else:
        weight = np.repeat(weight, n_columns)
        out = slerp_component_major(r0, _frames_of_major(major, high - first).reshape(3, 3, -1), weight)
    if not inside.all():
        out[:, :, np.repeat(~inside, n_columns)] = np.nan
    return out


def _frames_of_major(major: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``major[:, rows]`` for major (9, S, J): a view when the rows are consecutive."""
    if len(rows) and rows[-1] - rows[0] == len(rows) - 1 and bool(np.all(np.diff(rows) == 1)):
        return major[:, rows[0] : rows[-1] + 1]
    return major[:, rows]


def slerp_component_major(r0: np.ndarray, r1: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """The rotation ``weight`` of the way along the geodesic from R_0 to R_1, component-major.

    r0, r1 : (3, 3, M) rotation matrices, entry (r, c) of sample m at ``[r, c, m]``.
    weight : (M,) in [0, 1]. Returns a new (3, 3, M) array.

    ``R(w) = exp(w angle [v]) R_0`` with ``v`` the unit axis of ``R_1 R_0^T`` (world
    coordinates), so no product of matrices is formed: ``u = 2 sin(angle) v = sum_k R_0[:, k]
    x R_1[:, k]`` and ``2 cos(angle) + 1 = R_0 : R_1`` (the trace of ``R_0^T R_1``). Where the
    step is below 60 degrees (every step of a motion sampled finely enough) the angle is
    ``arcsin(|u| / 2)`` and Rodrigues' formula is written with ``u`` itself,
    ``R(w) = R_0 + a u x R_0 + b u x (u x R_0)`` (cross products with each column) with
    ``h = sin(w angle / 2)``, ``a = h sqrt(1 - h^2) / sin(angle)``, ``b = h^2 / (2 sin(angle)^2)``
    (the second product taken as ``(b / a) u x (a u x R_0)``, ``b / a = h / (2 sin(angle)
    sqrt(1 - h^2))``):
    no division by a vanishing axis length, full relative accuracy down to angle 0, two
    transcendental functions per sample. Larger steps go to :func:`_slerp_far` (the axis from
    the symmetric part, accurate up to 180 degrees).
    """
    u = np.empty((3, r0.shape[-1]))
    for i, (j, k) in enumerate(_NEXT):
        np.einsum("cm,cm->m", r0[j], r1[k], out=u[i])
        u[i] -= np.einsum("cm,cm->m", r0[k], r1[j])
    cos = np.einsum("ijm,ijm->m", r0, r1)
    cos -= 1.0
    cos *= 0.5
    sin = np.sqrt(np.einsum("km,km->m", u, u))
    sin *= 0.5
    with np.errstate(invalid="ignore"):
        far = cos < 0.5
        half = np.arcsin(np.minimum(sin, 1.0))  # the angle, halved below
        half *= weight
        half *= 0.5
        h = np.sin(half, out=half)
        sin[sin == 0.0] = 1.0  # angle 0: h = 0, no turn
        q = np.divide(h, sin, out=sin)
        root = np.multiply(h, h, out=h)
        np.subtract(1.0, root, out=root)
        root = np.sqrt(root, out=root)  # cos(w angle / 2), at least cos(30 degrees) here
        u_a = u * (q * root)  # a u
        q *= 0.5
        q /= root
        u *= q  # b / a u
    out = _cross_columns(u_a, r0)  # a u x each column of R_0
    twice = _cross_columns(u, out)  # b u x (u x column)
    out += r0
    out += twice
    if far.any():
        out[:, :, far] = _slerp_far(r0[:, :, far], r1[:, :, far], weight[far])
    return out


def _slerp_far(r0: np.ndarray, r1: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """:func:`slerp_component_major` for steps of 60 degrees or more, (3, 3, K) each.

    The axis is taken from the symmetric part of the relative rotation (``(P + P^T) / 2 -
    cos(angle) I = (1 - cos(angle)) v v^T``: its largest column, normalised), its sign from
    the skew part, so it stays accurate towards 180 degrees where ``|u|`` vanishes; the angle
    by ``arctan2``. At exactly 180 degrees either way round is the geodesic.
    """
    p0, p1 = np.moveaxis(r0, -1, 0), np.moveaxis(r1, -1, 0)  # (K, 3, 3)
    relative = np.matmul(np.swapaxes(p0, 1, 2), p1)  # R_0^T R_1, body axes
    r = relative
    skew = np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]], axis=-1)
    cos = 0.5 * (np.trace(relative, axis1=1, axis2=2) - 1.0)
    angle = np.arctan2(0.5 * np.linalg.norm(skew, axis=-1), cos)
    outer = 0.5 * (relative + np.swapaxes(relative, 1, 2)) - cos[:, None, None] * np.eye(3)
    pick = np.argmax(np.diagonal(outer, axis1=1, axis2=2), axis=-1)
    column = np.take_along_axis(outer, pick[:, None, None], axis=2)[:, :, 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        axis = column / np.linalg.norm(column, axis=-1, keepdims=True)
    axis *= np.where(np.einsum("ki,ki->k", axis, skew) < 0.0, -1.0, 1.0)[:, None]
    turn = weight * angle
    k = np.zeros((len(turn), 3, 3))
    k[:, 0, 1], k[:, 0, 2], k[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    k[:, 1, 0], k[:, 2, 0], k[:, 2, 1] = axis[:, 2], -axis[:, 1], axis[:, 0]
    step = np.eye(3) + np.sin(turn)[:, None, None] * k + (1.0 - np.cos(turn))[:, None, None] * (k @ k)
    return np.moveaxis(p0 @ step, 0, -1)


def _cross_columns(vector: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """``vector`` (3, M) crossed with each column of ``matrices`` (3, 3, M), component-major."""
    out = np.empty(matrices.shape)
    scratch = np.empty(matrices.shape[1:])
    for i, (j, k) in enumerate(_NEXT):
        np.multiply(vector[j], matrices[k], out=out[i])
        out[i] -= np.multiply(vector[k], matrices[j], out=scratch)
    return out
