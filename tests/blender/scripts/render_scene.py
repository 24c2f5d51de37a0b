"""Render a test scene with GRIDWALK (or another engine) to an uncompressed EXR.

usage: <python with bpy> render_scene.py SCENE OUT_DIR ENGINE [key=json ...]
       <python with bpy> render_scene.py --batch JOBS_JSON
         (a list of such argument lists, rendered one after the other in this
         one Blender, each from a new empty file; before each job a line
         "@@render_scene job N" marks where its output starts)
keys: samples (Cycles), settings (dict of Scene.gridwalk properties),
      transparent (film_transparent, default true), core (also render the
      exported arrays with gridwalk directly -> core.npz), blend (save a .blend).
Writes OUT_DIR/<engine>.exr (multilayer: Combined, Depth, Normal) and
OUT_DIR/<engine>.json (timings, Blender version, the error Blender reported).
"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def configure(scene, engine, opts):
    scene.render.engine = engine
    scene.render.film_transparent = opts.get("transparent", True)
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):                 # Blender 5.0+
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.exr_codec = "NONE"
    settings.color_depth = "32"
    view_layer = scene.view_layers[0]
    view_layer.use_pass_z = view_layer.use_pass_normal = True
    if engine == "CYCLES":
        scene.cycles.samples = opts.get("samples", 16)
        scene.cycles.device = "CPU"
        if hasattr(scene.cycles, "use_denoising"):
            scene.cycles.use_denoising = False
    for key, value in opts.get("settings", {}).items():
        setattr(scene.gridwalk, key, value)


def core_render(bpy, out_dir, scene):
    """The core's own render of the exported arrays (no Blender in the loop)."""
    import gridwalk
    import numpy as np

    from blender_addon.export import export_scene
    from blender_addon.settings import render_settings
    kwargs, _ = export_scene(bpy.context.evaluated_depsgraph_get())
    job = gridwalk.RenderJob(gridwalk.Scene(**kwargs), render_settings(gridwalk, scene.gridwalk))
    image = job.start().wait()
    np.savez(os.path.join(out_dir, "core.npz"), rgba=image, depth=job.depth, normal=job.normal)


def flush_all():
    """Flushes Python's and C's buffered output (Blender prints through C
    stdio), so that a batch's job markers fall between the jobs' outputs."""
    import ctypes
    sys.stdout.flush()
    sys.stderr.flush()
    ctypes.CDLL(None).fflush(None)


def main(argv):
    import bpy

    import blender_addon
    import scenes

    if argv[:1] == ["--batch"]:
        with open(argv[1]) as f:
            jobs = json.load(f)
        for index, job in enumerate(jobs):
            flush_all()
            print(f"@@render_scene job {index}", flush=True)
            main(job)
        flush_all()
        return
    name, out_dir, engine, *options = argv
    opts = {k: json.loads(v) for k, v in (o.split("=", 1) for o in options)}
    if not hasattr(bpy.types.Scene, "gridwalk"):   # (a batch's jobs after the first: registered already)
        blender_addon.register()
    scenes.BUILDERS[name](**opts.get("scene", {}))
    scene = bpy.context.scene
    configure(scene, engine, opts)
    scene.render.filepath = os.path.join(out_dir, engine.lower() + ".exr")
    if opts.get("blend"):
        scene.render.filepath = "//out_"
        bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, "scene.blend"))
        return
    t0 = time.perf_counter()
    info = {"blender": list(bpy.app.version)}
    try:
        bpy.ops.render.render(write_still=True)
    except RuntimeError as exc:           # the engine reported an error
        info["error"] = str(exc)
    info["seconds"] = time.perf_counter() - t0
    if opts.get("core"):
        core_render(bpy, out_dir, scene)
    with open(os.path.join(out_dir, engine.lower() + ".json"), "w") as f:
        json.dump(info, f)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main)
