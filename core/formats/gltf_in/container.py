"""The glTF 2.0 container: the JSON document, its buffers and typed accessor data.

Reads ``.glb`` (12-byte header, a JSON chunk, an optional BIN chunk) and ``.gltf`` (JSON
with buffers as data URIs or files beside it). Every count, index, offset and length the
file gives is checked against what is really there before anything is read, so a bad file
raises :class:`~core.errors.MotionFileError` naming what was wrong (never an IndexError or
a MemoryError): truncated chunks, accessors reaching beyond their buffer view, views beyond
their buffer, buffers shorter than they claim, sparse indices out of range.

Accessor data come out as float64 arrays ``(count, n_components)``; normalised integers
are mapped to [-1, 1] or [0, 1] as the specification says (``max(c / 127, -1)`` ...).
Animation keys stored as float32 come out as stored (:meth:`GltfDocument.key_values`):
every float32 is a float64 exactly, so converting them where they are worked on gives the
same numbers without a float64 copy of the keys.
"""

from __future__ import annotations

import base64
import binascii
import json
import struct
import urllib.parse
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError

GLB_MAGIC = b"glTF"
CHUNK_JSON, CHUNK_BIN = 0x4E4F534A, 0x004E4942
#: component type -> (little-endian dtype, divisor of a normalised value, lowest value)
COMPONENTS = {
    5120: ("<i1", 127.0, -1.0),
    5121: ("<u1", 255.0, 0.0),
    5122: ("<i2", 32767.0, -1.0),
    5123: ("<u2", 65535.0, 0.0),
    5125: ("<u4", None, None),
    5126: ("<f4", None, None),
}
TYPE_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
#: required extensions that change how buffer data (animation keys included) are stored
UNDECODED_EXTENSIONS = {"EXT_meshopt_compression", "KHR_meshopt_compression"}
#: the largest accessor the reader accepts (elements), far above any real animation
MAX_ACCESSOR_COUNT = 50_000_000


class GltfDocument:
    """A parsed glTF file: ``json`` (the document as a dict) and lazy access to buffers.

    ``path``: the file (errors name it; external buffers are found beside it);
    ``binary``: the GLB's BIN chunk, or None.
    """

    def __init__(self, path: str | Path, document: dict, binary: bytes | None) -> None:
        self.path = Path(path)
        self.json = document
        self.binary = binary
        self._buffers: dict[int, bytes] = {}
        self._accessors: dict[object, np.ndarray] = {}
        self._checked: dict[str, tuple[list, int]] = {}  # the arrays found to hold objects, and their lengths

    # ------------------------------------------------------------------ errors, fields
    def error(self, message: str) -> MotionFileError:
        return MotionFileError(self.path, message)

    def items(self, key: str) -> list:
        """A top-level array (``nodes``, ``accessors``...), empty if absent."""
        value = self.json.get(key, [])
        checked = self._checked.get(key)
        if checked is not None and checked[0] is value and checked[1] == len(value):
            return value  # checked once: the reader asks for an item of it many times
        if not isinstance(value, list) or not all(isinstance(item, dict) for item in value):
            raise self.error(f"'{key}' must be an array of objects")
        self._checked[key] = (value, len(value))
        return value

    def item(self, key: str, index: object, where: str) -> dict:
        """``json[key][index]``, the index checked."""
        items = self.items(key)
        if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(items):
            raise self.error(f"{where}: {key} index {index!r} out of range (the file has {len(items)})")
        return items[index]

    def integer(self, obj: dict, key: str, where: str, default: int | None = None, low: int = 0) -> int:
        value = obj.get(key, default)
        if not isinstance(value, int) or isinstance(value, bool) or value < low:
            raise self.error(f"{where}: '{key}' must be a whole number >= {low}, not {value!r}")
        return value

    def numbers(self, obj: dict, key: str, length: int, default: list[float], where: str) -> np.ndarray:
        """A fixed-length array of finite numbers (node TRS, matrices)."""
        value = obj.get(key, default)
        ok = isinstance(value, list) and len(value) == length
        ok = ok and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        array = np.asarray(value, dtype=np.float64) if ok else np.zeros(0)
        if not ok or not np.isfinite(array).all():
            raise self.error(f"{where}: '{key}' must be {length} finite numbers")
        return array

    # ------------------------------------------------------------------------ buffers
    def buffer(self, index: int, where: str) -> bytes:
        """The bytes of buffer ``index`` (exactly its ``byteLength``)."""
        if index in self._buffers:
            return self._buffers[index]
        spec = self.item("buffers", index, where)
        length = self.integer(spec, "byteLength", f"buffer {index}", low=1)
        uri = spec.get("uri")
        if uri is None:
            if index != 0 or self.binary is None:
                raise self.error(f"buffer {index} has no uri and the file has no binary chunk for it")
            data = self.binary
        elif not isinstance(uri, str):
            raise self.error(f"buffer {index}: 'uri' must be a string")
        elif uri.startswith("data:"):
            data = self._data_uri(uri, index)
        else:
            data = self._external(uri, index, length)
        if len(data) < length:
            raise self.error(f"buffer {index} holds {len(data)} bytes but claims byteLength {length}")
        self._buffers[index] = memoryview(data)[:length]  # a view: no copy of a large buffer
        return self._buffers[index]

    def _data_uri(self, uri: str, index: int) -> bytes:
        head, _, payload = uri.partition(",")
        if not head.endswith(";base64"):
            raise self.error(f"buffer {index}: only base64 data URIs are supported")
        try:
            return base64.b64decode(payload, validate=True)
        except (binascii.Error, ValueError):
            raise self.error(f"buffer {index}: its data URI is not valid base64") from None

    def _external(self, uri: str, index: int, length: int) -> bytes:
        relative = urllib.parse.unquote(uri)
        if "://" in uri or relative.startswith(("/", "\\")) or (len(relative) > 1 and relative[1] == ":"):
            raise self.error(f"buffer {index}: uri {uri!r} is not a path relative to the file")
        target = self.path.parent / relative
        if not target.is_file():
            raise self.error(f"buffer {index}: its file {relative!r} is missing beside the glTF")
        try:
            with target.open("rb") as handle:
                return handle.read(length)
        except OSError as exc:
            raise self.error(f"buffer {index}: cannot read {relative!r}: {exc.strerror or exc}") from None

    def view(self, index: int, where: str) -> tuple[bytes, int, int, int | None]:
        """(buffer bytes, view start, view length, byteStride or None) of buffer view ``index``."""
        view = self.item("bufferViews", index, where)
        at = f"bufferView {index}"
        buffer = self.buffer(self.integer(view, "buffer", at), at)
        start = self.integer(view, "byteOffset", at, default=0)
        length = self.integer(view, "byteLength", at, low=1)
        if start + length > len(buffer):
            raise self.error(f"{at}: bytes {start}..{start + length} lie outside its buffer of {len(buffer)} bytes")
        stride = view.get("byteStride")
        if stride is not None:
            stride = self.integer(view, "byteStride", at, low=4)
        return buffer, start, length, stride

    # ---------------------------------------------------------------------- accessors
    def accessor(self, index: object, where: str) -> np.ndarray:
        """Accessor ``index`` as float64 ``(count, n_components)`` (normalised integers
        mapped), read-only; read once, however many samplers share it."""
        spec = self.item("accessors", index, where)
        if index in self._accessors:
            return self._accessors[index]
        values = self._decoded(index, spec, where, stored_floats=False)
        self._accessors[index] = values  # type: ignore[index]
        return values

    def key_values(self, index: object, where: str) -> np.ndarray:
        """Accessor ``index`` as an animation sampler's outputs ``(count, n_components)``,
        read-only: float32 components as the file stores them (a view of its buffer, no
        copy; each is a float64 exactly, so whatever works on them in float64 gets what
        :meth:`accessor` would give), anything else as :meth:`accessor` gives it."""
        spec = self.item("accessors", index, where)
        key = ("keys", index)
        if key not in self._accessors:
            values = self._decoded(index, spec, where, stored_floats=True)
            if values.dtype == np.float64:  # what accessor() gives: one array for both
                self._accessors.setdefault(index, values)  # type: ignore[call-overload]
            self._accessors[key] = values  # type: ignore[index]
        return self._accessors[key]  # type: ignore[index]

    def _decoded(self, index: object, spec: dict, where: str, *, stored_floats: bool) -> np.ndarray:
        """The accessor's values, checked; float64, or with ``stored_floats`` float32
        components of a dense accessor as stored."""
        if stored_floats and index in self._accessors:
            return self._accessors[index]
        at = f"accessor {index}"
        kind = spec.get("type")
        if not isinstance(kind, str) or kind not in TYPE_SIZES:
            raise self.error(f"{at}: type {kind!r} is not one of {', '.join(TYPE_SIZES)}")
        component = spec.get("componentType")
        if not isinstance(component, int) or component not in COMPONENTS:
            raise self.error(f"{at}: componentType {component!r} is not a glTF component type")
        count = self.integer(spec, "count", at, low=1)
        if count > MAX_ACCESSOR_COUNT:
            raise self.error(f"{at}: count {count} is beyond the {MAX_ACCESSOR_COUNT} elements this reader accepts")
        width = TYPE_SIZES[kind]
        dtype, divisor, lowest = COMPONENTS[component]
        if "bufferView" in spec:
            values = self._read_elements(spec.get("bufferView"), spec, count, width, dtype, at)
        else:
            values = np.zeros((count, width), np.dtype(dtype))
        if values.dtype.kind == "f" and not np.isfinite(values).all():  # checked in float32: half the bytes
            raise self.error(f"{at}: holds NaN or infinite values")
        if stored_floats and values.dtype.kind == "f" and "sparse" not in spec and not spec.get("normalized"):
            values.flags.writeable = False
            return values
        values = values.astype(np.float64)
        if "sparse" in spec:
            self._apply_sparse(spec["sparse"], values, width, dtype, at)
            if not np.isfinite(values).all():
                raise self.error(f"{at}: its sparse values hold NaN or infinite values")
        if spec.get("normalized") is True and divisor is not None:
            values = np.maximum(values / divisor, lowest)
        elif spec.get("normalized") is True:
            raise self.error(f"{at}: only byte and short components can be normalized")
        values.flags.writeable = False
        return values

    def key_times(self, index: object, where: str) -> np.ndarray:
        """A SCALAR accessor as (count,) (one array per accessor, shared by its samplers)."""
        values = self.accessor(index, where)
        if values.shape[1] != 1:
            raise self.error(f"{where}: accessor {index} must be SCALAR times")
        key = ("times", index)
        if key not in self._accessors:
            self._accessors[key] = values[:, 0]  # type: ignore[index]
        return self._accessors[key]  # type: ignore[index]

    def _read_elements(self, view_index, spec: dict, count: int, width: int, dtype: str, at: str) -> np.ndarray:
        buffer, start, length, stride = self.view(view_index, at)
        offset = self.integer(spec, "byteOffset", at, default=0)
        item = np.dtype(dtype).itemsize * width
        stride = stride or item
        if stride < item:
            raise self.error(f"{at}: byteStride {stride} is shorter than one element ({item} bytes)")
        needed = offset + stride * (count - 1) + item
        if needed > length:
            raise self.error(
                f"{at}: {count} elements from byte {offset} need {needed} bytes but its bufferView has {length}"
            )
        return np.ndarray((count,), np.dtype((dtype, (width,))), buffer, start + offset, (stride,))

    def _apply_sparse(self, sparse: object, values: np.ndarray, width: int, dtype: str, at: str) -> None:
        if not isinstance(sparse, dict) or not isinstance(sparse.get("indices"), dict):
            raise self.error(f"{at}: 'sparse' needs 'count', 'indices' and 'values'")
        count = self.integer(sparse, "count", f"{at} sparse", low=1)
        if count > values.shape[0]:
            raise self.error(f"{at}: {count} sparse values for {values.shape[0]} elements")
        indices_spec, values_spec = sparse["indices"], sparse.get("values")
        if not isinstance(values_spec, dict):
            raise self.error(f"{at}: sparse 'values' missing")
        index_type = indices_spec.get("componentType")
        if not isinstance(index_type, int) or index_type not in (5121, 5123, 5125):
            raise self.error(f"{at}: sparse indices must be unsigned byte, short or int, not {index_type!r}")
        indices = self._read_elements(
            indices_spec.get("bufferView"), indices_spec, count, 1, COMPONENTS[index_type][0], f"{at} sparse indices"
        )[:, 0].astype(np.int64)
        if (indices >= values.shape[0]).any() or (np.diff(indices) <= 0).any():
            raise self.error(f"{at}: sparse indices must increase and stay below {values.shape[0]}")
        values[indices] = self._read_elements(
            values_spec.get("bufferView"), values_spec, count, width, dtype, f"{at} sparse values"
        )


def parse_glb(path: str | Path, data: bytes) -> tuple[dict, bytes | None]:
    """The JSON chunk (parsed) and BIN chunk of a ``.glb`` file."""
    if len(data) < 20:
        raise MotionFileError(path, f"a .glb file starts with a 12-byte header and a chunk; this has {len(data)} bytes")
    magic, version, length = struct.unpack_from("<4sII", data)
    if magic != GLB_MAGIC:
        raise MotionFileError(path, f"not a binary glTF file: it starts with {magic!r}, expected b'glTF'")
    if version != 2:
        raise MotionFileError(path, f"glTF version {version}: only 2 is supported")
    if length > len(data):
        raise MotionFileError(path, f"the header says {length} bytes but the file has {len(data)} (truncated?)")
    chunks: list[tuple[int, bytes]] = []
    at = 12
    while at + 8 <= length:
        size, kind = struct.unpack_from("<II", data, at)
        if at + 8 + size > length:
            raise MotionFileError(path, f"chunk {len(chunks)} at byte {at} claims {size} bytes beyond the file's end")
        chunks.append((kind, memoryview(data)[at + 8 : at + 8 + size]))
        at += 8 + size
    if not chunks or chunks[0][0] != CHUNK_JSON:
        raise MotionFileError(path, "the first chunk of a .glb must be its JSON")
    binary = chunks[1][1] if len(chunks) > 1 and chunks[1][0] == CHUNK_BIN else None
    return parse_json(path, bytes(chunks[0][1])), binary


def parse_json(path: str | Path, text: bytes) -> dict:
    try:
        document = json.loads(text.decode("utf-8"))
    except UnicodeDecodeError:
        raise MotionFileError(path, "the glTF JSON is not UTF-8 text") from None
    except (json.JSONDecodeError, RecursionError) as exc:
        detail = f": {exc.msg} at line {exc.lineno} column {exc.colno}" if isinstance(exc, json.JSONDecodeError) else ""
        raise MotionFileError(path, f"the glTF JSON is not valid JSON{detail}") from None
    if not isinstance(document, dict):
        raise MotionFileError(path, "the glTF JSON must be an object")
    required = document.get("extensionsRequired", [])
    named = {item for item in required if isinstance(item, str)} if isinstance(required, list) else set()
    refused = sorted(named & UNDECODED_EXTENSIONS)
    if refused:
        raise MotionFileError(path, f"the file requires {', '.join(refused)}, which this reader does not decode")
    asset = document.get("asset")
    version = asset.get("version") if isinstance(asset, dict) else None
    if not isinstance(version, str) or not version.startswith("2."):
        raise MotionFileError(path, f"asset.version is {version!r}: only glTF 2.x is supported")
    return document


def open_gltf(path: str | Path, data: bytes) -> GltfDocument:
    """Parse a ``.glb`` or ``.gltf`` file's bytes (binary if they start with ``glTF``)."""
    if data[:4] == GLB_MAGIC or str(path).lower().endswith(".glb"):
        document, binary = parse_glb(path, data)
        return GltfDocument(path, document, binary)
    return GltfDocument(path, parse_json(path, data.lstrip(b"\xef\xbb\xbf")), None)
