"""Frozen stretches, duplicated frames and rest-pose frames at the ends: whole poses.

Same pose. Frames f and f+1 show the same pose when no joint moves more than
``same_pose * size`` between them (1e-7: a frame copied in the file, not a subject holding
still, whose capture noise is far larger). A run of n consecutive frames showing one pose
is *frozen* when it lasts ``n * frame_time >= frozen_limits[0]`` seconds (frames
``a .. a+n-1``, valued in seconds), otherwise its ``n-1`` copies are *duplicates* (frames
``a+1 .. a+n-1``, valued in frames). Both have no joints: the whole pose.

Rest pose. A frame is in the rest pose when at least ``rest_fraction`` of the non-root
joints that move in the take (their rotation is not the same at every frame) are within
``rest_angle`` degrees of the identity (trace at least ``1 + 2 cos(rest_angle)``): the
T-pose frame exporters put at the start of a take. A fraction, not all: cgspeed's CMU BVH
frame 0 sets the thighs to 17 degrees and the arms to 5 (the 75-frame clip also the neck
and head) and every other joint to zero, while no frame of a take holds most of its
moving joints within half a degree of zero. Runs of such frames starting at the first frame
or ending at the last are reported, valued in frames; a motion in the rest pose throughout
is a pose, not a take with rest frames left in, and is not reported. The other checks skip
these frames (:func:`rest_frames`).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.checks.context import CheckData, levels_for, runs
from gmr_studio.core.checks.model import CheckSettings, Finding
from gmr_studio.core.motion import Motion


def same_pose_runs(data: CheckData, settings: CheckSettings) -> np.ndarray:
    """(R, 2) half-open runs ``[a, b)`` of frame steps ``f -> f+1`` that keep the pose: the
    frames ``a .. b`` show one pose."""
    if data.n_frames < 2:
        return np.zeros((0, 2), np.int64)
    steps = np.diff(data.positions, axis=0)
    moved = np.einsum("fja,fja->fj", steps, steps).max(axis=1)  # (F-1,) largest squared move
    return runs(moved <= (settings.same_pose * data.size) ** 2)


def _held(data: CheckData, settings: CheckSettings, frozen: bool) -> list[Finding]:
    findings = []
    for a, b in same_pose_runs(data, settings):
        n = int(b - a + 1)
        seconds = n * data.frame_time
        if frozen and seconds >= settings.frozen_limits[0]:
            level = levels_for(seconds, settings.frozen_limits)
            findings.append(data.finding("frozen", [], a, b, level, seconds, "s"))
        elif not frozen and seconds < settings.frozen_limits[0]:
            level = levels_for(n - 1, settings.duplicate_limits)
            if level:
                findings.append(data.finding("duplicate", [], a + 1, b, level, n - 1, "frames"))
    return findings


def frozen(data: CheckData, settings: CheckSettings) -> list[Finding]:
    return _held(data, settings, frozen=True)


def duplicate(data: CheckData, settings: CheckSettings) -> list[Finding]:
    return _held(data, settings, frozen=False)


def rest_mask(motion: Motion, settings: CheckSettings) -> np.ndarray:
    """(F,) bool: frames in the rest pose (module docstring)."""
    inner = motion.parents >= 0
    rotating = np.flatnonzero(inner & np.array([bool(o) for o in motion.rotation_orders]))
    rotations = motion.rotations[:, rotating].reshape(motion.n_frames, rotating.size, 9)
    moving = np.ptp(rotations, axis=0).max(axis=1) > 0 if motion.n_frames else np.zeros(0, bool)
    if not moving.any():
        return np.zeros(motion.n_frames, bool)
    diagonal = rotations[:, moving][..., [0, 4, 8]].sum(axis=-1)  # (F, K) traces
    at_rest = diagonal >= 1.0 + 2.0 * np.cos(np.radians(settings.rest_angle))
    return at_rest.mean(axis=1) >= settings.rest_fraction


def rest_frames(motion: Motion, settings: CheckSettings) -> tuple[int, int]:
    """How many frames at the start and at the end are in the rest pose ((0, 0) when all are)."""
    rest = rest_mask(motion, settings)
    if not rest.size or rest.all() or not (rest[0] or rest[-1]):
        return 0, 0
    lead = int(np.argmin(rest))
    trail = int(np.argmin(rest[::-1]))
    return lead, trail


def rest_pose(data: CheckData, settings: CheckSettings) -> list[Finding]:
    """Rest frames at the ends of ``data`` (the whole motion: ``data.first`` is 0)."""
    lead, trail = rest_frames(data.motion, settings)
    findings = []
    for start, count in ((0, lead), (data.n_frames - trail, trail)):
        level = levels_for(count, settings.rest_limits) if count else 0
        if level:
            findings.append(data.finding("rest-pose", [], start, start + count - 1, level, count, "frames"))
    return findings
