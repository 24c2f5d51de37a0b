"""Install the add-on zip the way a user does, enable it, render a scene.

usage: <python with bpy> install_zip.py ZIP OUT_DIR
   or: blender -b --factory-startup --python install_zip.py -- ZIP OUT_DIR
Blender 4.2+: installed as an extension (Blender installs the bundled wheel).
Blender 3.4 - 4.1: installed as a legacy add-on (the add-on unpacks the wheel).
Writes OUT_DIR/install.json and OUT_DIR/gridwalk.exr.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def install(bpy, zip_path):
    if bpy.app.version >= (4, 2, 0):
        bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                                 enable_on_install=True)
        return "bl_ext.user_default.gridwalk"
    bpy.ops.preferences.addon_install(filepath=zip_path)
    bpy.ops.preferences.addon_enable(module="gridwalk_blender")
    return "gridwalk_blender"


def main(zip_path, out_dir):
    import bpy
    import addon_utils

    import scenes
    scenes.reset(resolution=(96, 72))       # (resetting after the install would disable it)
    module = install(bpy, zip_path)
    import gridwalk
    scene = bpy.context.scene
    engines = [getattr(c, "bl_idname", "") for c in bpy.types.RenderEngine.__subclasses__()]
    info = {"module": module, "enabled": addon_utils.check(module)[1],
            "gridwalk_file": gridwalk.__file__, "blender": list(bpy.app.version),
            "engine_registered": "GRIDWALK" in engines}
    scenes.showcase_scene(fresh=False)
    scene.render.engine = "GRIDWALK"
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format, settings.exr_codec, settings.color_depth = "OPEN_EXR_MULTILAYER", "NONE", "32"
    scene.render.filepath = os.path.join(out_dir, "gridwalk.exr")
    bpy.ops.render.render(write_still=True)
    with open(os.path.join(out_dir, "install.json"), "w") as f:
        json.dump(info, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    # The repository root, for the script runner only: the add-on itself and
    # gridwalk come from the installed zip (the environment has no PYTHONPATH).
    sys.path.append(os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", "..")))
    from blender_addon.scripting import run_main as run
    run(main, spread=True)
