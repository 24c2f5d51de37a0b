"""Object ray visibility from GRIDWALK and from Cycles on the same scene.

usage: <python with bpy> ray_visibility.py OUT_DIR
Under a sun, on a grey floor, before a mirror: a red cube hidden from the
camera ("Ghost": its shadow and its reflection stay), a red cube that casts no
shadow ("Shadowless"), and a blue sphere hidden from glossy rays ("Unreflected":
seen, and its shadow, but not in the mirror). Writes gridwalk.exr, cycles.exr
and info.json.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def main(argv):
    import bpy

    import blender_addon
    from scenes import both_engines, render_exr, shader_material

    out_dir = argv[0]
    blender_addon.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    grey = shader_material("Grey", "ShaderNodeBsdfDiffuse", [("Color", (0.5, 0.5, 0.5, 1.0))])
    red = shader_material("Red", "ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.05, 0.05, 1.0))])
    blue = shader_material("Blue", "ShaderNodeBsdfDiffuse", [("Color", (0.05, 0.05, 0.8, 1.0))])
    mirror = shader_material("Mirror", "ShaderNodeBsdfGlossy", [("Color", (0.9, 0.9, 0.9, 1.0)), ("Roughness", 0.0)])
    bpy.ops.mesh.primitive_plane_add(size=30)
    bpy.context.object.data.materials.append(grey)
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.0, 2.5, 1.8), rotation=(math.radians(90), 0.0, 0.0))
    bpy.context.object.scale = (10.0, 3.2, 1.0)
    bpy.context.object.data.materials.append(mirror)
    for name, location, material, flag in (("Ghost", (-2.4, 0.0, 0.7), red, "visible_camera"),
                                           ("Shadowless", (0.0, 0.0, 0.7), red, "visible_shadow")):
        bpy.ops.mesh.primitive_cube_add(size=1.4, location=location)
        obj = bpy.context.object
        obj.name = name
        obj.data.materials.append(material)
        setattr(obj, flag, False)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.7, location=(2.4, 0.0, 0.7), segments=48, ring_count=24)
    sphere = bpy.context.object
    sphere.name, sphere.visible_glossy = "Unreflected", False
    sphere.data.materials.append(blue)
    bpy.ops.object.shade_smooth()
    bpy.ops.object.camera_add(location=(0.0, -9.0, 4.0), rotation=(math.radians(72), 0.0, 0.0))
    scene.camera = bpy.context.object
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(35), 0.0, math.radians(-30)))
    bpy.context.object.data.energy = 3.0
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 128, 80, 100
    scene.render.film_transparent = False
    both_engines(scene, aa_samples=3, cycles_samples=32)
    scene.cycles.max_bounces = 4
    for engine in ("GRIDWALK", "CYCLES"):
        scene.render.engine = engine
        render_exr(scene, os.path.join(out_dir, f"{engine.lower()}.exr"))
    with open(os.path.join(out_dir, "info.json"), "w") as f:
        json.dump({"blender": list(bpy.app.version)}, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
