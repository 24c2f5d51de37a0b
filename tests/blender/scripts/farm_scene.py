"""Save a small animation for the farm tests: the showcase scene, rendered with
GRIDWALK to multilayer float EXR (Combined, Depth, Normal), the monkey turning
over frames 1-3.

usage: <blender> --python farm_scene.py -- OUT.blend [failing_frame=N]
failing_frame=N keyframes the Gridwalk memory limit to 1 MiB at frame N only,
so the render of that frame is refused (an error Blender reports for one frame).
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def main(argv):
    import bpy

    import blender_addon
    import render_scene
    import scenes

    out, *options = argv
    opts = {k: json.loads(v) for k, v in (o.split("=", 1) for o in options)}
    blender_addon.register()
    scenes.BUILDERS["showcase"](resolution=(96, 72))
    scene = bpy.context.scene
    render_scene.configure(scene, "GRIDWALK", {"transparent": False})
    scene.frame_start, scene.frame_end = 1, 3
    monkey = bpy.data.objects["Suzanne"]
    for frame, angle in ((1, 0.0), (3, 1.2)):
        monkey.rotation_euler.z = angle
        monkey.keyframe_insert("rotation_euler", index=2, frame=frame)
    failing = opts.get("failing_frame")
    if failing:
        for frame in (failing - 1, failing, failing + 1):
            scene.gridwalk.memory_limit = 1 if frame == failing else 0
            scene.gridwalk.keyframe_insert("memory_limit", frame=frame)
        for curve in scene.animation_data.action.fcurves:
            for key in curve.keyframe_points:
                key.interpolation = "CONSTANT"
    scene.frame_set(1)
    scene.render.filepath = "//ref_####"
    bpy.ops.wm.save_as_mainfile(filepath=out)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
