"""Frozen stretches, duplicated frames and rest-pose frames at the ends: whole poses.

Same pose. Frames f and f+1 show the same pose when no joint moves more than
``same_pose * size`` between them (1e-7: a frame copied in the file, not a subject holding
still, whose capture noise is far larger; a marker missing at either frame, NaN, is left
out, and a step with none present never keeps the pose). A run of n consecutive frames showing one pose
is *frozen* when it lasts ``n * frame_time >= frozen_limits[0]`` seconds (frames
``a .. a+n-1``, valued in seconds), otherwise its ``n-1`` copies are *duplicates* (frames
``a+1 .. a+n-1``, valued in frames). Both have no joints: the whole pose.

Rest pose. A rest pose is a pose held by the whole body: the joints that move in the
take. A non-root joint with rotation channels *moves in the take* in proportion to the
share of the take's steps at which its rotation changes (:func:`moving_weights`: among
:data:`MOVING_SAMPLES` frames spread over the take), and a frame is in the rest pose when
the joints within ``rest_angle`` degrees of the identity (trace at least ``1 + 2
cos(rest_angle)``) weigh at least ``rest_fraction`` of them all: the T-pose frame
exporters put at the start of a take. A fraction, not all: cgspeed's CMU BVH frame 0 sets
the thighs to 17 degrees and the arms to 5 (the 75-frame clip also the neck and head) and
every other joint to zero, while no frame of a take holds most of its moving joints within
half a degree of zero. Weighted, not counted: a joint that changes once, between a
reference frame and the take (cgspeed's fingers, most of a Second Life animation's 150
face, finger and hand joints, which sit at zero after the reference frame 0), hardly moves
in the take, and a crouch whose face and fingers are at zero is no rest pose. Runs of such
frames starting at the first frame or ending at the last are reported, valued in frames; a
motion in the rest pose throughout is a pose, not a take with rest frames left in, and is
not reported. The other checks skip these frames (:func:`rest_frames`), and the report says
so (:func:`core.checks.run.skipped_frames`).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.checks.context import CheckData, runs
from gmr_studio.core.checks.model import CheckSettings, Finding, severity_levels
from gmr_studio.core.checks.passes import steps_within
from gmr_studio.core.model.motion import Motion


def same_pose_runs(data: CheckData, settings: CheckSettings) -> np.ndarray:
    """(R, 2) half-open runs ``[a, b)`` of frame steps ``f -> f+1`` that keep the pose: the
    frames ``a .. b`` show one pose."""
    if data.n_frames < 2:
        return np.zeros((0, 2), np.int64)
    p, tolerance = data.positions, (settings.same_pose * data.size) ** 2
    leaves = [j for j, kids in enumerate(data.motion.children) if not kids] + list(data.motion.roots)
    same = steps_within(p, leaves, tolerance)  # a first screen: the leaves and roots; NaN: a gap
    candidates = np.flatnonzero(same)
    if candidates.size:  # then every joint, at the steps that passed the screen
        steps = p[candidates + 1] - p[candidates]
        same[candidates] = np.fmax.reduce(np.einsum("fja,fja->fj", steps, steps), axis=1) <= tolerance
    return runs(same)


def _held(data: CheckData, settings: CheckSettings, frozen: bool) -> list[Finding]:
    findings = []
    for a, b in data.cached(("same pose", settings.same_pose), lambda: same_pose_runs(data, settings)):
        n = int(b - a + 1)
        seconds = n * data.frame_time
        if frozen and seconds >= settings.frozen_limits[0]:
            level = severity_levels(seconds, settings.frozen_limits)
            findings.append(data.finding("frozen", [], a, b, level, seconds, "s"))
        elif not frozen and seconds < settings.frozen_limits[0]:
            level = severity_levels(n - 1, settings.duplicate_limits)
            if level:
                findings.append(data.finding("duplicate", [], a + 1, b, level, n - 1, "frames"))
    return findings


def frozen(data: CheckData, settings: CheckSettings) -> list[Finding]:
    return _held(data, settings, frozen=True)


def duplicate(data: CheckData, settings: CheckSettings) -> list[Finding]:
    return _held(data, settings, frozen=False)


#: frames compared to tell the joints that move from those that never do
MOVING_SAMPLES = 64


def moving_weights(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """How much each joint moves in the take: (K,) int64 the non-root joints with rotation
    channels whose rotation changes among :data:`MOVING_SAMPLES` frames spread over the take,
    and (K,) float64 their weights, the share of the steps between those frames at which
    each one's rotation changes (1 for a joint moving throughout; 1/63 for one that changes
    between the first two sampled frames only)."""
    inner = np.array([p >= 0 and bool(o) for p, o in zip(motion.parents, motion.rotation_orders)], dtype=bool)
    sample = np.unique(np.linspace(0, motion.n_frames - 1, MOVING_SAMPLES).round().astype(np.int64))
    rotations = motion.rotations[sample]  # (S, J, 3, 3)
    if sample.size < 2:
        return np.zeros(0, np.int64), np.zeros(0)
    changes = (rotations[1:] != rotations[:-1]).any(axis=(2, 3)).mean(axis=0)  # (J,)
    moving = np.flatnonzero(inner & (changes > 0))
    return moving, changes[moving]


def _moving_joints(motion: Motion) -> np.ndarray:
    """(K,) int64: the joints of :func:`moving_weights`."""
    return moving_weights(motion)[0]


def rest_fractions(motion: Motion, settings: CheckSettings, frames: slice | np.ndarray = slice(None)) -> np.ndarray:
    """(N,) the share of the moving joints' weight (:func:`moving_weights`) within
    ``rest_angle`` of the identity at each of ``frames`` (0 when no joint moves)."""
    moving, weights = moving_weights(motion)
    rotations = motion.rotations[frames]
    if not moving.size:
        return np.zeros(rotations.shape[0])
    diagonal = np.stack([np.trace(rotations[:, j], axis1=-2, axis2=-1) for j in moving], axis=1)  # (N, K)
    at_rest = diagonal >= 1.0 + 2.0 * np.cos(np.radians(settings.rest_angle))
    return at_rest @ weights / weights.sum()


def rest_mask(motion: Motion, settings: CheckSettings, frames: slice | np.ndarray = slice(None)) -> np.ndarray:
    """(N,) bool: which of ``frames`` are in the rest pose (module docstring)."""
    return rest_fractions(motion, settings, frames) >= settings.rest_fraction


def _run_from_start(motion: Motion, settings: CheckSettings, backwards: bool) -> int:
    """How many frames from one end are in the rest pose, looking at growing chunks."""
    n, chunk = motion.n_frames, 16
    while True:
        count = min(chunk, n)
        frames = np.arange(n - 1, n - 1 - count, -1) if backwards else np.arange(count)
        rest = rest_mask(motion, settings, frames)
        if not rest.all() or count == n:
            return int(np.argmin(rest)) if not rest.all() else n
        chunk *= 4


def rest_frames(motion: Motion, settings: CheckSettings) -> tuple[int, int]:
    """How many frames at the start and at the end are in the rest pose ((0, 0) when all are)."""
    if not motion.n_frames:
        return 0, 0
    lead = _run_from_start(motion, settings, backwards=False)
    if lead == motion.n_frames:
        return 0, 0
    return lead, _run_from_start(motion, settings, backwards=True)


def rest_pose(data: CheckData, settings: CheckSettings) -> list[Finding]:
    """Rest frames at the ends of ``data`` (the whole motion: ``data.first`` is 0)."""
    lead, trail = rest_frames(data.motion, settings)
    findings = []
    for start, count in ((0, lead), (data.n_frames - trail, trail)):
        level = severity_levels(count, settings.rest_limits) if count else 0
        if level:
            findings.append(data.finding("rest-pose", [], start, start + count - 1, level, count, "frames"))
    return findings
