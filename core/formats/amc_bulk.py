"""The common AMC frame block read in bulk: every frame lists the same bones in the same
order, one space between tokens.

When the block has that shape (checked exactly, from its bytes), the bone names are blanked
where the first frame puts them and every number is parsed by one ``numpy.loadtxt``, a frame
a row, then each bone's columns put in the joint order. ``loadtxt`` and the general reader's
``numpy.fromstring`` (:func:`core.formats.amc.parse_amc_frames`) both turn each token into
the nearest double (Python's string-to-double), so the values are the same to the bit.
Anything else (bones missing or reordered, other white space, comments, bad input) returns
``None`` and the general reader decides, with its errors.

The shape checked, for a block of ``F`` frames of ``B`` bone lines:

- no control byte but the line break, no blank line, no space at either end of a line and
  never two in a row, so a line's tokens are its spaces plus one;
- ``F * (B + 1)`` lines; each frame's first line a frame number (1 to 16 digits, nothing
  else), the numbers counting up by one;
- the k-th bone line of every frame opens with the first frame's k-th bone name and a space
  and holds that bone's number of dofs in values; the first frame names every bone with
  dofs once, and no bone without; every bone line is at least 8 bytes long.
"""

from __future__ import annotations

import io

import numpy as np

from gmr_studio.core.formats.frames import within_range

#: the bytes a block of numbers may hold once the names are blanked (as the general reader)
NUMBER_CHARACTERS = b"0123456789+-.eE" + bytes(range(33))
_PAD = 16
_MAX_FRAME_DIGITS = 16
_SPACES = np.uint64(0x2020202020202020)


def _first_frame_bones(data: bytes, start: int, names: list[str], counts: np.ndarray) -> list[int] | None:
    """Joint index of each bone line of the first frame (from byte ``start`` of ``data``), in
    file order, or None when the first frame does not open with a frame number or does not
    name each bone with dofs once."""
    index = {name.encode("utf-8"): j for j, name in enumerate(names)}
    end = data.find(b"\n", start)
    first = data[start : end if end >= 0 else len(data)]
    if not (first.isdigit() and len(first) <= _MAX_FRAME_DIGITS):
        return None
    bones: list[int] = []
    while end >= 0 and len(bones) <= len(names):
        line_start, end = end + 1, data.find(b"\n", end + 1)
        line = data[line_start : end if end >= 0 else len(data)]
        if line.isdigit():
            break
        j = index.get(line.split(b" ", 1)[0], -1)
        if j < 0 or j in bones or counts[j] == 0:
            return None
        bones.append(j)
    else:
        return None  # no second frame within reach: a single frame, or too many bone lines
    if sorted(bones) != [int(j) for j in np.flatnonzero(counts > 0)]:
        return None
    return bones


def bulk_frames(
    data: bytes, names: list[str], counts: np.ndarray, column_of: np.ndarray, start: int = 0
) -> tuple[np.ndarray, int] | None:
    """The frame values of an AMC frame block of the common shape (module docstring).

    Parameters
    ----------
    data : bytes whose frame block (line breaks ``\\n``) starts at byte ``start`` and runs
        to the end (the header before it, left out).
    names : (J,) joint names, root first; counts : (J,) dofs per joint; column_of : (J,)
        first column of each joint's values.

    Returns
    -------
    ``(values, first_frame)``, values (F, V) float64 as written, each joint's dofs from
    ``column_of``; or None when the block is not of that shape or holds anything but numbers
    in range (the general reader then reads it or names the error).
    """
    if any(name.isdigit() and len(name) <= _MAX_FRAME_DIGITS for name in names):
        return None  # a bone named like a frame number: lines would be ambiguous
    size = len(data) - start
    if size <= 0 or data[start : start + 1] in b" \n" or data.endswith(b" "):
        return None
    bones = _first_frame_bones(data, start, names, counts)
    if bones is None:
        return None
    padded = np.zeros(size + _PAD, np.uint8)  # the block, then zeros (for 8-byte reads)
    padded[:size] = np.frombuffer(data, np.uint8, count=size, offset=start)
    buffer = padded[:size]
    # every white-space or control byte at once: only spaces and line breaks, never two in
    # a row (two spaces, a blank line, a space at either end of a line)
    blank = np.flatnonzero(buffer <= 32)
    kinds = buffer[blank]
    if ((kinds != 10) & (kinds != 32)).any():
        return None  # tabs, carriage returns or other control bytes
    if np.diff(blank).min(initial=2) < 2:
        return None  # two spaces in a row, a blank line or a space at either end of a line
    in_blank = np.flatnonzero(kinds == 10)  # the line breaks among them
    breaks = blank[in_blank]
    starts = np.concatenate(([0], breaks + 1))
    ends = np.append(breaks, size)
    if data.endswith(b"\n"):
        starts, ends = starts[:-1], ends[:-1]
    per_frame = len(bones) + 1
    if starts.size % per_frame:
        return None
    n_frames = starts.size // per_frame
    starts, ends = starts.reshape(n_frames, per_frame), ends.reshape(n_frames, per_frame)
    # frame lines: 1 to 16 digits and nothing else
    lengths = ends[:, 0] - starts[:, 0]
    if lengths.min() < 1 or lengths.max() > _MAX_FRAME_DIGITS:
        return None
    reach = np.arange(_MAX_FRAME_DIGITS)
    digits = buffer[np.minimum(starts[:, :1] + reach, size - 1)]
    if not ((digits >= 48) & (digits <= 57) | (reach >= lengths[:, None])).all():
        return None
    # bone lines: the first frame's name and a space, then that bone's number of values
    # (a line's spaces: the white-space bytes between its break and the one before)
    spaces = (np.diff(np.append(in_blank, blank.size), prepend=-1) - 1)[: starts.size].reshape(starts.shape)
    if not (spaces[:, 1:] == counts[bones]).all():
        return None
    # each bone line's first bytes as 8-byte words (unaligned), every line at once in file
    # order: its name checked and blanked; lines of 8 bytes or more keep one pass's words apart
    lines = starts[:, 1:]
    if (ends[:, 1:] - lines).min() < 8:
        return None
    words = np.ndarray(shape=(size,), dtype="<u8", buffer=padded, strides=(1,))
    encoded = [names[j].encode("utf-8") + b" " for j in bones]
    for offset in range(0, max(len(e) for e in encoded), 8):
        columns = [k for k, e in enumerate(encoded) if len(e) > offset]  # names this long
        pieces = [encoded[k][offset : offset + 8] for k in columns]
        keep = np.array([(1 << (8 * len(p))) - 1 for p in pieces], np.uint64)
        want = np.array([int.from_bytes(p, "little") for p in pieces], np.uint64)
        at = np.take(lines, columns, axis=1) + offset  # in file order (C order: one sweep of the block)
        found = words[at]
        if ((found & keep) != want).any():
            return None
        words[at] = (found & ~keep) | (_SPACES & keep)  # the names blanked
    buffer[breaks] = 32
    buffer[ends[:-1, -1]] = 10  # a frame a line
    text = buffer.tobytes()
    if text.translate(None, NUMBER_CHARACTERS):
        return None
    row = 1 + int(counts[bones].sum())
    try:
        numbers = np.loadtxt(io.BytesIO(text), dtype=np.float64, comments=None, ndmin=2)
    except ValueError:
        return None
    if numbers.shape != (n_frames, row) or not within_range(numbers):
        return None
    frame_numbers = numbers[:, 0]
    if (frame_numbers != frame_numbers[0] + np.arange(n_frames)).any():
        return None
    source = np.empty(int(counts.sum()), np.intp)
    file_column = 1
    for j in bones:
        source[column_of[j] : column_of[j] + counts[j]] = np.arange(file_column, file_column + counts[j])
        file_column += int(counts[j])
    return np.take(numbers, source, axis=1), int(frame_numbers[0])
