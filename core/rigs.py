"""Generated rigs covering the conventions real files come in, for the gallery and tests.

Each rig is a walk (or a pose) of a plain humanoid in BVH's convention (``"post"``, ZXY
rotation channels), built in closed form, so a test knows what it should look like:

=====================  ==============================================================
name                   what it covers
=====================  ==============================================================
``metres``             Y-up, metres: the humanoid (27 joints) walking 5 m along +Z
``origin_root``        a ``Root`` joint held at the world origin above the hips, which
                       carry the walk (game and dataset exports)
``game_root``          as ``origin_root`` with a game rig's names: ``UpperArm_L``, ``Hand_R``,
                       End Sites named ``<parent>_End`` (``Hand_L_End``, ``Toes_R_End``),
                       as a BVH holds them (no channels)
``second_life``        the walk named as a Second Life / Poser BVH: ``hip``, ``abdomen``,
                       ``lCollar``, ``rShldr``, ``lThigh``, ``lShin``, Bento's
                       ``mHandIndex1Left``, ``mToeRight``, End Sites ``mToeLeft_End``
``z_up_millimetres``   the walk in Z-up millimetres
``t_pose``             one frame: the rest pose, arms out
``six_channels``       translation and rotation channels on every joint
``one_joint``          a single joint moving on a circle
``fingers_and_face``   250 joints: the humanoid, 4-joint fingers and 185 face points
``long_take``          100,000 frames of the walk (28 minutes at 60 fps)
=====================  ==============================================================

``python -m gmr_studio.core.rigs OUT_DIR`` writes them all as BVH files.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import matrix_from_euler
from gmr_studio.core.space.units import UNITS

FRAME_RATE = 60.0
WALK_FRAMES = 300  # 5 s
WALK_SPEED = 1.0  # metres per second, along +Z
STEP_RATE = 0.9  # strides per second
HIP_HEIGHT = 0.95
ORDER = "ZXY"
SIDES = (("Left", 1.0), ("Right", -1.0))


def _humanoid(fingers: bool = False, face: int = 0) -> tuple[list[str], list[int], np.ndarray]:
    """Names, parents and (J, 3) offsets in metres, Y up, facing +Z, arms out (T-pose)."""
    table: list[tuple[str, str | None, tuple[float, float, float]]] = [
        ("Hips", None, (0.0, HIP_HEIGHT, 0.0)),
        ("Spine", "Hips", (0.0, 0.10, 0.0)),
        ("Spine1", "Spine", (0.0, 0.15, 0.0)),
        ("Chest", "Spine1", (0.0, 0.15, 0.0)),
        ("Neck", "Chest", (0.0, 0.15, 0.0)),
        ("Head", "Neck", (0.0, 0.10, 0.0)),
        ("HeadEnd", "Head", (0.0, 0.18, 0.0)),
    ]
    for side, s in SIDES:
        table += [
            (f"{side}Shoulder", "Chest", (s * 0.05, 0.12, 0.0)),
            (f"{side}Arm", f"{side}Shoulder", (s * 0.13, 0.0, 0.0)),
            (f"{side}ForeArm", f"{side}Arm", (s * 0.28, 0.0, 0.0)),
            (f"{side}Hand", f"{side}ForeArm", (s * 0.25, 0.0, 0.0)),
        ]
        if fingers:
            for k, finger in enumerate(("Thumb", "Index", "Middle", "Ring", "Pinky")):
                parent = f"{side}Hand"
                spread = (k - 2) * 0.02
                for phalanx, length in enumerate((0.05, 0.035, 0.025, 0.02)):
                    name = f"{side}Hand{finger}{phalanx + 1}"
                    step = (s * 0.04, 0.0, spread) if phalanx == 0 else (s * length, 0.0, 0.0)
                    table.append((name, parent, step))
                    parent = name
        else:
            table.append((f"{side}HandEnd", f"{side}Hand", (s * 0.08, 0.0, 0.0)))
        table += [
            (f"{side}UpLeg", "Hips", (s * 0.10, -0.05, 0.0)),
            (f"{side}Leg", f"{side}UpLeg", (0.0, -0.42, 0.0)),
            (f"{side}Foot", f"{side}Leg", (0.0, -0.42, 0.0)),
            (f"{side}Toe", f"{side}Foot", (0.0, -0.06, 0.12)),
            (f"{side}ToeEnd", f"{side}Toe", (0.0, 0.0, 0.05)),
        ]
    if face:  # points on the front half of an ellipsoid around the head's centre
        golden = np.pi * (3.0 - np.sqrt(5.0))
        k = np.arange(face)
        height = 1.0 - 2.0 * (k + 0.5) / face
        ring = np.sqrt(1.0 - height**2)
        points = np.column_stack([ring * np.cos(golden * k), height, np.abs(ring * np.sin(golden * k))])
        for n, (x, y, z) in enumerate(points * (0.08, 0.11, 0.10) + (0.0, 0.09, 0.0)):
            table.append((f"Face{n + 1:03d}", "Head", (float(x), float(y), float(z))))
    names = [row[0] for row in table]
    index = {name: j for j, name in enumerate(names)}
    parents = [-1 if row[1] is None else index[row[1]] for row in table]
    return names, parents, np.array([row[2] for row in table])


def _walk_angles(names: list[str], n_frames: int) -> np.ndarray:
    """(F, J, 3) ZXY Euler angles (radians) of a walk cycle: legs and arms swing about X,
    knees bend, arms hang down from the T-pose (about Z)."""
    phase = 2 * np.pi * STEP_RATE * np.arange(n_frames) / FRAME_RATE
    angles = np.zeros((n_frames, len(names), 3))
    for side, s in SIDES:
        swing = np.sin(phase + (0.0 if s > 0 else np.pi))
        angles[:, names.index(f"{side}UpLeg"), 1] = -0.45 * swing
        angles[:, names.index(f"{side}Leg"), 1] = 0.6 * np.clip(np.cos(phase + (0.0 if s > 0 else np.pi)), 0, None)
        angles[:, names.index(f"{side}Arm"), 0] = -s * 1.3
        angles[:, names.index(f"{side}Arm"), 1] = 0.35 * swing
        angles[:, names.index(f"{side}ForeArm"), 1] = -0.25
    angles[:, names.index("Spine"), 2] = 0.08 * np.sin(phase)
    return angles


def _motion(names, parents, offsets, angles, root_path, *, translating=None, comments=()) -> Motion:
    """A post-convention motion; ``root_path`` (F, 3) is the world position of joint 0;
    ``translating`` (J,) bool joints with translation channels (default: the roots)."""
    n_frames, n_joints = angles.shape[:2]
    parents = np.asarray(parents)
    flags = parents < 0 if translating is None else np.asarray(translating, bool)
    translations = np.broadcast_to(offsets, (n_frames, n_joints, 3)).copy()
    translations[:, 0] = root_path
    return Motion(
        names=names,
        parents=parents,
        offsets=offsets,
        rotation_orders=[ORDER] * n_joints,
        has_translation=flags,
        rotations=matrix_from_euler(angles, ORDER),
        translations=translations,
        frame_time=1.0 / FRAME_RATE,
        convention="post",
        comments=comments,
    )


def _walk_path(n_frames: int) -> np.ndarray:
    """(F, 3) the hips' world position: forward along +Z, bobbing twice a stride."""
    t = np.arange(n_frames) / FRAME_RATE
    phase = 2 * np.pi * STEP_RATE * t
    return np.column_stack([0.02 * np.sin(phase), HIP_HEIGHT + 0.02 * np.cos(2 * phase), WALK_SPEED * t])


def walk(n_frames: int = WALK_FRAMES, *, fingers: bool = False, face: int = 0) -> Motion:
    names, parents, offsets = _humanoid(fingers, face)
    return _motion(names, parents, offsets, _walk_angles(names, n_frames), _walk_path(n_frames))


def origin_root() -> Motion:
    """A ``Root`` joint fixed at the world origin, parent of hips that carry the walk."""
    names, parents, offsets = _humanoid()
    names = ["Root", *names]
    parents = [-1, *[p + 1 for p in parents]]
    parents[1] = 0
    offsets = np.vstack([np.zeros(3), offsets])
    angles = np.concatenate([np.zeros((WALK_FRAMES, 1, 3)), _walk_angles(names[1:], WALK_FRAMES)], axis=1)
    flags = np.zeros(len(names), bool)
    flags[:2] = True
    motion = _motion(names, parents, offsets, angles, np.zeros((WALK_FRAMES, 3)), translating=flags)
    translations = motion.translations.copy()
    translations[:, 1] = _walk_path(WALK_FRAMES)
    return motion.replace(translations=translations)


#: the humanoid's names as a game exporter spells them (``<bone>_L`` / ``_R``)
GAME_NAMES = {
    "Spine1": "Spine2",
    "Shoulder": "Shoulder",
    "Arm": "UpperArm",
    "ForeArm": "LowerArm",
    "Hand": "Hand",
    "UpLeg": "UpperLeg",
    "Leg": "LowerLeg",
    "Foot": "Foot",
    "Toe": "Toes",
}


def game_name(name: str) -> str:
    """``LeftForeArm`` -> ``LowerArm_L``, ``RightToeEnd`` -> ``Toes_R_End``, ``HeadEnd`` -> ``Head_End``."""
    end = name.endswith("End")
    stem = name[:-3] if end else name
    for side in ("Left", "Right"):
        if stem.startswith(side):
            stem = f"{GAME_NAMES[stem[len(side) :]]}_{side[0]}"
            break
    else:
        stem = GAME_NAMES.get(stem, stem)
    return f"{stem}_End" if end else stem


def game_root() -> Motion:
    """:func:`origin_root` named as a game rig, its end joints BVH End Sites (no channels)."""
    motion = origin_root()
    names = tuple(game_name(n) for n in motion.names)
    orders = tuple("" if n.endswith("_End") else o for n, o in zip(names, motion.rotation_orders))
    return motion.replace(names=names, rotation_orders=orders)


#: the humanoid's names as a Second Life (Poser) BVH spells them: a side letter before the
#: Poser bones, Bento's ``m<Bone><Side>`` for the fingers and toes
SECOND_LIFE_NAMES = {
    "Hips": "hip",
    "Spine": "abdomen",
    "Spine1": "mSpine2",
    "Chest": "chest",
    "Neck": "neck",
    "Head": "head",
    "HeadEnd": "figureHair",
    "Shoulder": "{s}Collar",
    "Arm": "{s}Shldr",
    "ForeArm": "{s}ForeArm",
    "Hand": "{s}Hand",
    "HandEnd": "mHandIndex1{Side}",
    "UpLeg": "{s}Thigh",
    "Leg": "{s}Shin",
    "Foot": "{s}Foot",
    "Toe": "mToe{Side}",
    "ToeEnd": "mToe{Side}_End",
}


def second_life_name(name: str) -> str:
    """``LeftShoulder`` -> ``lCollar``, ``RightHandEnd`` -> ``mHandIndex1Right``, ``Spine`` -> ``abdomen``."""
    for side in ("Left", "Right"):
        if name.startswith(side):
            return SECOND_LIFE_NAMES[name[len(side) :]].format(s=side[0].lower(), Side=side)
    return SECOND_LIFE_NAMES[name]


def second_life() -> Motion:
    """:func:`walk` named as a Second Life / Poser BVH, the toe ends End Sites (no channels)."""
    motion = walk()
    names = tuple(second_life_name(n) for n in motion.names)
    orders = tuple("" if n.endswith("_End") else o for n, o in zip(names, motion.rotation_orders))
    return motion.replace(names=names, rotation_orders=orders)


def z_up_millimetres() -> Motion:
    """The walk turned Z-up (world ``(x, y, z) -> (x, -z, y)``) and scaled to millimetres."""
    motion = walk()
    turn = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    # a root's rotation turns the whole tree, so turning the root's frame turns the figure;
    # every other joint keeps its local rotation and has its offset scaled only
    rotations = motion.rotations.copy()
    rotations[:, 0] = turn @ rotations[:, 0]
    translations = motion.translations * 1000.0
    translations[:, 0] = motion.translations[:, 0] @ turn.T * 1000.0
    offsets = motion.offsets * 1000.0
    offsets[0] = turn @ motion.offsets[0] * 1000.0
    mm = FileFacts(unit=UNITS["mm"])
    return motion.replace(rotations=rotations, translations=translations, offsets=offsets, facts=mm)


def t_pose() -> Motion:
    names, parents, offsets = _humanoid()
    return _motion(names, parents, offsets, np.zeros((1, len(names), 3)), offsets[None, 0])


def six_channels() -> Motion:
    return walk().replace(has_translation=np.ones(27, bool))


def one_joint() -> Motion:
    angle = 2 * np.pi * np.arange(120) / 120
    path = np.column_stack([np.cos(angle), np.full(120, 0.5), np.sin(angle)])
    return _motion(["Ball"], [-1], np.array([[1.0, 0.5, 0.0]]), np.zeros((120, 1, 3)), path)


RIGS: dict[str, Callable[[], Motion]] = {
    "metres": walk,
    "origin_root": origin_root,
    "game_root": game_root,
    "second_life": second_life,
    "z_up_millimetres": z_up_millimetres,
    "t_pose": t_pose,
    "six_channels": six_channels,
    "one_joint": one_joint,
    "fingers_and_face": lambda: walk(120, fingers=True, face=185),
    "long_take": lambda: walk(100_000),
}


def make_rig(name: str) -> Motion:
    """The rig called ``name`` (a key of :data:`RIGS`)."""
    return RIGS[name]()


def main(argv: list[str] | None = None) -> int:
    from gmr_studio.core.formats.bvh import write_bvh

    parser = argparse.ArgumentParser(prog="python -m gmr_studio.core.rigs", description="Write every rig as BVH.")
    parser.add_argument("folder", metavar="OUT_DIR", help="where to write <rig>.bvh (made if missing)")
    folder = Path(parser.parse_args(argv).folder)
    folder.mkdir(parents=True, exist_ok=True)
    for name in RIGS:
        write_bvh(make_rig(name), folder / f"{name}.bvh")
        print(folder / f"{name}.bvh")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
