"""Render every kind of camera (scenes.CAMERA_KINDS) with GRIDWALK and Cycles.

usage: <python with bpy> camera_kinds.py OUT_DIR [KIND ...]
Writes OUT_DIR/<kind>_gridwalk.exr and <kind>_cycles.exr (film transparent:
alpha is coverage; the panoramas of scenes.PANORAMA_KINDS as multilayer EXRs
with their Depth, which tells the opaque pixels a fisheye leaves without a ray,
at Blender's miss depth, from the objects). Both sample pixel centres (GRIDWALK: aa=center; Cycles:
a 0.01 px filter), so the alphas compare the cameras' geometry alone.

Also writes OUT_DIR/kinds.json (the Blender's version and the kinds it
has: Central Cylindrical came in 4.3) and OUT_DIR/rays.json: for each non-panoramic kind, how far the rays
of the exported camera (export/camera.py, from the lens and sensor
settings) lie from the rays of the same camera rebuilt from Blender's own
matrices (export/viewport_camera.py, as the viewport does: matrix_world
inverted and calc_matrix_camera).
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def segment_distance(a, b, px, py) -> float:
    """Largest distance between the clipped ray segments of cameras a and b
    through pixel positions (px, py), relative to the segment length."""
    import numpy as np
    worst = 0.0
    oa, da, ta0, ta1 = (np.asarray(x, np.float64) for x in a.rays(px, py))
    ob, db, tb0, tb1 = (np.asarray(x, np.float64) for x in b.rays(px, py))
    worst = max(worst, float(np.abs(da - db).max()))
    for ta, tb in ((ta0, tb0), (ta1, tb1)):
        pa, pb = oa + da * ta[:, None], ob + db * tb[:, None]
        scale = np.linalg.norm(pa - oa, axis=1) + 1.0
        worst = max(worst, float((np.linalg.norm(pa - pb, axis=1) / scale).max()))
    return worst


def compare_rays(bpy, scene):
    import numpy as np

    from blender_addon.export._matrix import to_numpy
    from blender_addon.export.camera import convert_camera, pixel_aspect, resolution
    from blender_addon.export.viewport_camera import view_camera
    depsgraph = bpy.context.evaluated_depsgraph_get()
    cam = scene.camera.evaluated_get(depsgraph)
    width, height = resolution(scene.render)
    exported = convert_camera(cam, scene.render)
    projection = cam.calc_matrix_camera(depsgraph, x=width, y=height, scale_x=scene.render.pixel_aspect_x,
                                        scale_y=scene.render.pixel_aspect_y)
    # the view matrix in double: Blender's own inverse is float32, 1 unit off at 1e7
    rebuilt = view_camera(np.linalg.inv(to_numpy(cam.matrix_world)), projection, width, height,
                          clip=(cam.data.clip_start, cam.data.clip_end))
    gx, gy = np.meshgrid(np.linspace(0, width, 9), np.linspace(0, height, 7))
    assert abs(rebuilt.pixel_aspect - pixel_aspect(scene.render)) < 1e-5, rebuilt
    return segment_distance(exported, rebuilt, gx.reshape(-1), gy.reshape(-1))


def single_layer(settings):
    """An RGBA EXR: Blender 5.0 fails to write a multilayer EXR with non-square
    pixels ("Conflicting attributes ... pixelAspectRatio")."""
    if hasattr(settings, "media_type"):
        settings.media_type = "IMAGE"
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"


def main(argv):
    import bpy

    import blender_addon
    import scenes
    from render_scene import configure

    out_dir, *kinds = argv
    blender_addon.register()
    rays, rendered = {}, []
    for kind in kinds or scenes.CAMERA_KINDS:
        if not scenes.has_panorama(kind):
            continue
        rendered.append(kind)
        base = kind.removeprefix("mirrored_")       # (a mirrored panorama renders as its panorama does)
        for engine in ("GRIDWALK", "CYCLES"):
            scenes.camera_kinds_scene(kind)
            scene = bpy.context.scene
            configure(scene, engine, {"samples": 4, "settings": {"aa": "CENTER"}})
            if base not in scenes.PANORAMA_KINDS:      # (a panorama's keeps its Depth: no-ray pixels lie at 1e10)
                single_layer(scene.render.image_settings)
            if engine == "CYCLES":
                scene.cycles.filter_width = 0.01
            scene.render.filepath = os.path.join(out_dir, f"{kind}_{engine.lower()}.exr")
            bpy.ops.render.render(write_still=True)
        if base != "panoramic" and base not in scenes.PANORAMA_KINDS:
            rays[kind] = compare_rays(bpy, bpy.context.scene)
        print("camera_kinds:", kind, "done", flush=True)
    with open(os.path.join(out_dir, "rays.json"), "w") as f:
        json.dump(rays, f)
    with open(os.path.join(out_dir, "kinds.json"), "w") as f:
        json.dump({"blender": list(bpy.app.version), "rendered": rendered}, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
