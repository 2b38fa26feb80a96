"""BVH-like text files to :class:`~core.model.motion.Motion` and back (shared by BVH and GMR).

Channel values are degrees for rotations and file units for positions. Rotation channels
of a joint, in file order, give its Euler order (intrinsic, left to right). Position
channels replace the joint's OFFSET for that frame, axis by axis.
"""

from __future__ import annotations

import os
import re
from collections import defaultdict
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from gmr_studio.core.edits.world import in_source_unit
from gmr_studio.core.errors import MotionFileError, read_input
from gmr_studio.core.formats.facts import fact_comments, facts_from_comments
from gmr_studio.core.formats.frames import format_frames, format_number, parse_frames
from gmr_studio.core.formats.hierarchy import CHANNEL_NAMES, ParsedHeader, normalise_newlines, parse_header
from gmr_studio.core.kinematics.euler_matrices import degrees_to_matrices_compiled
from gmr_studio.core.model.motion import Motion, build_translations
from gmr_studio.core.rotations.continuity import continuous_euler
from gmr_studio.core.rotations.euler import complete_order, euler_from_matrix, matrix_from_euler

#: significant digits of frame values; 15 keeps write -> read to ~1e-15 relative
FRAME_DIGITS = 15
#: frames converted to angles and formatted at a time when writing
WRITE_CHUNK_FRAMES = 4096
#: rotation channels whose angles are below this (radians) may be left out when a joint
#: was read with fewer than three rotation channels
_PARTIAL_ORDER_TOLERANCE = 1e-9
#: frames converted per task when turning Euler channels into matrices
_CHUNK_FRAMES = 2048


def read_text_motion(path: str | Path, dialect: str, data: bytes | None = None) -> Motion:
    """Read a BVH ('bvh', post-rotation) or GMR ('gmr', pre-rotation) file."""
    header, values, note = parse_text_file(path, dialect, data)
    return motion_from_header(header, values, dialect, str(path), note)


def parse_text_file(
    path: str | Path, dialect: str, data: bytes | None = None
) -> tuple[ParsedHeader, np.ndarray, str | None]:
    """A BVH or GMR file's parsed header, its (F, V) frame values as written (V channels in
    file order) and a note on what the reader tolerated (None if nothing)."""
    path_text = str(path)
    data = normalise_newlines(read_input(path, data))
    header = parse_header(data, path_text, dialect)
    n_values = sum(len(j.channels) for j in header.joints)
    values, note = parse_frames(
        data,
        header.data_offset,
        header.data_line,
        n_values,
        header.n_frames,
        header.frames_token.line,
        path_text,
        allow_extra=dialect == "bvh",
    )
    return header, values, note


def motion_from_header(
    header: ParsedHeader, values: np.ndarray, dialect: str, path: str, note: str | None = None
) -> Motion:
    """The motion of a parsed header and its (F, V) frame values; ``note`` (what the reader
    tolerated) is added to the comments."""
    joints = header.joints
    n_frames, n_joints = values.shape[0], len(joints)
    offsets = np.array([j.offset for j in joints], dtype=np.float64)
    orders: list[str] = []
    has_translation = np.zeros(n_joints, bool)
    position_columns: dict[int, list[tuple[int, int]]] = {}
    rotation_columns: dict[str, list[tuple[int, list[int]]]] = defaultdict(list)
    column = 0
    for j, joint in enumerate(joints):
        order, rot_cols, pos_cols = "", [], []
        for name in joint.channels:
            kind, axis = CHANNEL_NAMES[name]
            if kind == "rotation":
                order += axis
                rot_cols.append(column)
            else:
                pos_cols.append(("XYZ".index(axis), column))
            column += 1
        orders.append(order)
        if order:
            rotation_columns[order].append((j, rot_cols))
        if pos_cols:
            has_translation[j] = True
            position_columns[j] = pos_cols
    channels = {}
    for j, cols in position_columns.items():
        block = np.broadcast_to(offsets[j], (n_frames, 3)).copy()
        for axis, col in cols:
            block[:, axis] = values[:, col]
        channels[j] = block
    translations = build_translations(n_frames, offsets, channels)
    rotations = np.empty((n_frames, n_joints, 3, 3))
    groups = [
        (order, [j for j, _ in members], np.array([c for _, c in members]))
        for order, members in rotation_columns.items()
    ]
    _fill_rotations(rotations, values, groups, [j for j, order in enumerate(orders) if not order])
    names = [j.name for j in joints]
    soft_parents = np.full(n_joints, -1, np.int64)
    first_link = None
    for j, joint in enumerate(joints):
        if joint.softlink is not None:
            first_link = first_link or joint.softlink
            if joint.softlink.text not in names:
                raise MotionFileError(
                    path,
                    f"SOFTLINK names an unknown joint '{joint.softlink.text}'",
                    joint.softlink.line,
                    joint.softlink.column,
                )
            soft_parents[j] = names.index(joint.softlink.text)
    facts, comments = facts_from_comments(header.comments)
    try:
        return Motion(
            names=names,
            parents=[j.parent for j in joints],
            soft_parents=soft_parents,
            offsets=offsets,
            rotation_orders=orders,
            has_translation=has_translation,
            rotations=rotations,
            translations=translations,
            frame_time=header.frame_time,
            convention="post" if dialect == "bvh" else "pre",
            comments=(*comments, note) if note else comments,
            facts=facts,
        )
    except ValueError as exc:
        token = first_link or header.frames_token
        raise MotionFileError(path, str(exc), token.line, token.column) from None


def _fill_rotations(
    rotations: np.ndarray, values: np.ndarray, groups: list[tuple[str, list[int], np.ndarray]], without: list[int]
) -> None:
    """rotations[:, joints] from the degree columns of each order group, and the identity
    for the joints ``without`` rotation channels.

    With numba, one compiled pass on every core (no Python between its blocks of frames);
    without, frame chunks on a few threads (numpy's ufuncs release the GIL), which keep the
    temporaries in cache. Either writes the identities as it goes: written for all frames at
    once first, they made the main thread alone touch (and the system zero) every page of
    the new array.
    """
    if degrees_to_matrices_compiled(values, groups, rotations, 0, values.shape[0], identities=without, threads=None):
        return

    def convert(frames: slice) -> None:
        rotations[frames, without] = np.eye(3)
        block = values[frames]
        for order, joints, cols in groups:
            rotations[frames, joints] = matrix_from_euler(np.radians(block[:, cols]), order)

    chunks = [slice(start, start + _CHUNK_FRAMES) for start in range(0, values.shape[0], _CHUNK_FRAMES)]
    if len(chunks) <= 1:
        for chunk in chunks:
            convert(chunk)
        return
    with ThreadPoolExecutor(max_workers=min(len(chunks), os.cpu_count() or 1, 8)) as pool:
        list(pool.map(convert, chunks))


# ----------------------------------------------------------------------------- writing
def _written_order(motion: Motion, j: int) -> str:
    """The rotation channels to write for joint j: its own, completed to three axes when
    the rotation needs axes the joint was not read with."""
    order = motion.rotation_orders[j]
    if not order or len(order) == 3:
        return order
    full = complete_order(order)
    angles = euler_from_matrix(motion.rotations[:, j], full)
    if np.all(np.abs(angles[:, len(order) :]) < _PARTIAL_ORDER_TOLERANCE):
        return order
    return full


def _is_end_site(motion: Motion, j: int, dialect: str) -> bool:
    """A BVH End Site: a channel-free leaf named as the reader names end sites
    (``<parent>_End``, maybe numbered); other channel-free leaves keep their name as a
    JOINT with ``CHANNELS 0``."""
    parent = motion.parents[j]
    return (
        dialect == "bvh"
        and parent >= 0
        and not motion.children[j]
        and not motion.rotation_orders[j]
        and not motion.has_translation[j]
        and re.fullmatch(re.escape(motion.names[parent]) + r"_End\d*", motion.names[j]) is not None
    )


def format_text_motion(motion: Motion, dialect: str) -> Iterator[str]:
    """The file's text in chunks. ``dialect`` 'bvh' needs a post-rotation motion, 'gmr' a
    pre-rotation one (convert first; see :mod:`core.kinematics.convention`)."""
    expected = "post" if dialect == "bvh" else "pre"
    if motion.convention != expected:
        raise ValueError(
            f"a {dialect.upper()} file holds a {expected}-rotation motion; this one is "
            f"{motion.convention}-rotation (convert it first)"
        )
    if dialect == "bvh":  # BVH cannot state a unit: lengths go back to the unit they came from
        motion = in_source_unit(motion)
    order_of = {j: _written_order(motion, j) for j in range(motion.n_joints)}
    lines: list[str] = []
    if dialect == "gmr":
        lines.append("GMR 1")
        lines.extend(f"# {c}" if c else "#" for c in (*fact_comments(motion.facts), *motion.comments))
    lines.append("HIERARCHY")
    columns: list[tuple[str, int, str]] = []  # (kind, joint, order) in file order

    def write_joint(j: int, depth: int) -> None:
        indent = "\t" * depth
        parent = motion.parents[j]
        if _is_end_site(motion, j, dialect):
            lines.extend([f"{indent}End Site", f"{indent}{{"])
            lines.append(f"{indent}\tOFFSET " + " ".join(format_number(v) for v in motion.offsets[j]))
            lines.append(f"{indent}}}")
            return
        lines.append(f"{indent}{'ROOT' if parent < 0 else 'JOINT'} {motion.names[j]}")
        lines.append(f"{indent}{{")
        if motion.soft_parents[j] >= 0:
            lines.append(f"{indent}\tSOFTLINK {motion.names[motion.soft_parents[j]]}")
        lines.append(f"{indent}\tOFFSET " + " ".join(format_number(v) for v in motion.offsets[j]))
        names = []
        if motion.has_translation[j]:
            names += ["Xposition", "Yposition", "Zposition"]
            columns.append(("position", j, ""))
        if order_of[j]:
            names += [f"{axis}rotation" for axis in order_of[j]]
            columns.append(("rotation", j, order_of[j]))
        lines.append(f"{indent}\tCHANNELS {len(names)}" + "".join(" " + n for n in names))
        for child in motion.children[j]:
            write_joint(child, depth + 1)
        lines.append(f"{indent}}}")

    for root in motion.roots:
        write_joint(int(root), 0)
    lines += ["MOTION", f"Frames: {motion.n_frames}", f"Frame Time: {format_number(motion.frame_time)}", ""]
    yield "\n".join(lines)
    for values in _frame_values(motion, columns, WRITE_CHUNK_FRAMES):
        yield format_frames(values, FRAME_DIGITS)


def _frame_values(motion: Motion, columns: list[tuple[str, int, str]], chunk: int) -> Iterator[np.ndarray]:
    """(up to chunk, V) channel values in file order, block after block of frames: positions as
    stored, rotations in degrees, continuous over all the frames
    (:func:`core.rotations.continuity.continuous_euler`, carried from block to block). Only
    one block of angles is held at a time, so writing needs memory for ``chunk`` frames,
    not for the motion."""
    by_order: dict[str, list[int]] = defaultdict(list)
    for kind, j, order in columns:
        if kind == "rotation":
            by_order[order].append(j)
    last: dict[str, np.ndarray | None] = dict.fromkeys(by_order)
    for start in range(0, motion.n_frames, chunk):
        frames = slice(start, min(start + chunk, motion.n_frames))
        angles: dict[int, np.ndarray] = {}
        for order, joints in by_order.items():
            radians = continuous_euler(motion.rotations[frames, joints], order, last[order])
            last[order] = radians[-1]
            degrees = np.degrees(radians)
            for k, j in enumerate(joints):
                angles[j] = degrees[:, k]
        blocks = [motion.translations[frames, j] if kind == "position" else angles[j] for kind, j, _ in columns]
        yield np.concatenate(blocks, axis=1) if blocks else np.zeros((frames.stop - frames.start, 0))
