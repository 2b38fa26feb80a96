"""One clock for two tracks: B sampled at A's frame times, shifted by an offset.

A's frame ``i`` is at time ``i / rate_A``; it is compared with B at ``i / rate_A + offset``
(seconds), that is B's fractional frame ``u = (i / rate_A + offset) * rate_B``. Where every
``u`` is a whole number (same rate, offset a whole number of frames) B's frames are taken
as they are; otherwise positions are interpolated linearly and rotations along the geodesic
between B's two neighbouring frames. Outside B's time range, and next to B's gaps, the
samples are NaN.

:func:`find_offset` finds the offset that makes the root speeds of A and B agree best.
"""

from __future__ import annotations

import numpy as np

#: a fractional frame this close to a whole number is that frame (rounding of i / rate)
WHOLE_FRAME_TOLERANCE = 1e-6
#: the two other axes of each axis, in cyclic order (cross products by components)
_NEXT = ((1, 2), (2, 0), (0, 1))


def sample_frames(n_frames_a: int, rate_a: float, rate_b: float, offset_seconds: float, frames_a=None) -> np.ndarray:
    """B's fractional frame for each compared frame of A: (F,) float64."""
    frames = np.arange(n_frames_a) if frames_a is None else np.asarray(frames_a)
    return (frames / rate_a + offset_seconds) * rate_b


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


def resample(values: np.ndarray, at: np.ndarray, columns: np.ndarray | None = None) -> np.ndarray:
    """``values`` (N, ...) of B sampled at fractional frames ``at`` (F,) -> (F, ...), linear.

    ``columns``: only these indices of axis 1 (then (F, len(columns), ...)). NaN outside
    ``[0, N - 1]``; a NaN neighbour makes the sample NaN.
    """
    n = values.shape[0]
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n - 1 + WHOLE_FRAME_TOLERANCE)
    nearest = np.rint(at)
    if np.all(np.abs(at - nearest) <= WHOLE_FRAME_TOLERANCE):
        out = take(values, np.clip(nearest.astype(np.int64), 0, n - 1), columns)
    else:
        low = np.clip(np.floor(at).astype(np.int64), 0, max(n - 2, 0))
        high = np.minimum(low + 1, n - 1)
        first, second = take(values, low, columns), take(values, high, columns)
        weight = np.clip(at - low, 0.0, 1.0).reshape((-1,) + (1,) * (first.ndim - 1))
        out = first * (1.0 - weight)
        out += second * weight
    if not inside.all():
        out = np.array(out, dtype=np.float64)
        out[~inside] = np.nan
    return out


def resample_rotations(rotations: np.ndarray, at: np.ndarray, columns: np.ndarray | None = None) -> np.ndarray:
    """Rotations (N, J, 3, 3) at fractional frames (F,) -> (F, J, 3, 3), along the geodesic.

    ``R(w) = R_0 exp(w log(R_0^T R_1)) = exp(w angle [v]) R_0`` with ``v`` the unit axis in
    world coordinates, by Rodrigues' formula on the columns of ``R_0``. Neither the relative
    rotation nor any other (F, J, 3, 3) product is formed: ``cos(angle) = (R_0 : R_1 - 1) / 2``
    (the trace of ``R_0^T R_1`` as an elementwise sum) and ``2 sin(angle) v = sum_k R_0[:, k]
    x R_1[:, k]`` (the axis of ``R_1 R_0^T``), the angle by ``arctan2`` of both, accurate at
    every angle. An axis shorter than 1e-12 (angle 0 or pi) leaves ``R_0``. NaN outside B's
    range.
    """
    n = rotations.shape[0]
    nearest = np.rint(at)
    if np.all(np.abs(at - nearest) <= WHOLE_FRAME_TOLERANCE):
        return resample(rotations, at, columns)
    low = np.clip(np.floor(at).astype(np.int64), 0, max(n - 2, 0))
    high = np.minimum(low + 1, n - 1)
    first = take(rotations, low, columns)
    shape = first.shape
    # component-major (3, 3, M) copies: every operation below runs along the M samples
    r0 = np.ascontiguousarray(first.reshape(-1, 9).T).reshape(3, 3, -1)
    r1 = np.ascontiguousarray(take(rotations, high, columns).reshape(-1, 9).T).reshape(3, 3, -1)
    weight = np.repeat(np.clip(at - low, 0.0, 1.0), r0.shape[-1] // len(at))
    axis = np.empty((3, r0.shape[-1]))  # 2 sin(angle) v = sum_k R_0[:, k] x R_1[:, k]
    for i, (j, k) in enumerate(_NEXT):
        axis[i] = np.einsum("cm,cm->m", r0[j], r1[k])
        axis[i] -= np.einsum("cm,cm->m", r0[k], r1[j])
    sin = 0.5 * np.sqrt(np.einsum("km,km->m", axis, axis))
    cos = 0.5 * (np.einsum("ijm,ijm->m", r0, r1) - 1.0)
    turn = np.arctan2(sin, cos)
    turn *= weight  # the angle of the step
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(sin > 1e-12, axis / (2.0 * sin), 0.0)
    across = _cross_columns(unit, r0)  # v x each column of R_0
    twice = _cross_columns(unit, across)  # v x (v x column)
    across *= np.sin(turn)
    twice *= 1.0 - np.cos(turn)
    across += r0
    across += twice
    out = np.ascontiguousarray(across.reshape(9, -1).T).reshape(shape)
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n - 1 + WHOLE_FRAME_TOLERANCE)
    out[~inside] = np.nan
    return out


def _cross_columns(vector: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """``vector`` (3, M) crossed with each column of ``matrices`` (3, 3, M), component-major."""
    out = np.empty(matrices.shape)
    for i, (j, k) in enumerate(_NEXT):
        np.multiply(vector[j], matrices[k], out=out[i])
        out[i] -= vector[k] * matrices[j]
    return out


def find_offset(
    root_a: np.ndarray, root_b: np.ndarray, rate_a: float, rate_b: float, *, min_overlap: float = 0.5
) -> tuple[int, float]:
    """The offset (in A's frames) maximising the agreement of two root trajectories.

    root_a (Fa, 3), root_b (Fb, 3): one point per frame (NaN allowed), in the same units. B
    is resampled at A's rate over its whole duration; the speeds of both (so that position
    and orientation do not matter) are compared at every whole lag that keeps
    ``min_overlap`` of the shorter one overlapping, by mean squared difference (all lags at
    once through FFT correlations). Returns (lag, mean squared difference): A's frame ``i``
    goes with B at time ``(i + lag) / rate_a``.
    """
    grid = np.arange(int(np.floor((root_b.shape[0] - 1) / rate_b * rate_a + WHOLE_FRAME_TOLERANCE)) + 1)
    b_at_a_rate = resample(root_b, grid * rate_b / rate_a)
    speed_a = np.linalg.norm(np.diff(root_a, axis=0), axis=-1)
    speed_b = np.linalg.norm(np.diff(b_at_a_rate, axis=0), axis=-1)
    valid_a, valid_b = np.isfinite(speed_a), np.isfinite(speed_b)
    sa, sb = np.where(valid_a, speed_a, 0.0), np.where(valid_b, speed_b, 0.0)
    na, nb = len(sa), len(sb)
    size = 1 << int(np.ceil(np.log2(na + nb)))

    def correlate(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """sum_i x[i] * y[i + lag] for lag = -(na - 1) .. nb - 1."""
        full = np.fft.irfft(np.conj(np.fft.rfft(x, size)) * np.fft.rfft(y, size), size)
        return np.concatenate([full[size - (na - 1) :], full[:nb]]) if na > 1 else full[:nb]

    va, vb = valid_a.astype(np.float64), valid_b.astype(np.float64)
    count = correlate(va, vb)
    squared = correlate(sa * sa, vb) + correlate(va, sb * sb) - 2.0 * correlate(sa, sb)
    lags = np.arange(-(na - 1), nb)
    need = max(2.0, min_overlap * min(valid_a.sum(), valid_b.sum()))
    with np.errstate(invalid="ignore", divide="ignore"):
        score = np.where(np.rint(count) >= need, squared / np.maximum(count, 1.0), np.inf)
    best = int(np.argmin(score))
    return int(lags[best]), float(score[best])
