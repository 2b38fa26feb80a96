"""Foot skating and ground penetration, on the foot contacts of :mod:`core.analysis.contacts`.

Feet. The foot joints (:func:`core.analysis.contacts.foot_joints`: foot, toe, ankle, heel) joined by
bones make one foot (CMU ``LeftFoot`` + ``LeftToeBase``); contacts are
:func:`core.analysis.contacts.foot_contacts` with the settings' ``contact_height`` and
``contact_speed``.

Touching joints. The joints of a foot that touch the ground are those typically (median
over the frames) less than ``skate_height * size`` above the lowest joint of their foot:
the ball and toes, not the ankle of a foot that has toes (a heel striking the ground rolls
the ankle forward a few centimetres while the toes are still up). A foot of one joint keeps
it. CMU's BVH ``LeftFoot`` is the ankle, typically 0.6 units (3.4 cm, 2.2% of the size)
above ``LeftToeBase``, and is left out; its ASF ``lfoot`` ends at the ball and touches.

Foot skate. Per foot, with ``H`` the horizontal position (across the up axis) of each of
its touching joints and ``w`` the frames of 0.1 s. For skating a joint counts as planted when the
contacts say so and it is within ``skate_height * size`` of its lowest point (a foot
shuffled a few centimetres above the floor, as a boxer's, is moving, not sliding). A window
``f .. f+w`` slides when every foot joint planted throughout it moved more than
``skate_speed * size * w * frame_time`` in it (``|H_{f+w} - H_f|``: a foot rolling over its
toes keeps one joint still and does not slide; capture noise does not add up over a window
as it does frame by frame). The frame steps covered by sliding windows, joined across gaps
of 0.1 s, cut where no joint of the foot is planted at both ends of a step, and trimmed at
both ends to steps where the stillest planted joint moves more than ``skate_speed * size *
frame_time``, make one finding ``a .. b``. Its value is the distance slid: the smallest
``|H_b - H_a|`` of the joints planted at both ends (the sum of the stillest joint's steps
when none is), reported when it reaches ``skate_limits[0] * size``.

Penetration. Each touching joint has a contact level: the 10th percentile of its heights
(along the up axis) over its planted frames, the level it rests at flat on the ground (the
median mixed in the raised contacts of a foot rolling onto its toes, and put CMU 02_01's
first standing frames 3.6 cm "below the ground"). A frame where the joint is more than
``penetration_limits[0] * size`` below that level penetrates. Runs per joint, valued by the
deepest point. The level rests on the contacts (planted: within ``contact_height * size``
of the joint's lowest point): a foot pushed deeper than that band below its usual contacts,
or below them for more than a tenth of its planted frames, moves the level itself and is
underestimated or missed.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.analysis.contacts import foot_contacts, foot_joints
from gmr_studio.core.checks.context import CheckData, joint_runs, merge_runs, runs
from gmr_studio.core.checks.model import CheckSettings, Finding, severity_levels
from gmr_studio.core.checks.passes import column_medians, joint_coordinates, skate_windows

#: a touching joint's contact level: this quantile of its heights over its planted frames
LEVEL_QUANTILE = 0.1
#: the window (seconds) over which a planted foot must move to slide; gaps joined
SKATE_WINDOW_SECONDS = 0.1


def foot_groups(parents: np.ndarray, joints: list[int]) -> list[list[int]]:
    """Positions in ``joints`` grouped into feet: a joint whose parent is a foot joint is
    in its parent's foot."""
    position = {j: k for k, j in enumerate(joints)}
    group = list(range(len(joints)))
    for k, j in enumerate(joints):
        parent = int(parents[j])
        if parent in position:
            group[k] = group[position[parent]]
    feet: dict[int, list[int]] = {}
    for k, g in enumerate(group):
        feet.setdefault(g, []).append(k)
    return list(feet.values())


def _foot_coordinates(data: CheckData) -> np.ndarray:
    """(3, K, F) the world coordinates of the foot joints (:func:`foot_joints`), taken once
    (:func:`core.checks.passes.joint_coordinates`; ``.transpose(2, 1, 0)``: their positions)."""
    joints = np.asarray(foot_joints(data.motion), dtype=np.int64)
    return data.cached("foot coordinates", lambda: joint_coordinates(data.positions, joints))


def _contacts(data: CheckData, settings: CheckSettings):
    joints = foot_joints(data.motion)
    if not joints or data.n_frames < 2:
        return None
    key = ("contacts", settings.contact_height, settings.contact_speed)
    return data.cached(
        key,
        lambda: foot_contacts(
            data.motion,
            data.positions,
            joints,
            height=settings.contact_height,
            speed=settings.contact_speed,
            joint_positions=_foot_coordinates(data).transpose(2, 1, 0),
        ),
    )


def foot_skate(data: CheckData, settings: CheckSettings) -> list[Finding]:
    contacts = _contacts(data, settings)
    if contacts is None:
        return []
    across = [a for a in range(3) if a != data.up]
    coordinates = _foot_coordinates(data)  # (3, K, F)
    x, y = coordinates[across[0]], coordinates[across[1]]  # (K, F) horizontal coordinates
    heights = coordinates[data.up].T - coordinates[data.up].T.min(axis=0)
    planted = contacts.planted & (heights < settings.skate_height * data.size)
    w = max(1, min(round(SKATE_WINDOW_SECONDS / data.frame_time), data.n_frames - 1))
    speed = settings.skate_speed * data.size * data.frame_time  # per frame
    both = planted[1:] & planted[:-1]
    findings = []
    touching = _touching(data, contacts, settings)
    for whole in foot_groups(data.motion.parents, list(contacts.joints)):
        group = [k for k in whole if touching[k]]
        covered, stillest = skate_windows(x, y, planted, group, w, w * speed)  # (F-1,) each
        on_ground = np.isfinite(stillest)
        found = _split_off_ground(merge_runs(runs(covered), w), on_ground)
        # each run's first and last step where the stillest planted joint moves: frames a..b
        moving = np.flatnonzero(on_ground & (stillest > speed))
        lo, hi = np.searchsorted(moving, found[:, 0]), np.searchsorted(moving, found[:, 1])
        a, b = moving[lo[hi > lo]], moving[hi[hi > lo] - 1] + 1
        ends = planted[a][:, group] & planted[b][:, group]  # (R, G) planted at both ends
        dx, dy = (x[group][:, b] - x[group][:, a]).T, (y[group][:, b] - y[group][:, a]).T
        slid = np.sqrt(dx * dx + dy * dy)  # (R, G) lengths, as numpy.linalg.norm sums them
        distances = np.where(ends, slid, np.inf).min(axis=1)
        for r in np.flatnonzero(~ends.any(axis=1)):  # none planted at both ends: the steps' sum
            steps_slid = stillest[a[r] : b[r]]
            distances[r] = np.sum(steps_slid[np.isfinite(steps_slid)])
        levels = severity_levels(distances / data.size, settings.skate_limits)
        for r in np.flatnonzero(levels):
            joints = [int(contacts.joints[k]) for k in whole if both[a[r] : b[r], k].any()]
            findings.append(data.finding("foot-skate", joints, a[r], b[r], levels[r], distances[r], data.units))
    return findings


def depths(data: CheckData, settings: CheckSettings) -> tuple[np.ndarray, np.ndarray]:
    """(joints (K,), depth below each touching joint's contact level (F, K), NaN for joints
    that never touch or are never planted)."""
    contacts = _contacts(data, settings)
    if contacts is None:
        return np.zeros(0, np.int64), np.zeros((data.n_frames, 0))
    heights = _foot_coordinates(data)[data.up].T  # (F, K)
    planted = contacts.planted
    seen = planted.any(axis=0) & _touching(data, contacts, settings)
    level = np.array(
        [np.quantile(heights[planted[:, k], k], LEVEL_QUANTILE) if seen[k] else np.nan for k in range(heights.shape[1])]
    )
    return contacts.joints, level - heights


def penetration(data: CheckData, settings: CheckSettings) -> list[Finding]:
    joints, depth = depths(data, settings)
    below = depth > settings.penetration_limits[0] * data.size  # NaN compares False
    findings = []
    for k, start, stop in joint_runs(below):
        deepest = float(depth[start:stop, k].max())
        severity = severity_levels(deepest / data.size, settings.penetration_limits)
        findings.append(data.finding("penetration", [joints[k]], start, stop - 1, severity, deepest, data.units))
    return findings


def _split_off_ground(found: np.ndarray, on_ground: np.ndarray) -> np.ndarray:
    """Half-open runs of steps (R, 2) cut wherever no foot joint is planted at both ends of a
    step, of the runs ``found`` (sorted, none touching the next)."""
    inside = np.zeros(on_ground.size + 1, np.int64)
    np.add.at(inside, found[:, 0], 1)
    np.add.at(inside, found[:, 1], -1)
    return runs(on_ground & (np.cumsum(inside[:-1]) > 0))


def _touching(data: CheckData, contacts, settings: CheckSettings) -> np.ndarray:
    """(K,) bool: the foot joints that touch the ground: typically (median over the frames)
    less than ``skate_height * size`` above the lowest joint of their foot."""

    def touching() -> np.ndarray:
        heights = _foot_coordinates(data)[data.up].T  # (F, K)
        out = np.ones(len(contacts.joints), bool)
        for group in foot_groups(data.motion.parents, list(contacts.joints)):
            above = heights[:, group] - heights[:, group].min(axis=1, keepdims=True)
            out[group] = column_medians(above) < settings.skate_height * data.size
        return out

    return data.cached(("touching", settings.skate_height), touching)
