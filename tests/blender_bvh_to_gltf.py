"""Runs inside Blender's Python (the ``bpy`` module): import a BVH with Blender's own BVH
importer and export it with Blender's own glTF exporter, as a user would.

Usage: ``PYTHON_WITH_BPY tests/blender_bvh_to_gltf.py IN.bvh OUT.glb``

The BVH is imported at scale 1 (its units become Blender metres), Y up and -Z forward (the
importer's defaults), the scene's frame rate set from the file's frame time; the export
samples every frame of the action (no keyframe reduction), Y up (the exporter's default).
Prints Blender's version and the frame rate.
"""

from __future__ import annotations

import sys

import bpy


def main(argv: list[str]) -> None:
    source, output = argv[0], argv[1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_anim.bvh(filepath=source, global_scale=1.0, update_scene_fps=True, update_scene_duration=True)
    scene = bpy.context.scene
    bpy.ops.export_scene.gltf(
        filepath=output,
        export_format="GLB",
        export_animations=True,
        export_force_sampling=True,
        export_optimize_animation_size=False,
        export_frame_range=True,
    )
    print(f"blender {bpy.app.version_string} fps {scene.render.fps / scene.render.fps_base}")


if __name__ == "__main__":
    main(sys.argv[1:])
