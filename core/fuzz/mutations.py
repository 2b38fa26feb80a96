"""Mutations of motion and marker files, for the fuzzer.

Each mutation takes the seed file's bytes and a random generator and returns new bytes.
Text mutations know the structure of BVH-like and Acclaim files (line starts, keywords,
numbers, names); binary mutations cut and corrupt C3D files where their structure lives
(the 512-byte header, the parameter section, the data). All are deterministic given the
generator, so a case is identified by (format, seed, index) and can be regenerated.
"""

from __future__ import annotations

import re
from collections.abc import Callable

import numpy as np

Mutation = Callable[[bytes, np.random.Generator], bytes]

_NUMBER = re.compile(rb"(?<![\w.])[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?(?![\w.])")
_HOSTILE_NUMBERS = [
    b"nan",
    b"NaN",
    b"inf",
    b"-inf",
    b"Infinity",
    b"1e308",
    b"-1e308",
    b"1e309",
    b"1e-320",
    b"0",
    b"-0",
    b"",
    b"abc",
    b"1.2.3",
    b"--1",
    b"0x10",
    b"1_000",
    b"\xff\xfe",
    b"9" * 400,
]
_HUGE_COUNTS = [
    b"0",
    b"1",
    b"2",
    b"-1",
    b"-5",
    b"999999999999",
    b"1000000000000",
    b"18446744073709551616",
    b"3.5",
    b"x",
    b"",
]


def line_starts(data: bytes) -> list[int]:
    """Byte offsets of every line start (any line ending)."""
    return [0] + [m.end() for m in re.finditer(rb"\r\n|\r|\n", data)]


def _pick(rng: np.random.Generator, items):
    return items[int(rng.integers(len(items)))]


def truncate_at_line(data: bytes, rng: np.random.Generator) -> bytes:
    """Cut the file at the start of a line (a structural point)."""
    return data[: _pick(rng, line_starts(data))]


def truncate_in_header(data: bytes, rng: np.random.Generator) -> bytes:
    """Cut the file at a token boundary in its first few thousand bytes (the header)."""
    head = data[:8000]
    points = [m.start() for m in re.finditer(rb"\S+", head)] + [m.end() for m in re.finditer(rb"\S+", head)]
    return data[: _pick(rng, points)] if points else data[:0]


def truncate_anywhere(data: bytes, rng: np.random.Generator) -> bytes:
    return data[: int(rng.integers(len(data) + 1))]


def flip_bytes(data: bytes, rng: np.random.Generator) -> bytes:
    """Overwrite one to eight random bytes with random values."""
    if not data:
        return data
    out = bytearray(data)
    for _ in range(int(rng.integers(1, 9))):
        out[int(rng.integers(len(out)))] = int(rng.integers(256))
    return bytes(out)


def flip_bytes_in_header(data: bytes, rng: np.random.Generator) -> bytes:
    if not data:
        return data
    out = bytearray(data)
    for _ in range(int(rng.integers(1, 5))):
        out[int(rng.integers(min(len(out), 4096)))] = int(rng.integers(256))
    return bytes(out)


def delete_line(data: bytes, rng: np.random.Generator) -> bytes:
    lines = data.splitlines(keepends=True)
    if not lines:
        return data
    del lines[int(rng.integers(len(lines)))]
    return b"".join(lines)


def duplicate_line(data: bytes, rng: np.random.Generator) -> bytes:
    lines = data.splitlines(keepends=True)
    if not lines:
        return data
    i = int(rng.integers(len(lines)))
    lines.insert(i, lines[i])
    return b"".join(lines)


def swap_lines(data: bytes, rng: np.random.Generator) -> bytes:
    lines = data.splitlines(keepends=True)
    if len(lines) < 2:
        return data
    i, j = (int(v) for v in rng.integers(len(lines), size=2))
    lines[i], lines[j] = lines[j], lines[i]
    return b"".join(lines)


def hostile_number(data: bytes, rng: np.random.Generator) -> bytes:
    """Replace one number (in the header or the frames) by NaN, inf, 1e308, garbage, ..."""
    head = rng.random() < 0.5
    window = data[:8000] if head else data
    matches = list(_NUMBER.finditer(window))
    if not matches:
        return data
    m = _pick(rng, matches)
    return data[: m.start()] + _pick(rng, _HOSTILE_NUMBERS) + data[m.end() :]


def _replace_after_keyword(data: bytes, rng: np.random.Generator, keywords: list[bytes], values: list[bytes]) -> bytes:
    pattern = rb"(?m)(" + b"|".join(re.escape(k) for k in keywords) + rb")([ \t]*)([^\s]*)"
    matches = list(re.finditer(pattern, data[:200000]))
    if not matches:
        return data
    m = _pick(rng, matches)
    return data[: m.start(3)] + _pick(rng, values) + data[m.end(3) :]


def wrong_counts(data: bytes, rng: np.random.Generator) -> bytes:
    """A wrong channel count, frame count, marker count, or an enormous one."""
    keywords = [b"CHANNELS", b"Frames:", b"NumMarkers", b"NumFrames", b"dof"]
    return _replace_after_keyword(data, rng, keywords, [*_HUGE_COUNTS, str(int(rng.integers(0, 12))).encode()])


def enormous_frame_claim(data: bytes, rng: np.random.Generator) -> bytes:
    return _replace_after_keyword(data, rng, [b"Frames:"], [b"1000000000000", b"999999999999999999"])


def unknown_channel(data: bytes, rng: np.random.Generator) -> bytes:
    names = [
        b"Xrotation",
        b"Yrotation",
        b"Zrotation",
        b"Xposition",
        b"Yposition",
        b"Zposition",
        b"rx",
        b"ry",
        b"rz",
        b"tx",
        b"ty",
        b"tz",
    ]
    matches = [m for name in names for m in re.finditer(re.escape(name), data[:200000])]
    if not matches:
        return data
    m = _pick(rng, matches)
    return data[: m.start()] + _pick(rng, [b"Wrotation", b"Xrot", b"rw", b"position", b"\xc3\xa9"]) + data[m.end() :]


def duplicate_name(data: bytes, rng: np.random.Generator) -> bytes:
    """One joint or bone takes another's name."""
    matches = [m for m in re.finditer(rb"(?m)^[ \t]*(?:ROOT|JOINT|name)[ \t]+(\S+)", data[:200000])]
    if len(matches) < 2:
        return data
    a, b = (matches[int(i)] for i in rng.choice(len(matches), size=2, replace=False))
    return data[: a.start(1)] + b.group(1) + data[a.end(1) :]


def empty_name(data: bytes, rng: np.random.Generator) -> bytes:
    matches = [m for m in re.finditer(rb"(?m)^[ \t]*(?:ROOT|JOINT|name|SOFTLINK)[ \t]+(\S+)", data[:200000])]
    if not matches:
        return data
    m = _pick(rng, matches)
    return data[: m.start(1)] + data[m.end(1) :]


def non_utf8(data: bytes, rng: np.random.Generator) -> bytes:
    position = int(rng.integers(min(len(data), 8000) + 1))
    return data[:position] + _pick(rng, [b"\xff", b"\xfe\xff", b"\xc3", b"\x80\x81", b"\x00"]) + data[position:]


def zero_or_one_frame(data: bytes, rng: np.random.Generator) -> bytes:
    """Keep the header, claim 0 or 1 frames, keep 0, 1 or 2 frame lines."""
    match = re.search(rb"(?m)^Frames:[ \t]*\S*", data)
    if not match:
        return truncate_at_line(data, rng)
    claim = _pick(rng, [b"0", b"1"])
    after = data[match.end() :]
    lines = after.splitlines(keepends=True)
    keep = 2 + int(rng.integers(0, 3))  # the rest of the Frames line, Frame Time, then 0..2 frames
    return data[: match.start()] + b"Frames: " + claim + b"".join(lines[:keep])


def hierarchy_cycle(data: bytes, rng: np.random.Generator) -> bytes:
    """In an ASF :hierarchy, make a bone the parent of one of its ancestors, or orphan one."""
    match = re.search(rb":hierarchy\s*\n\s*begin\s*\n(.*?)\n\s*end", data, re.S)
    if not match:
        return swap_lines(data, rng)
    lines = match.group(1).split(b"\n")
    i = int(rng.integers(len(lines)))
    words = lines[i].split()
    if len(words) >= 2:
        choice = rng.random()
        if choice < 0.4:  # the child becomes the parent of its parent
            lines.append(b"  " + words[1] + b" " + words[0])
        elif choice < 0.7:  # orphan: drop the line that attaches a bone
            del lines[i]
        else:  # a bone attached twice
            j = int(rng.integers(len(lines)))
            other = lines[j].split()
            if other:
                lines.append(b"  " + other[0] + b" " + words[-1])
    return data[: match.start(1)] + b"\n".join(lines) + data[match.end(1) :]


TEXT_MUTATIONS: dict[str, Mutation] = {
    "truncate at a line": truncate_at_line,
    "truncate in the header": truncate_in_header,
    "truncate anywhere": truncate_anywhere,
    "flip bytes": flip_bytes,
    "flip header bytes": flip_bytes_in_header,
    "delete a line": delete_line,
    "duplicate a line": duplicate_line,
    "swap two lines": swap_lines,
    "hostile number": hostile_number,
    "wrong counts": wrong_counts,
    "enormous frame claim": enormous_frame_claim,
    "unknown channel": unknown_channel,
    "duplicate name": duplicate_name,
    "empty name": empty_name,
    "non-UTF-8 bytes": non_utf8,
    "zero or one frame": zero_or_one_frame,
}

ACCLAIM_MUTATIONS: dict[str, Mutation] = {**TEXT_MUTATIONS, "hierarchy cycle or orphan": hierarchy_cycle}


def c3d_huge_counts(data: bytes, rng: np.random.Generator) -> bytes:
    """Claim enormous numbers of points or frames in the C3D header (words 2, 4, 5, 6)."""
    if len(data) < 512:
        return data
    out = bytearray(data)
    word = _pick(rng, [1, 3, 4, 5, 6])  # 16-bit words: points, last/first frame, ...
    out[2 * word : 2 * word + 2] = _pick(rng, [b"\xff\xff", b"\xff\x7f", b"\x00\x80", b"\x00\x00"])
    return bytes(out)


def c3d_cut_short(data: bytes, rng: np.random.Generator) -> bytes:
    """Cut inside the header, the parameters, or the data."""
    points = [0, 1, 256, 511, 512, 513, 1024, 2048, 4096, len(data) // 2, len(data) - 1]
    return data[: min(len(data), _pick(rng, points) + int(rng.integers(0, 16)))]


BINARY_MUTATIONS: dict[str, Mutation] = {
    "truncate anywhere": truncate_anywhere,
    "cut short at a section": c3d_cut_short,
    "flip bytes": flip_bytes,
    "flip header bytes": flip_bytes_in_header,
    "huge counts in the header": c3d_huge_counts,
}
