"""AMASS / SMPL-family motion files (``.npz``) in, given the body model they were made with.

An AMASS sequence holds ``poses`` (F, 3K) axis-angle rotations (radians) of K joints,
``trans`` (F, 3) the root translation in metres, ``betas`` the body shape, ``gender`` and
``mocap_framerate`` (``mocap_frame_rate`` in SMPL-X releases). The skeleton comes from the
body model file (:mod:`core.formats.body_model`): its kinematic tree and joint names, and the
rest joint locations of the sequence's ``betas``.

SMPL's kinematics is post-rotation (BVH-like): ``G_j = G_p R_j`` and ``P_j = P_p + G_p (J_j -
J_p)``, with the root at ``J_0 + trans`` turned by ``R_0``. So the motion read is a
post-rotation motion with offsets ``J_j - J_p``, the root translating to ``J_0 + trans``,
and rotations ``R_j = exp(pose_j)`` (Rodrigues). Every world position equals the body
model's posed joints (before pose correctives, which move vertices, not joints).

Units metres; Z up as AMASS stores it (the file facts say so, so ``gmr convert --up
y`` and the glTF export turn it). Euler channel order for BVH output: ``ZYX``. Files are
read with ``allow_pickle=False``.
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError, read_input
from gmr_studio.core.formats.body_model import BodyModel, load_body_model, rest_joints
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.units import UNITS

#: rotation order of every joint (what a BVH written from it uses)
ROTATION_ORDER = "ZYX"
MISSING_MODEL = (
    "AMASS/SMPL motions need the body model they were made with: pass --body-model PATH "
    "(the model's .npz or .pkl, e.g. SMPL-H for AMASS; app: File > Body model...)"
)


def matrices_from_axis_angle(rotvecs: np.ndarray) -> np.ndarray:
    """Rotation matrices from axis-angle vectors (angle = norm, radians): (..., 3) -> (..., 3, 3)."""
    rotvecs = np.asarray(rotvecs, dtype=np.float64)
    angle = np.linalg.norm(rotvecs, axis=-1)[..., None, None]
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    x, y, z = np.moveaxis(rotvecs, -1, 0)
    zero = np.zeros_like(x)
    cross = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)], -2)
    # sin(a)/a and (1 - cos(a))/a^2, by their series near 0
    sin_term = np.where(small, 1.0 - angle**2 / 6, np.sin(safe) / safe)
    cos_term = np.where(small, 0.5 - angle**2 / 24, (1.0 - np.cos(safe)) / safe**2)
    return np.eye(3) + sin_term * cross + cos_term * (cross @ cross)


def _load_sequence(path: Path, data: bytes | None) -> dict[str, np.ndarray]:
    raw = read_input(path, data)
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files}
    except (ValueError, OSError, zipfile.BadZipFile, EOFError) as exc:
        raise MotionFileError(path, f"not an AMASS .npz archive ({exc})") from None


def _field(path: Path, arrays: dict, key: str, shape_text: str) -> np.ndarray:
    if key not in arrays:
        raise MotionFileError(path, f"the archive has no '{key}' array ({shape_text}): is it an AMASS motion?")
    try:
        value = np.asarray(arrays[key], dtype=np.float64)
    except (TypeError, ValueError):
        raise MotionFileError(path, f"'{key}' is not numeric") from None
    if not np.isfinite(value).all():
        raise MotionFileError(path, f"'{key}' holds NaN or infinite values")
    return value


def read_amass(
    path: str | Path, *, body_model: str | Path | BodyModel | None = None, data: bytes | None = None
) -> Motion:
    """Read an AMASS/SMPL ``.npz`` motion as a post-rotation motion (see the module docstring).

    ``body_model``: the body model (path or loaded); without it, MotionFileError saying what
    to pass.
    """
    path = Path(path)
    if body_model is None:
        raise MotionFileError(path, MISSING_MODEL)
    model = body_model if isinstance(body_model, BodyModel) else load_body_model(body_model)
    arrays = _load_sequence(path, data)
    poses = _field(path, arrays, "poses", "(F, 3K) axis-angle")
    trans = _field(path, arrays, "trans", "(F, 3) metres")
    rate_key = "mocap_framerate" if "mocap_framerate" in arrays else "mocap_frame_rate"
    rate = float(_field(path, arrays, rate_key, "frames per second").reshape(-1)[0])
    betas = _field(path, arrays, "betas", "(B,)") if "betas" in arrays else np.zeros(0)
    n_joints = model.n_joints
    if poses.ndim != 2 or poses.shape[1] % 3 or trans.shape != (poses.shape[0], 3):
        raise MotionFileError(path, f"poses must be (F, 3K) and trans (F, 3), not {poses.shape} and {trans.shape}")
    if poses.shape[1] != 3 * n_joints:
        raise MotionFileError(
            path,
            f"poses rotate {poses.shape[1] // 3} joints but the body model {Path(model.path).name} has "
            f"{n_joints}: pass the body model of the sequence's family (SMPL-H has 52, SMPL-X 55, SMPL 24)",
        )
    if not rate > 0:
        raise MotionFileError(path, f"{rate_key} must be a positive number of frames per second, not {rate}")
    n_frames = poses.shape[0]
    joints = rest_joints(model, betas)
    parents = model.parents
    offsets = np.where((parents >= 0)[:, None], joints - joints[np.maximum(parents, 0)], joints)
    translations = np.broadcast_to(offsets, (n_frames, n_joints, 3)).copy()
    roots = np.flatnonzero(parents < 0)
    translations[:, roots] = joints[roots] + trans[:, None]
    has_translation = np.zeros(n_joints, bool)
    has_translation[roots] = True
    gender = arrays.get("gender")
    gender_text = (
        str(gender.item() if gender is not None and gender.shape == () else gender) if gender is not None else "?"
    )
    return Motion(
        names=model.names,
        parents=parents,
        offsets=offsets,
        rotation_orders=(ROTATION_ORDER,) * n_joints,
        has_translation=has_translation,
        rotations=matrices_from_axis_angle(poses.reshape(n_frames, n_joints, 3)),
        translations=translations,
        frame_time=1.0 / rate,
        convention="post",
        comments=(
            f"AMASS/SMPL motion {path.name}, body model {Path(model.path).name}, gender {gender_text}, "
            f"{betas.size} betas",
        ),
        facts=FileFacts(unit=UNITS["m"], up_axis="z"),
    )
