"""Compare two tracks (or motions): match, one clock, one space, errors per frame and joint."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np

from gmr_studio.core.compare.align import ALIGN_KINDS, Alignment, fit_alignment, rms_of_squares
from gmr_studio.core.compare.clock import DEFAULT_OFFSET, check_overlap
from gmr_studio.core.compare.offset import find_offset_of_tracks
from gmr_studio.core.compare.result import Comparison
from gmr_studio.core.compare.tracks import Track, space_change, track_of_motion
from gmr_studio.core.jointmap import JointMap, JointMatch, match_joints
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.similarity import Similarity
from gmr_studio.core.timebase.clock import common_rate
from gmr_studio.core.timebase.sampling import (
    WHOLE_FRAME_TOLERANCE,
    interpolate,
    rotations_component_major,
    take,
    whole_frames,
)

#: frames per block of the rotation error (temporaries of ~3 MB for 38 joints)
ROTATION_BLOCK = 1024
#: frames per block when B is resampled between its frames (component-major temporaries)
ROTATION_BLOCK_INTERPOLATED = 256
#: rows per matrix product (:func:`_times_transposed`)
PRODUCT_CHUNK = 2048
FramesArg = slice | tuple[int | None, int | None] | np.ndarray | None


def compare_motions(
    a: Motion,
    b: Motion,
    *,
    joint_map: str | Path | JointMap | Mapping[str, str] | None = None,
    match: JointMatch | None = None,
    with_rotations: bool = True,
    label_a: str = "",
    label_b: str = "",
    **options,
) -> Comparison:
    """Compare motion B with motion A: :func:`compare_tracks` on their joints.

    ``match`` (explicit pairs) wins over ``joint_map``; with neither, equal names pair.
    ``options`` go to :func:`compare_tracks` (frames, offset, align, scale, up_b).
    """
    track_a = track_of_motion(a, with_rotations=with_rotations, label=label_a)
    track_b = track_of_motion(b, with_rotations=with_rotations, label=label_b)
    return compare_tracks(track_a, track_b, match or match_joints(a.names, b.names, joint_map), **options)


def compare_tracks(
    a: Track,
    b: Track,
    match: JointMatch,
    *,
    frames: FramesArg = None,
    offset: float | str = DEFAULT_OFFSET,
    align: str = "none",
    scale: float | None = None,
    up_b: str | None = None,
    max_offset_overlap: float = 0.5,
) -> Comparison:
    """B compared with A over A's ``frames``, B put on A's clock and in A's space.

    Parameters
    ----------
    a, b : the two tracks; errors come out in A's units, on A's frames.
    match : which point of A goes with which of B.
    frames : A's frames to compare: a slice, ``(start, stop)`` (stop excluded, None = end)
        or an array of indices; default all.
    offset : B's time minus A's, in A's frames (any real number), or ``"auto"`` to find it
        from the whole body (:func:`core.compare.offset.search_offset`); the default,
        :data:`core.compare.clock.DEFAULT_OFFSET`, is the CLI's and the app's.
    align : "none", "rigid" or "similarity", fitted over all compared frames.
    scale, up_b : A units per B unit and B's up axis, when the files do not say (or say
        wrong); see :func:`core.compare.tracks.space_change`.

    Raises ValueError for nothing matched, frames out of range, a bad option, or clocks that
    share no time at the offset (:func:`core.compare.clock.check_overlap`).
    """
    if not match.pairs:
        raise ValueError(
            "no joints matched: give a joint map (--map) that pairs their names "
            f"(A has {', '.join(match.unmatched_a[:4])}...; B has {', '.join(match.unmatched_b[:4])}...)"
        )
    if align not in ALIGN_KINDS:
        raise ValueError(f"alignment must be one of {', '.join(ALIGN_KINDS)}, not {align!r}")
    index_a = np.array([i for i, _ in match.pairs], dtype=np.int64)
    index_b = np.array([j for _, j in match.pairs], dtype=np.int64)
    rows = _frames_of(frames, a.n_frames)
    space = space_change(a, b, scale=scale, up_b=up_b)

    rate_b, notes = common_rate(a.frame_rate, b.frame_rate), list(space.notes)
    if rate_b != b.frame_rate:
        notes.append(
            f"frame rates {a.frame_rate:.7g} and {b.frame_rate:.7g} Hz taken as equal "
            "(they differ by the rounding of a printed frame time)"
        )
    search = None
    if isinstance(offset, str):
        if offset != "auto":
            raise ValueError(f"the offset must be a number of frames or 'auto', not {offset!r}")
        search = find_offset_of_tracks(
            a, b, index_a, index_b, rate_b, space.scale, up_rotation=space.up_rotation, min_overlap=max_offset_overlap
        )
        offset_frames, found = float(search.lag), True
    else:
        offset_frames, found = float(offset), False
        if not np.isfinite(offset_frames):
            raise ValueError(f"the offset must be a finite number of frames, not {offset}")
    offset_seconds = offset_frames / a.frame_rate
    times = rows / a.frame_rate  # (core.timebase.clock.frame_seconds, by the rate: the bits the tests pin)
    at = (times + offset_seconds) * rate_b
    check_overlap(at, b.n_frames, rows, offset_frames, offset_seconds)

    positions_a = take(a.positions, rows, index_a)
    positions_b = interpolate(b.positions, at, index_b)
    q = space.up_rotation
    pre_fit = positions_b
    if space.scale != 1.0 or not np.array_equal(q, np.eye(3)):
        pre_fit = _transformed(positions_b, space.scale * q, np.zeros(3))
    # B's frames outside its time range are NaN: fit on the run of the others (views, so
    # that the fit need not gather the points present on both sides when none else is missing)
    fit_rows = _run_inside(at, b.n_frames)
    rotation, translation, fitted_scale = fit_alignment(positions_a[fit_rows], pre_fit[fit_rows], align)
    aligned_b = pre_fit if align == "none" else _transformed(pre_fit, fitted_scale * rotation, translation)
    difference = np.subtract(positions_a, pre_fit)
    if align != "none":
        rms_before = rms_of_squares(np.einsum("fjk,fjk->fj", difference, difference))
        np.subtract(positions_a, aligned_b, out=difference)
    squared = np.einsum("fjk,fjk->fj", difference, difference)
    rms_after = rms_of_squares(squared)
    if align == "none":
        rms_before = rms_after
    position_error = np.sqrt(squared, out=squared)

    alignment = Alignment(
        kind=align,
        space=space.transform,
        fit=Similarity(rotation, fitted_scale, translation),
        offset_frames=offset_frames,
        offset_seconds=offset_seconds,
        offset_found=found,
        offset_search=search,
        rms_before=rms_before,
        rms_after=rms_after,
        notes=tuple(notes),
    )
    rotation_error = None
    if a.rotations is not None and b.rotations is not None:
        rotation_error = _rotation_error(a, b, rows, at, index_a, index_b, alignment)
    return Comparison(
        names_a=tuple(a.names[i] for i in index_a),
        names_b=tuple(b.names[j] for j in index_b),
        index_a=index_a,
        index_b=index_b,
        unmatched_a=list(match.unmatched_a),
        unmatched_b=list(match.unmatched_b),
        frames=rows,
        times=times,
        positions_a=positions_a,
        positions_b=aligned_b,
        position_error=position_error,
        rotation_error=rotation_error,
        alignment=alignment,
        units=a.units,
        size_a=a.size,
        label_a=a.label,
        label_b=b.label,
    )


def _rotation_error(
    a: Track,
    b: Track,
    rows: np.ndarray,
    at: np.ndarray,
    index_a: np.ndarray,
    index_b: np.ndarray,
    alignment: Alignment,
) -> np.ndarray:
    """(F, J) degrees between A's world rotations and B's, B's moved into A's space.

    The angle comes from the chord ``|W_a - W_b|_F = 2 sqrt(2) sin(angle / 2)``, accurate
    near 0 where a trace formula loses half the digits; above 90 degrees, where the chord's
    arcsin amplifies rounding, from ``arctan2`` of the axis and the trace
    (:func:`angle_between`). Computed in blocks of frames so that the temporaries stay in
    the cache and no (F, J, 3, 3) copy is made.

    B's whole frames are taken as they are (row-major); B between its frames is resampled
    component-major (:func:`core.compare.clock.rotations_component_major`) and A is put in
    the same order, turned by the inverse of B's turn instead of B (``|W_a - M W_b N| =
    |M^T W_a N^T - W_b|`` for rotations M, N).
    """
    turn = None
    if not (alignment.kind == "none" and np.array_equal(alignment.space.rotation, np.eye(3))):
        # W_b -> M W_b N on the 9 entries: vec(M W N)[a, d] = sum_bc M[a, b] N[c, d] W[b, c]
        m, n = alignment.fit.rotation @ alignment.space.rotation, alignment.space.rotation.T
        turn = np.einsum("ab,cd->adbc", m, n).reshape(9, 9)
    n_pairs = len(index_a)
    angle = np.empty((len(rows), n_pairs))
    whole = whole_frames(at)
    block_frames = ROTATION_BLOCK if whole else ROTATION_BLOCK_INTERPOLATED
    for start in range(0, len(rows), block_frames):
        block = slice(start, start + block_frames)
        ra = take(a.rotations, rows[block], index_a).reshape(-1, 9)
        if whole:
            rb = interpolate(b.rotations, at[block], index_b).reshape(-1, 9)
            if turn is not None:
                rb = _times_transposed(rb, turn)  # a new (n, 9) array, turned B
            difference = np.subtract(ra, rb, out=rb if turn is not None else None)
            chord2 = np.einsum("np,np->n", difference, difference)
        else:
            rb = rotations_component_major(b.rotations, at[block], index_b).reshape(9, -1)
            if turn is not None:
                ra = _times_transposed(ra, turn.T)  # A turned back: M^T W_a N^T
            ra = np.ascontiguousarray(ra.T)  # (9, n), component-major
            difference = np.subtract(ra, rb)
            chord2 = np.einsum("pn,pn->n", difference, difference)
        result = np.sqrt(chord2)
        result *= 1.0 / (2.0 * np.sqrt(2.0))
        np.minimum(result, 1.0, out=result)
        np.arcsin(result, out=result)
        result *= 2.0
        far = chord2 > 4.0  # above 90 degrees
        if far.any():
            if whole:
                result[far] = angle_between(ra[far], ra[far] - difference[far])
            else:
                result[far] = angle_between(ra[:, far].T, rb[:, far].T)
        angle[block] = result.reshape(-1, n_pairs)
    angle = np.degrees(angle, out=angle)
    oriented = a.has_rotation[index_a] & b.has_rotation[index_b]
    if not oriented.all():
        angle[:, ~oriented] = np.nan
    return angle


def angle_between(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Geodesic angle (radians) between rotations given as rows (K, 9) of row-major 3 x 3
    matrices: ``arctan2(|sum_k A[:, k] x B[:, k]|, A : B - 1)`` (twice the sine and cosine),
    accurate at every angle, 0 and 180 degrees included."""
    a, b = first.reshape(-1, 3, 3), second.reshape(-1, 3, 3)
    axis = np.cross(a, b, axis=1).sum(axis=-1)
    return np.arctan2(np.linalg.norm(axis, axis=-1), np.einsum("kij,kij->k", a, b) - 1.0)


def _transformed(points: np.ndarray, matrix: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """``matrix @ p + translation`` for points (..., 3)."""
    out = _times_transposed(points.reshape(-1, 3), matrix).reshape(points.shape)
    if np.any(translation):
        out += translation
    return out


def _times_transposed(rows: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """``rows @ matrix.T`` for rows (N, K), matrix (L, K) -> (N, L), in chunks of
    :data:`PRODUCT_CHUNK` rows: each product is small enough for BLAS to run it on the
    calling thread (a whole-array product starts threads that cost more CPU than the work;
    einsum's generic loop is slower still)."""
    out = np.empty((rows.shape[0], matrix.shape[0]))
    right = np.ascontiguousarray(matrix.T)
    for start in range(0, rows.shape[0], PRODUCT_CHUNK):
        chunk = slice(start, start + PRODUCT_CHUNK)
        np.matmul(rows[chunk], right, out=out[chunk])
    return out


def _run_inside(at: np.ndarray, n_frames_b: int) -> slice:
    """The rows of ``at`` (F,) from the first inside B's range to the last, if all between are
    inside (``at`` increasing); else all rows."""
    inside = (at >= -WHOLE_FRAME_TOLERANCE) & (at <= n_frames_b - 1 + WHOLE_FRAME_TOLERANCE)
    where = np.flatnonzero(inside)
    if where.size and where[-1] - where[0] == where.size - 1:
        return slice(int(where[0]), int(where[-1]) + 1)
    return slice(None)


def _frames_of(frames: FramesArg, n_frames: int) -> np.ndarray:
    """A's frames to compare as sorted unique indices (F,) int64; ValueError if out of range."""
    if frames is None:
        return np.arange(n_frames, dtype=np.int64)
    if isinstance(frames, tuple):
        frames = slice(*frames)
    if isinstance(frames, slice):
        rows = np.arange(n_frames, dtype=np.int64)[frames]
    else:
        rows = np.unique(np.asarray(frames, dtype=np.int64))
        if rows.size and (rows[0] < 0 or rows[-1] >= n_frames):
            raise ValueError(f"frames must be within 0..{n_frames - 1} (A's frames)")
    if not rows.size:
        raise ValueError(f"no frames to compare: A has {n_frames} frames")
    return rows
