"""Passes are written with their tiles: cancel a render once some tiles are
in, and the Depth, Normal and Denoising passes of those tiles are there.

usage: <python with bpy> tile_passes.py OUT_DIR
Writes OUT_DIR/partial.exr (multilayer) from a render cancelled about 0.2 s
after its first tile was written, and OUT_DIR/info.json.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def main(argv):
    import bpy

    import blender_addon
    import scenes
    from blender_addon import streaming
    from render_scene import configure

    out_dir = argv[0]
    blender_addon.register()
    scenes.BUILDERS["showcase"](resolution=(128, 96))
    scene = bpy.context.scene
    configure(scene, "GRIDWALK", {"settings": {"tile_size": 16, "threads": 1, "aa": "JITTERED", "aa_samples": 10,
                                               "denoising_data": True}})
    scene.render.filepath = os.path.join(out_dir, "partial.exr")
    polls = {"n": 0}
    real = streaming.break_requested

    def break_requested(engine):            # cancel 10 checks (~0.2 s) after the first tile was written
        writer = getattr(engine, "writer", None)
        if writer is not None and writer.written:
            polls["n"] += 1
        return polls["n"] >= 10

    streaming.break_requested = break_requested
    try:
        bpy.ops.render.render(write_still=True)
    finally:
        streaming.break_requested = real
    with open(os.path.join(out_dir, "info.json"), "w") as f:
        json.dump({"polls": polls["n"]}, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
