"""The frame lines of BVH-like files: numbers in, numbers out, with numpy.

Reading: the whole block goes to ``numpy.loadtxt`` (a C parser; no Python loop over
tokens). Only when numpy rejects the block, or its shape or values are wrong, does a
line-by-line scan run to find the first bad line and column for the error message.
"""

from __future__ import annotations

import io
import re
import warnings

import numpy as np

from gmr_studio.core.errors import MotionFileError, quoted

_VALUE = re.compile(rb"\S+")
#: largest magnitude a reader accepts: far beyond any real length or angle, and small enough
#: that forward kinematics cannot overflow to infinity (or NaN) from finite input
MAX_ABS_VALUE = 1e12


def within_range(values, *, allow_nan: bool = False) -> bool:
    """True when every value is a number of magnitude at most MAX_ABS_VALUE (NaN counts as
    out of range unless ``allow_nan``: missing marker samples)."""
    values = np.asarray(values, dtype=np.float64)
    if not allow_nan:  # two passes without temporaries (a frame block is tens of megabytes)
        return bool(values.size == 0 or (values.max() <= MAX_ABS_VALUE and values.min() >= -MAX_ABS_VALUE))
    inside = np.abs(values) <= MAX_ABS_VALUE
    return bool(np.all(inside | np.isnan(values)))


def out_of_range(text: str) -> str:
    """The error message for a number beyond MAX_ABS_VALUE, as written in the file."""
    return f"{quoted(text)} is out of range (at most {MAX_ABS_VALUE:g})"


_NUMBER = re.compile(rb"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z")


def parse_frames(
    data: bytes,
    offset: int,
    first_line: int,
    n_values: int,
    n_frames: int,
    frames_line: int,
    path: str,
    *,
    allow_extra: bool = False,
) -> tuple[np.ndarray, str | None]:
    """Parse the frame lines that start at byte ``offset`` of normalised ``data``.

    Parameters
    ----------
    first_line : 1-based line number of ``data[offset]``.
    n_values : numbers per frame (the total channel count).
    n_frames : frames the header promised (``Frames:`` on line ``frames_line``).
    allow_extra : complete frame lines beyond ``n_frames`` are read too, and the returned
        note says so (BVH: other exporters write one row more than they count, and Blender
        and assimp read such files); otherwise they are an error (GMR, our own format).

    Returns
    -------
    values : (F, n_values) float64, finite; F is ``n_frames``, or more with ``allow_extra``.
    note : what was tolerated (extra rows kept), or None.

    Raises
    ------
    MotionFileError at the first line that has the wrong count of values, a value that
    is not a finite number, a frame beyond ``n_frames`` (unless ``allow_extra``), or at the
    end of the file when there are fewer frames than promised.
    """
    values = None
    if _VALUE.search(data, offset) is None:  # nothing but white space
        if n_values == 0 or n_frames == 0:
            return np.zeros((n_frames, n_values)), None
    elif n_values:
        stream = io.BytesIO(data)  # shares the bytes: the frame lines are not copied
        stream.seek(offset)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                values = np.loadtxt(stream, dtype=np.float64, comments=None, ndmin=2)
        except ValueError:
            values = None
    if values is not None and values.shape == (n_frames, n_values) and within_range(values):
        return values, None  # NaN fails the comparison too
    if allow_extra and values is not None and values.shape[0] > n_frames and values.shape[1] == n_values:
        if within_range(values):
            extra = values.shape[0] - n_frames
            note = (
                f"the MOTION section holds {values.shape[0]} frame lines, {extra} more than the {n_frames} "
                f"that 'Frames:' on line {frames_line} promises: all {values.shape[0]} were read (as Blender does)"
            )
            return values, note
    _raise_first_problem(data[offset:], first_line, n_values, n_frames, frames_line, path, allow_extra)
    raise MotionFileError(path, "the frame data could not be read", first_line, 1)  # pragma: no cover


def _raise_first_problem(
    block: bytes, first_line: int, n_values: int, n_frames: int, frames_line: int, path: str, allow_extra: bool
) -> None:
    """Raise at the first bad line (``allow_extra``: lines past ``n_frames`` are not an error)."""
    frame = 0
    line_number = first_line - 1
    for line_number, line in enumerate(block.split(b"\n"), start=first_line):
        values = list(_VALUE.finditer(line))
        if not values:
            continue
        if frame == n_frames and not allow_extra:
            raise MotionFileError(
                path,
                f"more frame lines than the {n_frames} promised by 'Frames:' on line {frames_line}",
                line_number,
                values[0].start() + 1,
            )
        frame += 1
        for index, match in enumerate(values):
            text = match.group()
            if not _NUMBER.match(text):
                found = text.decode("utf-8", "replace")
                what = "a finite number" if found.lower().lstrip("+-") in ("nan", "inf", "infinity") else "a number"
                raise MotionFileError(
                    path,
                    f"frame {frame}, value {index + 1}: expected {what}, found {quoted(found)}",
                    line_number,
                    _column(line, match.start()),
                )
            if not within_range(float(text)):
                raise MotionFileError(
                    path,
                    f"frame {frame}, value {index + 1}: {out_of_range(text.decode())}",
                    line_number,
                    _column(line, match.start()),
                )
        if len(values) != n_values:
            column = values[n_values].start() + 1 if len(values) > n_values else len(line.rstrip()) + 1
            raise MotionFileError(
                path,
                f"frame {frame} has {len(values)} values, expected {n_values} (one per channel)",
                line_number,
                column,
            )
    if frame < n_frames:
        raise MotionFileError(
            path,
            f"the file ends after {frame} frames, but 'Frames:' on line {frames_line} promised {n_frames}",
            line_number,
            1,
        )


def _column(line: bytes, byte_index: int) -> int:
    return len(line[:byte_index].decode("utf-8", "replace")) + 1


def format_frames(values: np.ndarray, digits: int) -> str:
    """Frame lines for (F, V) values: ``digits`` significant digits, space separated.

    One format string per line, applied by Python's C formatter; -0 prints as 0.
    """
    values = np.asarray(values, dtype=np.float64) + 0.0  # turns -0.0 into 0.0
    if values.size == 0:
        return "\n" * values.shape[0]
    line = " ".join([f"%.{digits}g"] * values.shape[1]) + "\n"
    return "".join(line % tuple(row) for row in values.tolist())


def format_number(value: float) -> str:
    """Shortest text that reads back to the same float (for offsets and header values)."""
    value = float(value) + 0.0
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text
