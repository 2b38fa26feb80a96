"""Small C3D files built byte by byte, in either byte order (tests of core.markers.c3d_byteorder).

:func:`c3d_bytes` lays out the three sections the C3D standard defines (c3d.org, "The C3D file
format": a 512-byte header, the parameter section, the 3D data) from the same numbers, with
every 16-bit word and 32-bit float written in the byte order asked (``">"`` for SGI/MIPS,
``"<"`` for Intel) and the text as it is. An SGI file's Intel copy must then be, byte for byte,
the file built from the same numbers in Intel order.
"""

from __future__ import annotations

import struct

import numpy as np

BLOCK = 512


def header_block(order: str, *, scale: float, data_start: int, n_points: int, n_frames: int) -> bytes:
    """The 512-byte header: distinct numbers in every word, floats where the standard has
    them, event flags and labels as bytes and text."""
    out = bytearray(BLOCK)
    out[0], out[1] = 2, 0x50  # the parameters start in block 2
    word = lambda number, value: struct.pack_into(f"{order}H", out, 2 * (number - 1), value)  # noqa: E731
    real = lambda number, value: struct.pack_into(f"{order}f", out, 2 * (number - 1), value)  # noqa: E731
    word(2, n_points)
    word(3, 0)  # no analog values
    word(4, 1)
    word(5, n_frames)
    word(6, 10)
    real(7, scale)
    word(9, data_start)
    word(10, 0)
    real(11, 59.94)  # both halves of the float non-zero: a half swapped as a word shows
    for number in range(13, 153):
        word(number, 0x0100 + number)  # asymmetric: a word left unswapped, or swapped twice, shows
    for number in range(153, 189, 2):
        real(number, 0.25 * number)
    out[2 * 188 : 2 * 188 + 18] = bytes(range(1, 19))  # event display flags: bytes
    out[2 * 198 : 2 * 198 + 8] = b"HEEL\0ST\x01"  # event labels: text
    return bytes(out)


def record(order: str, name: str, ident: int, body: bytes, *, locked: bool = False, pad: int = 0, last=False):
    """A group (ident < 0) or parameter record: its bytes, the offset to the next one stored
    in ``order`` (0 for the last record; ``pad`` bytes of free space after it)."""
    description = b"\x03abc"
    length = len(name) * (-1 if locked else 1)
    size = 2 + len(body) + len(description) + pad
    head = struct.pack("bb", length, ident) + name.encode()
    return head + struct.pack(f"{order}h", 0 if last else size) + body + description + b"\xaa" * pad


def parameter(order: str, kind: int, values, dims: tuple[int, ...] = ()) -> bytes:
    """A parameter's type, dimensions and data (kind -1 text, 1 byte, 2 int16, 4 float)."""
    head = struct.pack("bB", kind, len(dims)) + bytes(dims)
    if kind == -1:
        return head + values.encode()
    code = {1: "b", 2: "h", 4: "f"}[kind]
    values = [int(v) if kind in (1, 2) else float(v) for v in np.atleast_1d(values)]
    return head + struct.pack(f"{order}{len(values)}{code}", *values)


def parameter_section(
    order: str, processor: int, *, scale: float | None, data_start: int | None, n_points: int, scale_kind: int = 4
):
    """The parameter section (as many blocks as its records need): POINT and ANALOG groups;
    SCALE and DATA_START left out when None."""
    records = [record(order, "POINT", -1, b""), record(order, "ANALOG", -2, b"", locked=True)]
    records.append(record(order, "USED", 1, parameter(order, 2, n_points)))
    if scale is not None:
        records.append(record(order, "SCALE", 1, parameter(order, scale_kind, scale)))
    if data_start is not None:
        records.append(record(order, "DATA_START", 1, parameter(order, 2, data_start), pad=3))
    records.append(record(order, "RATE", 1, parameter(order, 4, 100.0), locked=True))
    labels = "".join(f"M{m:<3d}" for m in range(n_points))
    records.append(record(order, "LABELS", 1, parameter(order, -1, labels, (4, n_points))))
    records.append(record(order, "GAIN", 2, parameter(order, 1, [1, -2, 3], (3,))))
    records.append(record(order, "OFFSET", 2, parameter(order, 2, [-300, 7], (2,))))
    records.append(record(order, "EMPTY", 2, parameter(order, 4, [], (0,))))
    records.append(record(order, "SCALES", 2, parameter(order, 4, [0.5, -1.5], (2,)), last=True))
    body = b"".join(records)
    n_blocks = -(-(4 + len(body)) // BLOCK)
    section = bytes([1, 0x50, n_blocks, processor]) + body
    return section + bytes(-len(section) % BLOCK)


def c3d_bytes(
    order: str,
    *,
    scale: float = -1.0,
    n_points: int = 2,
    n_frames: int = 3,
    in_parameters: bool = True,
    header_scale: float | None = None,
    header_start: int | None = None,
    tail: bytes = b"",
    scale_kind: int = 4,
) -> bytes:
    """A whole C3D in byte order ``order`` (processor 86 for ``">"``, 84 for ``"<"``): float
    samples when ``scale`` < 0, else int16; ``in_parameters`` False leaves POINT:SCALE and
    DATA_START to the header's copies (``header_scale``, ``header_start``: when they differ
    from the parameters'); ``tail``: bytes after the data; ``scale_kind``: POINT:SCALE's type
    (4 float, as the standard has it; 2 an integer)."""
    processor = 86 if order == ">" else 84
    # the data follow the parameter section, which grows with the labels (4 bytes a point)
    data_start = 2 + len(parameter_section(order, processor, scale=scale, data_start=0, n_points=n_points)) // BLOCK
    header = header_block(
        order,
        scale=scale if header_scale is None else header_scale,
        data_start=data_start if header_start is None else header_start,
        n_points=n_points,
        n_frames=n_frames,
    )
    section = parameter_section(
        order,
        processor,
        scale=scale if in_parameters else None,
        data_start=data_start if in_parameters else None,
        n_points=n_points,
        scale_kind=scale_kind,
    )
    samples = np.arange(n_frames * n_points * 4, dtype=np.float64).reshape(n_frames, n_points, 4) * 3 + 1
    samples[..., 3] = 0x0203  # a residual word: camera bits and residual byte
    kind = "f4" if scale < 0 else "i2"
    data = samples.astype(f"{order}{kind}").tobytes()
    data += bytes(-len(data) % BLOCK)
    return header + section + data + tail
