"""The SGI-to-Intel rewrite (core.markers.c3d_byteorder) on small C3D files built byte by byte
(tests/c3d_bytes.py): an SGI file's Intel copy is, byte for byte, the same numbers laid out in
Intel order, whatever the sample format, where the data start and scale are read, free space
between records, and records whose stored offset cannot be right; and each malformed section
gives its message."""

from __future__ import annotations

import struct

import pytest

from gmr_studio.core.markers.c3d_byteorder import C3DLayoutError, intel_from_sgi, processor_of
from tests.c3d_bytes import BLOCK, c3d_bytes


@pytest.mark.parametrize(
    "layout",
    [
        {},  # float samples
        {"scale": 0.5},  # int16 samples
        {"in_parameters": False},  # POINT:SCALE and DATA_START from the header's copies
        {"in_parameters": False, "scale": 0.5},
        {"header_scale": 0.5, "header_start": 7},  # the parameters' copies win
        {"scale": 0.5, "header_scale": -1.0},
        {"tail": b"\x07"},  # a byte past the last whole sample stays as it is
        {"tail": b"\x07\x08\x09", "n_frames": 1, "n_points": 1},
        {"scale": 0.0},  # not negative: int16 samples
        {"scale": -0.1},  # scales whose floats have two non-zero halves
        {"scale": 0.3, "in_parameters": False},
        {"n_points": 200},  # a parameter section of two blocks
        {"scale": -1.0, "scale_kind": 2},  # POINT:SCALE an integer: negative, float samples
        {"scale": 2.0, "scale_kind": 2},
    ],
)
def test_the_intel_copy_is_the_same_numbers_in_intel_order(layout):
    sgi, intel = c3d_bytes(">", **layout), c3d_bytes("<", **layout)
    assert sgi != intel and processor_of(sgi) == 86 and processor_of(intel) == 84
    assert intel_from_sgi(sgi) == intel


def offset_position(data: bytes, name: bytes) -> int:
    """Where the offset of the record named ``name`` is stored (the first such name in the
    parameter section, which starts at block 2)."""
    return data.index(name, BLOCK) + len(name)


def test_a_stored_offset_that_cannot_be_right_is_the_records_length():
    """c3d.org's SGI sample 02 stores one offset little-endian among big-endian ones: the
    record's own length decides, and the Intel copy stores that."""
    sgi, intel = bytearray(c3d_bytes(">")), c3d_bytes("<")
    at = offset_position(sgi, b"USED")
    (right,) = struct.unpack(">h", sgi[at : at + 2])
    sgi[at : at + 2] = struct.pack("<h", right)  # read big-endian: 256 times too far
    assert struct.unpack(">h", sgi[at : at + 2])[0] > BLOCK
    assert intel_from_sgi(bytes(sgi)) == intel
    end = 2 * BLOCK  # the section's end: one block
    for wrong in (right - 1, -right, end - at + 1, end + at):  # short of the record; backwards; past the end
        sgi[at : at + 2] = struct.pack(">h", wrong)
        assert intel_from_sgi(bytes(sgi)) == intel, wrong
    sgi = bytearray(c3d_bytes(">"))
    group = offset_position(sgi, b"POINT")
    sgi[group : group + 2] = struct.pack(">h", 1)  # a group record's offset, wrong
    assert intel_from_sgi(bytes(sgi)) == intel


def test_an_offset_reaching_the_sections_end_is_believed():
    """EMPTY's record said to end the section: the records after it (SCALES) are not read,
    and its offset is kept."""
    sgi, intel = bytearray(c3d_bytes(">")), c3d_bytes("<")
    at = offset_position(sgi, b"EMPTY")
    sgi[at : at + 2] = struct.pack(">h", 2 * BLOCK - at)
    out = intel_from_sgi(bytes(sgi))
    assert out[at : at + 2] == struct.pack("<h", 2 * BLOCK - at)
    scales = offset_position(sgi, b"SCALES")
    assert out[scales + 2 :][:12] == sgi[scales + 2 :][:12] != intel[scales + 2 :][:12]
    assert out[:at] == intel[:at] and out[2 * BLOCK :] == intel[2 * BLOCK :]


def test_free_space_between_records_is_kept():
    """DATA_START's record is followed by 3 free bytes: its stored offset (longer than the
    record) is the right one; up to the section's end an offset is believed."""
    sgi, intel = c3d_bytes(">"), c3d_bytes("<")
    at = offset_position(sgi, b"DATA_START")
    assert struct.unpack(">h", sgi[at : at + 2])[0] == struct.unpack("<h", intel[at : at + 2])[0]
    assert intel_from_sgi(sgi)[at : at + 2] == intel[at : at + 2]


def test_a_zero_length_name_ends_the_section():
    """Nothing after a record whose name has no length is read as a record: left as it is."""
    sgi, intel = bytearray(c3d_bytes(">")), bytearray(c3d_bytes("<"))
    at = offset_position(sgi, b"GAIN") - len(b"GAIN") - 2  # the GAIN record's first byte
    sgi[at] = intel[at] = 0
    out = intel_from_sgi(bytes(sgi))
    assert out[:at] == intel[:at] and out[2 * BLOCK :] == intel[2 * BLOCK :]
    assert out[at : 2 * BLOCK] == sgi[at : 2 * BLOCK] != intel[at : 2 * BLOCK]


@pytest.mark.parametrize("n_blocks", [0, 2])
def test_a_section_of_no_block_is_one_block_and_records_end_at_the_last(n_blocks):
    sgi, intel = bytearray(c3d_bytes(">")), bytearray(c3d_bytes("<"))
    sgi[BLOCK + 2] = intel[BLOCK + 2] = n_blocks
    assert intel_from_sgi(bytes(sgi)) == intel


def test_records_past_the_blocks_the_section_says_it_has():
    """200 labels need a second block: a section said to hold one ends inside them."""
    sgi = bytearray(c3d_bytes(">", n_points=200))
    assert sgi[BLOCK + 2] == 2
    sgi[BLOCK + 2] = 1
    with pytest.raises(C3DLayoutError, match=r"parameter LABELS at byte .* holds more data than the section"):
        intel_from_sgi(bytes(sgi))


def malformed(change) -> str:
    data = bytearray(c3d_bytes(">"))
    change(data)
    with pytest.raises(C3DLayoutError) as info:
        intel_from_sgi(bytes(data))
    return str(info.value)


def test_the_messages_of_malformed_files():
    assert processor_of(c3d_bytes("<")[: BLOCK + 4]) == 84
    assert processor_of(bytes([1, 0x50, 0, 85]) + bytes(BLOCK - 4)) == 85  # block 1: the header's own bytes
    with pytest.raises(C3DLayoutError, match="not a C3D header"):
        processor_of(c3d_bytes("<")[: BLOCK - 1])
    with pytest.raises(C3DLayoutError, match=r"\(block 2\) lies outside the file"):
        processor_of(c3d_bytes("<")[: BLOCK + 3])
    with pytest.raises(C3DLayoutError, match=r"\(block 0\) lies outside the file"):
        processor_of(bytes([0, 0x50]) + c3d_bytes("<")[2:])
    with pytest.raises(C3DLayoutError, match="not an SGI/MIPS C3D"):
        intel_from_sgi(c3d_bytes("<"))

    def key(data):
        data[1] = 0x51

    assert "byte 2 is not 0x50" in malformed(key)

    def data_start(value):
        def change(data):
            at = offset_position(data, b"DATA_START") + 2 + 2  # past the offset, type and dimension count
            data[at : at + 2] = struct.pack(">h", value)

        return change

    assert malformed(data_start(0)) == "the data section (block 0) lies outside the file"
    assert malformed(data_start(5)) == "the data section (block 5) lies outside the file"
    # block 4 starts where the file ends: an empty data section, nothing swapped there
    sgi = _changed(data_start(4))
    assert intel_from_sgi(bytes(sgi))[2 * BLOCK :] == sgi[2 * BLOCK :] != c3d_bytes("<")[2 * BLOCK :]

    # block 1: the whole file is swapped as data words (no error)
    assert len(intel_from_sgi(bytes(_changed(data_start(1))))) == len(c3d_bytes(">"))

    def kind(data):
        data[offset_position(data, b"RATE") + 2] = 3

    assert (
        malformed(kind)
        == f"parameter RATE at byte {offset_position(c3d_bytes('>'), b'RATE') + 2} has type 3: expected -1, 1, 2 or 4"
    )
    for byte, read in [(127, 127), (128, -128), (255, -1)]:  # the type byte is an int8

        def typed(data, byte=byte):
            data[offset_position(data, b"GAIN") + 2] = byte

        if read == -1:  # text: GAIN's three bytes read as characters, left as they are
            intel = bytearray(c3d_bytes("<"))
            typed(intel)
            assert intel_from_sgi(bytes(_changed(typed))) == intel
        else:
            assert f"has type {read}: expected" in malformed(typed)


def _changed(change) -> bytearray:
    data = bytearray(c3d_bytes(">"))
    change(data)
    return data


def short_section(n_bytes: int) -> bytes:
    """The SGI file cut ``n_bytes`` after the start of its parameter section (which says it
    holds one block: the file's end comes first)."""
    return c3d_bytes(">")[: BLOCK + n_bytes]


def test_records_running_past_the_section():
    data = c3d_bytes(">")
    used, scale, point, gain = (offset_position(data, name) for name in (b"USED", b"SCALE", b"POINT", b"GAIN"))
    cases = [
        (used + 1, f"a parameter record at byte {used - 6} runs past the parameter section"),
        (used + 3, f"parameter USED at byte {used + 2} runs past the parameter section"),
        (used + 4, f"parameter USED at byte {used + 2} holds more data than the section"),
        (used + 6, f"the parameter record at byte {used - 6} runs past the parameter section"),
        (used + 7, f"the parameter record at byte {used - 6} runs past the parameter section"),
        (scale + 7, f"parameter SCALE at byte {scale + 2} holds more data than the section"),
        (point + 2, "the parameter record at byte 516 runs past the parameter section"),
        (point + 3, "the parameter record at byte 516 runs past the parameter section"),
        # USED's record ends where the file does: no record runs past, the data section is absent
        (used + 10, "the data section (block 3) lies outside the file"),
        # two bytes left for the next record (GAIN): its name runs past; one byte: no record
        (gain - 6 + 2, f"a parameter record at byte {gain - 6} runs past the parameter section"),
        (gain - 6 + 1, "the data section (block 3) lies outside the file"),
    ]
    for cut, message in cases:
        with pytest.raises(C3DLayoutError) as info:
            intel_from_sgi(short_section(cut - BLOCK))
        assert str(info.value) == message, cut


def test_a_data_start_above_32767_is_read_unsigned():
    """A word above 32767 (negative read signed) points past this file, as the block it says."""
    data = bytearray(c3d_bytes(">"))
    at = offset_position(data, b"DATA_START") + 4
    data[at : at + 2] = struct.pack(">H", 40001)
    with pytest.raises(C3DLayoutError, match=r"the data section \(block 40001\) lies outside"):
        intel_from_sgi(bytes(data))
