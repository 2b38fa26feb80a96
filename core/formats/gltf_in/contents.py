"""What a glTF file holds, for ``gmr info``: its skins and animations (names, sizes)."""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.errors import read_input
from gmr_studio.core.formats.gltf_in.container import open_gltf


def gltf_contents(path: str | Path, data: bytes | None = None) -> dict:
    """``{"skins": [{"index", "name", "joints"}], "animations": [{"index", "name",
    "channels", "interpolations"}]}`` (JSON-ready)."""
    doc = open_gltf(path, read_input(path, data))
    skins = [
        {"index": i, "name": str(s.get("name", "")), "joints": len(s.get("joints") or [])}
        for i, s in enumerate(doc.items("skins"))
    ]
    animations = []
    for i, animation in enumerate(doc.items("animations")):
        samplers = animation.get("samplers") if isinstance(animation.get("samplers"), list) else []
        kinds = sorted({str(s.get("interpolation", "LINEAR")) for s in samplers if isinstance(s, dict)})
        channels = animation.get("channels") if isinstance(animation.get("channels"), list) else []
        animations.append(
            {"index": i, "name": str(animation.get("name", "")), "channels": len(channels), "interpolations": kinds}
        )
    return {"skins": skins, "animations": animations}


def contents_text(contents: dict) -> list[str]:
    """Lines for ``gmr info``: one per skin and one per animation."""
    lines = []
    for skin in contents["skins"]:
        lines.append(f"skin:       {skin['index']} '{skin['name']}', {skin['joints']} joints (--skin)")
    for anim in contents["animations"]:
        lines.append(
            f"animation:  {anim['index']} '{anim['name']}', {anim['channels']} channels, "
            f"{'/'.join(anim['interpolations']) or '-'} (--animation)"
        )
    return lines
