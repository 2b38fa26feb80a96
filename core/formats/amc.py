"""AMC files (Acclaim motion capture) read straight into GMR (pre-rotation) motion.

A bone's END is the joint (MATH.md "ASF/AMC -> GMR"). With ``C`` the bone's axis rotation
and ``R_b`` its AMC rotation, Acclaim's ``world(b) = world(parent) C R_b C^-1`` and
``end(b) = end(parent) + length_b world(b) direction_b`` are exactly pre-rotation with

- ``R'_b = C R_b C^-1`` and ``t'_b = length_b direction_b`` for every bone,
- the root joint (named ``root``): ``R'_root = C_root R_root C_root^-1`` and, as its
  translation, ``G = position + (TX, TY, TZ)``.

Joints: ``root`` first, then the bones in ``:bonedata`` order. Bones without dofs get the
identity. Rarely used translation dofs are read too: ``tx ty tz`` move the bone's end in the
bone's local (axis) frame, ``l`` adds to its length, so ``t'_b = (length_b + l) direction_b
+ C (tx, ty, tz)`` per frame.

Speed: a frame block in which every frame lists the same bones in the same order, one
space between tokens (what CMU's files and most exporters write), is read in bulk by
:mod:`core.formats.amc_bulk`: its shape checked from the bytes, the names blanked and every
number parsed by one ``numpy.loadtxt``, a frame a row. Any other block is tokenised by numpy
over the bytes (no Python work per line or value): token boundaries from a white-space mask,
the first token of each line read as 8-byte words and matched against the bone names (hash,
binary search, exact compare), the names blanked out, and every number parsed at once by
``numpy.fromstring``. Both give the same values to the bit; errors come from the second.
Bones may come in any order in a frame; each bone with dofs must appear exactly once per
frame; frame numbers count up by one.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from gmr_studio.core.compiled import Backend
from gmr_studio.core.errors import MotionFileError, quoted, read_input
from gmr_studio.core.formats.acclaim_skeleton import ROOT_NAME, ROTATION_DOFS, AcclaimSkeleton
from gmr_studio.core.formats.amc_bulk import NUMBER_CHARACTERS, bulk_frames
from gmr_studio.core.formats.asf import read_asf
from gmr_studio.core.formats.frames import out_of_range, within_range
from gmr_studio.core.formats.hierarchy import normalise_newlines
from gmr_studio.core.kinematics.euler_matrices import conjugated_matrices_compiled
from gmr_studio.core.model.channels import FileChannels
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion, identity_rotations
from gmr_studio.core.rotations.euler import complete_order, matrix_from_euler
from gmr_studio.core.space.units import acclaim_unit

#: frame rate assumed for AMC files, which do not store one (CMU's motions are 120 Hz)
DEFAULT_FRAME_RATE = 120.0
_HEADER_KEYWORDS = (":FULLY-SPECIFIED", ":DEGREES", ":RADIANS")
_PAD = 16
_ALL_BYTES = np.uint64(0xFFFFFFFFFFFFFFFF)
_ZEROS = np.uint64(0x3030303030303030)
_DIGIT_CARRY = np.uint64(0x7676767676767676)
_HIGH_BITS = np.uint64(0x8080808080808080)
#: frames per matrix product in :func:`conjugate` (OpenBLAS keeps a product of at most
#: 262,144 multiply-adds on one thread; a frame takes 27)
CONJUGATE_BLOCK = 8192
_HASH_MULTIPLIERS = (np.uint64(0x9E3779B97F4A7C15), np.uint64(0xC2B2AE3D27D4EB4F), np.uint64(0x165667B19E3779F9))


def _hash_words(words: np.ndarray, multiplier: np.uint64) -> np.ndarray:
    """(N, W) uint64 -> (N,) uint64, a multiply-xor hash of each row (wrapping arithmetic)."""
    out = words[:, 0].copy()
    for k in range(1, words.shape[1]):
        out = (out * multiplier) ^ words[:, k]
    return out * multiplier


def conjugate(c: np.ndarray, rotations: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``C R C^T`` for one (3, 3) ``C`` and (F, 3, 3) ``R``, as two (3B, 3) x (3, 3) matrix
    products per block of B = :data:`CONJUGATE_BLOCK` frames (one BLAS call each, instead of
    F small ones). A block is small enough for OpenBLAS to multiply on the calling thread:
    a larger product is split over threads, which on a busy machine wait for each other
    longer than the product takes. The numbers are those of one product over every frame.
    ``out``: an (F, 3, 3) array (or view) to write them to, returned."""
    out = np.empty_like(rotations, dtype=np.float64) if out is None else out
    for start in range(0, rotations.shape[0], CONJUGATE_BLOCK):
        block = rotations[start : start + CONJUGATE_BLOCK]
        n = block.shape[0]
        right = (block.reshape(-1, 3) @ c.T).reshape(n, 3, 3)  # R C^T
        out[start : start + n] = (np.swapaxes(right, 1, 2).reshape(-1, 3) @ c.T).reshape(n, 3, 3).swapaxes(1, 2)
    return out  # C X = (X^T C^T)^T above


# --------------------------------------------------------------------------- skeleton
def _joint_orders(skeleton: AcclaimSkeleton) -> list[str]:
    """Intrinsic rotation order per joint (root first): the dof rotations reversed (they
    apply in file order about the bone's axes), completed to three axes."""

    def order(dofs: tuple[str, ...], fallback: str) -> str:
        axes = "".join(d[1].upper() for d in dofs if d in ROTATION_DOFS)[::-1]
        return complete_order(axes) if axes else fallback[::-1]

    return [order(skeleton.root_order, skeleton.root_axis)] + [order(b.dof, b.axis_order) for b in skeleton.bones]


def skeleton_motion(skeleton: AcclaimSkeleton, n_frames: int = 1, frame_rate: float = DEFAULT_FRAME_RATE) -> Motion:
    """The skeleton's rest pose as a GMR motion of ``n_frames`` identical frames.

    Joints: ``root`` (at ``root_position``) then the bones in ``:bonedata`` order, each at
    its bone's end; offsets ``length * direction``; every rotation the identity.
    """
    n_joints = len(skeleton.bones) + 1
    offsets = np.zeros((n_joints, 3))
    offsets[0] = skeleton.root_position
    for j, bone in enumerate(skeleton.bones, start=1):
        offsets[j] = bone.length * bone.direction
    has_translation = np.zeros(n_joints, bool)
    has_translation[0] = True
    return Motion(
        names=(ROOT_NAME, *skeleton.names),
        parents=[-1] + [b.parent + 1 if b.parent >= 0 else 0 for b in skeleton.bones],
        offsets=offsets,
        rotation_orders=_joint_orders(skeleton),
        has_translation=has_translation,
        rotations=identity_rotations(n_frames, n_joints),
        translations=np.broadcast_to(offsets, (n_frames, n_joints, 3)).copy(),
        frame_time=1.0 / frame_rate,
        convention="pre",
        comments=_skeleton_comments(skeleton),
        facts=FileFacts(unit=acclaim_unit(skeleton.units.length)),
    )


def _skeleton_comments(skeleton: AcclaimSkeleton) -> tuple[str, ...]:
    units = skeleton.units
    return (
        f"skeleton: {Path(skeleton.path).name} (ASF{' ' + skeleton.name if skeleton.name else ''})",
        f"ASF units: length {units.length:g}, mass {units.mass:g}, angle {units.angle}; "
        "positions are in the ASF's length units",
    )


# ------------------------------------------------------------------------------ header
def _split_header(data: bytes, path: str) -> tuple[dict, int, int]:
    """Keywords and comments before the first frame: (flags, byte offset of the body,
    1-based line number of the body's first line)."""
    flags = {"fully_specified": False, "angle": None}
    offset, line = 0, 1
    while offset < len(data):
        end = data.find(b"\n", offset)
        end = len(data) if end < 0 else end
        text = data[offset:end].split(b"#", 1)[0].strip()
        if text:
            if not text.startswith(b":"):
                break
            word = text.split()[0].decode("utf-8", "replace").upper()
            column = data[offset:end].find(b":") + 1
            if word not in _HEADER_KEYWORDS or len(text.split()) > 1:
                raise MotionFileError(
                    path,
                    f"expected {', '.join(_HEADER_KEYWORDS)} or a frame number, found "
                    f"{quoted(text.decode('utf-8', 'replace'))}",
                    line,
                    column,
                )
            if word == ":FULLY-SPECIFIED":
                flags["fully_specified"] = True
            else:
                flags["angle"] = "deg" if word == ":DEGREES" else "rad"
        offset, line = end + 1, line + 1
    return flags, min(offset, len(data)), line


# ------------------------------------------------------------------------------- frames
class _Block:
    """The frame block as numpy arrays: its tokens, the first token of each line, and
    what each line starts with. Line and column numbers are computed only for errors."""

    def __init__(self, body: bytes, first_line: int, path: str) -> None:
        self.body = body
        self.first_line = first_line
        self.path = path
        padded = body + bytes(_PAD)
        self.buffer = np.frombuffer(padded, np.uint8)[: len(body)]
        # every byte at or below the space is white space (tab, LF, CR, VT, FF, NUL...)
        space = self.buffer <= 32
        edges = np.flatnonzero(space[1:] != space[:-1]) + 1
        if body and not space[0]:
            edges = np.concatenate(([0], edges))
        if body and not space[-1]:
            edges = np.concatenate((edges, [len(body)]))
        self.starts = edges[0::2]  # first byte of each token
        self.ends = edges[1::2]  # one past its last byte
        # a token opens a line when the white space before it holds a line break
        first = np.ones(self.starts.size, bool)
        gap_start, gap_end = self.ends[:-1], self.starts[1:]
        single = gap_end - gap_start == 1
        first[1:][single] = self.buffer[gap_start[single]] == 10
        wide = np.flatnonzero(~single)
        if wide.size:
            newlines = np.flatnonzero(self.buffer == 10)
            first[1:][wide] = np.searchsorted(newlines, gap_end[wide]) > np.searchsorted(newlines, gap_start[wide])
        self.line_first_token = np.flatnonzero(first)  # per non-blank line, its first token
        self.line_tokens = np.diff(np.append(self.line_first_token, self.starts.size))
        # 8 bytes starting at every byte, as little-endian words (an unaligned view)
        self.words = np.ndarray(shape=(len(body),), dtype="<u8", buffer=padded, strides=(1,))

    def where(self, token: int) -> tuple[int, int]:
        """1-based (line, column) of a token."""
        start = int(self.starts[token])
        line_start = self.body.rfind(b"\n", 0, start) + 1
        column = len(self.body[line_start:start].decode("utf-8", "replace")) + 1
        return self.first_line + self.body.count(b"\n", 0, start), column

    def text(self, token: int) -> str:
        return self.body[int(self.starts[token]) : int(self.ends[token])].decode("utf-8", "replace")

    def error(self, token: int, message: str) -> MotionFileError:
        line, column = self.where(token)
        return MotionFileError(self.path, message, line, column)

    def line_end_error(self, token: int, message: str) -> MotionFileError:
        """An error placed just after ``token`` (missing values at the end of a line)."""
        line, column = self.where(token)
        return MotionFileError(self.path, message, line, column + int(self.ends[token] - self.starts[token]))

    def first_words(self, names: list[str]) -> tuple[np.ndarray, np.ndarray]:
        """Per line: the index in ``names`` of its first token (-1 if none matches) and
        whether that token is a whole number of at most 16 digits (a frame number).

        Each first token is read as words of 8 bytes (bytes past its end zeroed), the
        words hashed to one, looked up among the names' hashes by binary search and then
        compared word for word, so a hash collision cannot give a wrong match.
        """
        starts = self.starts[self.line_first_token]
        lengths = self.ends[self.line_first_token] - starts
        encoded = [n.encode("utf-8") for n in names]
        n_words = max(2, -(-max(len(e) for e in encoded) // 8))
        words = np.empty((starts.size, n_words), np.uint64)
        is_number = lengths <= 16
        for k in range(n_words):
            valid = np.clip(lengths - 8 * k, 0, 8).astype(np.uint64)
            keep = np.where(valid == 8, _ALL_BYTES, (np.uint64(1) << (np.uint64(8) * valid)) - np.uint64(1))
            words[:, k] = self.words[np.minimum(starts + 8 * k, len(self.body) - 1)] & keep
            if k < 2:  # SWAR: every kept byte a digit (bytes past the end count as '0')
                offset = (words[:, k] | (_ZEROS & ~keep)) ^ _ZEROS
                is_number &= ((offset + _DIGIT_CARRY) | offset) & _HIGH_BITS == 0
        width = 8 * n_words
        table = np.stack([np.frombuffer(e.ljust(width, b"\0"), "<u8") for e in encoded]).astype(np.uint64)
        for multiplier in _HASH_MULTIPLIERS:
            table_hash = _hash_words(table, multiplier)
            if np.unique(table_hash).size == len(names):
                break
        order = np.argsort(table_hash)
        position = np.minimum(np.searchsorted(table_hash[order], _hash_words(words, multiplier)), len(names) - 1)
        candidate = order[position]
        found = (lengths <= width) & (words == table[candidate]).all(axis=1)
        return np.where(found, candidate, -1), is_number

    def numbers(self, joint: np.ndarray, name_lengths: np.ndarray) -> np.ndarray:
        """Every token except the bone names that open lines, as floats in file order.

        ``joint``: per line, the joint it names (-1 for frame lines); ``name_lengths``:
        bytes per joint name. MotionFileError at the first token that is not a finite number.
        """
        text = self.buffer.copy()
        text[text < 32] = 32  # white space as the tokens have it (numpy parses only its own)
        keep = np.ones(text.size, bool)  # the names left out (white space stays around them)
        for j in np.unique(joint[joint >= 0]):
            starts = self.starts[self.line_first_token[joint == j]]
            keep[np.add.outer(starts, np.arange(name_lengths[j])).ravel()] = False
        data = text[keep].tobytes()
        values = None
        if not data.translate(None, NUMBER_CHARACTERS):
            try:
                values = np.fromstring(data, dtype=np.float64, sep=" ")
            except ValueError:
                values = None
        expected = self.starts.size - int((joint >= 0).sum())
        if values is not None and values.size == expected and within_range(values):
            return values
        names = set(self.line_first_token[joint >= 0].tolist())
        for token in range(self.starts.size):
            if token in names:
                continue
            text_token = self.text(token)
            try:
                number = float(text_token)
            except ValueError:
                number = None
            if number is None or text_token.encode().translate(None, NUMBER_CHARACTERS):
                raise self.error(token, f"expected a number, found {quoted(text_token)}")
            if not np.isfinite(number):
                raise self.error(token, f"expected a finite number, found {quoted(text_token)}")
            if not within_range(number):
                raise self.error(token, out_of_range(text_token))
        raise MotionFileError(self.path, "the frame data could not be read", self.first_line, 1)  # pragma: no cover


def _dof_layout(skeleton: AcclaimSkeleton) -> tuple[list[str], list[tuple[str, ...]], np.ndarray]:
    """Names (root first), dofs per joint and the first column of each joint's values."""
    names = [ROOT_NAME, *skeleton.names]
    dofs = [skeleton.root_order] + [b.dof for b in skeleton.bones]
    counts = np.array([len(d) for d in dofs])
    return names, dofs, np.concatenate(([0], np.cumsum(counts)[:-1]))


def parse_amc_frames(
    data: bytes, path: str, skeleton: AcclaimSkeleton, *, bulk: bool = True
) -> tuple[np.ndarray, int, dict]:
    """The frame values of an AMC file. A frame block of the common shape (every frame the
    same bones in the same order: :mod:`core.formats.amc_bulk`) is read in bulk unless
    ``bulk`` is False; the values are the same either way.

    Returns
    -------
    values : (F, V) float64, the dof values of every joint (root first, then bones in
        ``:bonedata`` order, each in its dof order), as written (degrees or radians).
    first_frame : int, the number of the first frame.
    flags : dict, ``fully_specified`` (bool) and ``angle`` ('deg', 'rad' or None).
    """
    data = normalise_newlines(data)
    flags, offset, first_line = _split_header(data, path)
    names, dofs, column_of = _dof_layout(skeleton)
    counts = np.array([len(d) for d in dofs])
    n_values = int(counts.sum())
    if bulk and data.find(b"#", offset) < 0:
        found = bulk_frames(data, names, counts, column_of, start=offset)
        if found is not None:
            return found[0], found[1], flags
    body = data[offset:]
    if b"#" in body:  # comments inside the frames: blank them (columns stay right)
        body = re.sub(rb"#[^\n]*", lambda match: b" " * len(match.group()), body)
    block = _Block(body, first_line, path)
    n_lines = block.line_first_token.size
    if n_lines == 0:
        return np.zeros((0, n_values)), 1, flags
    joint, is_number = block.first_words(names)
    # every line starts with a frame number or a known bone name
    unknown = np.flatnonzero((joint < 0) & ~is_number)
    if unknown.size:
        token = int(block.line_first_token[unknown[0]])
        word = block.text(token)
        raise block.error(
            token, f"unknown bone {quoted(word)}: expected a frame number or a bone of {Path(skeleton.path).name}"
        )
    frame_lines = np.flatnonzero(is_number & (joint < 0))
    if frame_lines.size == 0 or frame_lines[0] != 0:
        token = int(block.line_first_token[0])
        raise block.error(token, f"expected a frame number before the data of bone {quoted(block.text(token))}")
    extra = np.flatnonzero(block.line_tokens[frame_lines] > 1)
    if extra.size:
        token = int(block.line_first_token[frame_lines[extra[0]]]) + 1
        raise block.error(token, f"expected only the frame number on its line, found {quoted(block.text(token))}")
    bone_lines = np.flatnonzero(joint >= 0)
    numbers = block.numbers(joint, np.array([len(n.encode("utf-8")) for n in names]))
    # numbers per line, in file order: frame lines hold one, bone lines their values
    per_line = block.line_tokens.copy()
    per_line[bone_lines] -= 1
    line_start = np.concatenate(([0], np.cumsum(per_line)[:-1]))
    bone_of_line = joint[bone_lines]
    wrong = np.flatnonzero(per_line[bone_lines] != counts[bone_of_line])
    if wrong.size:
        line = int(bone_lines[wrong[0]])
        j = int(bone_of_line[wrong[0]])
        found, want = int(per_line[line]), int(counts[j])
        first = int(block.line_first_token[line])
        message = (
            f"bone '{names[j]}' has {want} dof ({' '.join(dofs[j]) or 'none'}): expected {want} values, found {found}"
        )
        if found > want:
            raise block.error(first + 1 + want, message)
        raise block.line_end_error(first + found, message)
    frame_numbers = numbers[line_start[frame_lines]]
    n_frames = frame_lines.size
    expected = frame_numbers[0] + np.arange(n_frames)
    jump = np.flatnonzero(frame_numbers != expected)
    if jump.size:
        token = int(block.line_first_token[frame_lines[jump[0]]])
        raise block.error(
            token,
            f"frame number {block.text(token)}: expected {int(expected[jump[0]])} (frames count up by one)",
        )
    frame_of_line = np.cumsum(is_number & (joint < 0)) - 1
    # each bone once per frame; bones with dofs in every frame
    key = frame_of_line[bone_lines] * len(names) + bone_of_line
    seen = np.bincount(key, minlength=n_frames * len(names)).reshape(n_frames, len(names))
    if (seen > 1).any():
        repeats = np.flatnonzero(seen.ravel()[key] > 1)
        second = int(repeats[np.flatnonzero(key[repeats] == key[repeats[0]])[1]])
        line = int(bone_lines[second])
        first_line = block.where(int(block.line_first_token[bone_lines[repeats[0]]]))[0]
        raise block.error(
            int(block.line_first_token[line]),
            f"bone '{names[int(bone_of_line[second])]}' appears twice in frame "
            f"{int(frame_numbers[frame_of_line[line]])} (first at line {first_line})",
        )
    missing = np.argwhere((seen == 0) & (counts > 0))
    if missing.size:
        frame, j = (int(v) for v in missing[0])
        raise block.error(
            int(block.line_first_token[frame_lines[frame]]),
            f"frame {int(frame_numbers[frame])} has no line for bone '{names[j]}' "
            f"({' '.join(dofs[j])}): every bone with dofs must appear in every frame",
        )
    # every bone line's numbers in one scatter: the k-th number of a line of bone j in frame f
    # goes to (f, column_of[j] + k), its place in ``numbers`` shifted by one amount per line
    values = np.empty((n_frames, n_values))
    shift = frame_of_line[bone_lines] * n_values + column_of[bone_of_line] - line_start[bone_lines]
    is_value = np.ones(numbers.size, bool)
    is_value[line_start[frame_lines]] = False  # the frame numbers
    source = np.flatnonzero(is_value)  # the bone lines' numbers, line after line
    values.ravel()[source + np.repeat(shift, counts[bone_of_line])] = numbers[source]
    return values, int(frame_numbers[0]), flags


# ------------------------------------------------------------------------------ motion
def _columns(values: np.ndarray, columns: list[int]) -> np.ndarray:
    """``values[:, columns]``: a view when the columns are evenly spaced (a bone's dofs in
    file order), else a copy."""
    step = columns[1] - columns[0] if len(columns) > 1 else 1
    if step > 0 and columns == list(range(columns[0], columns[-1] + 1, step)):
        return values[:, columns[0] : columns[-1] + 1 : step]
    return values[:, columns]


def _axis_rotations(
    values: np.ndarray,
    groups: list[tuple[str, list[int], np.ndarray]],
    axes: np.ndarray,
    scale: float,
    without: list[int],
    out: np.ndarray,
    backend: Backend = "auto",
) -> None:
    """``out[:, j] = C_j R_j C_j^T`` (F, J, 3, 3) for each (order, [j], columns) group, ``R_j``
    the rotation of the Euler angles ``values[:, columns] * scale`` in ``order`` and ``C_j =
    axes[j]``; the identity for the joints ``without`` rotation dofs.

    The compiled kernel when ``backend`` chooses it (:mod:`core.compiled`): one pass on
    every core, equal to the numpy path to rounding
    (:func:`core.kinematics.euler_matrices.conjugated_matrices_compiled`). The numpy path, the
    reference: :func:`core.rotations.euler.matrix_from_euler` and :func:`conjugate` per joint
    and block of :data:`CONJUGATE_BLOCK` frames (no temporary of the take's size).
    """
    if conjugated_matrices_compiled(
        values, groups, axes, out, scale=scale, identities=without, threads=None, backend=backend
    ):
        return
    out[:, without] = np.eye(3)
    for start in range(0, values.shape[0], CONJUGATE_BLOCK):
        block = values[start : start + CONJUGATE_BLOCK]
        for order, (j,), cols in groups:
            rotations = matrix_from_euler(block[:, cols[0]] * scale, order)
            conjugate(axes[j], rotations, out=out[start : start + CONJUGATE_BLOCK, j])


def read_amc(
    amc_path: str | Path,
    skeleton: AcclaimSkeleton | str | Path,
    *,
    frame_rate: float = DEFAULT_FRAME_RATE,
    data: bytes | None = None,
) -> Motion:
    """Read an AMC file with its skeleton into a GMR (pre-rotation) motion
    (:func:`read_amc_with_channels` without the channels)."""
    return read_amc_with_channels(amc_path, skeleton, frame_rate=frame_rate, data=data)[0]


def read_amc_with_channels(
    amc_path: str | Path,
    skeleton: AcclaimSkeleton | str | Path,
    *,
    frame_rate: float = DEFAULT_FRAME_RATE,
    data: bytes | None = None,
    backend: Backend = "auto",
) -> tuple[Motion, FileChannels]:
    """Read an AMC file with its skeleton into a GMR (pre-rotation) motion, and the file's
    rotation dofs as written (:class:`core.model.channels.FileChannels`, kind ``"amc"``: degrees,
    one column per rotation dof in file order, with each bone's ASF frame).

    Parameters
    ----------
    amc_path : the AMC file.
    skeleton : its :class:`AcclaimSkeleton`, or the path of its ASF file.
    frame_rate : frames per second (AMC files do not say; CMU's are 120).
    data : the AMC's bytes, if already in hand.
    backend : 'auto', 'numba' or 'numpy' (:mod:`core.compiled`): how the rotations are
        computed; the compiled kernel equals the numpy path to rounding.

    Returns
    -------
    Motion with joints ``root`` then the bones in ``:bonedata`` order (each at its bone's
    end), ``rotations`` (F, J, 3, 3) ``C R C^-1``, the root's translation ``G`` per frame;
    and the file's channels.

    Raises
    ------
    MotionFileError (path, line, column, what was expected) for a bad AMC or ASF.
    """
    if not isinstance(skeleton, AcclaimSkeleton):
        skeleton = read_asf(skeleton)
    path_text = str(amc_path)
    data = read_input(amc_path, data)
    if not np.isfinite(frame_rate) or frame_rate <= 0:
        raise ValueError(f"frame rate must be a positive number, not {frame_rate}")
    values, first_frame, flags = parse_amc_frames(data, path_text, skeleton)
    angle_unit = flags["angle"] or skeleton.units.angle
    rest = skeleton_motion(skeleton, 0, frame_rate)
    n_frames, n_joints = values.shape[0], rest.n_joints
    _, dofs, column_of = _dof_layout(skeleton)
    scale = np.pi / 180.0 if angle_unit == "deg" else 1.0
    rotations = np.empty((n_frames, n_joints, 3, 3))  # every joint's filled below
    translations = np.empty((n_frames, n_joints, 3))
    translations[:] = rest.offsets
    has_translation = rest.has_translation.copy()
    axes = np.array([skeleton.root_axis_rotation] + [b.axis_rotation for b in skeleton.bones])
    channels = FileChannels({}, {}, {}, kind="amc", axes={})
    groups: list[tuple[str, list[int], np.ndarray]] = []  # (order, [joint], its angles' columns)
    for j, dof in enumerate(dofs):
        columns = {d: int(column_of[j]) + k for k, d in enumerate(dof)}
        rotation_dofs = [d for d in dof if d in ROTATION_DOFS]
        if rotation_dofs:
            name = rest.names[j]
            written = _columns(values, [columns[d] for d in rotation_dofs])
            written = written if angle_unit == "deg" else np.degrees(written)
            written.flags.writeable = False
            channels.orders[name] = "".join(d[1].upper() for d in rotation_dofs)
            channels.angles[name], channels.labels[name], channels.axes[name] = written, tuple(rotation_dofs), axes[j]
            # applied in file order about the local axes: R = R_last ... R_first
            order = "".join(d[1].upper() for d in reversed(rotation_dofs))
            groups.append((order, [j], np.array([[columns[d] for d in reversed(rotation_dofs)]])))
        moved = any(d in columns for d in ("tx", "ty", "tz", "l"))
        if j == 0 or moved:
            shift = np.zeros((n_frames, 3))
            for k, axis in enumerate("xyz"):
                if f"t{axis}" in columns:
                    shift[:, k] = values[:, columns[f"t{axis}"]]
        if j == 0:
            translations[:, 0] = skeleton.root_position + shift
        elif moved:
            bone = skeleton.bones[j - 1]
            stretch = values[:, columns["l"]] if "l" in columns else 0.0
            translations[:, j] = (
                np.multiply.outer(bone.length + stretch, bone.direction) if "l" in columns else rest.offsets[j]
            ) + shift @ axes[j].T
            has_translation[j] = True
    rotated = {joints[0] for _, joints, _ in groups}
    without = [j for j in range(n_joints) if j not in rotated]
    _axis_rotations(values, groups, axes, scale, without, rotations, backend)
    comments = (
        f"converted from {Path(path_text).name} (AMC frames {first_frame} to {first_frame + n_frames - 1}, "
        f"angles in {'degrees' if angle_unit == 'deg' else 'radians'})",
        *rest.comments,
        f"frame rate {frame_rate:g} Hz (AMC files do not store one)",
    )
    motion = rest.replace(
        rotations=rotations,
        translations=translations,
        has_translation=has_translation,
        comments=comments,
    )
    return motion, channels
