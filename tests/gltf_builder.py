"""Small glTF files written from scratch for the reader's tests (JSON and a binary buffer,
saved as ``.glb``, ``.gltf`` with a data URI, or ``.gltf`` with a ``.bin`` beside it)."""

from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

import numpy as np

COMPONENT = {"<f4": 5126, "<i1": 5120, "<u1": 5121, "<i2": 5122, "<u2": 5123, "<u4": 5125}
KIND = {1: "SCALAR", 3: "VEC3", 4: "VEC4", 16: "MAT4"}


class GltfBuilder:
    """A document and its buffer, built up accessor by accessor."""

    def __init__(self) -> None:
        self.doc: dict = {"asset": {"version": "2.0", "generator": "test"}, "nodes": [], "accessors": []}
        self.doc["bufferViews"] = []
        self.blob = bytearray()

    def node(self, **fields) -> int:
        self.doc["nodes"].append(fields)
        return len(self.doc["nodes"]) - 1

    def view(self, data: bytes) -> int:
        self.blob += b"\0" * (-len(self.blob) % 4)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)})
        self.blob += data
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, dtype: str = "<f4", normalized: bool = False, **extra) -> int:
        """An accessor of rows (count, width) stored as ``dtype``."""
        array = np.asarray(values)
        rows = array.reshape(array.shape[0], -1)
        spec = {
            "bufferView": self.view(np.ascontiguousarray(rows, dtype=dtype).tobytes()),
            "componentType": COMPONENT[dtype],
            "count": rows.shape[0],
            "type": KIND[rows.shape[1]],
            **extra,
        }
        if normalized:
            spec["normalized"] = True
        self.doc["accessors"].append(spec)
        return len(self.doc["accessors"]) - 1

    def animation(self, channels: list[tuple[int, str, np.ndarray, np.ndarray, str]], name: str = "") -> int:
        """channels: (node, path, times (K,), values, interpolation)."""
        samplers, targets = [], []
        for node, path, times, values, interpolation in channels:
            values = np.asarray(values, dtype=np.float64)
            samplers.append(
                {
                    "input": self.accessor(np.asarray(times, dtype=np.float64)[:, None]),
                    "output": self.accessor(values),
                    "interpolation": interpolation,
                }
            )
            targets.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})
        self.doc.setdefault("animations", []).append({"name": name, "samplers": samplers, "channels": targets})
        return len(self.doc["animations"]) - 1

    def save(self, path: Path, mode: str = "glb") -> Path:
        """``mode``: ``glb``, ``embedded`` (data URI) or ``external`` (``<stem>.bin`` beside)."""
        doc = json.loads(json.dumps(self.doc))
        blob = bytes(self.blob)
        doc["buffers"] = [{"byteLength": len(blob)}]
        if mode == "embedded":
            doc["buffers"][0]["uri"] = "data:application/gltf-buffer;base64," + base64.b64encode(blob).decode()
        elif mode == "external":
            doc["buffers"][0]["uri"] = path.stem + ".bin"
            path.with_suffix(".bin").write_bytes(blob)
        if mode != "glb":
            path.write_text(json.dumps(doc))
            return path
        path.write_bytes(glb_bytes(doc, blob))
        return path


def glb_bytes(doc: dict, blob: bytes) -> bytes:
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    blob = blob + b"\0" * (-len(blob) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def quaternion(axis, degrees: float) -> np.ndarray:
    """Unit quaternion ``x, y, z, w`` of a rotation about ``axis``."""
    axis = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    half = np.radians(degrees) / 2
    return np.append(axis * np.sin(half), np.cos(half))


def post_rotation_forward(parents, rotations, translations) -> tuple[np.ndarray, np.ndarray]:
    """World rotations (F, J, 3, 3) and positions (F, J, 3) of a post-rotation motion, joint by
    joint in a loop (a reference apart from the core's FK): W_j = W_p R_j, P_j = P_p + W_p t_j.
    ``parents`` (J,) with each parent before its children; rotations (F, J, 3, 3),
    translations (F, J, 3)."""
    worlds, places = np.empty_like(rotations), np.empty_like(translations)
    for j, p in enumerate(parents):
        if p < 0:
            worlds[:, j], places[:, j] = rotations[:, j], translations[:, j]
        else:
            worlds[:, j] = worlds[:, p] @ rotations[:, j]
            places[:, j] = places[:, p] + (worlds[:, p] @ translations[:, j, :, None])[..., 0]
    return worlds, places
