"""Fuzz target for glTF (``.glb``): the real files and our own exports, cut at their chunks
and corrupted where their structure lives, in the JSON (counts, offsets, lengths, indices,
the node tree) as much as in the bytes.

Seeds are self-contained ``.glb`` files: a ``.gltf`` with its buffer beside it or in a data
URI is packed into one (its JSON and buffer unchanged otherwise), so a case never depends
on a companion file. Errors name JSON objects (accessor 3, node 7), not lines.
"""

from __future__ import annotations

import base64
import json
import struct
from functools import cache
from pathlib import Path

import numpy as np

from gmr_studio.core.fuzz.mutations import BINARY_MUTATIONS, Mutation, _pick
from gmr_studio.core.fuzz.targets import SEED_FRAMES, Target, _shared

JSON_CHUNK, BIN_CHUNK = 0x4E4F534A, 0x004E4942
#: what a number in the JSON is replaced by
HOSTILE_VALUES = [-1, 0, 1, 3, 2**31, 2**40, 10**20, -(2**63), 3.5, float("nan"), "x", None, [], {}, True]


def pack_glb(document: dict, blob: bytes) -> bytes:
    """A ``.glb`` of a JSON document and a binary buffer (chunks padded to 4 bytes)."""
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), JSON_CHUNK) + text
    if blob:
        blob += b"\0" * (-len(blob) % 4)
        chunks += struct.pack("<II", len(blob), BIN_CHUNK) + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def split_glb(data: bytes) -> tuple[dict, bytes] | None:
    """(JSON document, BIN chunk) of a well-formed ``.glb``, else None."""
    try:
        json_length = struct.unpack_from("<I", data, 12)[0]
        document = json.loads(data[20 : 20 + json_length])
        rest = data[20 + json_length :]
        blob = rest[8 : 8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else b""
        return (document, blob) if isinstance(document, dict) else None
    except (struct.error, ValueError, UnicodeDecodeError, RecursionError):
        return None


def _self_contained(path: Path) -> bytes:
    if path.suffix.lower() == ".glb":
        return path.read_bytes()
    document = json.loads(path.read_text(encoding="utf-8"))
    buffer = document["buffers"][0]
    uri = buffer.pop("uri")
    blob = base64.b64decode(uri.split(",", 1)[1]) if uri.startswith("data:") else (path.parent / uri).read_bytes()
    return pack_glb(document, blob)


@cache
def gltf_seeds() -> list[tuple[str, bytes]]:
    """The shared glTF files, and our exports of a short CMU clip (a tree and a forest)."""
    from gmr_studio.core.edits.operations import split_all
    from gmr_studio.core.formats.bvh import read_bvh
    from gmr_studio.core.formats.gltf import build_gltf
    from gmr_studio.core.kinematics.convention import pre_from_post

    seeds = [(path.name, _self_contained(path)) for path in _shared("gltf/**/*.gl*")]
    for path in _shared("bvh/cmu_*.bvh")[:1]:
        motion = pre_from_post(read_bvh(path)).frame_slice(slice(0, SEED_FRAMES))
        for label, edited in (("tree", motion), ("forest", split_all(motion))):
            gltf, blob, _ = build_gltf(edited)
            seeds.append((f"{path.name} as glTF, {label}", pack_glb(json.loads(gltf.gltf_to_json()), blob)))
    return seeds


def glb_structure(data: bytes) -> list[int]:
    """Cuts inside the header, at and inside each chunk header, and in each chunk."""
    points = [0, 4, 8, 12, 16, 20]
    at = 12
    while at + 8 <= len(data):
        size = struct.unpack_from("<I", data, at)[0]
        points += [at + 4, at + 8, at + 8 + size // 2, at + 8 + size - 1]
        at += 8 + size
    return sorted({p for p in points if 0 <= p < len(data)})


def _numbers(node, path=()) -> list[tuple]:
    """Paths to every number in a JSON value."""
    if isinstance(node, dict):
        return [p for key, value in node.items() for p in _numbers(value, (*path, key))]
    if isinstance(node, list):
        return [p for i, value in enumerate(node) for p in _numbers(value, (*path, i))]
    return [path] if isinstance(node, (int, float)) and not isinstance(node, bool) else []


def _json_edit(edit):
    """A mutation that parses the ``.glb``, edits its JSON and packs it again."""

    def mutate(data: bytes, rng: np.random.Generator) -> bytes:
        parts = split_glb(data)
        if parts is None:
            return data
        document, blob = parts
        edit(document, rng)
        return pack_glb(document, blob)

    mutate.__doc__ = edit.__doc__
    return mutate


def _set(document: dict, path: tuple, value) -> None:
    target = document
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value


def _dicts(document: dict, key: str) -> list[dict]:
    """The objects of a top-level array (earlier mutations may have put other things there)."""
    items = document.get(key)
    return [item for item in items if isinstance(item, dict)] if isinstance(items, list) else []


def hostile_number(document: dict, rng: np.random.Generator) -> None:
    """Replace a number (a count, offset, length, index, TRS value) by a hostile value."""
    paths = _numbers(document)
    if paths:
        _set(document, _pick(rng, paths), _pick(rng, HOSTILE_VALUES))


def grow_count(document: dict, rng: np.random.Generator) -> None:
    """Make an accessor's count or a view's length larger than the data behind it."""
    kind = _pick(rng, ["accessors", "bufferViews", "buffers"])
    items = _dicts(document, kind)
    if items:
        item = _pick(rng, items)
        key = {"accessors": "count", "bufferViews": "byteLength", "buffers": "byteLength"}[kind]
        if isinstance(item.get(key), int):
            item[key] = item[key] * int(_pick(rng, [2, 1000, 2**20])) + int(rng.integers(1, 64))


def node_cycle(document: dict, rng: np.random.Generator) -> None:
    """Give a node a child that is its ancestor, itself, or another node's child."""
    nodes = _dicts(document, "nodes")
    if nodes:
        node = _pick(rng, nodes)
        if not isinstance(node.get("children"), list):
            node["children"] = []
        node["children"].append(int(rng.integers(len(nodes))))


def outside_buffer(document: dict, rng: np.random.Generator) -> None:
    """Point a buffer at a file outside (absolute, parent folder, URL) or a broken data URI."""
    buffers = _dicts(document, "buffers")
    if buffers:
        uri = _pick(rng, ["/etc/hostname", "../x.bin", "http://example.com/b.bin", "data:;base64,@@", "missing.bin"])
        _pick(rng, buffers)["uri"] = uri


def drop_key(document: dict, rng: np.random.Generator) -> None:
    """Remove one key of one object (a required field, often)."""
    kinds = ("accessors", "bufferViews", "nodes", "skins", "animations")
    objects = [item for key in kinds for item in _dicts(document, key) if item]
    if objects:
        target = _pick(rng, objects)
        del target[_pick(rng, sorted(target))]


def truncate_chunk_claim(data: bytes, rng: np.random.Generator) -> bytes:
    """Claim a longer file or a longer chunk than there is."""
    if len(data) < 20:
        return data
    out = bytearray(data)
    at = _pick(rng, [8, 12])
    out[at : at + 4] = struct.pack("<I", int(_pick(rng, [len(data) + 1, 2**31, 2**32 - 1])))
    return bytes(out)


GLTF_MUTATIONS: dict[str, Mutation] = {
    "truncate anywhere": BINARY_MUTATIONS["truncate anywhere"],
    "flip bytes": BINARY_MUTATIONS["flip bytes"],
    "chunk or file longer than it is": truncate_chunk_claim,
    "hostile number in the JSON": _json_edit(hostile_number),
    "count or length beyond the data": _json_edit(grow_count),
    "node cycle or second parent": _json_edit(node_cycle),
    "buffer outside the file": _json_edit(outside_buffer),
    "required key dropped": _json_edit(drop_key),
}


def _read_gltf(path: Path, data: bytes, seed: str):
    from gmr_studio.core.formats.gltf_in import read_gltf

    return read_gltf(path, data=data)


def targets(check_motion) -> dict[str, Target]:
    return {
        "gltf": Target("gltf", ".glb", gltf_seeds, _read_gltf, check_motion, GLTF_MUTATIONS, structure=glb_structure)
    }
