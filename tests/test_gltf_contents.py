"""What ``gmr info`` lists of a glTF file (core.formats.gltf_in.contents): skins and
animations with their sizes, unnamed ones, missing or malformed joints, channels and
samplers, interpolations by default."""

from __future__ import annotations

import json
from pathlib import Path

from gmr_studio.core.formats.gltf_in.contents import contents_text, gltf_contents


def _file(tmp_path: Path, **fields) -> Path:
    document = {"asset": {"version": "2.0"}, "nodes": [{}, {}], **fields}
    (tmp_path / "c.gltf").write_text(json.dumps(document))
    return tmp_path / "c.gltf"


def test_skins_and_animations_listed_with_their_sizes(tmp_path):
    path = _file(
        tmp_path,
        skins=[{"name": "body", "joints": [0, 1]}, {"joints": None}, {}],
        animations=[
            {
                "name": "walk",
                "channels": [{}, {}, {}],
                "samplers": [{"interpolation": "STEP"}, {}, 5, {"interpolation": "CUBICSPLINE"}, {}],
            },
            {"channels": {}, "samplers": {}},
        ],
    )
    contents = gltf_contents(path)
    assert contents == {
        "skins": [
            {"index": 0, "name": "body", "joints": 2},
            {"index": 1, "name": "", "joints": 0},
            {"index": 2, "name": "", "joints": 0},
        ],
        "animations": [
            {"index": 0, "name": "walk", "channels": 3, "interpolations": ["CUBICSPLINE", "LINEAR", "STEP"]},
            {"index": 1, "name": "", "channels": 0, "interpolations": []},
        ],
    }
    assert contents_text(contents) == [
        "skin:       0 'body', 2 joints (--skin)",
        "skin:       1 '', 0 joints (--skin)",
        "skin:       2 '', 0 joints (--skin)",
        "animation:  0 'walk', 3 channels, CUBICSPLINE/LINEAR/STEP (--animation)",
        "animation:  1 '', 0 channels, - (--animation)",
    ]


def test_a_file_without_skins_or_animations_lists_nothing_and_bytes_in_hand_are_read(tmp_path):
    path = _file(tmp_path)
    assert gltf_contents(path) == {"skins": [], "animations": []}
    assert contents_text(gltf_contents(path)) == []
    data = _file(tmp_path, skins=[{"joints": [1]}]).read_bytes()
    assert gltf_contents(tmp_path / "elsewhere.gltf", data)["skins"] == [{"index": 0, "name": "", "joints": 1}]
