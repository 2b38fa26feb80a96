"""The benchmark's motion: real BVH files, grouped by skeleton, tiled to N frames at 120 fps.

How the files are combined (the real files have different skeletons): files whose
skeletons have the same tree and channel layout (joint names and bone lengths aside) form
a group; the group with the most frames is the benchmark motion, the others are listed
as left out. Within the group, the frame lines of every file, as written, are concatenated
under the header (joint names, offsets) of the group's longest file and repeated until
there are N frames; the frame time is set to 1/120 s. So the text timed by the parser is
the files' own text, and every frame is a real pose, but frames of the shorter files are
shown on the longest file's bone lengths (which changes nothing in what is timed).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.hierarchy import normalise_newlines, parse_header
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.model.motion import Motion

FRAME_TIME = 1 / 120


@dataclasses.dataclass(frozen=True)
class SourceFile:
    """One BVH file found: its frames, and whether (and why not) it is in the motion."""

    path: Path
    frames: int
    joints: int
    frame_time: float
    included: bool
    note: str = ""


@dataclasses.dataclass(frozen=True)
class BenchmarkData:
    """The tiled BVH file and its motion in both conventions.

    path : the tiled BVH file (in the caller's folder).
    file_bytes, block_bytes : sizes of the file and of its frame lines.
    block : the frame lines (what numpy.loadtxt is timed on).
    post : the file read as BVH (post-rotation), (F, J) as tiled.
    gmr : its GMR (pre-rotation) form, one root.
    sources : every BVH file found, included or not.
    """

    path: Path
    file_bytes: int
    block: bytes
    post: Motion
    gmr: Motion
    sources: tuple[SourceFile, ...]

    @property
    def block_bytes(self) -> int:
        return len(self.block)


def find_bvh_files(folders: list[Path]) -> list[Path]:
    """Every ``*.bvh`` under the folders (recursively, case-insensitive suffix), sorted."""
    found: set[Path] = set()
    for folder in folders:
        if folder.is_file():
            found.add(folder)
        elif folder.is_dir():
            found.update(p for p in folder.rglob("*") if p.is_file() and p.suffix.lower() == ".bvh")
    return sorted(found)


def _signature(motion: Motion) -> tuple:
    """What must match for frame lines of two files to be read under one header."""
    return (tuple(motion.parents), motion.rotation_orders, tuple(motion.has_translation))


def _split_file(path: Path) -> tuple[bytes, list[bytes]]:
    """(header through the MOTION line, non-empty frame lines) of a BVH file."""
    data = normalise_newlines(path.read_bytes())
    header = parse_header(data, str(path), "bvh")
    head = data[: data.rindex(b"MOTION", 0, header.data_offset)] + b"MOTION\n"
    lines = [line.strip() for line in data[header.data_offset :].split(b"\n") if line.strip()]
    return head, lines


def tiled_text(head: bytes, lines: list[bytes], n_frames: int) -> tuple[bytes, bytes]:
    """A BVH file (and its frame block) repeating ``lines`` under ``head`` to ``n_frames``."""
    repeats = -(-n_frames // len(lines))
    block = b"\n".join((lines * repeats)[:n_frames]) + b"\n"
    return head + b"Frames: %d\nFrame Time: %.8f\n" % (n_frames, FRAME_TIME) + block, block


def tile_bvh(path: Path, n_frames: int) -> bytes:
    """The BVH file at ``path`` with its frames repeated to ``n_frames`` at 120 fps."""
    head, lines = _split_file(path)
    if not lines:
        raise MotionFileError(path, "the file holds no frames to tile")
    return tiled_text(head, lines, n_frames)[0]


def build_benchmark_data(folders: list[Path], n_frames: int, workdir: Path) -> BenchmarkData:
    """Group, concatenate and tile the BVH files of ``folders`` to ``n_frames`` frames,
    write the tiled BVH file into ``workdir`` and read it back in both conventions."""
    files = find_bvh_files(folders)
    motions: list[tuple[Path, Motion]] = []
    for path in files:
        motions.append((path, read_bvh(path)))  # MotionFileError for a bad file: the user should know
    if not motions:
        where = ", ".join(str(f) for f in folders)
        raise MotionFileError(where, "no BVH files found for the benchmark (is the shared data folder missing?)")
    groups: dict[tuple, list[tuple[Path, Motion]]] = {}
    for path, motion in motions:
        groups.setdefault(_signature(motion), []).append((path, motion))
    chosen = max(groups.values(), key=lambda group: (sum(m.n_frames for _, m in group), -len(group)))
    longest = max(chosen, key=lambda item: item[1].n_frames)[0]
    sources = []
    for path, motion in motions:
        included = any(path == p for p, _ in chosen)
        note = "" if included else "different skeleton from the benchmark group"
        if included and path != longest and motion.names != dict(chosen)[longest].names:
            note = f"joint names differ; read under {longest.name}'s header"
        sources.append(SourceFile(path, motion.n_frames, motion.n_joints, motion.frame_time, included, note))
    head, _ = _split_file(longest)
    lines = [line for path, _ in chosen for line in _split_file(path)[1]]
    if not lines:
        raise MotionFileError(longest, "the benchmark files hold no frames")
    text, block = tiled_text(head, lines, n_frames)
    path = workdir / "benchmark.bvh"
    path.write_bytes(text)
    post = read_bvh(path)
    return BenchmarkData(path, len(text), block, post, pre_from_post(post), tuple(sources))


def tile_amc(path: Path, n_frames: int) -> bytes:
    """The AMC file at ``path`` with its frames repeated to ``n_frames``, numbered from 1
    (the lines of every frame as written; the header keywords kept)."""
    lines = normalise_newlines(path.read_bytes()).split(b"\n")
    starts = [k for k, line in enumerate(lines) if line.strip().isdigit()]
    if not starts:
        raise MotionFileError(path, "the file holds no frames to tile")
    ends = [*starts[1:], len(lines)]
    bodies = [b"".join(line.strip() + b"\n" for line in lines[a + 1 : b] if line.strip()) for a, b in zip(starts, ends)]
    head = b"".join(line + b"\n" for line in lines[: starts[0]])
    return head + b"".join(b"%d\n%s" % (k + 1, bodies[k % len(bodies)]) for k in range(n_frames))
