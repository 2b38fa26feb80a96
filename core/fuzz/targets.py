"""What the fuzzer attacks: per format, the seed files, the reader, and what a good read is.

Seeds are the real files of ``../shared/data`` (long ones trimmed to a few dozen frames so
that each case runs in milliseconds; a few are kept whole) and the project's own writer
outputs (GMR files of every configuration, BVH and TRC re-written). A target whose reader
is not available in this build is left out, and the report says so.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable
from functools import cache
from pathlib import Path

import numpy as np

from gmr_studio.core.fuzz.mutations import ACCLAIM_MUTATIONS, BINARY_MUTATIONS, TEXT_MUTATIONS, Mutation
from gmr_studio.core.shared_data import shared_data_dir

#: frames kept when a seed file is trimmed
SEED_FRAMES = 40


@dataclasses.dataclass(frozen=True)
class Target:
    """One format under attack.

    ``read(path, data, seed)`` reads a case (``data`` are the case's bytes, also written at
    ``path`` for readers that need a file; ``seed`` names the seed file it was made from, for
    readers that need a companion file); ``check(result)`` raises AssertionError when a
    successful read returned something impossible (NaN from finite input, a reflection...).
    """

    name: str
    suffix: str
    seeds: Callable[[], list[tuple[str, bytes]]]
    read: Callable[[Path, bytes, str], object]
    check: Callable[[object], None]
    mutations: dict[str, Mutation]
    needs_file: bool = False
    structure: Callable[[bytes], list[int]] = lambda data: text_structure(data)
    #: seconds a case may take at least (a reader with its own time limit needs more)
    timeout: float = 0.0


def text_structure(data: bytes, frame_lines: int = 3) -> list[int]:
    """Byte offsets of every line start of a text file's header and its first frame lines
    (the header ends at the first line that starts with a number)."""
    points = [0]
    for match in re.finditer(rb"\r\n|\r|\n", data):
        points.append(match.end())
        if re.match(rb"[ \t]*[-+.\d]", data[match.end() : match.end() + 20]):
            frame_lines -= 1
            if frame_lines < 0:
                break
    return points


def _trim_bvh_like(data: bytes, frames: int = SEED_FRAMES) -> bytes:
    data = data.replace(b"\r\n", b"\n")
    match = re.search(rb"(?m)^Frames:[ \t]*(\d+)[ \t]*\n(Frame Time:[^\n]*\n)", data)
    if not match:
        return data
    body = data[match.end() :].split(b"\n")
    keep = min(int(match.group(1)), frames)
    head = data[: match.start()] + b"Frames: %d\n" % keep + match.group(2)
    return head + b"\n".join(body[:keep]) + b"\n"


def _shared(pattern: str) -> list[Path]:
    folder = shared_data_dir()
    return sorted(folder.glob(pattern)) if folder.is_dir() else []


@cache
def bvh_seeds() -> list[tuple[str, bytes]]:
    from gmr_studio.core.edits.operations import shift_root
    from gmr_studio.core.formats.bvh import bvh_text, read_bvh
    from gmr_studio.core.kinematics.convention import post_from_pre, pre_from_post

    seeds = []
    for path in _shared("**/*.bvh"):
        data = path.read_bytes()
        seeds.append((path.name, _trim_bvh_like(data)))
        if len(data) < 100_000:
            seeds.append((path.name + " (whole)", data))
        motion = pre_from_post(read_bvh(path.name, _trim_bvh_like(data, 5)))
        far = motion.names[int(np.argmax(motion.depths))]
        seeds.append(
            (path.name + " re-rooted, written by us", bvh_text(post_from_pre(shift_root(motion, far))[0]).encode())
        )
    return seeds


@cache
def gmr_seeds() -> list[tuple[str, bytes]]:
    from gmr_studio.core.edits.operations import shift_root, split, split_all
    from gmr_studio.core.formats.bvh import read_bvh
    from gmr_studio.core.formats.gmr import gmr_text
    from gmr_studio.core.kinematics.convention import pre_from_post

    seeds = []
    for path in _shared("**/*.bvh"):
        motion = pre_from_post(read_bvh(path.name, _trim_bvh_like(path.read_bytes(), 20)))
        far = motion.names[int(np.argmax(motion.depths))]
        forest = split(split(motion, 3), motion.n_joints - 2)
        for label, edited in (
            ("tree", motion),
            ("re-rooted", shift_root(motion, far)),
            ("forest", forest),
            ("all roots", split_all(motion)),
        ):
            seeds.append((f"{path.name} as GMR, {label}", gmr_text(edited).encode()))
    return seeds


@cache
def trc_seeds() -> list[tuple[str, bytes]]:
    from gmr_studio.core.markers.trc import read_trc, trc_text

    seeds = []
    for path in _shared("**/*.trc"):
        data = path.read_bytes()
        lines = data.splitlines(keepends=True)
        seeds.append((path.name, b"".join(lines[: 6 + SEED_FRAMES])))
        markers = read_trc(path.name, data).frame_slice(slice(0, 10))
        seeds.append((path.name + " written by us", trc_text(markers).encode()))
    return seeds


def _check_motion(motion) -> None:
    try:
        motion.check_invariants()
    except ValueError as exc:
        raise AssertionError(f"read an impossible motion: {exc}") from None


def _check_markers(markers) -> None:
    if np.isinf(markers.positions).any():
        raise AssertionError("read infinite marker positions")


def _read_bvh(path: Path, data: bytes, seed: str):
    from gmr_studio.core.formats.bvh import read_bvh

    return read_bvh(path, data)


def _read_gmr(path: Path, data: bytes, seed: str):
    from gmr_studio.core.formats.gmr import read_gmr

    return read_gmr(path, data)


def _read_trc(path: Path, data: bytes, seed: str):
    from gmr_studio.core.markers.trc import read_trc

    return read_trc(path, data)


def all_targets() -> dict[str, Target]:
    """Every target this build can attack, by name."""
    targets = {
        "bvh": Target("bvh", ".bvh", bvh_seeds, _read_bvh, _check_motion, TEXT_MUTATIONS),
        "gmr": Target("gmr", ".gmr", gmr_seeds, _read_gmr, _check_motion, TEXT_MUTATIONS),
        "trc": Target("trc", ".trc", trc_seeds, _read_trc, _check_markers, TEXT_MUTATIONS),
    }
    targets.update(_optional_targets())
    return targets


def _optional_targets() -> dict[str, Target]:
    """Targets whose readers live in modules that may not be in this build."""
    out: dict[str, Target] = {}
    try:
        from gmr_studio.core.fuzz import acclaim_targets
    except ImportError:
        acclaim_targets = None
    if acclaim_targets is not None:
        out.update(acclaim_targets.targets(ACCLAIM_MUTATIONS, _check_motion))
    try:
        from gmr_studio.core.fuzz import c3d_targets
    except ImportError:
        c3d_targets = None
    if c3d_targets is not None:
        out.update(c3d_targets.targets(BINARY_MUTATIONS, _check_markers))
    try:
        from gmr_studio.core.fuzz import gltf_targets
    except ImportError:
        gltf_targets = None
    if gltf_targets is not None:
        out.update(gltf_targets.targets(_check_motion))
    try:
        from gmr_studio.core.fuzz import fbx_targets
    except ImportError:
        fbx_targets = None
    if fbx_targets is not None:
        out.update(fbx_targets.targets(_check_motion))
    return out
