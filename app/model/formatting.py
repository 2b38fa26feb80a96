"""Numbers as the app shows them: rounded to the motion's precision, so that float noise
such as ``9.917e-14`` left by a split and a join shows as ``0``.

A length is shown to :data:`LENGTH_DIGITS` significant digits of the motion's size (the
extent of the skeleton): in a 35-inch skeleton a step of 1e-5 inch, in a 1.7 m one 1e-6 m.
Anything smaller than that step is below what a file holds anyway (BVH files write about 6
significant digits) and far above rounding noise (~1e-14 of the size).

Frame numbers are 0-based everywhere, as the command line's ranges (docs/conventions.md):
:func:`frame_of` is how the inspector and the timeline say where a frame is in the take.
"""

from __future__ import annotations

import math

import numpy as np

#: significant digits of the motion's size kept in shown lengths
LENGTH_DIGITS = 7
#: decimals of shown rotation-matrix entries and of angles in degrees
MATRIX_DECIMALS = 4
ANGLE_DECIMALS = 3


def length_decimals(size: float, digits: int = LENGTH_DIGITS) -> int:
    """Decimals that keep ``digits`` significant digits of ``size`` (at least 0)."""
    if not np.isfinite(size) or size <= 0:
        size = 1.0
    return max(0, digits - 1 - math.floor(math.log10(size)))


def format_number(value: float, decimals: int) -> str:
    """``value`` rounded to ``decimals``, trailing zeros dropped, never ``-0``."""
    if not np.isfinite(value):
        return str(value)
    rounded = round(float(value), decimals) + 0.0  # + 0.0 turns -0.0 into 0.0
    text = f"{rounded:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def frame_of(frame: int | str, n_frames: int) -> str:
    """A frame's place in a take of ``n_frames`` frames, 0-based: ``"60 of 0-194"`` (the
    first frame is 0 and the last ``n_frames - 1``, as in ``gmr check``, ``gmr curves``,
    ``gmr edit --frames``); ``frame`` may be given as text already marked up."""
    return f"{frame} of 0-{max(n_frames - 1, 0)}"


def format_length(value: float, size: float) -> str:
    """A length of a motion of this size, to the motion's precision."""
    return format_number(value, length_decimals(size))


def format_lengths(values: np.ndarray, size: float) -> str:
    """Lengths (e.g. an offset or a position), space-separated, to the motion's precision."""
    decimals = length_decimals(size)
    return " ".join(format_number(v, decimals) for v in np.ravel(values))


def format_angles(degrees: np.ndarray) -> str:
    """Angles in degrees, comma-separated, to :data:`ANGLE_DECIMALS`."""
    return ", ".join(f"{round(float(v), ANGLE_DECIMALS) + 0.0:.{ANGLE_DECIMALS}f}" for v in np.ravel(degrees))


def format_matrix(matrix: np.ndarray, size: float | None = None, *, lengths: bool = False) -> str:
    """Rows of a matrix as aligned text, each column as wide as its widest entry, two spaces
    apart (narrow enough for a side dock).

    Rotation entries get :data:`MATRIX_DECIMALS`; lengths (every entry with ``lengths``) the
    precision of a motion of this ``size``.
    """
    matrix = np.atleast_2d(np.asarray(matrix, dtype=np.float64))
    places = length_decimals(size) if lengths and size is not None else MATRIX_DECIMALS
    return _aligned(matrix, places)


def _aligned(matrix: np.ndarray, places: int) -> str:
    """Rows of ``matrix`` rounded to ``places``, columns right-aligned, two spaces apart."""
    cells = [[f"{round(float(v), places) + 0.0:.{places}f}" for v in row] for row in matrix]
    widths = [max(len(row[k]) for row in cells) for k in range(matrix.shape[1])]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in cells)
