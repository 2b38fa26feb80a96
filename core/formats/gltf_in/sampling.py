"""Animation samplers of glTF 2.0 evaluated at frame times, and the frame times themselves.

- STEP: the value of the last key at or before the time.
- LINEAR: linear interpolation; rotations by spherical linear interpolation (slerp) along
  the shorter arc.
- CUBICSPLINE: each key holds an in-tangent ``a``, a value ``v`` and an out-tangent ``b``;
  between keys ``k`` and ``k+1`` (``d = t_{k+1} - t_k``, ``s`` the fraction)
  ``p(s) = (2s³-3s²+1) v_k + (s³-2s²+s) d b_k + (-2s³+3s²) v_{k+1} + (s³-s²) d a_{k+1}``
  (the specification's Appendix C); rotations are normalised afterwards.
- Before the first key the first value holds, after the last key the last.

Frame times (:func:`frame_times`): at a given rate, or, by default, the keys' own spacing
when every key lies on one regular grid (then each frame falls exactly on its keys, which
are read without interpolation), else 30 Hz.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.rotations.quaternions import slerp

#: frame rate used when the keys are irregular (or there is only one)
FALLBACK_RATE = 30.0
#: a key lies on the grid if it is within this fraction of a frame of it (times are float32)
GRID_TOLERANCE = 0.01
#: the most frames a file may be sampled to
MAX_FRAMES = 2_000_000
#: a frame within this fraction of a frame of a key is put on the key
SNAP_TOLERANCE = 1e-4
INTERPOLATIONS = ("LINEAR", "STEP", "CUBICSPLINE")


@dataclasses.dataclass(frozen=True)
class Sampler:
    """One animation sampler: key times (K,), outputs (K, C) or (3K, C) for CUBICSPLINE."""

    times: np.ndarray
    values: np.ndarray
    interpolation: str


@dataclasses.dataclass(frozen=True)
class Clock:
    """The frames a motion is sampled at: times (F,) seconds, frame_time, and how they were
    chosen (a sentence for the motion's notes)."""

    times: np.ndarray
    frame_time: float
    note: str


def frame_times(key_times: list[np.ndarray], frame_rate: float | None) -> Clock:
    """The frames covering every key of one animation (see the module docstring).

    ``key_times``: each channel's key times (sorted); ``frame_rate``: frames per second
    asked for, or None for the keys' own spacing.
    """
    keys = np.unique(np.concatenate(key_times)) if key_times else np.zeros(1)
    start, span = float(keys[0]), float(keys[-1] - keys[0])
    if frame_rate is not None:
        step = 1.0 / frame_rate
        times = _on_keys(start + np.arange(_frame_count(span, step)) * step, keys, step)
        return Clock(times, step, f"sampled at {frame_rate:g} Hz (--frame-rate)")
    if keys.size < 2:
        return Clock(keys[:1].copy(), 1.0 / FALLBACK_RATE, f"a single key: one frame, {FALLBACK_RATE:g} Hz")
    grid = regular_grid(keys)
    if grid is not None:
        step, index = grid
        times = start + np.arange(index[-1] + 1) * step
        times[index] = keys  # exactly on the keys
        return Clock(times, step, f"keys every {step:.6g} s ({1 / step:.6g} Hz), one frame per key time")
    step = 1.0 / FALLBACK_RATE
    return Clock(
        _on_keys(start + np.arange(_frame_count(span, step)) * step, keys, step),
        step,
        f"keys at irregular times: sampled at {FALLBACK_RATE:g} Hz (--frame-rate to choose)",
    )


def regular_grid(keys: np.ndarray) -> tuple[float, np.ndarray] | None:
    """(step, frame index of each key) when the sorted distinct keys (K,) lie on one grid,
    else None. Each gap counts whole steps of the smallest gap (float32 rounding makes gaps
    late in a long take differ by a few per mille, far from half a step); the step is then
    the whole span over the steps counted, and every key must lie within
    :data:`GRID_TOLERANCE` of a frame of it."""
    gaps = np.diff(keys)
    smallest = float(gaps.min())
    if not smallest > 0:
        return None
    counts = np.round(gaps / smallest)
    if counts.sum() >= MAX_FRAMES:  # (each gap counts at most the sum)
        return None
    index = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    step = float(keys[-1] - keys[0]) / float(index[-1])
    off = np.abs((keys - keys[0]) / step - index).max()
    return (step, index) if off <= GRID_TOLERANCE else None


def _on_keys(times: np.ndarray, keys: np.ndarray, step: float) -> np.ndarray:
    """Frame times moved onto the keys within :data:`SNAP_TOLERANCE` of a frame of them
    (float32 key times are rarely exactly on a float64 grid): such frames read the key."""
    nearest = np.clip(np.searchsorted(keys, times), 1, keys.size - 1) if keys.size > 1 else np.zeros(times.size, int)
    for candidate in (nearest - 1, nearest):
        close = np.abs(keys[candidate] - times) <= SNAP_TOLERANCE * step
        times = np.where(close, keys[candidate], times)
    return times


def _frame_count(span: float, step: float) -> int:
    count = int(np.ceil(span / step - 1e-6)) + 1  # the last frame at or after the last key
    if count > MAX_FRAMES:
        raise ValueError(f"the animation lasts {span:.6g} s: {count} frames at {1 / step:g} Hz, more than {MAX_FRAMES}")
    return count


def segments(keys: np.ndarray, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For each time: the key at or before it and the next (clamped), the gap between their
    times, and the fraction of it (0 on a key): (F,) each."""
    after = np.searchsorted(keys, times, side="right")  # first key later than t
    before = np.maximum(after - 1, 0)
    nxt = np.minimum(after, keys.size - 1)
    gap = keys[nxt] - keys[before]
    fraction = np.where(gap > 0, (times - keys[before]) / np.where(gap > 0, gap, 1.0), 0.0)
    return before, nxt, gap, fraction


def sample(sampler: Sampler, times: np.ndarray, rotation: bool, located: tuple | None = None) -> np.ndarray:
    """The sampler's value at each time: (F, C); ``rotation``: quaternions ``x, y, z, w``;
    ``located``: :func:`segments` of the sampler's keys at these times, if in hand. When
    every frame is on a key the values are the keys' own (float32 keys stay float32, each
    a float64 exactly); interpolated values are float64."""
    keys = sampler.times
    cubic = sampler.interpolation == "CUBICSPLINE"
    values = sampler.values.reshape(keys.size, 3, -1)[:, 1] if cubic else sampler.values
    before, nxt, gap, fraction = located if located is not None else segments(keys, times)
    if sampler.interpolation == "STEP" or not fraction.any():  # every frame on a key
        if np.array_equal(before, np.arange(keys.size)):
            return values  # frame k on key k (STEP frames between keys may be as many): no copy
        return values[before]  # (quaternions are normalised when they become matrices)
    values = values.astype(np.float64, copy=False)  # worked on in float64 from here
    fraction = fraction[:, None]
    if cubic:
        tangents = sampler.values.reshape(keys.size, 3, -1).astype(np.float64, copy=False)
        s, s2, s3 = fraction, fraction**2, fraction**3
        d = gap[:, None]
        out = (
            (2 * s3 - 3 * s2 + 1) * values[before]
            + (s3 - 2 * s2 + s) * d * tangents[before, 2]
            + (-2 * s3 + 3 * s2) * values[nxt]
            + (s3 - s2) * d * tangents[nxt, 0]
        )
        return normalised(out) if rotation else out
    if rotation:  # slerp does not depend on the component order; on a key, the key itself
        turned = slerp(normalised(values[before]), normalised(values[nxt]), fraction[:, 0])
        return np.where(fraction == 0.0, normalised(values[before]), turned)
    exact = fraction == 0.0  # on a key: its value, bit for bit
    return np.where(exact, values[before], values[before] + fraction * (values[nxt] - values[before]))


def normalised(quaternions: np.ndarray) -> np.ndarray:
    """Unit quaternions (..., 4); a zero quaternion becomes the identity."""
    norm = np.linalg.norm(quaternions, axis=-1, keepdims=True)
    identity = np.zeros_like(quaternions)
    identity[..., 3] = 1.0
    return np.where(norm > 0, quaternions / np.where(norm > 0, norm, 1.0), identity)
