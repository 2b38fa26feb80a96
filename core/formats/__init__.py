"""Motion file formats: read any supported file, write BVH or GMR.

``read_motion`` returns the file's own convention (post-rotation for BVH, pre-rotation for
GMR; Acclaim AMC is read straight into pre-rotation, ``.asf`` alone gives the skeleton's
rest pose); ``load_gmr`` converts to GMR. The suffix picks the format, case-insensitively.
Options go to the reader: ``read_motion("walk.amc", asf="subject.asf", frame_rate=120)``
(by default the AMC's skeleton is the single ``.asf`` beside it); AMASS/SMPL ``.npz``
motions need their body model: ``read_motion("walk.npz", body_model="smplh.npz")``; glTF
(``.glb``/``.gltf``) takes ``animation=``, ``skin=`` and ``frame_rate=`` (:mod:`.gltf_in`); FBX
(``.fbx``, read only) takes ``animation=`` (:mod:`.fbx_in`).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.acclaim import read_amc_file, read_amc_file_with_channels, read_asf_file
from gmr_studio.core.formats.amass import read_amass
from gmr_studio.core.formats.bvh import read_bvh, read_bvh_with_channels, write_bvh
from gmr_studio.core.formats.fbx_in import read_fbx
from gmr_studio.core.formats.gltf_in import read_gltf
from gmr_studio.core.formats.gmr import read_gmr, write_gmr
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.model.channels import FileChannels
from gmr_studio.core.model.motion import Motion

READERS: dict[str, Callable[..., Motion]] = {
    ".bvh": read_bvh,
    ".gmr": read_gmr,
    ".amc": read_amc_file,
    ".asf": read_asf_file,
    ".npz": read_amass,  # AMASS/SMPL motions; needs body_model=PATH
    ".glb": read_gltf,  # glTF 2.0: a skin and its animation (animation=, skin=, frame_rate=)
    ".gltf": read_gltf,
    ".vrma": read_gltf,  # VRM animation: a .glb whose humanoid bones are the skeleton
    ".fbx": read_fbx,  # FBX (binary and ASCII), read only: the skeleton and a take (animation=)
}
WRITERS: dict[str, Callable[[Motion, Path], None]] = {".bvh": write_bvh, ".gmr": write_gmr}
#: formats whose files store a joint's rotation as something other than Euler angles, and
#: what: their ``channels`` are always angles computed from it, never the file's own values
NON_EULER_ROTATIONS = {".npz": "axis-angle vectors", ".glb": "quaternions", ".gltf": "quaternions"}


def motion_suffix(path: str | Path) -> str:
    return Path(path).suffix.lower()


def read_motion(path: str | Path, **options) -> Motion:
    """Read a motion file in its own convention; MotionFileError for unknown formats."""
    reader = READERS.get(motion_suffix(path))
    if reader is None:
        known = ", ".join(sorted(READERS))
        raise MotionFileError(path, f"unknown motion format '{Path(path).suffix}': expected one of {known}")
    return reader(path, **options)


def read_motion_with_channels(path: str | Path, **options) -> tuple[Motion, FileChannels | None]:
    """:func:`read_motion`, and the file's rotation channels as written for the formats that
    have their own (BVH channels, AMC dofs: :mod:`core.model.channels`); None for the others (a
    GMR file's channels are its motion's)."""
    suffix = motion_suffix(path)
    if suffix == ".bvh":
        return read_bvh_with_channels(path, **options)
    if suffix == ".amc":
        return read_amc_file_with_channels(path, **options)
    return read_motion(path, **options), None


def load_gmr(path: str | Path, **options) -> Motion:
    """Read any motion file and return its GMR (pre-rotation) form."""
    return pre_from_post(read_motion(path, **options))


def write_motion(motion: Motion, path: str | Path) -> None:
    """Write by suffix (.gmr or .bvh), atomically. The motion must already be in the
    convention of the format (see :func:`core.kinematics.convention.pre_from_post`)."""
    writer = WRITERS.get(motion_suffix(path))
    if writer is None:
        known = ", ".join(sorted(WRITERS))
        raise ValueError(f"cannot write '{Path(path).suffix}' files: expected one of {known}")
    writer(motion, Path(path))
