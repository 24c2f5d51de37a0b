"""Import an NFF file with File > Import > NFF, export the scene, optionally render it.

usage: <python with bpy> nff_import_dump.py FILE.nff OUT_DIR [key=json ...]
keys: render (dict of Scene.gridwalk settings: render with GRIDWALK to
      OUT_DIR/gridwalk.exr), segments (the operator's option).
Writes OUT_DIR/import.json (the operator's result or error, the objects it
made, timings, the exported records and render settings) and OUT_DIR/arrays.npz
(the exported arrays).
"""
import dataclasses
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def objects_made(bpy):
    objs = list(bpy.context.scene.objects)
    spheres = [o for o in objs if o.type == "MESH" and o.gridwalk.render_as_sphere]
    meshes = [o for o in objs if o.type == "MESH" and not o.gridwalk.render_as_sphere]
    return {
        "objects": len(objs),
        "spheres": len(spheres),
        "meshes": {o.name: {"polygons": len(o.data.polygons), "loops": len(o.data.loops),
                            "smooth": any(p.use_smooth for p in o.data.polygons),
                            "custom_normals": o.data.has_custom_normals,
                            "materials": [m.name for m in o.data.materials]} for o in meshes},
        "light_objects": [{"type": o.data.type, "energy": o.data.energy, "color": list(o.data.color),
                    "radius": o.data.shadow_soft_size,
                    "nff_intensity": list(o.data["nff_intensity"]),
                    "nff_reference_distance": o.data["nff_reference_distance"]}
                   for o in objs if o.type == "LIGHT"],
        "cameras": [o.name for o in objs if o.type == "CAMERA"],
        "scene_camera": bpy.context.scene.camera.name if bpy.context.scene.camera else None,
        "resolution": [bpy.context.scene.render.resolution_x, bpy.context.scene.render.resolution_y],
        "collections": [c.name for c in bpy.context.scene.collection.children],
    }


def export(bpy, out_dir, info):
    import numpy as np

    from blender_addon.export import export_scene
    t0 = time.perf_counter()
    kwargs, warnings = export_scene(bpy.context.evaluated_depsgraph_get())
    info["seconds_export"] = time.perf_counter() - t0
    arrays = {k: v for k, v in kwargs.items() if isinstance(v, np.ndarray)}
    np.savez(os.path.join(out_dir, "arrays.npz"), **arrays)
    info.update(has_normals=kwargs["normals"] is not None, warnings=warnings,
                materials=[dataclasses.asdict(m) for m in kwargs["materials"]],
                lights=[dataclasses.asdict(light) for light in kwargs["lights"]],
                camera=dataclasses.asdict(kwargs["camera"]), background=list(kwargs["background"]))


def render(bpy, out_dir, settings, info):
    import gridwalk

    from blender_addon.settings import render_settings
    from render_scene import configure
    scene = bpy.context.scene
    configure(scene, "GRIDWALK", {"settings": settings, "transparent": True})
    scene.render.filepath = os.path.join(out_dir, "gridwalk.exr")
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    info["seconds_render"] = time.perf_counter() - t0
    info["render_settings"] = dict(vars(render_settings(gridwalk, scene.gridwalk)))


def main(argv):
    import bpy

    import blender_addon

    path, out_dir, *options = argv
    opts = {k: json.loads(v) for k, v in (o.split("=", 1) for o in options)}
    bpy.ops.wm.read_factory_settings(use_empty=True)
    blender_addon.register()
    info = {"blender": list(bpy.app.version), "objects_before": len(bpy.context.scene.objects)}
    t0 = time.perf_counter()
    try:
        extra = {"segments": opts["segments"]} if "segments" in opts else {}
        info["result"] = sorted(bpy.ops.import_scene.gridwalk_nff(filepath=path, **extra))
    except RuntimeError as exc:                 # the operator reported an error
        info["error"] = str(exc)
    info["seconds_import"] = time.perf_counter() - t0
    info.update(objects_made(bpy))
    if "error" not in info:
        export(bpy, out_dir, info)
        if "render" in opts:
            render(bpy, out_dir, opts["render"], info)
    with open(os.path.join(out_dir, "import.json"), "w") as f:
        json.dump(info, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main)
