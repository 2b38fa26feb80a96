"""Run the checks: :func:`run_checks` (all frames once, every kind asked for)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from gmr_studio.core.checks import feet, frames, joints, spikes
from gmr_studio.core.checks.context import CheckData
from gmr_studio.core.checks.model import KINDS, CheckSettings, Finding, Skipped
from gmr_studio.core.kinematics.engine import thread_count
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion

#: kind -> the check that finds it
CHECKS: dict[str, Callable[[CheckData, CheckSettings], list[Finding]]] = {
    "foot-skate": feet.foot_skate,
    "penetration": feet.penetration,
    "pop": spikes.pop,
    "jitter": spikes.jitter,
    "flip": joints.flip,
    "bone-length": joints.bone_length,
    "frozen": frames.frozen,
    "duplicate": frames.duplicate,
    "teleport": spikes.teleport,
    "rest-pose": frames.rest_pose,
}


def check_data(
    motion: Motion, settings: CheckSettings, positions: np.ndarray | None = None, *, threads: int | None = None
) -> tuple[CheckData, CheckData]:
    """What the checks read: the whole motion (for ``rest-pose``) and the frames between
    the rest frames at its ends (for every other check). Without ``positions`` (F, J, 3)
    they are computed on ``threads`` (None: every core; the app and the library hand theirs over)."""
    if positions is None:
        positions = forward_kinematics(motion, with_rotations=False, threads=threads)[0]
    lead, trail = frames.rest_frames(motion, settings)
    stop = motion.n_frames - trail
    whole = CheckData(motion, positions, motion.size)
    inner = CheckData(motion.frame_slice(slice(lead, stop)), positions[lead:stop], motion.size, first=lead)
    return whole, inner


def skipped_frames(motion: Motion, settings: CheckSettings) -> list[Skipped]:
    """The frames :func:`run_checks` leaves out of some of ``settings.kinds``, and why: the
    rest-pose frames at either end (:func:`core.checks.frames.rest_frames`), which every
    kind but ``rest-pose`` skips (a T-pose next to the take reads as pops, flips and a
    jump). Empty when there are none or only ``rest-pose`` runs."""
    kinds = tuple(k for k in settings.kinds if k != "rest-pose")
    lead, trail = frames.rest_frames(motion, settings) if kinds else (0, 0)
    skipped = []
    for start, count, where in ((0, lead, "start"), (motion.n_frames - trail, trail, "end")):
        if count:
            skipped.append(Skipped(start, start + count - 1, kinds, f"the rest pose at the {where}"))
    return skipped


def run_checks(
    motion: Motion,
    settings: CheckSettings | None = None,
    positions: np.ndarray | None = None,
    *,
    threads: int | None = None,
) -> list[Finding]:
    """Every check of ``settings.kinds`` on a motion, findings sorted by frame then kind.

    Parameters
    ----------
    motion : the motion in its own convention (as read; flips are judged on its rotations).
    settings : which checks and their thresholds (default :class:`CheckSettings`).
    positions : optional (F, J, 3) world positions of the motion already computed.
    threads : the checks run side by side on this many threads (None: one per core; one for
        a short motion, :func:`core.kinematics.engine.thread_count`); the findings do not
        depend on it.

    Rest-pose frames at the ends (:func:`core.checks.frames.rest_frames`) are reported as
    ``rest-pose`` only; every other check looks at the frames between them, and
    :func:`skipped_frames` says which frames those checks left out (whether ``rest-pose``
    runs or not: reports list them beside the findings). A pop of joints
    that hang from a joint flipping at that frame is the flip's doing and is not reported.
    """
    settings = settings or CheckSettings()
    whole, inner = check_data(motion, settings, positions, threads=threads)

    def check(kind: str) -> list[Finding]:
        return CHECKS[kind](whole if kind == "rest-pose" else inner, settings)

    count = min(thread_count(motion.n_frames, threads), len(settings.kinds))
    if count > 1:  # their compiled passes release the GIL
        with ThreadPoolExecutor(max_workers=count) as pool:
            each = list(pool.map(check, settings.kinds))
    else:
        each = [check(kind) for kind in settings.kinds]
    found = _without_flipped_pops([finding for findings in each for finding in findings], motion)
    order = {kind: k for k, kind in enumerate(KINDS)}
    return sorted(found, key=lambda f: (f.start, order[f.kind], f.end, f.joints))


def _without_flipped_pops(found: list[Finding], motion: Motion) -> list[Finding]:
    """The findings without the pops a flip explains: pops of joints in the subtree of a
    joint whose rotation flips at that frame (turning a joint moves what hangs from it)."""
    popped = {f.start for f in found if f.kind == "pop"}
    flipped: dict[int, set[int]] = {}  # frame of a pop -> joints moved by a flip
    subtrees: dict[int, list[int]] = {}
    for finding in found:
        frames = popped.intersection(range(finding.start, finding.end + 1)) if finding.kind == "flip" else ()
        if frames:
            moved = set()
            for joint in finding.joints:
                moved.update(subtrees.setdefault(joint, motion.subtree(joint)))
            for frame in frames:
                flipped.setdefault(frame, set()).update(moved)
    if not flipped:
        return found
    return [f for f in found if f.kind != "pop" or not set(f.joints) <= flipped.get(f.start, set())]
