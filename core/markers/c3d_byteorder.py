"""C3D files written on SGI/MIPS machines, rewritten in Intel byte order for ezc3d.

ezc3d (1.7) reads Intel and DEC files and refuses SGI/MIPS ones ("MIPS processor type not
supported yet"). SGI files are the Intel layout with every 16-bit word and every 32-bit
float stored big-endian (IEEE floats, as Intel's), so :func:`intel_from_sgi` turns one
into the other by walking the three sections the C3D standard defines (c3d.org, "The C3D
file format", chapters 2-4) and swapping exactly the numbers, never the text:

- the header block: 16-bit words, except words 7-8 (POINT:SCALE) and 11-12 (frame rate)
  and words 153-188 (event times), which are floats; bytes 1-2 (parameter block, key
  0x50), the event flags and labels are bytes and text;
- the parameter section: its 4-byte start (the processor byte becomes 84, Intel), then
  records of ``int8 name length, int8 id, name, int16 offset to the next record`` and,
  for a parameter, ``int8 type (-1 text, 1 byte, 2 int16, 4 float), uint8 dimension
  count, dimensions, data, uint8 description length, description``: only the offsets and
  the int16 and float data are swapped;
- the data section, from POINT:DATA_START: every value is an int16 (POINT:SCALE > 0) or
  a float32 (POINT:SCALE < 0), so it is swapped as one array.

Malformed input raises :class:`C3DLayoutError` with what was wrong and where (the caller
names the file).
"""

from __future__ import annotations

import numpy as np

#: the processor byte of the parameter section
INTEL, DEC, SGI = 84, 85, 86
BLOCK = 512
#: header words (1-based, as the standard numbers them) that hold 32-bit floats
_HEADER_FLOAT_WORDS = (7, 11, *range(153, 189, 2))
#: header words that are 16-bit numbers (word 1 is two bytes; the rest is flags and text)
_HEADER_INT_WORDS = (*range(2, 7), 9, 10, *range(13, 153))


class C3DLayoutError(ValueError):
    """The bytes do not follow the C3D layout (message says where)."""


def processor_of(data: bytes) -> int:
    """The processor byte of a C3D's parameter section (84 Intel, 85 DEC, 86 SGI/MIPS)."""
    if len(data) < BLOCK or data[1] != 0x50:
        raise C3DLayoutError("not a C3D header (byte 2 is not 0x50)")
    start = (data[0] - 1) * BLOCK
    if data[0] < 1 or start + 4 > len(data):
        raise C3DLayoutError(f"the parameter section (block {data[0]}) lies outside the file")
    return data[start + 3]


def intel_from_sgi(data: bytes) -> bytes:
    """The same C3D in Intel byte order (``data``: an SGI/MIPS file's bytes)."""
    if processor_of(data) != SGI:
        raise C3DLayoutError("not an SGI/MIPS C3D (processor byte is not 86)")
    out = bytearray(data)
    _swap_header(out)
    scale, data_start = _swap_parameters(out, (data[0] - 1) * BLOCK)
    if scale is None:  # POINT:SCALE absent: the header's copy of it decides the sample format
        scale = float(np.frombuffer(bytes(out[12:16]), "<f4")[0])
    if data_start is None:
        data_start = int(np.frombuffer(bytes(out[16:18]), "<u2")[0])
    offset = (data_start - 1) * BLOCK
    if data_start < 1 or offset > len(out):
        raise C3DLayoutError(f"the data section (block {data_start}) lies outside the file")
    width = 4 if scale < 0 else 2
    count = (len(out) - offset) // width
    _swap_in_place(out, offset, count, width)
    return bytes(out)


def _signed(byte: int) -> int:
    """A byte read as an int8."""
    return byte - 256 if byte > 127 else byte


def _swap_in_place(buffer: bytearray, offset: int, count: int, width: int) -> None:
    """Reverse the bytes of ``count`` numbers of ``width`` bytes starting at ``offset``."""
    if count <= 0:
        return
    end = offset + count * width
    values = np.frombuffer(bytes(buffer[offset:end]), dtype=f">u{width}")
    buffer[offset:end] = values.astype(f"<u{width}").tobytes()


def _swap_header(out: bytearray) -> None:
    for word in _HEADER_INT_WORDS:
        _swap_in_place(out, 2 * (word - 1), 1, 2)
    for word in _HEADER_FLOAT_WORDS:
        _swap_in_place(out, 2 * (word - 1), 1, 4)


def _swap_parameters(out: bytearray, start: int) -> tuple[float | None, int | None]:
    """Swap the parameter section in place; returns POINT:SCALE and POINT:DATA_START if found."""
    n_blocks = out[start + 2]
    end = min(len(out), start + max(n_blocks, 1) * BLOCK)
    out[start + 3] = INTEL
    groups: dict[int, str] = {}
    found: dict[tuple[int, str], float] = {}
    position = start + 4
    while position + 2 <= end:
        length = abs(_signed(out[position]))
        ident = _signed(out[position + 1])
        if length == 0:
            break
        name_end = position + 2 + length
        if name_end + 2 > end:
            raise C3DLayoutError(f"a parameter record at byte {position} runs past the parameter section")
        name = bytes(out[position + 2 : name_end]).decode("latin-1").strip().upper()
        next_offset = int(np.frombuffer(bytes(out[name_end : name_end + 2]), ">i2")[0])
        body = name_end + 2
        if ident < 0:
            groups[-ident] = name
            record_end = body + 1 + out[body] if body < end else end + 1
        else:
            data_end, values = _swap_parameter_data(out, body, end, ident, name)
            found.update(values)
            record_end = data_end + 1 + out[data_end] if data_end < end else end + 1
        if record_end > end:
            raise C3DLayoutError(f"the parameter record at byte {position} runs past the parameter section")
        needed = record_end - name_end
        if next_offset != 0 and not needed <= next_offset <= end - name_end:
            # the stored offset cannot be right (c3d.org's SGI sample 02 stores the LABELS
            # record's offset little-endian among big-endian ones): the record's own length
            # decides, and is what the Intel copy stores
            next_offset = needed
        out[name_end : name_end + 2] = np.array([next_offset], "<i2").tobytes()
        if next_offset == 0:
            break
        position = name_end + next_offset
    point = next((i for i, name in groups.items() if name == "POINT"), None)
    scale = found.get((point, "SCALE")) if point is not None else None
    data_start = found.get((point, "DATA_START")) if point is not None else None
    return scale, None if data_start is None else int(data_start) & 0xFFFF


def _swap_parameter_data(out: bytearray, body: int, end: int, group: int, name: str) -> tuple[int, dict]:
    """Swap one parameter's numbers; returns where its data end (its description's length
    byte) and ``{(group, name): first value}`` for a number."""
    if body + 2 > end:
        raise C3DLayoutError(f"parameter {name} at byte {body} runs past the parameter section")
    kind = _signed(out[body])
    n_dims = out[body + 1]
    dims = list(out[body + 2 : body + 2 + n_dims])
    count = int(np.prod(dims)) if dims else 1
    width = abs(kind)
    if width not in (1, 2, 4):
        raise C3DLayoutError(f"parameter {name} at byte {body} has type {kind}: expected -1, 1, 2 or 4")
    first = body + 2 + n_dims
    if first + count * width > end:
        raise C3DLayoutError(f"parameter {name} at byte {body} holds more data than the section")
    data_end = first + count * width
    if kind in (2, 4):
        _swap_in_place(out, first, count, width)
        if count:
            dtype = "<i2" if kind == 2 else "<f4"
            value = float(np.frombuffer(bytes(out[first : first + width]), dtype)[0])
            if kind == 2 and name == "DATA_START":
                value = float(int(value) & 0xFFFF)  # a block number, unsigned (a SCALE keeps its sign)
            return data_end, {(group, name): value}
    return data_end, {}
