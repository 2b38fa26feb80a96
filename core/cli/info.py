"""``gmr info FILE [--json]``: what a motion file holds, including its dummy joints
(zero-offset joints with children that GMR does not need; :mod:`core.edits.dummies`)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from gmr_studio.core.cli.markers import add_marker_options, marker_options
from gmr_studio.core.cli.reading import add_reading_options, read_with_args
from gmr_studio.core.edits.dummies import find_dummies
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.up_axis import up_axis_of
from gmr_studio.core.timebase.clock import duration_of, nominal_rate, rate_text

#: what ``info`` calls each format, by suffix
FORMAT_NAMES = {
    ".bvh": "BVH",
    ".gmr": "GMR",
    ".amc": "AMC (Acclaim, with its ASF)",
    ".asf": "ASF (Acclaim skeleton)",
    ".npz": "AMASS/SMPL (with its body model)",
    ".glb": "glTF 2.0 binary",
    ".gltf": "glTF 2.0",
    ".vrma": "VRM animation (glTF 2.0 binary)",
    ".fbx": "FBX (read only)",
}


def register(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "file", help="a .bvh, .gmr, .amc, .asf, AMASS .npz, glTF or FBX file, or a .c3d or .trc marker file"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    add_marker_options(parser)
    add_reading_options(parser)
    parser.set_defaults(run=run)


def channel_names(motion: Motion, j: int) -> list[str]:
    """The channels joint j has, in the order a writer puts them."""
    names = ["Xposition", "Yposition", "Zposition"] if motion.has_translation[j] else []
    return names + [f"{axis}rotation" for axis in motion.rotation_orders[j]]


def describe(motion: Motion, path: str) -> dict:
    """A JSON-ready description of a motion."""

    def name(index: int) -> str | None:
        return motion.names[index] if index >= 0 else None

    return {
        "path": path,
        "format": FORMAT_NAMES.get(Path(path).suffix.lower(), "BVH" if motion.convention == "post" else "GMR"),
        "convention": f"{motion.convention}-rotation",
        "frames": motion.n_frames,
        "frame_time": motion.frame_time,
        "frame_rate": motion.frame_rate,
        "nominal_rate": nominal_rate(motion.frame_time),
        "duration": duration_of(motion),
        "units": None if motion.facts.unit is None else motion.facts.unit.name,
        "metres_per_unit": None if motion.facts.unit is None else motion.facts.unit.metres,
        "up_axis": up_axis_of(motion),
        "up_axis_stated": motion.facts.up_axis is not None,
        "source_units": None if motion.facts.source_unit is None else motion.facts.source_unit.name,
        "size": motion.size,
        "roots": [motion.names[r] for r in motion.roots],
        "soft_links": {motion.names[j]: motion.names[s] for j, s in enumerate(motion.soft_parents) if s >= 0},
        "dummies": [motion.names[j] for j in find_dummies(motion)],
        "joints": [
            {
                "name": motion.names[j],
                "parent": name(int(motion.parents[j])),
                "soft_parent": name(int(motion.soft_parents[j])),
                "offset": [float(v) for v in motion.offsets[j]],
                "channels": channel_names(motion, j),
            }
            for j in range(motion.n_joints)
        ],
        "comments": list(motion.comments),
    }


def format_text(info: dict) -> str:
    joints = info["joints"]
    roots = info["roots"]
    links = info["soft_links"]
    lines = [
        f"file:       {info['path']}",
        f"format:     {info['format']} ({info['convention']})",
        f"frames:     {info['frames']} at {rate_text(info['frame_time'])} Hz "
        f"(frame time {info['frame_time']:.6g} s, {info['frame_rate']:.6g} Hz exactly; "
        f"duration {info['duration']:.3f} s: frames x frame time)",
        f"joints:     {len(joints)}",
        f"roots:      {len(roots)} ({', '.join(roots)})",
        "soft links: " + (", ".join(f"{a} -> {b}" for a, b in links.items()) if links else "none"),
        f"dummies:    {len(info['dummies'])}"
        + (f" ({', '.join(info['dummies'])}; gmr convert --remove-dummies folds them)" if info["dummies"] else ""),
        f"size:       {info['size']:.6g} (the figure's largest extent in one frame)",
        f"units:      {info['units'] or 'not stated'}"
        + (f" (data from {info['source_units']})" if info["source_units"] else ""),
        f"up axis:    {info['up_axis']} "
        + ("(stated)" if info["up_axis_stated"] else "(not stated: the axis the figure stands on)"),
    ]
    lines += [f"comment:    {c}" for c in info["comments"]]
    width = max(len(j["name"]) for j in joints)
    lines += ["", f"{'joint':<{width}}  {'parent':<{width}}  channels"]
    for j in joints:
        parent = j["parent"] or ("(root)" if j["soft_parent"] is None else f"(root, soft link {j['soft_parent']})")
        lines.append(f"{j['name']:<{width}}  {parent:<{width}}  {' '.join(j['channels']) or '-'}")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    if Path(args.file).suffix.lower() in (".c3d", ".trc"):  # marker files: core.markers.report
        from gmr_studio.core.markers import read_markers
        from gmr_studio.core.markers.report import describe_markers, markers_text

        info = describe_markers(read_markers(args.file, **marker_options(args)), args.file)
        print(json.dumps(info, indent=2) if args.json else markers_text(info))
        return 0
    info = describe(read_with_args(args.file, args), args.file)
    gltf_lines = []
    if Path(args.file).suffix.lower() in (".glb", ".gltf", ".vrma"):  # its skins and animations
        from gmr_studio.core.formats.gltf_in.contents import contents_text, gltf_contents

        info["gltf"] = gltf_contents(args.file)
        gltf_lines = contents_text(info["gltf"])
    if Path(args.file).suffix.lower() == ".fbx":  # its takes and what it holds besides the skeleton
        from gmr_studio.core.formats.fbx_in.reader import contents_text as fbx_text
        from gmr_studio.core.formats.fbx_in.reader import fbx_contents

        info["fbx"] = fbx_contents(args.file)
        gltf_lines = fbx_text(info["fbx"])
    if args.json:
        json.dump(info, sys.stdout, indent=2)
        print()
    else:
        text = format_text(info).split("\n")
        print("\n".join(text[:3] + gltf_lines + text[3:]))
    return 0
