"""Rotation flips and bone-length changes, joint by joint.

Flip. The step of joint j's local rotation (in the file's convention) from frame f to f+1
is the angle of ``R_f^T R_{f+1}``: ``theta = arccos((trace(R_f^T R_{f+1}) - 1) / 2)``. A step
flips when ``theta`` exceeds both ``flip_limits[0]`` degrees and ``flip_speed * frame_time``
(no joint turns that fast: 1800 deg/s is 15 degrees a frame at 120 Hz, 75 at 24 Hz). A
flipped step followed within 0.5 s by another after which the rotation is back within the
limit of where it was is one flip of frames ``a+1 .. b`` (the frames shown turned); a
flipped step alone marks the two frames of the jump. Siblings flipped over the same frames
make one finding (in a GMR form of a BVH every child carries its parent's rotation, so the
BVH's flipped joint shows as its children, together). The value is the largest step
(degrees). Joints without rotation channels are skipped.

Bone length. The length of the bone ending at a non-root joint with translation channels
is ``|t_j|`` (in either convention the world offset is a rotation of ``t_j``), and a split
root's soft link is ``|P_j - P_soft(j)|``; rigid bones cannot change and are not examined,
nor is the link from an anchor root (a ``Root`` pinned at the origin,
:attr:`core.model.motion.Motion.anchors`) to the hips whose translation carries the walk.
Each length's reference is its median over the frames; frames where it differs by more
than ``bone_limits[0]`` percent make runs (joined across gaps of 0.1 s), valued by the
largest difference in percent.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.checks.context import CheckData, joint_runs, merge_runs
from gmr_studio.core.checks.model import CheckSettings, Finding, severity_levels
from gmr_studio.core.checks.passes import cosines_below, step_angles

#: a flip and its return at most this far apart (seconds) make one flip
FLIP_PAIR_SECONDS = 0.5
#: gaps (seconds) across which a bone's changed frames make one finding
BONE_GAP_SECONDS = 0.1
#: steps whose cosine is above the limit's by more than this are taken as under the limit
COSINE_MARGIN = 1e-9
#: bones shorter than this, times the size, have no length to compare
MIN_BONE = 1e-6


def rotation_steps(rotations: np.ndarray, joints: np.ndarray | None = None) -> np.ndarray:
    """Angles in degrees between consecutive rotations: (F, J, 3, 3) -> (F-1, K) of the
    ``joints`` (K,) (None: all; :func:`core.checks.passes.step_angles`)."""
    return step_angles(rotations, joints)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.degrees(np.arccos(np.clip(0.5 * (np.sum(a * b) - 1.0), -1.0, 1.0))))


def flip(data: CheckData, settings: CheckSettings) -> list[Finding]:
    motion = data.motion
    rotating = np.array([j for j, order in enumerate(motion.rotation_orders) if order], dtype=np.int64)
    if data.n_frames < 2 or not rotating.size:
        return []
    rotations = motion.rotations  # (F, J, 3, 3), all joints (a copy of some would cost more)
    limit = max(settings.flip_limits[0], settings.flip_speed * data.frame_time)
    # the angle falls as the cosine rises: only steps with a cosine below the limit's (a
    # margin for rounding) can pass it, and only theirs are worth an arccos
    near, cosines = cosines_below(rotations, rotating, np.cos(np.radians(limit)) + COSINE_MARGIN)
    angles = np.degrees(np.arccos(cosines))  # of the near steps, flat indices f * K + k
    passed = angles > limit
    flagged, angles = near[passed], angles[passed]
    by_joint = np.argsort(flagged % rotating.size, kind="stable")  # each joint's steps in order
    pair = round(FLIP_PAIR_SECONDS / data.frame_time)
    together: dict[tuple[int, int, int], list[tuple[int, float]]] = {}  # (start, end, parent) -> joints
    for k, where in _groups(flagged[by_joint] % rotating.size):
        steps_k = flagged[by_joint[where]] // rotating.size
        steps = angles[by_joint[where]]
        i = 0
        while i < len(steps_k):
            a = int(steps_k[i])
            b = int(steps_k[i + 1]) if i + 1 < len(steps_k) else -1
            if b >= 0 and b - a <= pair and _angle(rotations[a, rotating[k]], rotations[b + 1, rotating[k]]) <= limit:
                start, end, value, i = a + 1, b, max(steps[i], steps[i + 1]), i + 2
            else:
                start, end, value, i = a, a + 1, steps[i], i + 1
            together.setdefault((start, end, int(motion.parents[rotating[k]])), []).append((int(rotating[k]), value))
    findings = []
    for (start, end, _), joints in together.items():  # siblings flipped together: one finding
        value = max(v for _, v in joints)
        level = severity_levels(value, settings.flip_limits)
        findings.append(data.finding("flip", [j for j, _ in joints], start, end, level, value, "deg"))
    return findings


def _groups(keys: np.ndarray) -> list[tuple[int, slice]]:
    """(key, slice) of each run of equal values of sorted keys (N,)."""
    starts = np.flatnonzero(np.diff(keys, prepend=-1))
    stops = np.append(starts[1:], keys.size)
    return [(int(keys[a]), slice(int(a), int(b))) for a, b in zip(starts, stops)]


def bone_lengths(data: CheckData) -> tuple[np.ndarray, np.ndarray]:
    """(joints (K,), lengths (F, K)) of the bones that can change length (module docstring)."""
    motion = data.motion
    inner = motion.parents >= 0
    under_anchor = inner & motion.anchors[np.maximum(motion.parents, 0)]  # hips that carry the walk
    moving = np.flatnonzero(motion.has_translation & inner & ~under_anchor)
    linked = np.flatnonzero(motion.soft_parents >= 0)
    lengths = [np.linalg.norm(motion.translations[:, moving], axis=-1)]
    if linked.size:
        soft = motion.soft_parents[linked]
        lengths.append(np.linalg.norm(data.positions[:, linked] - data.positions[:, soft], axis=-1))
    return np.concatenate([moving, linked]), np.concatenate(lengths, axis=1)


def bone_length(data: CheckData, settings: CheckSettings) -> list[Finding]:
    if data.n_frames < 2:
        return []
    joints, lengths = bone_lengths(data)
    reference = np.median(lengths, axis=0) if joints.size else np.zeros(0)
    keep = reference > MIN_BONE * data.size
    joints, lengths, reference = joints[keep], lengths[:, keep], reference[keep]
    if not joints.size:
        return []
    change = 100.0 * np.abs(lengths - reference) / reference  # (F, K) percent
    changed = change > settings.bone_limits[0]
    gap = max(1, round(BONE_GAP_SECONDS / data.frame_time))
    findings = []
    found = joint_runs(changed)
    for k in np.unique(found[:, 0]):
        for start, stop in merge_runs(found[found[:, 0] == k, 1:], gap):
            value = float(change[start:stop, k].max())
            level = severity_levels(value, settings.bone_limits)
            findings.append(data.finding("bone-length", [joints[k]], start, stop - 1, level, value, "%"))
    return findings
