"""Compiled per-frame statistics of the checks (numba); imported by :mod:`core.checks.passes` only.

Importing this module raises ImportError when numba is not installed; the checks then run
the numpy path of :mod:`core.checks.passes`, the reference these kernels are tested
against. Each kernel reads the positions or rotations once, in storage order, and writes
only its small result: no temporaries of the motion's size. The middles are formed with the
numpy path's operations (the same numbers); sums of three products may differ from numpy's
in the last bit.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(nogil=True, cache=True, boundscheck=False)
def second_differences(positions, deviations, products, block, limit, counts):  # pragma: no cover - compiled
    """positions (F, J, 3) -> deviations (F-2, J): the length of each middle ``m_f = P_f -
    (P_{f-1} + P_{f+1}) / 2`` (frames 1..F-2), and the products ``m_f . m_{f+1}`` (row i:
    frames i..i+3): into products (F-3, J) unless it is empty, and counted into counts
    (B, J) unless it is empty: how many of each block of ``block`` rows are at most
    ``limit`` (NaN is not)."""
    n_frames, n_joints = positions.shape[0], positions.shape[1]
    keep, count = products.shape[0] > 0, counts.shape[0] > 0
    if count:
        counts[:] = 0
    previous = np.empty((n_joints, 3))
    for f in range(n_frames - 2):
        b = (f - 1) // block if count else 0
        counted = count and f > 0 and b < counts.shape[0]
        for j in range(n_joints):
            m0 = (positions[f, j, 0] + positions[f + 2, j, 0]) * -0.5 + positions[f + 1, j, 0]
            m1 = (positions[f, j, 1] + positions[f + 2, j, 1]) * -0.5 + positions[f + 1, j, 1]
            m2 = (positions[f, j, 2] + positions[f + 2, j, 2]) * -0.5 + positions[f + 1, j, 2]
            deviations[f, j] = math.sqrt((m0 * m0 + m1 * m1) + m2 * m2)
            if f > 0:
                product = (previous[j, 0] * m0 + previous[j, 1] * m1) + previous[j, 2] * m2
                if keep:
                    products[f - 1, j] = product
                if counted and product <= limit:
                    counts[b, j] += 1
            previous[j, 0] = m0
            previous[j, 1] = m1
            previous[j, 2] = m2


@numba.njit(inline="always", boundscheck=False)
def _squared_step(positions, f, j):  # pragma: no cover - compiled
    """``|P_{f+1} - P_f|^2`` of joint j, summed in the order x, y, z."""
    d0 = positions[f + 1, j, 0] - positions[f, j, 0]
    d1 = positions[f + 1, j, 1] - positions[f, j, 1]
    d2 = positions[f + 1, j, 2] - positions[f, j, 2]
    return (d0 * d0 + d1 * d1) + d2 * d2


@numba.njit(nogil=True, cache=True, boundscheck=False)
def largest_steps(positions, joints, out):  # pragma: no cover - compiled
    """positions (F, J, 3) -> out (F-1,): the largest squared step ``|P_{f+1} - P_f|^2`` of
    the ``joints``, NaN ignored as ``numpy.fmax`` ignores it (NaN when every one is)."""
    for f in range(positions.shape[0] - 1):
        largest = np.nan
        for k in range(joints.shape[0]):
            j = joints[k]
            value = _squared_step(positions, f, j)
            if math.isnan(largest) or value > largest:
                if not math.isnan(value):
                    largest = value
        out[f] = largest


@numba.njit(inline="always", boundscheck=False)
def _step_cosine(rotations, f, j):  # pragma: no cover - compiled
    """The cosine of the angle of ``R_f^T R_{f+1}`` of joint j, clipped to [-1, 1]."""
    total = 0.0
    for a in range(3):
        for b in range(3):
            total += rotations[f + 1, j, a, b] * rotations[f, j, a, b]
    cos = 0.5 * (total - 1.0)
    if cos < -1.0:
        return -1.0
    if cos > 1.0:
        return 1.0
    return cos


@numba.njit(nogil=True, cache=True, boundscheck=False)
def step_cosines(rotations, joints, out):  # pragma: no cover - compiled
    """rotations (F, J, 3, 3) -> out (F-1, K): the cosine of the angle of ``R_f^T R_{f+1}``
    of each of the ``joints`` (K,), ``(trace - 1) / 2`` from the sum of the entries'
    products, clipped to [-1, 1] (NaN stays NaN)."""
    for f in range(rotations.shape[0] - 1):
        for k in range(joints.shape[0]):
            out[f, k] = _step_cosine(rotations, f, joints[k])


@numba.njit(nogil=True, cache=True, boundscheck=False)
def counts_at_most(values, block, limit, out):  # pragma: no cover - compiled
    """values (N, J) -> out (B, J): how many of each block of ``block`` rows (block b: rows
    ``b * block ..``) are at most ``limit`` (NaN is not)."""
    n_blocks, n_columns = out.shape
    for b in range(n_blocks):
        for j in range(n_columns):
            out[b, j] = 0
        for r in range(b * block, (b + 1) * block):
            for j in range(n_columns):
                if values[r, j] <= limit:
                    out[b, j] += 1


#: the bits of a float64 other than its sign
_MAGNITUDE = 0x7FFF_FFFF_FFFF_FFFF
#: a radix digit: 12 bits, the first the sign and exponent
_DIGIT_BITS = 12
_DIGITS = 1 << _DIGIT_BITS


@numba.njit(inline="always", boundscheck=False)
def _keys(values, n, keys):  # pragma: no cover - compiled
    """keys[:n]: int64 numbers in the order of the finite float64 values[:n] (-0 before +0)."""
    bits = values[:n].view(np.int64)
    for i in range(n):
        b = bits[i]
        keys[i] = b if b >= 0 else b ^ _MAGNITUDE


@numba.njit(inline="always", boundscheck=False)
def _value(key):  # pragma: no cover - compiled
    """The float64 of a key of :func:`_keys`."""
    bits = np.empty(1, np.int64)
    bits[0] = key if key >= 0 else key ^ _MAGNITUDE
    return bits.view(np.float64)[0]


@numba.njit(inline="always", boundscheck=False)
def _digit(key, shift):  # pragma: no cover - compiled
    if shift == 64 - _DIGIT_BITS:
        return (key >> shift) + _DIGITS // 2  # the top digit, signed
    return (key >> shift) & (_DIGITS - 1)


@numba.njit(inline="always", boundscheck=False)
def _select(keys, n, rank, pair, scratch, counts):  # pragma: no cover - compiled
    """The keys of ranks ``rank`` and, when ``pair``, ``rank + 1`` (else ``rank`` again) among
    keys[:n] (0: the smallest), by radix: the digits from the top, keeping the keys of the
    digit that holds the ranks; ranks in two digits are the largest key of the one and the
    smallest of the next (scratch, counts: work space)."""
    source = keys
    m = n
    shift = 64 - _DIGIT_BITS
    while shift >= 0 and m > 16:  # shifts 52, 40, 28, 16, 4, then 0 (bits 4 to 11 again)
        counts[:] = 0
        for i in range(m):
            counts[_digit(source[i], shift)] += 1
        digit, below = 0, 0
        while below + counts[digit] <= rank:
            below += counts[digit]
            digit += 1
        rank -= below
        if pair and rank + 1 == counts[digit]:  # the next rank in the next digit that has keys
            following = digit + 1
            while counts[following] == 0:
                following += 1
            low, high = source[0], source[0]
            found_low, found_high = False, False
            for i in range(m):
                d = _digit(source[i], shift)
                if d == digit and (not found_low or source[i] > low):
                    low, found_low = source[i], True
                elif d == following and (not found_high or source[i] < high):
                    high, found_high = source[i], True
            return low, high
        if counts[digit] < m:  # keep those with that digit (in place once in scratch)
            kept = 0
            for i in range(m):
                if _digit(source[i], shift) == digit:
                    scratch[kept] = source[i]
                    kept += 1
            source, m = scratch, kept
        shift = -1 if shift == 0 else max(shift - _DIGIT_BITS, 0)
    if shift < 0:  # every digit the same: the keys left are equal
        return source[0], source[0]
    for i in range(1, m):  # a few left: sort them
        key, j = source[i], i - 1
        while j >= 0 and source[j] > key:
            source[j + 1] = source[j]
            j -= 1
        source[j + 1] = key
    return source[rank], source[rank + 1] if pair else source[rank]


@numba.njit(inline="always", boundscheck=False)
def _median(values, n, keys, scratch, counts):  # pragma: no cover - compiled
    """The median of the finite values[:n] as numpy's: the middle value, or the mean
    ``(a + b) / 2`` of the two middle ones."""
    _keys(values, n, keys)
    if n % 2:
        return _value(_select(keys, n, n // 2, False, scratch, counts)[0])
    lower, upper = _select(keys, n, n // 2 - 1, True, scratch, counts)
    return (_value(lower) + _value(upper)) / 2.0


@numba.njit(nogil=True, cache=True, boundscheck=False)
def medians_and_deviations(values, step, medians, deviations):  # pragma: no cover - compiled
    """values (N, J) -> medians (J,), deviations (J,): of each column of ``values[::step]``
    its median and (when deviations holds J values) the median of its absolute deviations
    from it. Returns False, with the outputs unset, when one of those values is NaN or
    infinite."""
    n = (values.shape[0] + step - 1) // step
    n_columns = values.shape[1]
    if n == 0:
        return False
    buffer = np.empty((n_columns, n))
    for i in range(n):
        for j in range(n_columns):
            value = values[i * step, j]
            if not math.isfinite(value):
                return False
            buffer[j, i] = value
    column = np.empty(n)
    keys, scratch, counts = np.empty(n, np.int64), np.empty(n, np.int64), np.empty(_DIGITS, np.int64)
    for j in range(n_columns):
        middle = _median(buffer[j], n, keys, scratch, counts)
        medians[j] = middle
        if deviations.shape[0]:
            for i in range(n):
                column[i] = abs(buffer[j, i] - middle)
            deviations[j] = _median(column, n, keys, scratch, counts)
    return True


@numba.njit(nogil=True, cache=True, boundscheck=False)
def cosines_below(rotations, joints, limit, indices, cosines):  # pragma: no cover - compiled
    """The steps of :func:`step_cosines` whose cosine is below ``limit``: their flat indices
    ``f * K + k`` in order into indices and their cosines into cosines, as far as those hold
    (K = joints.size). Returns how many there are."""
    n_joints = joints.shape[0]
    count = 0
    capacity = indices.shape[0]
    for f in range(rotations.shape[0] - 1):
        for k in range(n_joints):
            cos = _step_cosine(rotations, f, joints[k])
            if cos < limit:
                if count < capacity:
                    indices[count] = f * n_joints + k
                    cosines[count] = cos
                count += 1
    return count


@numba.njit(nogil=True, cache=True, boundscheck=False)
def joint_coordinates(positions, joints, out):  # pragma: no cover - compiled
    """positions (F, J, 3) -> out (3, K, F): each coordinate of the ``joints`` (K,)."""
    for f in range(positions.shape[0]):
        for k in range(joints.shape[0]):
            j = joints[k]
            out[0, k, f] = positions[f, j, 0]
            out[1, k, f] = positions[f, j, 1]
            out[2, k, f] = positions[f, j, 2]


@numba.njit(nogil=True, cache=True, boundscheck=False)
def above(values, limits, indices):  # pragma: no cover - compiled
    """values (N, J), limits (J,): the flat indices ``n * J + j`` where ``values[n, j] >
    limits[j]``, in order, into indices as far as it holds. Returns how many there are."""
    n_columns = values.shape[1]
    count = 0
    capacity = indices.shape[0]
    for n in range(values.shape[0]):
        for j in range(n_columns):
            if values[n, j] > limits[j]:
                if count < capacity:
                    indices[count] = n * n_columns + j
                count += 1
    return count


@numba.njit(nogil=True, cache=True, boundscheck=False)
def root_jumps(positions, roots, jumps, changes):  # pragma: no cover - compiled
    """positions (F, J, 3) -> jumps, changes (F-3, R) of the ``roots`` (R,): with steps
    ``V_f = P_{f+1} - P_f``, ``|V_{f+1} - (V_f + V_{f+2}) / 2|`` and ``|V_{f+2} - V_f|``,
    each formed as numpy forms them (``0.5 * (a + b)``; lengths ``sqrt((x² + y²) + z²)``)."""
    for f in range(positions.shape[0] - 3):
        for r in range(roots.shape[0]):
            j = roots[r]
            jump = 0.0
            change = 0.0
            for a in range(3):
                v0 = positions[f + 1, j, a] - positions[f, j, a]
                v1 = positions[f + 2, j, a] - positions[f + 1, j, a]
                v2 = positions[f + 3, j, a] - positions[f + 2, j, a]
                d = v1 - 0.5 * (v0 + v2)
                c = v2 - v0
                jump = jump + d * d if a else d * d
                change = change + c * c if a else c * c
            jumps[f, r] = math.sqrt(jump)
            changes[f, r] = math.sqrt(change)


@numba.njit(nogil=True, cache=True, boundscheck=False)
def skate_windows(x, y, planted, group, w, limit, covered, stillest):  # pragma: no cover - compiled
    """x, y, planted (K, F) of the foot joints; of the joints ``group`` (G,): covered (F-1,)
    the steps in some window ``f .. f+w`` that slides (every joint of the group planted
    throughout it moved more than ``limit``, and one is), stillest (F-1,) the smallest step
    of the joints planted at both ends of it (inf: none; NaN as ``numpy.min`` passes it on)."""
    n = x.shape[1]
    held = np.zeros(group.shape[0], np.int64)  # frames planted in a row, up to frame e
    last = -n  # the last window that slid
    for e in range(n):
        for i in range(group.shape[0]):
            held[i] = held[i] + 1 if planted[group[i], e] else 0
        if e >= 1:
            s = e - 1
            least = np.inf
            for i in range(group.shape[0]):
                k = group[i]
                if planted[k, s] and planted[k, e] and not math.isnan(least):
                    dx = x[k, e] - x[k, s]
                    dy = y[k, e] - y[k, s]
                    step = math.sqrt(dx * dx + dy * dy)
                    if math.isnan(step) or step < least:
                        least = step
            stillest[s] = least
        f = e - w
        if f >= 0:
            slides, inside = True, False
            for i in range(group.shape[0]):
                if held[i] >= w + 1:
                    inside = True
                    k = group[i]
                    dx = x[k, e] - x[k, f]
                    dy = y[k, e] - y[k, f]
                    if not math.sqrt(dx * dx + dy * dy) > limit:
                        slides = False
            if slides and inside:
                last = f
            covered[f] = last > f - w
    for s in range(max(n - w, 0), n - 1):  # the steps after the last window's start
        covered[s] = last > s - w


@numba.njit(nogil=True, cache=True, boundscheck=False)
def steps_within(positions, joints, tolerance, out):  # pragma: no cover - compiled
    """positions (F, J, 3) -> out (F-1,) bool: whether :func:`largest_steps` of the ``joints``
    is at most ``tolerance``: some step not NaN, none above (each frame left at the first
    step above)."""
    for f in range(positions.shape[0] - 1):
        seen, within = False, True
        for k in range(joints.shape[0]):
            j = joints[k]
            value = _squared_step(positions, f, j)
            if not math.isnan(value):
                seen = True
                if value > tolerance:
                    within = False
                    break
        out[f] = seen and within
