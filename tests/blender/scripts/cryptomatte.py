"""Cryptomatte passes from GRIDWALK and from Cycles on the same scene.

usage: <python with bpy> cryptomatte.py OUT_DIR
A floor ("Floor"), a cube whose top face is "Blue" and the rest "Red"
("Box"), a sphere ("Ball", "Red") parented to an empty ("Rig"), a cube with no
material ("Bare": Cycles' "default_surface") and a sphere GRIDWALK renders as
an analytic sphere ("Orb", "Blue", Render as Sphere); Cryptomatte
Object, Material and Asset at 6 levels, and the Object and Material Index
passes (objects' pass indices 1-3, Red's 4, Blue's 5). Writes gridwalk.exr and cycles.exr
(multilayer, uncompressed) and info.json (the Blender version).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def material(bpy, name, color):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*color, 1.0)
    return m


def build(bpy):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    red, blue, floor = material(bpy, "Red", (0.8, 0.1, 0.1)), material(bpy, "Blue", (0.1, 0.1, 0.8)), \
        material(bpy, "Floor", (0.5, 0.5, 0.5))
    bpy.ops.mesh.primitive_plane_add(size=12)
    bpy.context.object.name = "Floor"
    bpy.context.object.data.materials.append(floor)
    bpy.ops.mesh.primitive_cube_add(location=(-1.0, 0.0, 1.0))
    box = bpy.context.object
    box.name = "Box"
    box.data.materials.append(red)
    box.data.materials.append(blue)
    for poly in box.data.polygons:
        poly.material_index = 1 if poly.normal.z > 0.5 else 0
    bpy.ops.object.empty_add(location=(1.5, 0.0, 0.0))
    rig = bpy.context.object
    rig.name = "Rig"
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.9, location=(1.6, 0.3, 0.9), segments=48, ring_count=24)
    ball = bpy.context.object
    ball.name = "Ball"
    ball.data.materials.append(red)
    ball.parent = rig
    ball.matrix_parent_inverse = rig.matrix_world.inverted()
    bpy.ops.object.shade_smooth()
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(-2.6, -1.6, 0.4))
    bpy.context.object.name = "Bare"
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0.4, -2.2, 0.5), segments=64, ring_count=32)
    orb = bpy.context.object
    orb.name = "Orb"
    orb.data.materials.append(blue)
    orb.gridwalk.render_as_sphere = True
    bpy.ops.object.shade_smooth()
    bpy.ops.object.camera_add(location=(0.0, -7.0, 4.0), rotation=(math.radians(62), 0.0, 0.0))
    scene.camera = bpy.context.object
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(30), 0.0, math.radians(20)))
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 120, 90, 100
    layer = scene.view_layers[0]
    layer.use_pass_cryptomatte_object = layer.use_pass_cryptomatte_material = True
    layer.use_pass_cryptomatte_asset = True
    layer.pass_cryptomatte_depth = 6
    layer.use_pass_object_index = layer.use_pass_material_index = True
    for index, name in enumerate(("Floor", "Box", "Ball"), start=1):
        bpy.data.objects[name].pass_index = index
    red.pass_index, blue.pass_index = 4, 5
    return scene


def main(argv):
    import bpy

    import blender_addon
    from scenes import both_engines, render_exr

    out_dir = argv[0]
    blender_addon.register()
    scene = build(bpy)
    both_engines(scene)
    scene.render.engine = "GRIDWALK"
    render_exr(scene, os.path.join(out_dir, "gridwalk.exr"))
    scene.render.engine = "CYCLES"
    render_exr(scene, os.path.join(out_dir, "cycles.exr"))
    with open(os.path.join(out_dir, "info.json"), "w") as f:
        json.dump({"blender": list(bpy.app.version)}, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
