"""Pops, jitter and root teleports: outliers of a joint's path against its own typical motion.

Pop. With ``P`` (F, J, 3) the world positions, a frame's deviation from the midpoint of its
neighbours is ``e_f = |P_f - (P_{f-1} + P_{f+1}) / 2|`` (half the second difference; a joint
knocked by ``d`` at one frame has ``e_f = d`` and ``e_{f±1} = d/2``; smooth motion gives
``|acceleration| dt² / 2``). Per joint, ``m`` is the median of ``e`` and ``s`` 1.4826 times
its median absolute deviation. Frame f pops when ``e_f > m + pop_mad * s``,
``e_f > pop_limits[0] * size``, ``e_f`` exceeds the span ``|P_{f+1} - P_{f-1}|`` of its
neighbours (a step or a fast stop spans as much as it deviates) and is at least 1.5 times
``e_{f-1}`` and ``e_{f+1}`` (a spike, not a bend). The joints reported are the popping
joints whose parent does not pop at that frame (children follow their parent), largest
first; the value is the largest ``e_f``.

Jitter. Noise makes a path zigzag: consecutive deviations point opposite ways, while smooth
motion bends one way over several frames. With ``m_f = P_f - (P_{f-1} + P_{f+1}) / 2`` (the
vector of ``e_f``), white noise of variance ``σ²`` per axis gives ``m_f · m_{f+1}`` a mean
of ``-3 σ²`` and a median of ``-2.2474 σ²``; smooth motion makes it positive. Frames are
cut into blocks of ``jitter_window`` seconds (at least 10 frames); a block's noise is
``sqrt(max(0, -1.3349 * median(m_f · m_{f+1})))``, the RMS length of the noise vector
(``sqrt(3) σ``; a median, so one pop or step in a block does not count, and fast smooth
motion at 24 Hz reads as no noise; third differences, blind to constant jerk, were tried
and read the 24 Hz swing of a foot as noise). Blocks whose noise reaches
``jitter_limits[0] * size`` are jittery. A joint's runs of them (across gaps of one block)
make a finding, joined by the jittery joints below it whose runs overlap it (a child shakes
with its parent): frames from the first block's start to the last block's end, valued by
the largest of its joints' noise, each the same estimate over all the products of that
joint's jittery blocks.

Teleport. For each root that carries the figure (a root, or the child of an anchor root:
:attr:`core.model.motion.Motion.anchors`), with steps ``V_f = P_{f+1} - P_f``: the jump at step
f is ``|V_f - (V_{f-1} + V_{f+1}) / 2|`` (the step beyond the root's own velocity). A step
is a teleport when its jump is at least ``teleport_limits[0] * size`` and twice
``|V_{f+1} - V_{f-1}|`` (the root keeps its velocity on both sides: a step, not a pop).
The finding covers the frames on both sides of the jump, ``f .. f+1``.
"""

from __future__ import annotations

import math
import struct
import warnings

import numpy as np

from gmr_studio.core.checks.context import CheckData, joint_runs, merge_runs
from gmr_studio.core.checks.model import CheckSettings, Finding, severity_levels
from gmr_studio.core.checks.passes import (
    block_counts_at_most,
    deviations_and_block_counts,
    flat_indices_above,
    medians_and_deviations,
    root_jumps,
    second_differences,
)

#: 1.4826 * MAD estimates a normal standard deviation
MAD_SCALE = 1.4826
#: white noise: 3 σ² (the mean square of the noise vector) over -median(m_f · m_{f+1})
NOISE_FROM_MEDIAN = 3.0 / 2.247362
#: the median and MAD of a joint's deviations are taken from at most this many frames
#: (evenly spread): plenty for a level, and a median costs a partition of them
ROBUST_SAMPLES = 20_000
#: shortest jitter block, frames
MIN_BLOCK = 10


def robust_level(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per column median and 1.4826 MAD of (N, J) values: two (J,) arrays (of every k-th
    row when there are more than :data:`ROBUST_SAMPLES`)."""
    step = max(1, -(-values.shape[0] // ROBUST_SAMPLES))
    median, spread = medians_and_deviations(values, step)
    if np.isnan(median).any() or np.isnan(spread).any():
        columns = np.ascontiguousarray(values[::step].T)
        if np.isnan(columns).any():  # markers' gaps: NaN, and a column without a value gives NaN
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                median = np.nanmedian(columns, axis=1)
                spread = np.nanmedian(np.abs(columns - median[:, None]), axis=1)
    return median, MAD_SCALE * spread


def pop(data: CheckData, settings: CheckSettings) -> list[Finding]:
    p = data.positions
    if data.n_frames < 3:
        return []
    e = _spikes(data, settings)[0]  # (F-2, J)
    median, spread = robust_level(e)
    threshold = np.maximum(median + settings.pop_mad * spread, settings.pop_limits[0] * data.size)
    frames, joints = np.divmod(flat_indices_above(e, threshold), e.shape[1])  # e > threshold
    if not frames.size:
        return []
    span = np.linalg.norm(p[frames + 2, joints] - p[frames, joints], axis=-1)
    last = e.shape[0] - 1
    before = np.where(frames > 0, e[np.maximum(frames - 1, 0), joints], 0.0)  # 0 beyond the ends
    after = np.where(frames < last, e[np.minimum(frames + 1, last), joints], 0.0)
    keep = (e[frames, joints] > span) & (e[frames, joints] >= 1.5 * np.maximum(before, after))
    rows = np.unique(frames[keep])  # the frames where some joint pops, and which joints
    popping = np.zeros((rows.size, e.shape[1]), bool)
    popping[np.searchsorted(rows, frames[keep]), joints[keep]] = True
    parents = data.motion.parents
    source = popping & ~np.where(parents >= 0, popping[:, np.maximum(parents, 0)], False)
    findings = []
    for i in np.flatnonzero(source.any(axis=1)):
        row = int(rows[i])
        found = np.flatnonzero(source[i])
        found = found[np.argsort(-e[row, found], kind="stable")]
        value = float(e[row, found[0]])
        level = severity_levels(value / data.size, settings.pop_limits)
        findings.append(data.finding("pop", found, row + 1, row + 1, level, value, data.units))
    return findings


def block_noise(medians: np.ndarray) -> np.ndarray:
    """The noise of blocks from the medians of their products: ``sqrt(max(0, -1.3349 m))``."""
    return np.sqrt(np.maximum(0.0, -NOISE_FROM_MEDIAN * medians))


def noisiest_product(limit: float) -> float:
    """The largest product whose :func:`block_noise` reaches ``limit`` (inf when every one
    does, NaN when none does): as the noise falls while the median rises, a block's noise
    reaches the limit exactly when its median is at most this, that is when more than half
    of its products are. Found by bisection over the float64 numbers in their order."""

    def reaches(key: int) -> bool:
        with np.errstate(over="ignore"):
            return bool(block_noise(np.float64(_float_of(key))) >= limit)

    low, high = _key_of(-math.inf), _key_of(math.inf)
    if not reaches(low):
        return math.nan
    if reaches(high):
        return math.inf
    while high - low > 1:  # reaches(low), not reaches(high)
        middle = (low + high) // 2
        low, high = (middle, high) if reaches(middle) else (low, middle)
    return _float_of(low)


def _key_of(value: float) -> int:
    """An integer that orders float64 numbers as their values (NaN aside; -0 as +0)."""
    bits = struct.unpack("<q", struct.pack("<d", value))[0]
    return bits if bits >= 0 else -(bits & 0x7FFF_FFFF_FFFF_FFFF)


def _float_of(key: int) -> float:
    """The float64 number of a :func:`_key_of` key."""
    bits = key if key >= 0 else -key | -0x8000_0000_0000_0000
    return struct.unpack("<d", struct.pack("<q", bits))[0]


def jittery_blocks(products: np.ndarray, block: int, limit: float, *, backend: str = "auto") -> np.ndarray:
    """(B, J) bool: the blocks of ``block`` rows of products (N, J) (B = N // block) whose
    :func:`block_noise` of the median reaches ``limit``. Counted against
    :func:`noisiest_product` (the median itself found by numpy with ``backend='numpy'``)."""
    middle = block // 2
    if backend == "numpy":
        n_blocks = products.shape[0] // block
        blocks = products[: n_blocks * block].reshape(n_blocks, block, products.shape[1])
        return block_noise(np.partition(blocks, middle, axis=1)[:, middle]) >= limit
    return block_counts_at_most(products, block, noisiest_product(limit), backend=backend) > middle


def jitter_block(data: CheckData, settings: CheckSettings) -> int:
    """The frames of a jitter block: ``jitter_window`` seconds, at least :data:`MIN_BLOCK`."""
    return max(MIN_BLOCK, round(settings.jitter_window / data.frame_time))


def _spikes(data: CheckData, settings: CheckSettings) -> tuple[np.ndarray, np.ndarray | None]:
    """(deviations (F-2, J), jitter's counts (B, J) of each block's products at most
    :func:`noisiest_product`, or None when jitter does not run): one pass over the positions,
    shared by pops and jitter, that counts the products without keeping them."""
    block = jitter_block(data, settings)
    if "jitter" not in settings.kinds or (data.n_frames - 3) // block < 1:
        return data.deviations, None
    limit = noisiest_product(settings.jitter_limits[0] * data.size)
    return data.cached(
        ("deviations and jitter counts", block, limit),
        lambda: deviations_and_block_counts(data.positions, block, limit),
    )


def jitter(data: CheckData, settings: CheckSettings) -> list[Finding]:
    block = jitter_block(data, settings)
    n_blocks = (data.n_frames - 3) // block
    if n_blocks < 1:
        return []
    counts = _spikes(data, settings)[1]
    if counts is None:  # called without jitter among the kinds
        counts = block_counts_at_most(
            data.middle_products, block, noisiest_product(settings.jitter_limits[0] * data.size)
        )
    jittery = counts > block // 2  # (B, J): more than half at most the noisiest product (jittery_blocks)
    found = joint_runs(jittery)
    runs_of = {int(k): merge_runs(found[found[:, 0] == k, 1:], 1) for k in np.unique(found[:, 0])}
    groups: list[dict] = []  # a jittery joint, the jittery joints below it, their block range
    held: dict[int, list[dict]] = {}  # joint -> the groups it is in
    parents = data.motion.parents
    for k in data.motion.topological_order:
        for start, stop in runs_of.get(int(k), ()):
            above = [g for g in held.get(int(parents[k]), []) if g["start"] < stop and start < g["stop"]]
            group = above[0] if above else {"joints": [], "start": start, "stop": stop, "value": 0.0}
            if not above:
                groups.append(group)
            products = second_differences(data.positions[start * block : stop * block + 3])[1]  # of the run's blocks
            inside = products.reshape(stop - start, block, -1)[:, :, k][jittery[start:stop, k]]  # of its jittery ones
            value = float(np.sqrt(max(0.0, -NOISE_FROM_MEDIAN * np.nanmedian(inside))))
            group["joints"].append(int(k))
            group.update(start=min(group["start"], start), stop=max(group["stop"], stop))
            group["value"] = max(group["value"], value)
            held.setdefault(int(k), []).append(group)
    findings = []
    for g in groups:
        level = max(1, severity_levels(g["value"] / data.size, settings.jitter_limits))  # its blocks passed
        first, last = g["start"] * block, g["stop"] * block + 2  # the last block ends by frame F - 1
        findings.append(data.finding("jitter", g["joints"], first, last, level, g["value"], data.units))
    return findings


def figure_roots(data: CheckData) -> list[int]:
    """The roots that carry the figure: each root, or the children of an anchor root."""
    motion = data.motion
    out: list[int] = []
    for root in motion.roots:
        out.extend(motion.children[root] if motion.anchors[root] else [int(root)])
    return out


def teleport(data: CheckData, settings: CheckSettings) -> list[Finding]:
    if data.n_frames < 4:
        return []
    roots = figure_roots(data)
    jump, change = root_jumps(data.positions, roots)  # (F-3, R), step i+1
    teleporting = (jump >= settings.teleport_limits[0] * data.size) & (jump >= 2.0 * change)
    findings = []
    for k, start, stop in joint_runs(teleporting):
        value = float(jump[start:stop, k].max())
        level = severity_levels(value / data.size, settings.teleport_limits)
        findings.append(data.finding("teleport", [roots[k]], start + 1, stop + 1, level, value, data.units))
    return findings
