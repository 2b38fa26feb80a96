"""The glTF container (core.formats.gltf_in.container): every field check and its message,
buffers by chunk, data URI or file (escaped names, drive letters), accessors at exactly their
view's end, strides, normalised integers of each type, sparse values, the GLB header and
chunks, the JSON's encoding, depth and required extensions."""

from __future__ import annotations

import base64
import json
import struct

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.gltf_in import container
from gmr_studio.core.formats.gltf_in.container import GltfDocument, open_gltf, parse_glb, parse_json

ASSET = {"version": "2.0"}


def doc(binary: bytes | None = None, path="c.glb", **fields) -> GltfDocument:
    return GltfDocument(path, {"asset": ASSET, **fields}, binary)


def refused(call, *args) -> str:
    with pytest.raises(MotionFileError) as caught:
        call(*args)
    return caught.value.message


# ------------------------------------------------------------------------ fields
def test_items_item_integer_and_numbers_check_their_fields():
    d = doc(nodes=[{"a": 1}, {}], skins={}, scenes=[3])
    assert d.items("nodes") == [{"a": 1}, {}] and d.items("animations") == []
    assert refused(d.items, "skins") == "'skins' must be an array of objects"
    assert refused(d.items, "scenes") == "'scenes' must be an array of objects"
    assert d.item("nodes", 1, "here") == {}
    for index in (2, -1, True, "0"):
        assert refused(d.item, "nodes", index, "here") == f"here: nodes index {index!r} out of range (the file has 2)"
    assert d.integer({"n": 0}, "n", "at") == 0 and d.integer({}, "n", "at", default=5) == 5
    assert d.integer({"n": 4}, "n", "at", low=4) == 4
    for value in (-1, True, 1.0, None):
        assert refused(d.integer, {"n": value}, "n", "at") == f"at: 'n' must be a whole number >= 0, not {value!r}"
    assert refused(d.integer, {"n": 3}, "n", "at", None, 4) == "at: 'n' must be a whole number >= 4, not 3"
    np.testing.assert_array_equal(d.numbers({"t": [1, 2.5, 3]}, "t", 3, [0, 0, 0], "n"), [1, 2.5, 3])
    np.testing.assert_array_equal(d.numbers({}, "t", 3, [0, 0, 1], "n"), [0, 0, 1])
    for value in ([1, 2], [1, 2, True], [1, 2, "3"], [1, 2, float("nan")], [1, 2, float("inf")], 3):
        assert refused(d.numbers, {"t": value}, "t", 3, [0, 0, 0], "n") == "n: 't' must be 3 finite numbers"


# ------------------------------------------------------------------------ buffers
def test_the_binary_chunk_is_buffer_zero_cut_to_its_length_and_read_once():
    d = doc(b"abcdef", buffers=[{"byteLength": 4}, {"byteLength": 2}])
    assert bytes(d.buffer(0, "w")) == b"abcd"
    d.binary = b"zzzzzz"
    assert bytes(d.buffer(0, "w")) == b"abcd"  # kept
    assert refused(d.buffer, 1, "w") == "buffer 1 has no uri and the file has no binary chunk for it"
    assert refused(doc(None, buffers=[{"byteLength": 4}]).buffer, 0, "w") == (
        "buffer 0 has no uri and the file has no binary chunk for it"
    )
    assert refused(doc(b"ab", buffers=[{"byteLength": 3}]).buffer, 0, "w") == (
        "buffer 0 holds 2 bytes but claims byteLength 3"
    )
    assert refused(doc(b"ab", buffers=[{"byteLength": 0}]).buffer, 0, "w") == (
        "buffer 0: 'byteLength' must be a whole number >= 1, not 0"
    )
    assert (
        refused(doc(b"ab", buffers=[{"byteLength": 2, "uri": 7}]).buffer, 0, "w") == "buffer 0: 'uri' must be a string"
    )


def test_data_uris_base64_only():
    payload = base64.b64encode(b"\x01\x02\x03").decode()
    d = doc(buffers=[{"byteLength": 3, "uri": f"data:application/octet-stream;base64,{payload}"}])
    assert bytes(d.buffer(0, "w")) == b"\x01\x02\x03"
    plain = doc(buffers=[{"byteLength": 3, "uri": "data:text/plain,abc"}])
    assert refused(plain.buffer, 0, "w") == "buffer 0: only base64 data URIs are supported"


def test_external_buffers_beside_the_file_escaped_names_and_paths_refused(tmp_path):
    (tmp_path / "my data.bin").write_bytes(b"0123456789")
    d = doc(path=tmp_path / "c.gltf", buffers=[{"byteLength": 4, "uri": "my%20data.bin"}])
    assert bytes(d.buffer(0, "w")) == b"0123"
    for uri in ("C:/x.bin", "c:x.bin", "c:", "\\\\server\\x.bin", "/x.bin", "file:///x.bin"):
        bad = doc(path=tmp_path / "c.gltf", buffers=[{"byteLength": 4, "uri": uri}])
        assert refused(bad.buffer, 0, "w") == f"buffer 0: uri {uri!r} is not a path relative to the file"
    (tmp_path / "a").write_bytes(b"abcd")  # a one-letter name is relative
    assert bytes(doc(path=tmp_path / "c.gltf", buffers=[{"byteLength": 4, "uri": "a"}]).buffer(0, "w")) == b"abcd"
    (tmp_path / "sub").mkdir()
    folder = doc(path=tmp_path / "c.gltf", buffers=[{"byteLength": 4, "uri": "sub"}])
    assert refused(folder.buffer, 0, "w") == "buffer 0: its file 'sub' is missing beside the glTF"


def test_views_within_their_buffer_and_their_strides():
    d = doc(b"\0" * 16, buffers=[{"byteLength": 16}], bufferViews=[{"buffer": 0, "byteOffset": 4, "byteLength": 12}])
    buffer, start, length, stride = d.view(0, "w")
    assert (len(buffer), start, length, stride) == (16, 4, 12, None)
    d.json["bufferViews"].append({"buffer": 0, "byteOffset": 5, "byteLength": 12})
    assert refused(d.view, 1, "w") == "bufferView 1: bytes 5..17 lie outside its buffer of 16 bytes"
    d.json["bufferViews"].append({"buffer": 0, "byteLength": 16, "byteStride": 4})
    assert d.view(2, "w")[1:] == (0, 16, 4)
    d.json["bufferViews"].append({"buffer": 0, "byteLength": 16, "byteStride": 3})
    assert refused(d.view, 3, "w") == "bufferView 3: 'byteStride' must be a whole number >= 4, not 3"


# ------------------------------------------------------------------------ accessors
def _accessor_doc(data: bytes, **accessor) -> GltfDocument:
    view = {"buffer": 0, "byteLength": len(data)}
    if "byteStride" in accessor:
        view["byteStride"] = accessor.pop("byteStride")
    spec = {"bufferView": 0, "componentType": 5126, "count": 1, "type": "SCALAR", **accessor}
    return doc(data, buffers=[{"byteLength": len(data)}], bufferViews=[view], accessors=[spec])


def test_an_accessor_may_end_exactly_at_its_view_and_is_read_only_and_read_once():
    d = _accessor_doc(np.arange(6, dtype="<f4").tobytes(), count=2, type="VEC3")
    values = d.accessor(0, "w")
    np.testing.assert_array_equal(values, [[0, 1, 2], [3, 4, 5]])
    assert values.dtype == np.float64 and not values.flags.writeable and d.accessor(0, "w") is values
    shifted = _accessor_doc(np.arange(6, dtype="<f4").tobytes(), count=1, type="VEC3", byteOffset=12)
    np.testing.assert_array_equal(shifted.accessor(0, "w"), [[3, 4, 5]])
    beyond = _accessor_doc(np.arange(6, dtype="<f4").tobytes(), count=1, type="VEC3", byteOffset=16)
    assert refused(beyond.accessor, 0, "w") == (
        "accessor 0: 1 elements from byte 16 need 28 bytes but its bufferView has 24"
    )


def test_float32_keys_come_as_stored_and_are_the_accessors_numbers():
    data = np.array([0.1, -0.0, 3.5, 1e-30, 2.0, 7.25], dtype="<f4").tobytes()
    d = _accessor_doc(data, count=2, type="VEC3")
    keys = d.key_values(0, "w")
    assert keys.dtype == np.float32 and not keys.flags.writeable and d.key_values(0, "w") is keys
    assert keys.astype(np.float64).tobytes() == d.accessor(0, "w").tobytes()
    normalised = _accessor_doc(np.array([127, -127], "<i1").tobytes() + b"\0\0", componentType=5120, normalized=True)
    assert normalised.key_values(0, "w") is normalised.accessor(0, "w")  # other components: float64, once
    assert refused(_accessor_doc(np.array([np.nan], "<f4").tobytes()).key_values, 0, "w") == (
        "accessor 0: holds NaN or infinite values"
    )


def test_strided_accessors_read_every_stride():
    data = np.arange(8, dtype="<f4").tobytes()  # 4 elements of 2 floats, read 1 float each 8 bytes
    d = _accessor_doc(data, count=4, byteStride=8)
    np.testing.assert_array_equal(d.accessor(0, "w")[:, 0], [0, 2, 4, 6])
    short = _accessor_doc(data, count=2, type="VEC3", byteStride=8)
    assert refused(short.accessor, 0, "w") == "accessor 0: byteStride 8 is shorter than one element (12 bytes)"


@pytest.mark.parametrize(
    ("dtype", "component", "stored", "expected"),
    [
        ("<i1", 5120, [-128, -127, 127], [-1.0, -1.0, 1.0]),
        ("<u1", 5121, [0, 51, 255], [0.0, 0.2, 1.0]),
        ("<i2", 5122, [-32768, -32767, 32767], [-1.0, -1.0, 1.0]),
        ("<u2", 5123, [0, 13107, 65535], [0.0, 0.2, 1.0]),
    ],
)
def test_normalised_integers_map_to_the_unit_range(dtype, component, stored, expected):
    data = np.array(stored, dtype=dtype).tobytes()
    data += b"\0" * (-len(data) % 4)
    d = _accessor_doc(data, componentType=component, count=3, normalized=True)
    np.testing.assert_allclose(d.accessor(0, "w")[:, 0], expected, rtol=0, atol=1e-15)
    raw = _accessor_doc(data, componentType=component, count=3)
    np.testing.assert_array_equal(raw.accessor(0, "w")[:, 0], stored)


def test_normalised_floats_or_ints_and_bad_types_are_refused():
    data = np.zeros(2, "<f4").tobytes()
    assert refused(_accessor_doc(data, normalized=True).accessor, 0, "w") == (
        "accessor 0: only byte and short components can be normalized"
    )
    assert refused(_accessor_doc(data, componentType=5125, normalized=True).accessor, 0, "w") == (
        "accessor 0: only byte and short components can be normalized"
    )
    assert refused(_accessor_doc(data, type="VEC5").accessor, 0, "w") == (
        "accessor 0: type 'VEC5' is not one of SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4"
    )
    assert refused(_accessor_doc(data, componentType=5124).accessor, 0, "w") == (
        "accessor 0: componentType 5124 is not a glTF component type"
    )
    assert refused(_accessor_doc(data, componentType=True).accessor, 0, "w") == (
        "accessor 0: componentType True is not a glTF component type"
    )
    assert refused(_accessor_doc(np.array([1.0, np.inf], "<f4").tobytes(), count=2).accessor, 0, "w") == (
        "accessor 0: holds NaN or infinite values"
    )


def test_the_accessor_count_limit_is_inclusive(monkeypatch):
    monkeypatch.setattr(container, "MAX_ACCESSOR_COUNT", 3)
    spec = {"componentType": 5126, "count": 3, "type": "SCALAR"}
    np.testing.assert_array_equal(doc(accessors=[spec]).accessor(0, "w"), np.zeros((3, 1)))  # no view: zeros
    too_many = doc(accessors=[{**spec, "count": 4}])
    assert refused(too_many.accessor, 0, "w") == "accessor 0: count 4 is beyond the 3 elements this reader accepts"


def test_key_times_are_one_array_per_accessor_and_scalar_only():
    d = _accessor_doc(np.arange(4, dtype="<f4").tobytes(), count=2, type="VEC2")
    assert refused(d.key_times, 0, "input") == "input: accessor 0 must be SCALAR times"
    times = _accessor_doc(np.arange(4, dtype="<f4").tobytes(), count=4)
    first = times.key_times(0, "input")
    assert first.shape == (4,) and times.key_times(0, "again") is first


# ------------------------------------------------------------------------ sparse
def _sparse_doc(indices, values, count=None, index_type=5123, n=4) -> GltfDocument:
    index_bytes = np.array(indices, dtype=container.COMPONENTS[index_type][0]).tobytes()
    index_bytes += b"\0" * (-len(index_bytes) % 4)
    value_bytes = np.array(values, "<f4").tobytes()
    data = index_bytes + value_bytes
    views = [
        {"buffer": 0, "byteLength": len(index_bytes)},
        {"buffer": 0, "byteOffset": len(index_bytes), "byteLength": len(value_bytes)},
    ]
    sparse = {
        "count": len(indices) if count is None else count,
        "indices": {"bufferView": 0, "componentType": index_type},
        "values": {"bufferView": 1},
    }
    spec = {"componentType": 5126, "count": n, "type": "SCALAR", "sparse": sparse}
    return doc(data, buffers=[{"byteLength": len(data)}], bufferViews=views, accessors=[spec])


@pytest.mark.parametrize("index_type", [5121, 5123, 5125])
def test_sparse_values_replace_their_elements(index_type):
    values = _sparse_doc([0, 3], [5.0, 7.0], index_type=index_type).accessor(0, "w")[:, 0]
    np.testing.assert_array_equal(values, [5, 0, 0, 7])
    np.testing.assert_array_equal(_sparse_doc([3], [2.0]).accessor(0, "w")[:, 0], [0, 0, 0, 2])


@pytest.mark.parametrize(
    ("indices", "values", "options", "expected"),
    [
        ([1, 1], [1.0, 2.0], {}, "sparse indices must increase and stay below 4"),
        ([2, 1], [1.0, 2.0], {}, "sparse indices must increase and stay below 4"),
        ([4], [1.0], {}, "sparse indices must increase and stay below 4"),
        ([0, 1], [1.0, 2.0], {"n": 1}, "2 sparse values for 1 elements"),
        ([0], [np.nan], {}, "its sparse values hold NaN or infinite values"),
        ([0], [1.0], {"index_type": 5122}, "sparse indices must be unsigned byte, short or int, not 5122"),
    ],
)
def test_bad_sparse_values_are_refused(indices, values, options, expected):
    assert refused(_sparse_doc(indices, values, **options).accessor, 0, "w") == f"accessor 0: {expected}"


def test_sparse_without_its_parts_is_refused():
    d = _sparse_doc([0], [1.0])
    d.json["accessors"][0]["sparse"].pop("values")
    assert refused(d.accessor, 0, "w") == "accessor 0: sparse 'values' missing"
    d = _sparse_doc([0], [1.0])
    d.json["accessors"][0]["sparse"]["indices"] = 3
    assert refused(d.accessor, 0, "w") == "accessor 0: 'sparse' needs 'count', 'indices' and 'values'"
    d = _sparse_doc([0], [1.0], count=0)
    assert refused(d.accessor, 0, "w") == "accessor 0 sparse: 'count' must be a whole number >= 1, not 0"


# ------------------------------------------------------------------------ GLB and JSON
def _glb(chunks: list[tuple[int, bytes]], version: int = 2, extra: int = 0) -> bytes:
    body = b"".join(struct.pack("<II", len(data), kind) + data for kind, data in chunks)
    return struct.pack("<4sII", b"glTF", version, 12 + len(body) + extra) + body


JSON_TEXT = json.dumps({"asset": ASSET}).encode() + b"  "


def test_glb_chunks_json_then_binary():
    document, binary = parse_glb("m.glb", _glb([(container.CHUNK_JSON, JSON_TEXT), (container.CHUNK_BIN, b"1234")]))
    assert document == {"asset": ASSET} and bytes(binary) == b"1234"
    assert parse_glb("m.glb", _glb([(container.CHUNK_JSON, JSON_TEXT)]))[1] is None
    empty = parse_glb("m.glb", _glb([(container.CHUNK_JSON, JSON_TEXT), (container.CHUNK_BIN, b"")]))[1]
    assert empty is not None and len(empty) == 0  # a last chunk of its 8-byte header alone
    other = parse_glb("m.glb", _glb([(container.CHUNK_JSON, JSON_TEXT), (0x12345678, b"1234")]))
    assert other[1] is None  # a second chunk that is no BIN


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        (b"glTF" + b"\0" * 15, "a .glb file starts with a 12-byte header and a chunk; this has 19 bytes"),
        (b"glTX" + b"\0" * 16, "not a binary glTF file: it starts with b'glTX', expected b'glTF'"),
        (_glb([(0x4E4F534A, JSON_TEXT)], version=1), "glTF version 1: only 2 is supported"),
        (_glb([(0x4E4F534A, JSON_TEXT)], extra=1), "the header says 52 bytes but the file has 51 (truncated?)"),
        (_glb([(0x004E4942, JSON_TEXT)]), "the first chunk of a .glb must be its JSON"),
    ],
)
def test_bad_glb_headers_are_refused(data, expected):
    assert refused(parse_glb, "m.glb", data) == expected


def test_a_chunk_ending_exactly_at_the_file_end_is_read_and_one_beyond_is_refused():
    data = bytearray(_glb([(container.CHUNK_JSON, JSON_TEXT)]))
    assert parse_glb("m.glb", bytes(data))[0] == {"asset": ASSET}
    data[12:16] = struct.pack("<I", len(JSON_TEXT) + 1)
    assert (
        refused(parse_glb, "m.glb", bytes(data))
        == f"chunk 0 at byte 12 claims {len(JSON_TEXT) + 1} bytes beyond the file's end"
    )


def test_json_text_encoding_depth_extensions_and_version():
    assert refused(parse_json, "m.gltf", b"\xff{}") == "the glTF JSON is not UTF-8 text"
    assert refused(parse_json, "m.gltf", b'{"asset":\n  }') == (
        "the glTF JSON is not valid JSON: Expecting value at line 2 column 3"
    )
    assert refused(parse_json, "m.gltf", b"[" * 100_000) == "the glTF JSON is not valid JSON"
    assert refused(parse_json, "m.gltf", b"[1]") == "the glTF JSON must be an object"
    required = {
        "asset": ASSET,
        "extensionsRequired": ["KHR_meshopt_compression", "KHR_x", 3, "EXT_meshopt_compression"],
    }
    assert refused(parse_json, "m.gltf", json.dumps(required).encode()) == (
        "the file requires EXT_meshopt_compression, KHR_meshopt_compression, which this reader does not decode"
    )
    fine = {"asset": ASSET, "extensionsRequired": "EXT_meshopt_compression"}  # not a list: nothing named
    assert parse_json("m.gltf", json.dumps(fine).encode()) == fine
    for asset in ({"version": "3.0"}, {"version": 2}, "2.0", None):
        text = json.dumps({"asset": asset}).encode()
        version = asset.get("version") if isinstance(asset, dict) else None
        assert refused(parse_json, "m.gltf", text) == f"asset.version is {version!r}: only glTF 2.x is supported"


def test_open_by_magic_or_suffix_and_a_byte_order_mark_is_skipped():
    glb = _glb([(container.CHUNK_JSON, JSON_TEXT)])
    assert open_gltf("m.gltf", glb).json == {"asset": ASSET}  # binary by its magic, whatever the name
    assert refused(open_gltf, "M.GLB", JSON_TEXT).startswith("not a binary glTF file")  # by its suffix
    assert open_gltf("m.gltf", b"\xef\xbb\xbf" + JSON_TEXT).binary is None


@pytest.mark.parametrize(
    ("kind", "width"), [("SCALAR", 1), ("VEC2", 2), ("VEC3", 3), ("VEC4", 4), ("MAT2", 4), ("MAT3", 9), ("MAT4", 16)]
)
def test_each_type_reads_its_number_of_components(kind, width):
    d = _accessor_doc(np.arange(2 * width, dtype="<f4").tobytes(), count=2, type=kind)
    np.testing.assert_array_equal(d.accessor(0, "w"), np.arange(2 * width).reshape(2, width))


def test_a_view_of_one_byte_and_counts_of_zero():
    np.testing.assert_array_equal(_accessor_doc(b"\x07", componentType=5121).accessor(0, "w"), [[7]])
    zero = _accessor_doc(np.zeros(1, "<f4").tobytes(), count=0)
    assert refused(zero.accessor, 0, "w") == "accessor 0: 'count' must be a whole number >= 1, not 0"


def test_sparse_values_may_replace_every_element_consecutively():
    values = _sparse_doc([0, 1, 2, 3], [1.0, 2.0, 3.0, 4.0]).accessor(0, "w")[:, 0]
    np.testing.assert_array_equal(values, [1, 2, 3, 4])
    d = _sparse_doc([0, 1, 2], [1.0, 2.0, 3.0], n=2)
    assert refused(d.accessor, 0, "w") == "accessor 0: 3 sparse values for 2 elements"


def test_a_buffer_file_that_cannot_be_read_says_why(tmp_path, monkeypatch):
    (tmp_path / "x.bin").write_bytes(b"0123")
    for error, reason in ((OSError(13, "Permission denied"), "Permission denied"), (OSError("plain"), "plain")):

        def fail(*args, error=error, **kwargs):
            raise error

        monkeypatch.setattr(container.Path, "open", fail)
        d = doc(path=tmp_path / "c.gltf", buffers=[{"byteLength": 4, "uri": "x.bin"}])
        assert refused(d.buffer, 0, "w") == f"buffer 0: cannot read 'x.bin': {reason}"


def test_bytes_after_the_last_chunk_too_few_for_a_header_are_ignored_and_empty_views_refused():
    data = _glb([(container.CHUNK_JSON, JSON_TEXT)], extra=7) + b"\0" * 7
    assert parse_glb("m.glb", data)[0] == {"asset": ASSET}
    d = doc(b"\0" * 4, buffers=[{"byteLength": 4}], bufferViews=[{"buffer": 0, "byteLength": 0}])
    assert refused(d.view, 0, "w") == "bufferView 0: 'byteLength' must be a whole number >= 1, not 0"
