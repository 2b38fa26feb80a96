"""C3D files longer than 65,535 frames: the real frame count and the 3D points, by numpy.

The header's frame numbers are 16-bit words, and so is the usual ``POINT:FRAMES``: past
65,535 frames they saturate, and ezc3d (1.7) reads that many frames and stops. The C3D
standard keeps the real count in the parameters, in one of three places (c3d.org, "The C3D
frame count"):

- ``POINT:FRAMES`` stored as a floating-point number (the recommended way);
- ``POINT:LONG_FRAMES`` (floating point, Vicon);
- ``TRIAL:ACTUAL_START_FIELD`` and ``TRIAL:ACTUAL_END_FIELD``, each two 16-bit words (low,
  high) of a 32-bit frame number (Motion Analysis); the count is end - start + 1.

:func:`parameter_frame_count` finds it; :func:`read_points` decodes the 3D point block of
every frame straight from the file with numpy (Intel, DEC and SGI byte orders; float and
scaled-integer samples), the same numbers ezc3d gives for the frames it reads (tested on
every shared C3D file). Only the worker process calls these, on ezc3d's parameters.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: the parameter section's processor byte: byte order of the file
INTEL, DEC, SGI = 84, 85, 86
#: the largest count the 16-bit fields can hold
SATURATED = 0xFFFF


def _first(parameters, group: str, name: str) -> tuple[np.ndarray, bool] | None:
    """(values, is_float) of a parameter of ezc3d's parameter mapping, or None."""
    if group not in parameters or name not in parameters[group]:
        return None
    entry = parameters[group][name]
    values = np.asarray(entry["value"]).reshape(-1)
    return (values, entry["type"] == 4) if values.size else None  # ezc3d type 4: FLOAT


def parameter_frame_count(parameters) -> tuple[int, str] | None:
    """The number of 3D frames the parameters announce and where it was found, or None.

    ``parameters``: ezc3d's parameter mapping (``c3d["parameters"]``). Integer words are
    read unsigned (a 16-bit ``POINT:FRAMES`` of 40,000 reads as -25,536 when signed).
    """
    frames = _first(parameters, "POINT", "FRAMES")
    if frames is not None and frames[1]:
        return int(frames[0][0]), "POINT:FRAMES (floating point)"
    long_frames = _first(parameters, "POINT", "LONG_FRAMES")
    if long_frames is not None:
        return int(long_frames[0][0]), "POINT:LONG_FRAMES"
    start, end = _first(parameters, "TRIAL", "ACTUAL_START_FIELD"), _first(parameters, "TRIAL", "ACTUAL_END_FIELD")
    if start is not None and end is not None and start[0].size >= 2 and end[0].size >= 2:
        first, last = (_word_pair(values) for values, _ in (start, end))
        if last >= first:
            return last - first + 1, "TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD"
    if frames is not None:
        return int(frames[0][0]) & SATURATED, "POINT:FRAMES"
    return None


def _word_pair(values: np.ndarray) -> int:
    """A 32-bit number stored as two 16-bit words, low word first."""
    return (int(values[0]) & SATURATED) + ((int(values[1]) & SATURATED) << 16)


def analog_values_per_frame(path: Path) -> int:
    """Header word 3: the analog samples stored with each 3D frame (channels x samples)."""
    with path.open("rb") as stream:
        header = stream.read(512)
        stream.seek((header[0] - 1) * 512 + 3)
        processor = stream.read(1)[0]
    return int(np.frombuffer(header[4:6], dtype=">u2" if processor == SGI else "<u2")[0])


def read_points(path: Path, parameters, n_frames: int) -> tuple[np.ndarray, np.ndarray, int]:
    """The 3D points of the first ``n_frames`` frames, read from the file's data section.

    Parameters
    ----------
    path : the C3D file.
    parameters : ezc3d's parameter mapping (POINT:USED, SCALE, DATA_START, RATE; ANALOG:USED,
        RATE give the layout of a frame).
    n_frames : frames wanted; fewer are read if the file ends before.

    Returns
    -------
    points : (F, M, 3) float64, NaN where the sample is invalid (negative residual word).
    residuals : (F, M) float64, ``((word >> 8) & 0xFF) * |POINT:SCALE|`` of the sample's
        fourth word, -1 where invalid (the byte ezc3d reads: the same residuals for the same
        frames, so the zero-residual rule of :mod:`core.markers.c3d` reads both alike).
    F : the number of frames read.
    """
    with path.open("rb") as stream:
        header = stream.read(512)
        stream.seek((header[0] - 1) * 512 + 3)
        processor = stream.read(1)[0]
    big = processor == SGI
    n_points = int(_first(parameters, "POINT", "USED")[0][0])
    scale = float(_first(parameters, "POINT", "SCALE")[0][0])
    data_start = int(_first(parameters, "POINT", "DATA_START")[0][0])
    analog_per_frame = int(np.frombuffer(header[4:6], dtype=">u2" if big else "<u2")[0])
    width = 4 if scale < 0 else 2
    values_per_frame = 4 * n_points + analog_per_frame
    offset = (data_start - 1) * 512
    available = max(0, (path.stat().st_size - offset) // (width * values_per_frame))
    count = int(min(n_frames, available))
    raw = np.fromfile(path, dtype=np.uint8, count=count * values_per_frame * width, offset=offset)
    block = _decode(raw, width, processor).reshape(count, values_per_frame)[:, : 4 * n_points]
    block = block.reshape(count, n_points, 4)
    word = np.round(block[..., 3]).astype(np.int64)
    word = np.where(word >= 1 << 15, word - (1 << 16), word)  # the fourth word is a signed 16-bit number
    invalid = word < 0
    points = block[..., :3] * (1.0 if scale < 0 else scale)
    points[invalid] = np.nan
    residuals = np.where(invalid, -1.0, ((word >> 8) & 0xFF) * abs(scale))
    return points, residuals, count


def _decode(raw: np.ndarray, width: int, processor: int) -> np.ndarray:
    """Samples as float64 from their bytes: float32 or int16 in the processor's format."""
    if width == 2:
        return raw.view(">i2" if processor == SGI else "<i2").astype(np.float64)
    if processor == SGI:
        return raw.view(">f4").astype(np.float64)
    if processor == DEC:  # VAX F: the 16-bit halves swapped, and 4 times the IEEE value
        return raw.reshape(-1, 4)[:, [2, 3, 0, 1]].copy().view("<f4").reshape(-1).astype(np.float64) / 4.0
    return raw.view("<f4").astype(np.float64)
