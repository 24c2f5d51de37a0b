"""PLY through Blender's own importer and exporter (bpy.ops.wm.ply_import / ply_export).

usage: <python with bpy> ply_blender.py import FILE.ply OUT_DIR VIEW.json
         import FILE.ply, add the camera and lights of VIEW.json (gridwalk
         Camera / Light fields, "settings"), render with GRIDWALK ->
         OUT_DIR/gridwalk.exr and OUT_DIR/render_settings.json
       <python with bpy> ply_blender.py export OUT_DIR
         a smooth Suzanne with a Subdivision modifier, written by Blender to
         OUT_DIR/suzanne.ply
Both also export the scene with the add-on's exporter -> OUT_DIR/arrays.npz.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def export_arrays(bpy, out_dir):
    import numpy as np

    from blender_addon.export import export_scene
    kwargs, _ = export_scene(bpy.context.evaluated_depsgraph_get())
    np.savez(os.path.join(out_dir, "arrays.npz"),
             **{k: v for k, v in kwargs.items() if isinstance(v, np.ndarray)})


def import_and_render(bpy, path, out_dir, view_path):
    import numpy as np
    from gridwalk.model import Camera, Light

    from blender_addon.nff_import import add_camera, add_lights
    from render_scene import configure
    bpy.ops.wm.read_factory_settings(use_empty=True)
    import blender_addon
    blender_addon.register()
    bpy.ops.wm.ply_import(filepath=str(path), forward_axis="Y", up_axis="Z")
    with open(view_path) as f:
        view = json.load(f)
    camera, lights = Camera(**view["camera"]), [Light(**light) for light in view["lights"]]
    scene = bpy.context.scene
    add_camera(scene, scene.collection, "ply", camera)
    target = np.asarray(camera.target)
    add_lights(scene.collection, "ply", lights,
               [float(np.linalg.norm(np.asarray(light.position) - target)) for light in lights])
    configure(scene, "GRIDWALK", {"settings": view["settings"], "transparent": True})
    scene.render.filepath = os.path.join(out_dir, "gridwalk.exr")
    bpy.ops.render.render(write_still=True)
    export_arrays(bpy, out_dir)
    import gridwalk

    from blender_addon.settings import render_settings
    with open(os.path.join(out_dir, "render_settings.json"), "w") as f:
        json.dump(dict(vars(render_settings(gridwalk, scene.gridwalk))), f)


def suzanne_to_ply(bpy, out_dir):
    import blender_addon
    import scenes
    scenes.suzanne_scene(levels=2)
    blender_addon.register()
    bpy.ops.wm.ply_export(filepath=os.path.join(out_dir, "suzanne.ply"), apply_modifiers=True,
                          export_triangulated_mesh=False, ascii_format=False)
    export_arrays(bpy, out_dir)


def main(argv):
    import bpy
    if argv[0] == "import":
        import_and_render(bpy, *argv[1:])
    else:
        suzanne_to_ply(bpy, argv[1])


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main)
