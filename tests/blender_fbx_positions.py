"""Runs inside Blender's Python (the ``bpy`` module): import an FBX file with Blender's own
FBX importer and write every node's world position at the frames asked for, as JSON.

Usage: ``PYTHON_WITH_BPY tests/blender_fbx_positions.py IN.fbx OUT.json TIMES_JSON``

``TIMES_JSON``: a JSON list of the file's times (seconds). Blender's importer puts the key
at FBX time ``t`` on Blender frame ``1 + t * fps``, ``fps`` the scene's integer frame rate
it sets from the file (``anim_offset`` 1 and ``scene.render.fps``: import_fbx.py), so each
time is evaluated there (whole frame plus subframe). Positions are Blender's world
coordinates, in metres and Z up (the importer converts the file's units and axes). Bones
give the pose bone's head, other nodes (empties, meshes) their object's origin.

Output: ``{"blender": version, "fps": fps, "positions": {name: [[x, y, z], ...]}}``.
"""

from __future__ import annotations

import json
import sys

import bpy


def main(argv: list[str]) -> None:
    source, output, times = argv[0], argv[1], json.loads(argv[2])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.fbx(filepath=source)
    scene = bpy.context.scene
    fps = scene.render.fps
    objects = [o for o in scene.objects if o.type != "ARMATURE"]
    armatures = [o for o in scene.objects if o.type == "ARMATURE"]
    positions: dict[str, list[list[float]]] = {o.name: [] for o in objects + armatures}
    for armature in armatures:
        positions.update({bone.name: [] for bone in armature.pose.bones})
    for time in times:
        frame = 1.0 + time * fps
        whole = int(frame // 1)
        scene.frame_set(whole, subframe=frame - whole)
        for o in objects + armatures:
            positions[o.name].append(list(o.matrix_world.translation))
        for armature in armatures:
            for bone in armature.pose.bones:
                positions[bone.name].append(list(armature.matrix_world @ bone.head))
    result = {"blender": bpy.app.version_string, "fps": fps, "positions": positions}
    with open(output, "w", encoding="utf-8") as handle:
        json.dump(result, handle)


if __name__ == "__main__":
    main(sys.argv[1:])
