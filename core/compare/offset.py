"""The time offset between two tracks, found from the whole body, and how sure it is.

Every frame of each side is described by features that no change of place, heading, up axis,
units or fitted alignment alters (:func:`pose_features`):

- each matched point's distance from the centroid of the matched points, in A's sizes;
- where both sides have orientations, each oriented point's chord ``|W_j - W_r|_F`` to the
  first oriented point's world rotation ``W_r`` (``M W N`` for fixed rotations M, N leaves
  it unchanged): the turn of every bone relative to one of them;
- the travel of the centroid: its speed over :data:`SPEED_WINDOW` seconds, in sizes per
  second (the only feature of a single point, such as a root trajectory).

So every joint counts: a root pinned at the origin while the hips carry the walk gives the
pose of the figure as much as any rig. The features are not differences of frames (but
the travel, over a window), so per-frame noise is not amplified.

B's features are resampled at A's rate; at every whole lag that keeps ``min_overlap`` of the
shorter side overlapping, the mean squared difference of all features present on both sides
is computed (all lags at once: FFT correlations, summed over the features in the frequency
domain). The best lag is the one of least mismatch (ties go to the lag nearest 0, so a still
or periodic motion compared with itself keeps offset 0); the runner-up is the best lag at
least :data:`SEPARATION_SECONDS` away from it, so that the pair says how sure the search is:
a mismatch near 0 against a clearly larger runner-up is a sure find, two equal ones (a
perfectly periodic motion) say that the data cannot tell.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.timebase.sampling import interpolate, resample_grid

#: seconds over which the centroid's travel is measured
SPEED_WINDOW = 0.1
#: the runner-up lag is at least this far (seconds) from the best one
SEPARATION_SECONDS = 0.25
#: lags whose mean squared mismatch is within this (relative to the features' mean square,
#: plus an absolute floor) of the least one tie; the positions, then nearness to 0, decide
TIE_RELATIVE = 1e-12
#: feature channels whose rfft are taken at once (bounds the temporaries)
CHANNEL_BLOCK = 16
#: more complete (gap-free) feature channels than this are projected onto this many fixed
#: random directions before the FFTs (squared distances are kept on average, Johnson-
#: Lindenstrauss; identical features stay identical), and the mismatch of the lags kept is
#: then computed on every channel
PROJECTED_CHANNELS = 12
#: frames per block of :func:`pose_features`
FEATURE_BLOCK = 4096


@dataclasses.dataclass(frozen=True)
class OffsetSearch:
    """The offset found and how sure it is.

    lag : int, the best offset in A's frames (B's time minus A's).
    mismatch : float, RMS difference of the features at ``lag`` (distances in A's sizes, chords,
        travel in sizes per second: 0 for B a cut of A).
    runner_up : int or None, the best lag at least :data:`SEPARATION_SECONDS` away (None when
        no other lag overlaps enough). runner_up_mismatch : its RMS difference (NaN if none).
    overlap : int, frames of A that overlap B at ``lag``. rate : A's frame rate (Hz).
    """

    lag: int
    mismatch: float
    runner_up: int | None
    runner_up_mismatch: float
    overlap: int
    rate: float

    def to_json(self) -> dict:
        finite = np.isfinite(self.runner_up_mismatch)
        return {
            "lag": self.lag,
            "mismatch": float(self.mismatch) if np.isfinite(self.mismatch) else None,
            "runner_up": self.runner_up,
            "runner_up_mismatch": float(self.runner_up_mismatch) if finite else None,
            "overlap": self.overlap,
        }

    def text(self) -> str:
        """One line: the best lag's mismatch and the runner-up's."""
        best = f"whole-body mismatch {self.mismatch:.3g}"
        if self.runner_up is None:
            return best + " (no other offset overlaps enough to compare)"
        return (
            f"{best} against {self.runner_up_mismatch:.3g} at the next best, "
            f"{self.runner_up:+d} frames ({self.runner_up / self.rate:+.4g} s)"
        )


def pose_features(
    positions: np.ndarray, rotations: np.ndarray | None, columns: np.ndarray, oriented: np.ndarray | None, size: float
) -> tuple[np.ndarray, np.ndarray]:
    """Instantaneous features of one side (module docstring) and its centroid path.

    positions (F, N, 3), rotations (F, N, 3, 3) or None; columns (J,) the matched points;
    oriented (Jo,) the matched points with orientations on both sides (or None); size: A's
    size in this side's units. Returns features (F, J + Jo) and centroid (F, 3), NaN where
    points are missing (the centroid over the points present).
    """
    n = positions.shape[0]
    n_oriented = 0 if rotations is None or oriented is None or not len(oriented) else len(oriented)
    features = np.empty((n, len(columns) + n_oriented))
    centroid = np.empty((n, 3))
    every = len(columns) == positions.shape[1] and bool(np.all(columns == np.arange(len(columns))))
    for start in range(0, n, FEATURE_BLOCK):  # blocks of frames: small temporaries
        rows = slice(start, start + FEATURE_BLOCK)
        points = positions[rows] if every else positions[rows][:, columns]
        if np.isfinite(points).all():
            middle = np.einsum("fjk->fk", points) / points.shape[1]
        else:  # the centroid of the points present
            present = np.isfinite(points).all(axis=-1)
            with np.errstate(invalid="ignore", divide="ignore"):
                middle = np.where(present[..., None], points, 0.0).sum(axis=1) / present.sum(axis=1)[:, None]
        centroid[rows] = middle
        away = points - middle[:, None]
        features[rows, : len(columns)] = np.sqrt(np.einsum("fjk,fjk->fj", away, away)) / size
        if n_oriented:
            turns = rotations[rows][:, oriented].reshape(-1, n_oriented, 9)
            relative = turns - turns[:, :1]
            features[rows, len(columns) :] = np.sqrt(np.einsum("fjk,fjk->fj", relative, relative))
    return features, centroid


def travel(centroid: np.ndarray, rate: float, size: float) -> np.ndarray:
    """(F, 1) the centroid's speed over :data:`SPEED_WINDOW` (at least a frame), sizes per
    second, at the middle of the window (NaN where the window leaves the motion)."""
    step = max(1, round(SPEED_WINDOW * rate))
    out = np.full((centroid.shape[0], 1), np.nan)
    if centroid.shape[0] > step:
        moved = centroid[step:] - centroid[:-step]
        speed = np.sqrt(np.einsum("fk,fk->f", moved, moved)) * (rate / (step * size))
        out[step // 2 : step // 2 + speed.shape[0], 0] = speed
    return out


def at_rate(values: np.ndarray, rate: float, rate_a: float) -> np.ndarray:
    """Rows of B (N, ...) at B's rate, resampled at A's rate over B's frames (the one grid
    and interpolator, :mod:`core.timebase.sampling`)."""
    if rate == rate_a or values.shape[0] < 2:
        return values
    return interpolate(values, resample_grid(values.shape[0], 1.0 / rate, rate_a))


def lag_scores(
    features_a: np.ndarray, features_b: np.ndarray, *, min_overlap: float = 0.5
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean squared difference of the features at every lag: (lags (L,), scores (L,), overlap (L,)).

    A's frame ``i`` goes with B's frame ``i + lag``, ``lag = -(Na - 1) .. Nb - 1``. NaN
    features are left out; lags where fewer than ``min_overlap`` of the shorter side's frames
    (at least 2) overlap, or no feature is present on both sides, score ``inf``.
    """
    na, nb = features_a.shape[0], features_b.shape[0]
    lags = np.arange(-(na - 1), nb)
    frames_overlap = np.minimum(na, nb - lags) - np.maximum(0, -lags)  # frames of A with a B frame
    if na == 0 or nb == 0 or features_a.shape[1] == 0:
        return lags, np.full(len(lags), np.inf), frames_overlap
    size = 1 << int(np.ceil(np.log2(na + nb)))  # (a 2-3-5-smooth size measured slower)

    def spectrum(values: np.ndarray, reverse: bool) -> np.ndarray:
        out = np.fft.rfft(values, size, axis=0)
        return np.conj(out) if reverse else out

    ones_a, ones_b = spectrum(np.ones((na, 1)), True)[:, 0], spectrum(np.ones((nb, 1)), False)[:, 0]
    cross = np.zeros(size // 2 + 1, dtype=np.complex128)
    energy = np.zeros(size // 2 + 1, dtype=np.complex128)
    counts = np.zeros(size // 2 + 1, dtype=np.complex128)
    complete = np.isfinite(features_a).all(axis=0) & np.isfinite(features_b).all(axis=0)
    order = np.concatenate([np.flatnonzero(complete), np.flatnonzero(~complete)])
    n_complete = int(complete.sum())
    # blocks of complete channels first (one transform of their squares a side), then the others
    starts = [*range(0, n_complete, CHANNEL_BLOCK), *range(n_complete, len(order), CHANNEL_BLOCK)]
    for start in starts:
        block = order[start : min(start + CHANNEL_BLOCK, n_complete if start < n_complete else len(order))]
        va, vb = np.isfinite(features_a[:, block]), np.isfinite(features_b[:, block])
        a, b = np.where(va, features_a[:, block], 0.0), np.where(vb, features_b[:, block], 0.0)
        cross += np.einsum("sk,sk->s", spectrum(a, True), spectrum(b, False))
        if va.all() and vb.all():
            # every feature present: the squares and counts need one transform a side
            energy += spectrum((a * a).sum(axis=1, keepdims=True), True)[:, 0] * ones_b
            energy += ones_a * spectrum((b * b).sum(axis=1, keepdims=True), False)[:, 0]
            counts += a.shape[1] * ones_a * ones_b
        else:
            fva, fvb = spectrum(va.astype(np.float64), True), spectrum(vb.astype(np.float64), False)
            energy += np.einsum("sk,sk->s", spectrum(a * a, True), fvb)
            energy += np.einsum("sk,sk->s", fva, spectrum(b * b, False))
            counts += np.einsum("sk,sk->s", fva, fvb)

    def correlation(spectrum_sum: np.ndarray) -> np.ndarray:
        """sum_i x[i] y[i + lag] for lag = -(na - 1) .. nb - 1."""
        full = np.fft.irfft(spectrum_sum, size)
        return np.concatenate([full[size - (na - 1) :], full[:nb]]) if na > 1 else full[:nb]

    squared = correlation(energy) - 2.0 * correlation(cross)
    count = np.rint(correlation(counts))
    allowed = (frames_overlap >= max(2.0, min_overlap * min(na, nb))) & (count > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        score = np.where(allowed, np.maximum(squared, 0.0) / np.maximum(count, 1.0), np.inf)
    return lags, score, frames_overlap


def search_offset(
    features_a: np.ndarray,
    features_b: np.ndarray,
    rate: float,
    *,
    min_overlap: float = 0.5,
    tie_break=None,
) -> OffsetSearch:
    """The lag (A's frames) at which B's features (Nb, K) best follow A's (Na, K), both at A's rate.

    :func:`lag_scores`, then the least; lags within :data:`TIE_RELATIVE` of it tie, and of
    those the one where the ``tie_break()`` features (a function returning A's (Na, M) and
    B's (Nb, M), called only then: e.g. the raw positions) agree best wins, then the one
    nearest 0. With no lag overlapping enough, the
    lag is 0 with NaN mismatch.
    """
    lags, score, frames_overlap = lag_scores(*_projected(features_a, features_b), min_overlap=min_overlap)
    if not np.isfinite(score).any():
        return OffsetSearch(0, float("nan"), None, float("nan"), 0, rate)
    least = float(score.min())
    scale = float(np.nanmean(np.where(np.isfinite(features_a), features_a, np.nan) ** 2))
    tie = least + TIE_RELATIVE * (scale if np.isfinite(scale) else 0.0) + 1e-300
    candidates = np.flatnonzero(score <= tie)
    if len(candidates) > 1 and tie_break is not None:
        second = lag_scores(*_projected(*tie_break()), min_overlap=min_overlap)[1][candidates]
        if np.isfinite(second).any():
            candidates = candidates[second <= second.min() * (1.0 + 1e-9) + 1e-300]
    best = int(candidates[np.argmin(np.abs(lags[candidates]))])
    far = np.abs(lags - lags[best]) >= max(1.0, SEPARATION_SECONDS * rate)
    runner, runner_score = None, float("nan")
    if (far & np.isfinite(score)).any():
        other = int(np.argmin(np.where(far, score, np.inf)))
        runner, runner_score = int(lags[other]), float(np.sqrt(score[other]))
    overlap = int(frames_overlap[best])
    mismatch = float(np.sqrt(score[best]))
    if features_a.shape[1] > PROJECTED_CHANNELS:  # the lags kept, on every channel
        mismatch = direct_mismatch(features_a, features_b, int(lags[best]))
        if runner is not None:
            runner_score = direct_mismatch(features_a, features_b, runner)
    return OffsetSearch(int(lags[best]), mismatch, runner, runner_score, overlap, rate)


def direct_mismatch(features_a: np.ndarray, features_b: np.ndarray, lag: int) -> float:
    """RMS difference of the features present on both sides at one lag (A's ``i`` with B's ``i + lag``)."""
    first, stop = max(0, -lag), min(features_a.shape[0], features_b.shape[0] - lag)
    difference = features_a[first:stop] - features_b[first + lag : stop + lag]
    present = np.isfinite(difference)
    return float(np.sqrt(np.mean(difference[present] ** 2))) if present.any() else float("nan")


def _projected(features_a: np.ndarray, features_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Both sides' features (N, K): the channels complete on both sides (no NaN) projected
    onto :data:`PROJECTED_CHANNELS` fixed random directions when there are more of them, the
    others kept as they are (a channel with gaps needs its own counts)."""
    complete = np.isfinite(features_a).all(axis=0) & np.isfinite(features_b).all(axis=0)
    k = int(complete.sum())
    if k <= PROJECTED_CHANNELS:
        return features_a, features_b
    directions = np.random.default_rng(k).normal(size=(k, PROJECTED_CHANNELS)) / np.sqrt(PROJECTED_CHANNELS)
    rest = ~complete
    return (
        np.concatenate([features_a[:, complete] @ directions, features_a[:, rest]], axis=1),
        np.concatenate([features_b[:, complete] @ directions, features_b[:, rest]], axis=1),
    )


def find_offset_of_tracks(
    a,
    b,
    index_a: np.ndarray,
    index_b: np.ndarray,
    rate_b: float,
    units_scale: float,
    *,
    up_rotation: np.ndarray | None = None,
    min_overlap: float = 0.5,
) -> OffsetSearch:
    """:func:`search_offset` on the features of every matched point of two
    :class:`~core.compare.tracks.Track` (module docstring).

    index_a, index_b : (J,) the matched points; rate_b : B's rate as compared
    (:func:`~core.compare.clock.common_rate`); units_scale : A units per B unit; up_rotation :
    (3, 3) B's up axis to A's. Lags the features cannot tell apart (a periodic or uniform
    motion) are told apart by the points' positions in A's space (units and up axis applied,
    no fit), then by nearness to 0.
    """
    oriented = a.has_rotation[index_a] & b.has_rotation[index_b]
    turns = a.rotations is not None and b.rotations is not None and bool(oriented.any())
    size = a.size if a.size > 0 else 1.0
    features_a, centroid_a = pose_features(
        a.positions, a.rotations if turns else None, index_a, index_a[oriented] if turns else None, size
    )
    features_b, centroid_b = pose_features(
        b.positions, b.rotations if turns else None, index_b, index_b[oriented] if turns else None, size / units_scale
    )
    features_b, centroid_b = at_rate(features_b, rate_b, a.frame_rate), at_rate(centroid_b, rate_b, a.frame_rate)
    features_a = np.concatenate([features_a, travel(centroid_a, a.frame_rate, size)], axis=1)
    features_b = np.concatenate([features_b, travel(centroid_b, a.frame_rate, size / units_scale)], axis=1)
    turn = units_scale * (np.eye(3) if up_rotation is None else up_rotation)

    def tie_break() -> tuple[np.ndarray, np.ndarray]:
        places_a = a.positions[:, index_a].reshape(a.n_frames, -1)
        places_b = at_rate((b.positions[:, index_b] @ turn.T).reshape(b.n_frames, -1), rate_b, a.frame_rate)
        return places_a / size, places_b / size

    return search_offset(features_a, features_b, a.frame_rate, min_overlap=min_overlap, tie_break=tie_break)


def find_offset(
    points_a: np.ndarray, points_b: np.ndarray, rate_a: float, rate_b: float, *, min_overlap: float = 0.5
) -> tuple[int, float]:
    """:func:`search_offset` on point trajectories (Fa, [J,] 3) and (Fb, [J,] 3) in the same
    units (NaN allowed): (lag in A's frames, RMS mismatch of their features)."""
    from gmr_studio.core.compare.tracks import track_of_points

    a = points_a.reshape(points_a.shape[0], -1, 3)
    b = points_b.reshape(points_b.shape[0], -1, 3)
    names = tuple(f"p{k}" for k in range(a.shape[1]))
    track_a, track_b = track_of_points(names, a, rate_a), track_of_points(names, b, rate_b)
    columns = np.arange(a.shape[1])
    found = find_offset_of_tracks(track_a, track_b, columns, columns, rate_b, 1.0, min_overlap=min_overlap)
    return found.lag, found.mismatch
