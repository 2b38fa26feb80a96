"""Runs inside Blender's Python (the ``bpy`` module): import a BVH with Blender's own BVH
importer and export it with Blender's own FBX exporter, as a user would.

Usage: ``PYTHON_WITH_BPY tests/blender_bvh_to_fbx.py IN.bvh OUT.fbx [UP]``

The BVH is imported at scale 1 (its units become Blender metres), the scene's frame rate
set from the file's frame time (Blender keeps 120 fps with ``fps_base`` 0.999996 for
CMU's 0.0083333 s). The export bakes every frame with curve simplification off
(``bake_anim_simplify_factor=0``), without leaf bones, ``UP`` (``Y`` by default, or ``Z``)
as the file's up axis; Blender writes its metres as centimetres (its armature scaled by 100).
Prints Blender's version and the frame rate.
"""

from __future__ import annotations

import sys

import bpy


def main(argv: list[str]) -> None:
    source, output = argv[0], argv[1]
    up = argv[2] if len(argv) > 2 else "Y"
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_anim.bvh(filepath=source, global_scale=1.0, update_scene_fps=True, update_scene_duration=True)
    scene = bpy.context.scene
    bpy.ops.export_scene.fbx(
        filepath=output,
        bake_anim=True,
        bake_anim_simplify_factor=0.0,
        add_leaf_bones=False,
        axis_up=up,
        axis_forward="-Z" if up == "Y" else "-Y",  # Z up: Blender's own axes
    )
    print(f"blender {bpy.app.version_string} fps {scene.render.fps} fps_base {scene.render.fps_base}")


if __name__ == "__main__":
    main(sys.argv[1:])
