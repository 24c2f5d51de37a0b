"""Passes are written with their tiles: cancel a render once some tiles are
in, and the Depth, Normal and Denoising passes of those tiles are there.

usage: <python with bpy> tile_passes.py OUT_DIR
Writes OUT_DIR/partial.exr (multilayer) from a render cancelled two tiles after
the first tile holding pixels that every sample hit was written (tiles go row by
row from the top, the sky first), and OUT_DIR/info.json. (Cancelling 10 polls
after the first tile was timing: a slower render or a busy machine had no such
tile written by then.)
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
    seen = {"covered": False, "after": 0, "tiles": 0}
    real, real_write = streaming.break_requested, streaming.ResultWriter.write

    def write(writer, x, y, arrays):
        real_write(writer, x, y, arrays)
        seen["tiles"] += 1
        seen["after"] += seen["covered"]
        seen["covered"] = seen["covered"] or bool((arrays["rgba"][..., 3] > 0.999).any())

    def break_requested(engine):            # two tiles after the first with fully covered pixels
        return seen["covered"] and seen["after"] >= 2

    streaming.break_requested, streaming.ResultWriter.write = break_requested, write
    try:
        bpy.ops.render.render(write_still=True)
    finally:
        streaming.break_requested, streaming.ResultWriter.write = real, real_write
    with open(os.path.join(out_dir, "info.json"), "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
