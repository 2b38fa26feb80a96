"""A clean synthetic walk for the quality checks' tests: planted feet that do not slide.

The humanoid of :mod:`core.rigs` (metres, Y up, ZXY channels, facing +Z). The hips move
forward at a constant speed, bobbing a little; each ankle follows a path in the world (at
rest on the ground for 60% of a stride, then lifted straight up, carried forward and put
down, each part a minimum-jerk curve), and the legs reach it by two-bone inverse kinematics
in the sagittal plane; the feet stay level. So a planted foot does not move at all and every
path is smooth. Frame rate and length unit are parameters: the same walk at 24 to 240 Hz in
metres, centimetres or inches.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.motion import Motion
from gmr_studio.core.rigs import ORDER, walk
from gmr_studio.core.rotations import matrix_from_euler

STRIDE_SECONDS = 1.1
SPEED = 0.6  # metres per second
STANCE = 0.6  # fraction of a stride a foot is planted
LIFT = 0.10  # metres
THIGH = SHIN = 0.42
ANKLE_HEIGHT = 0.06  # the rig's ankle above the ground, standing
HIP_HEIGHT = 0.89  # the root's height while walking (knees never straight)


def _min_jerk(t: np.ndarray) -> np.ndarray:
    t = np.clip(t, 0.0, 1.0)
    return t**3 * (10.0 - 15.0 * t + 6.0 * t * t)


def _ankle_path(time: np.ndarray, shift: float) -> np.ndarray:
    """(F, 2) height and forward position of one ankle; ``shift`` its phase (strides)."""
    phase = time / STRIDE_SECONDS + shift
    stride = np.floor(phase)
    within = phase - stride  # 0..1: planted until STANCE, then swings
    step = SPEED * STRIDE_SECONDS
    planted_at = SPEED * (stride - shift + STANCE / 2) * STRIDE_SECONDS  # under the hips mid-stance
    swing = np.clip((within - STANCE) / (1.0 - STANCE), 0.0, 1.0)
    lift = _min_jerk(swing / 0.2) - _min_jerk((swing - 0.8) / 0.2)
    forward = _min_jerk((swing - 0.2) / 0.6)
    return np.column_stack([ANKLE_HEIGHT + LIFT * lift, planted_at + step * forward])


def _leg_angles(hip: np.ndarray, ankle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """X angles of thigh and knee reaching ``ankle`` from ``hip`` ((F, 2) height, forward)."""
    dy, dz = ankle[:, 0] - hip[:, 0], ankle[:, 1] - hip[:, 1]
    reach = np.hypot(dy, dz)
    knee = np.pi - np.arccos(np.clip((THIGH**2 + SHIN**2 - reach**2) / (2 * THIGH * SHIN), -1.0, 1.0))
    direction = np.arctan2(-dz, -dy)  # the leg (0, -cos a, -sin a) points at the ankle
    return direction - np.arctan2(SHIN * np.sin(knee), THIGH + SHIN * np.cos(knee)), knee


def clean_walk(rate: float = 120.0, seconds: float = 5.0, unit: float = 1.0) -> Motion:
    """The walk at ``rate`` Hz for ``seconds``, lengths in units of ``unit`` metres
    (0.01: centimetres, 0.0254: inches). Post-rotation convention, as a BVH reads."""
    skeleton = walk(1)  # the humanoid rig's joints and offsets
    names, parents, offsets = list(skeleton.names), list(skeleton.parents), skeleton.offsets
    n = round(rate * seconds)
    time = np.arange(n) / rate
    beat = 2 * np.pi * time / STRIDE_SECONDS
    root = np.column_stack([np.zeros(n), HIP_HEIGHT + 0.01 * np.cos(2 * beat), SPEED * time])
    angles = np.zeros((n, len(names), 3))
    for side, shift in (("Left", 0.0), ("Right", 0.5)):
        hip_offset = offsets[names.index(f"{side}UpLeg")]
        hip = np.column_stack([root[:, 1] + hip_offset[1], root[:, 2] + hip_offset[2]])
        thigh, knee = _leg_angles(hip, _ankle_path(time, shift))
        angles[:, names.index(f"{side}UpLeg"), 1] = thigh
        angles[:, names.index(f"{side}Leg"), 1] = knee
        angles[:, names.index(f"{side}Foot"), 1] = -(thigh + knee)
        s = 1.0 if side == "Left" else -1.0
        angles[:, names.index(f"{side}Arm"), 0] = -s * 1.3
        angles[:, names.index(f"{side}Arm"), 1] = 0.3 * np.sin(beat + np.pi * shift * 2)
        angles[:, names.index(f"{side}ForeArm"), 1] = -0.25 - 0.1 * np.cos(beat + np.pi * shift * 2)
    angles[:, names.index("Spine"), 2] = 0.06 * np.sin(beat)
    angles[:, names.index("Head"), 0] = 0.05 * np.sin(2 * beat)
    translations = np.broadcast_to(offsets, (n, len(names), 3)).copy()
    translations[:, 0] = root
    scale = 1.0 / unit
    return Motion(
        names=names,
        parents=parents,
        offsets=offsets * scale,
        rotation_orders=[ORDER] * len(names),
        has_translation=np.array(parents) < 0,
        rotations=matrix_from_euler(angles, ORDER),
        translations=translations * scale,
        frame_time=1.0 / rate,
        convention="post",
    )
