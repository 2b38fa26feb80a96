"""Runs inside Blender's Python (the ``bpy`` module): import a glTF file with Blender's own
glTF importer and write every node's world position at every keyframe as JSON.

Usage: ``PYTHON_WITH_BPY tests/blender_gltf_positions.py IN.glb OUT.json FRAMES FRAME_TIME``

The scene's frame rate is set to the motion's (rounded) before the import, so keyframe
``f`` sits at Blender frame ``time_f * fps`` (the importer's mapping, ``time_f`` as stored:
float32); each is evaluated there (integer frame plus subframe). Positions are Blender's
world coordinates (Z up: the importer maps glTF's ``(x, y, z)`` to ``(x, -z, y)``). Nodes
imported as objects (empties) give ``matrix_world``'s translation; nodes that became bones
of an armature (a skinned file) give the pose bone's head in world space.

Output: ``{"blender": version, "fps": fps, "frames": [...], "positions": {name: [[x, y, z], ...]}}``.
"""

from __future__ import annotations

import json
import sys

import bpy
import numpy as np


def main(argv: list[str]) -> None:
    source, output, n_frames, frame_time = argv[0], argv[1], int(argv[2]), float(argv[3])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    fps = max(1, round(1 / frame_time))
    scene.render.fps = fps
    scene.render.fps_base = 1.0
    bpy.ops.import_scene.gltf(filepath=source)
    keys = (np.arange(n_frames) * frame_time).astype(np.float32).astype(np.float64) * fps
    empties = [o for o in scene.objects if o.type == "EMPTY"]
    armatures = [o for o in scene.objects if o.type == "ARMATURE"]
    positions: dict[str, list[list[float]]] = {o.name: [] for o in empties}
    for armature in armatures:
        positions.update({bone.name: [] for bone in armature.pose.bones})
    for key in keys:
        whole = int(np.floor(key))
        scene.frame_set(whole, subframe=float(key - whole))
        for o in empties:
            positions[o.name].append(list(o.matrix_world.translation))
        for armature in armatures:
            for bone in armature.pose.bones:
                positions[bone.name].append(list(armature.matrix_world @ bone.head))
    result = {"blender": bpy.app.version_string, "fps": fps, "frames": keys.tolist(), "positions": positions}
    with open(output, "w", encoding="utf-8") as handle:
        json.dump(result, handle)


if __name__ == "__main__":
    main(sys.argv[1:])
