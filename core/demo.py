"""The demo: a humanoid walk with arm swing and matching markers, made by this project.

``python -m gmr_studio.core.demo [FOLDER]`` writes ``walk.gmr`` (the motion) and ``walk.trc`` (its
markers) into ``resources/demo/`` (or FOLDER). Everything here is pure numpy, seeded and
deterministic: the same call always gives the same arrays (a test regenerates the files
and compares them with the committed ones).

The skeleton uses the CMU ASF bone names (``root``, ``lhipjoint``, ``lfemur``, ...). As in
the ASF -> GMR conversion, each joint sits at the END of the bone it is named after and its
pre-rotation ``R_j`` turns that bone: ``lfemur`` is at the knee and its rotation is the hip
flexion. Lengths are centimetres, Y is up, the figure walks along +Z, left is +X.

The markers are in millimetres with Z up (as a C3D file would be): one virtual marker on
every joint (labelled with the joint's name) and ten surface markers, with 0.5 mm of seeded
noise and a few gaps, so the app's marker alignment (units, up axis) has work to do.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.euler import matrix_from_euler
from gmr_studio.core.space.units import UNITS
from gmr_studio.resources import resource_path

if TYPE_CHECKING:
    from gmr_studio.core.markers.markerset import MarkerSet

#: joint name -> (parent name, bone vector in the rest pose, cm); the CMU ASF hierarchy
SKELETON: dict[str, tuple[str | None, tuple[float, float, float]]] = {
    "root": (None, (0.0, 0.0, 0.0)),
    "lhipjoint": ("root", (9.0, -6.0, 1.0)),
    "lfemur": ("lhipjoint", (0.0, -43.0, 0.0)),
    "ltibia": ("lfemur", (0.0, -42.0, 0.0)),
    "lfoot": ("ltibia", (0.0, -6.0, 13.0)),
    "ltoes": ("lfoot", (0.0, 0.0, 5.0)),
    "rhipjoint": ("root", (-9.0, -6.0, 1.0)),
    "rfemur": ("rhipjoint", (0.0, -43.0, 0.0)),
    "rtibia": ("rfemur", (0.0, -42.0, 0.0)),
    "rfoot": ("rtibia", (0.0, -6.0, 13.0)),
    "rtoes": ("rfoot", (0.0, 0.0, 5.0)),
    "lowerback": ("root", (0.0, 12.0, -1.0)),
    "upperback": ("lowerback", (0.0, 12.0, 0.0)),
    "thorax": ("upperback", (0.0, 12.0, 1.0)),
    "lowerneck": ("thorax", (0.0, 8.0, 0.5)),
    "upperneck": ("lowerneck", (0.0, 7.0, 0.0)),
    "head": ("upperneck", (0.0, 14.0, 0.0)),
    "lclavicle": ("thorax", (16.0, 3.0, -1.0)),
    "lhumerus": ("lclavicle", (0.0, -29.0, 0.0)),
    "lradius": ("lhumerus", (0.0, -25.0, 0.0)),
    "lwrist": ("lradius", (0.0, -3.0, 0.0)),
    "lhand": ("lwrist", (0.0, -7.0, 0.0)),
    "lfingers": ("lhand", (0.0, -6.0, 0.0)),
    "lthumb": ("lwrist", (-1.0, -4.0, 3.5)),
    "rclavicle": ("thorax", (-16.0, 3.0, -1.0)),
    "rhumerus": ("rclavicle", (0.0, -29.0, 0.0)),
    "rradius": ("rhumerus", (0.0, -25.0, 0.0)),
    "rwrist": ("rradius", (0.0, -3.0, 0.0)),
    "rhand": ("rwrist", (0.0, -7.0, 0.0)),
    "rfingers": ("rhand", (0.0, -6.0, 0.0)),
    "rthumb": ("rwrist", (1.0, -4.0, 3.5)),
}

#: surface marker -> (joint whose frame carries it, offset in that joint's frame, cm)
SURFACE_MARKERS: dict[str, tuple[str, tuple[float, float, float]]] = {
    "LASI": ("root", (12.0, 2.0, 9.0)),
    "RASI": ("root", (-12.0, 2.0, 9.0)),
    "LKNE": ("lfemur", (5.5, 0.0, 0.0)),
    "RKNE": ("rfemur", (-5.5, 0.0, 0.0)),
    "LANK": ("ltibia", (4.5, 0.0, 0.0)),
    "RANK": ("rtibia", (-4.5, 0.0, 0.0)),
    "C7": ("lowerneck", (0.0, 0.0, -6.0)),
    "LELB": ("lhumerus", (0.0, 0.0, -4.0)),
    "RELB": ("rhumerus", (0.0, 0.0, -4.0)),
    "LWRA": ("lradius", (3.0, 0.0, 1.0)),
}

#: (marker, first frame, last frame) of the gaps, inclusive
GAPS: tuple[tuple[str, int, int], ...] = (
    ("LWRA", 100, 131),
    ("RKNE", 250, 262),
    ("head", 400, 409),
    ("C7", 30, 33),
)

FRAME_RATE = 120.0
DURATION = 4.0  # seconds
STRIDE_PERIOD = 1.1  # seconds per two steps
WALK_SPEED = 125.0  # cm/s
PELVIS_HEIGHT = 97.0  # cm
SEED = 20261121
ORDER = "ZYX"
MOTION_FILE = "walk.gmr"
MARKERS_FILE = "walk.trc"


def demo_folder() -> Path:
    """Where the demo files live: ``resources/demo/`` beside the packages."""
    return resource_path("demo")


def _joint_angles(phase: np.ndarray) -> dict[str, np.ndarray]:
    """Euler angles (F, 3) in radians, order ZYX (z, y, x), for every moving joint.

    ``phase`` (F,) is the gait phase in radians (0 at left heel strike). Signs: a rotation
    about +X by a negative angle swings a downward bone forward (+Z).
    """
    deg = np.radians
    zero = np.zeros_like(phase)

    def zyx(z=zero, y=zero, x=zero) -> np.ndarray:
        return np.stack([z + zero, y + zero, x + zero], axis=-1)

    angles: dict[str, np.ndarray] = {}
    for side, shift in (("l", 0.0), ("r", np.pi)):
        p = phase + shift
        hip = deg(22.0) * np.cos(p)  # forward at heel strike
        knee = deg(6.0) + deg(48.0) * np.clip(np.sin(p - 0.35 * np.pi), 0.0, None) ** 2
        ankle = deg(8.0) * np.sin(p + 0.4)
        toes = deg(25.0) * np.clip(-np.sin(p + 0.6), 0.0, None) ** 3
        sway = deg(3.0) * (1 if side == "l" else -1)
        angles[f"{side}femur"] = zyx(z=sway + zero, x=-hip)
        angles[f"{side}tibia"] = zyx(x=knee)
        angles[f"{side}foot"] = zyx(x=ankle - knee * 0.15)
        angles[f"{side}toes"] = zyx(x=-toes)
        # arms swing against the leg of their side, elbows bend a little more when forward
        mirror = 1 if side == "l" else -1
        swing = deg(18.0) * np.cos(p + np.pi)
        angles[f"{side}humerus"] = zyx(z=mirror * deg(8.0) + zero, x=-swing)
        angles[f"{side}radius"] = zyx(x=-(deg(18.0) + deg(12.0) * np.clip(np.cos(p + np.pi), 0.0, None)))
        angles[f"{side}wrist"] = zyx(y=mirror * deg(10.0) * np.sin(p))
        angles[f"{side}clavicle"] = zyx(y=deg(4.0) * np.cos(p + np.pi))
    angles["lowerback"] = zyx(y=deg(-4.0) * np.cos(phase), x=deg(4.0) + zero)
    angles["upperback"] = zyx(y=deg(-3.0) * np.cos(phase))
    angles["thorax"] = zyx(z=deg(1.5) * np.sin(2 * phase))
    angles["lowerneck"] = zyx(x=deg(-6.0) + zero)
    angles["upperneck"] = zyx(y=deg(5.0) * np.cos(phase))
    angles["head"] = zyx(x=deg(4.0) + deg(2.0) * np.sin(2 * phase))
    return angles


def demo_motion() -> Motion:
    """The demo walk as a GMR (pre-rotation) motion: 31 joints, 480 frames at 120 Hz."""
    names = list(SKELETON)
    index = {name: j for j, name in enumerate(names)}
    parents = np.array([index[p] if p else -1 for p, _ in SKELETON.values()])
    offsets = np.array([bone for _, bone in SKELETON.values()], dtype=np.float64)
    n_frames = round(DURATION * FRAME_RATE)
    time = np.arange(n_frames) / FRAME_RATE
    phase = 2 * np.pi * time / STRIDE_PERIOD
    angles = np.zeros((n_frames, len(names), 3))
    for name, values in _joint_angles(phase).items():
        angles[:, index[name]] = values
    # the pelvis turns with the stride and bobs twice per stride
    angles[:, 0] = np.stack(
        [np.radians(2.5) * np.sin(phase), np.radians(6.0) * np.cos(phase), np.radians(2.0) + 0 * phase], axis=-1
    )
    rotations = matrix_from_euler(angles, ORDER)
    root_path = np.stack(
        [
            1.5 * np.sin(phase),
            PELVIS_HEIGHT - 1.8 * np.cos(2 * phase),
            WALK_SPEED * time - 250.0,
        ],
        axis=-1,
    )
    has_translation = np.zeros(len(names), bool)
    has_translation[0] = True
    return Motion(
        names=names,
        parents=parents,
        offsets=offsets,
        rotation_orders=[ORDER] * len(names),
        has_translation=has_translation,
        rotations=rotations,
        translations=build_translations(n_frames, offsets, {0: root_path}),
        frame_time=1.0 / FRAME_RATE,
        comments=("GMR Studio demo: a synthetic walk made by core/demo.py",),
        facts=FileFacts(unit=UNITS["cm"], up_axis="y"),
    )


def demo_markers(motion: Motion | None = None) -> MarkerSet:
    """Markers of the demo walk: (F, 41, 3) millimetres, Z up, seeded noise, a few gaps.

    The first 31 markers sit on the joints and carry their names; ten surface markers
    follow (``SURFACE_MARKERS``)."""
    # imported here: the demo's file names are read by gmr-studio's argument parser, which
    # loads no kinematics engine to print its usage
    from gmr_studio.core.kinematics.fk import forward_kinematics
    from gmr_studio.core.markers.markerset import Y_UP_TO_Z_UP, MarkerSet

    motion = demo_motion() if motion is None else motion
    positions, world = forward_kinematics(motion)
    labels = list(motion.names)
    samples = [positions]
    for label, (carrier, offset) in SURFACE_MARKERS.items():
        j = motion.joint_index(carrier)
        samples.append((positions[:, j] + world[:, j] @ np.asarray(offset))[:, None])
        labels.append(label)
    points = np.concatenate(samples, axis=1)
    rng = np.random.default_rng(SEED)
    points = points + rng.normal(scale=0.05, size=points.shape)  # 0.5 mm
    for label, first, last in GAPS:
        points[first : last + 1, labels.index(label)] = np.nan
    millimetres = 10.0 * np.einsum("ab,fmb->fma", Y_UP_TO_Z_UP, points)
    return MarkerSet(
        labels=labels,
        positions=np.round(millimetres, 4),
        rate=FRAME_RATE,
        units="mm",
        source=MARKERS_FILE,
        first_frame=1,
    )


def write_demo(folder: str | Path | None = None) -> tuple[Path, Path]:
    """Write ``walk.gmr`` and ``walk.trc`` (atomically) and return their paths."""
    from gmr_studio.core.formats.gmr import write_gmr
    from gmr_studio.core.markers.trc import write_trc

    target = Path(folder) if folder is not None else demo_folder()
    target.mkdir(parents=True, exist_ok=True)
    motion = demo_motion()
    write_gmr(motion, target / MOTION_FILE)
    write_trc(demo_markers(motion), target / MARKERS_FILE)
    return target / MOTION_FILE, target / MARKERS_FILE


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m gmr_studio.core.demo", description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", help="where to write (default: resources/demo/)")
    args = parser.parse_args(argv)
    for path in write_demo(args.folder):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
