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

from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rigs import ORDER, _humanoid, walk
from gmr_studio.core.rotations.euler import matrix_from_euler

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


#: the crouch's frames after the reference frame, and its rate (a Second Life animation)
CROUCH_FRAMES = 60
CROUCH_RATE = 24.0
CROUCH_HIPS = (0.89, 0.45)  # the hips' height standing and crouched (metres)


def reference_frame_crouch(reference: str = "t-pose", slide: float = 0.08) -> Motion:
    """A Second Life (OpenCollar-style) take: 150 joints (the humanoid with fingers and 85
    face points), frame 0 the reference pose, frames 1-60 a crouch at 24 Hz, in centimetres.

    Frame 0 is the *reference* frame SL's uploader reads to learn which joints the animation
    drives (a joint is driven when it differs there from frame 1). ``reference="t-pose"``:
    the body in the T-pose (the identity) and the 125 face and finger joints turned a few
    degrees, to mark them driven; ``"marked"``: every joint turned a few degrees. In frames
    1-60 the face and fingers sit at the identity, so they change only between frames 0 and
    1; the hips sink 44 cm and move 10 cm forward, the knees bend from 12 to 125 degrees with
    the feet kept planted by two-bone inverse kinematics, the spine leans and the arms reach
    forward. The right foot slides ``slide`` metres forward over frames 1-11 (a foot skate),
    the left one stays put.
    """
    names, parents, offsets = _humanoid(fingers=True, face=85)
    n = CROUCH_FRAMES + 1
    t = np.clip((np.arange(n) - 1) / (CROUCH_FRAMES - 1), 0.0, 1.0)  # 0 at frame 1, 1 at the last
    sink = _min_jerk(t)
    root = np.column_stack([np.zeros(n), CROUCH_HIPS[0] + (CROUCH_HIPS[1] - CROUCH_HIPS[0]) * sink, 0.10 * sink])
    angles = np.zeros((n, len(names), 3))
    for side in ("Left", "Right"):
        hip_offset = offsets[names.index(f"{side}UpLeg")]
        hip = np.column_stack([root[:, 1] + hip_offset[1], root[:, 2] + hip_offset[2]])
        forward = np.zeros(n) + 0.08
        if side == "Right":
            forward += slide * np.clip((np.arange(n) - 1) / 10.0, 0.0, 1.0)
        thigh, knee = _leg_angles(hip, np.column_stack([np.full(n, ANKLE_HEIGHT), forward]))
        angles[:, names.index(f"{side}UpLeg"), 1] = thigh
        angles[:, names.index(f"{side}Leg"), 1] = knee
        angles[:, names.index(f"{side}Foot"), 1] = -(thigh + knee)
        s = 1.0 if side == "Left" else -1.0
        angles[:, names.index(f"{side}Arm"), 0] = -s * (1.3 - 0.4 * sink)
        angles[:, names.index(f"{side}Arm"), 1] = -1.2 * sink
    angles[:, names.index("Spine"), 1] = 0.5 * sink
    angles[:, names.index("Spine1"), 1] = 0.2 * sink
    if reference not in ("t-pose", "marked"):
        raise ValueError(f"reference must be 't-pose' or 'marked', not {reference!r}")
    marked = np.array([reference == "marked" or n.startswith("Face") or "Hand" in n[4:] for n in names])
    marks = np.radians(3.0 + 4.0 * (np.arange(len(names)) % 5)) * marked
    angles[0] = 0.0
    angles[0, :, 0] = marks
    angles[0, :, 2] = -0.5 * marks
    root[0] = root[1]
    translations = np.broadcast_to(offsets, (n, len(names), 3)).copy()
    translations[:, 0] = root
    return Motion(
        names=names,
        parents=parents,
        offsets=offsets * 100.0,
        rotation_orders=[ORDER] * len(names),
        has_translation=np.array(parents) < 0,
        rotations=matrix_from_euler(angles, ORDER),
        translations=translations * 100.0,
        frame_time=1.0 / CROUCH_RATE,
        convention="post",
    )
