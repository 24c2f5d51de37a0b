"""Name Blender's session temp folder, put a file in it, and leave through
scripting.run_main (os._exit, which skips Blender's own clean-up).

usage: <python with bpy> temp_folder.py OUT_DIR   (writes OUT_DIR/temp_folder.json)
"""
import json
import os


def main(out_dir):
    import bpy

    session = bpy.app.tempdir
    with open(os.path.join(session, "render_scratch.txt"), "w") as f:   # as a render's scratch files would
        f.write("scratch")
    with open(os.path.join(out_dir, "temp_folder.json"), "w") as f:
        json.dump({"session": session, "existed": os.path.isdir(session)}, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main, spread=True)
