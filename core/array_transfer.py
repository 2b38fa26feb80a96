"""Arrays handed from a child process to its parent through a file, as raw bytes.

A reader that runs a library in a child process (the FBX reader: ufbx) hands its result
back as a JSON header and arrays. An ``.npz`` through a pipe costs several copies of every
byte (the archive, the pipe in small chunks, the members unpacked), which on a long take
is more than the work itself; here the child writes each array's bytes once to a file the
parent named, and the parent maps the file (or reads it once) and takes every array as a
view of it.

The file: :data:`MAGIC`, the header's length (8 bytes, little-endian), the header (JSON:
``{"header": ..., "arrays": [[name, dtype, shape, offset], ...]}``), then each array's
bytes from an offset (a multiple of :data:`ALIGN` after the header). Imports numpy only:
the child runs it without the package of every format.
"""

from __future__ import annotations

import json
import mmap
import os
from pathlib import Path

import numpy as np

MAGIC = b"gmr-arr\x00"
#: arrays start at offsets that are multiples of this many bytes
ALIGN = 64


def _aligned(size: int) -> int:
    return -(-size // ALIGN) * ALIGN


def write_arrays(path: str | os.PathLike[str], header: dict, arrays: dict[str, np.ndarray | list[np.ndarray]]) -> None:
    """Write ``header`` (JSON-ready) and ``arrays`` (name -> array of any numeric dtype,
    any shape) to ``path``; each array's bytes are written as they are, once. A list of
    arrays of one dtype and shape is written as their stack (N, ...), each row from its
    own array (no stacked copy is made); it reads back as one array."""
    table, offset, parts = [], 0, []
    for name, value in arrays.items():
        stacked = isinstance(value, (list, tuple))
        rows = list(value) if stacked else [value]
        shape = ([len(rows), *rows[0].shape] if rows else [0]) if stacked else list(value.shape)
        dtype = rows[0].dtype if rows else np.dtype(np.float64)
        if any(row.dtype != dtype or row.shape != rows[0].shape for row in rows):
            raise ValueError(f"the rows of {name} differ in dtype or shape")
        table.append([name, dtype.str, shape, offset])
        offset = _aligned(offset + sum(row.nbytes for row in rows))
        parts.append(rows)
    text = json.dumps({"header": header, "arrays": table}).encode("utf-8")
    start = _aligned(len(MAGIC) + 8 + len(text))
    with open(path, "wb") as handle:
        handle.write(MAGIC + len(text).to_bytes(8, "little") + text)
        for (_, _, _, at), rows in zip(table, parts):
            handle.seek(start + at)
            for row in rows:
                handle.write(np.ascontiguousarray(row).reshape(-1).view(np.uint8))


def read_arrays(path: str | os.PathLike[str]) -> tuple[dict, dict[str, np.ndarray]]:
    """(header, name -> array) of a file :func:`write_arrays` wrote; the arrays are views
    of one buffer: on POSIX the file mapped copy-on-write (the pages the child wrote, not a
    copy; the file may be removed while the arrays live), elsewhere the file read into
    memory. ValueError when the file is not one."""
    raw = _contents(Path(path))
    size = len(raw)
    if size < len(MAGIC) + 8 or bytes(raw[: len(MAGIC)]) != MAGIC:
        raise ValueError("not an array transfer file")
    length = int.from_bytes(bytes(raw[len(MAGIC) : len(MAGIC) + 8]), "little")
    body = json.loads(bytes(raw[len(MAGIC) + 8 : len(MAGIC) + 8 + length]).decode("utf-8"))
    start = _aligned(len(MAGIC) + 8 + length)
    arrays = {}
    for name, dtype, shape, at in body["arrays"]:
        kind = np.dtype(dtype)
        count = int(np.prod(shape, dtype=np.int64))
        if count == 0:  # no bytes in the file
            arrays[name] = np.zeros(shape, kind)
            continue
        if start + at + count * kind.itemsize > size:
            raise ValueError(f"array {name} is cut short")
        arrays[name] = np.frombuffer(raw, kind, count, start + at).reshape(shape)
    return body["header"], arrays


def _contents(path: Path) -> np.ndarray:
    """The file's bytes (N,) uint8, writable: mapped on POSIX, else read."""
    with open(path, "rb", buffering=0) as handle:
        size = os.fstat(handle.fileno()).st_size
        if os.name == "posix" and size:
            return np.frombuffer(mmap.mmap(handle.fileno(), size, access=mmap.ACCESS_COPY), np.uint8)
        raw = np.empty(size, np.uint8)
        view, done = memoryview(raw), 0
        while done < size:
            count = handle.readinto(view[done:])
            if not count:
                break
            done += count
    return raw[:done]
