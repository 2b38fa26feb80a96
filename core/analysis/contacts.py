"""Foot contacts: per frame, whether each foot joint (and toe) is planted on the ground.

A joint is planted at a frame when both

- its height above its own lowest point over the motion is under ``height`` times the
  skeleton's size (:attr:`core.model.motion.Motion.size`), and
- its speed (norm of the world velocity, :func:`core.analysis.curves.world_speed`) is under
  ``speed`` times the size per second.

Heights are measured along the motion's up axis (:func:`core.space.up_axis.up_axis_of`: Y
unless the comments say Z). Each joint's ground is its own lowest point, so an ankle and a
toe both count as planted when they rest, whatever their height above the floor; a
motion on uneven ground (stairs) needs other thresholds. Both fractions are adjustable;
:data:`DEFAULT_HEIGHT` and :data:`DEFAULT_SPEED` were chosen on CMU walks (01_01, 02_01).
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from gmr_studio.core.analysis.curves import world_speed
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.up_axis import axis_index, up_axis_of

#: height threshold, as a fraction of the skeleton's size
DEFAULT_HEIGHT = 0.03
#: speed threshold, as a fraction of the skeleton's size per second
DEFAULT_SPEED = 0.4
#: names of foot joints: foot, toe(s), ankle, heel, in any case (CMU lfoot, ltoes, LeftToeBase)
FOOT_NAME = re.compile(r"foot|toe|ankle|heel", re.IGNORECASE)


@dataclasses.dataclass(frozen=True, eq=False)
class Contacts:
    """Planted feet over frames.

    Attributes
    ----------
    joints : (K,) int64, the foot joints examined.
    names : their K names.
    planted : (F, K) bool, joint k planted at frame f.
    height_threshold : absolute height threshold (file units).
    speed_threshold : absolute speed threshold (file units per second).
    """

    joints: np.ndarray
    names: tuple[str, ...]
    planted: np.ndarray
    height_threshold: float
    speed_threshold: float


def foot_joints(motion: Motion) -> list[int]:
    """Indices of joints whose name says foot, toe, ankle or heel (:data:`FOOT_NAME`) and
    that are not End Site leaves of a toe already listed (``*_end`` names are skipped)."""
    return [j for j, name in enumerate(motion.names) if FOOT_NAME.search(name) and not name.lower().endswith("_end")]


def foot_contacts(
    motion: Motion,
    positions: np.ndarray | None = None,
    joints: list[int] | None = None,
    *,
    height: float = DEFAULT_HEIGHT,
    speed: float = DEFAULT_SPEED,
    joint_positions: np.ndarray | None = None,
) -> Contacts:
    """Planted foot joints per frame (see the module docstring).

    Parameters
    ----------
    motion : the motion (either convention).
    positions : optional (F, J, 3) world positions already computed.
    joints : the joints to examine (default :func:`foot_joints`).
    height, speed : thresholds as fractions of the size (per second for speed).
    joint_positions : optional (F, K, 3) world positions of ``joints`` alone, already
        taken out of the positions (then ``positions`` is not read).
    """
    joints = foot_joints(motion) if joints is None else [motion.joint_index(j) for j in joints]
    index = np.asarray(joints, dtype=np.int64)
    if joint_positions is not None:
        feet = joint_positions
    else:
        feet = (world_positions(motion) if positions is None else positions)[:, index]  # (F, K, 3)
    up = axis_index(up_axis_of(motion))
    heights = feet[..., up] - (feet[..., up].min(axis=0) if feet.shape[0] else 0.0)
    height_threshold = height * motion.size
    speed_threshold = speed * motion.size
    planted = (heights < height_threshold) & (world_speed(feet, motion.frame_time) < speed_threshold)
    return Contacts(index, tuple(motion.names[j] for j in index), planted, height_threshold, speed_threshold)


def contact_runs(planted: np.ndarray) -> np.ndarray:
    """Runs of planted frames of one joint: (F,) bool -> (R, 2) int64 half-open ``[start, stop)``."""
    edges = np.diff(np.concatenate([[0], np.asarray(planted, dtype=np.int8), [0]]))
    return np.stack([np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)], axis=1).astype(np.int64)
