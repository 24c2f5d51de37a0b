"""Holdouts from GRIDWALK and from Cycles on the same scene.

usage: <python with bpy> holdout.py OUT_DIR
A floor and a mirror wall, and in front of them three holdouts: a red sphere set to
Visibility > Holdout ("HeldObject"), a cube in a collection set to Holdout in
the view layer ("InMask"), and a cube whose material is a Holdout shader
("HoldShader"). The mirror shows the sphere red (an object's holdout is for
camera rays only) and the shader's cube black. Renders each engine with the film opaque and transparent:
{gridwalk,cycles}_{opaque,transparent}.exr, and info.json (the Blender version).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def material(bpy, name, color=None, holdout=False):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    tree = m.node_tree
    if holdout:
        tree.nodes.remove(tree.nodes["Principled BSDF"])
        shader = tree.nodes.new("ShaderNodeHoldout")
        tree.links.new(shader.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    else:
        tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*color, 1.0)
    return m


def build(bpy):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    grey, red = material(bpy, "Grey", (0.5, 0.5, 0.5)), material(bpy, "Red", (0.8, 0.1, 0.1))
    bpy.ops.mesh.primitive_plane_add(size=20)
    bpy.context.object.data.materials.append(grey)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 3.0, 1.5), scale=(6.0, 0.2, 3.0))
    mirror = bpy.data.materials.new("Mirror")
    mirror.use_nodes = True
    principled = mirror.node_tree.nodes["Principled BSDF"]
    principled.inputs["Metallic"].default_value, principled.inputs["Roughness"].default_value = 1.0, 0.0
    principled.inputs["Base Color"].default_value = (0.9, 0.9, 0.9, 1.0)
    bpy.context.object.data.materials.append(mirror)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(-2.0, 0.0, 1.0), segments=48, ring_count=24)
    held = bpy.context.object
    held.name, held.is_holdout = "HeldObject", True
    held.data.materials.append(red)
    bpy.ops.object.shade_smooth()
    mask = bpy.data.collections.new("Mask")
    scene.collection.children.link(mask)
    bpy.ops.mesh.primitive_cube_add(size=1.2, location=(0.2, 0.0, 0.8))
    cube = bpy.context.object
    cube.name = "InMask"
    cube.data.materials.append(grey)
    for collection in list(cube.users_collection):
        collection.objects.unlink(cube)
    mask.objects.link(cube)
    bpy.context.view_layer.layer_collection.children["Mask"].holdout = True
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(2.2, -0.5, 0.6))
    bpy.context.object.name = "HoldShader"
    bpy.context.object.data.materials.append(material(bpy, "Hold", holdout=True))
    bpy.ops.object.camera_add(location=(0.0, -8.0, 3.0), rotation=(math.radians(75), 0.0, 0.0))
    scene.camera = bpy.context.object
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(40), 0.0, math.radians(30)))
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 120, 80, 100
    return scene


def main(argv):
    import bpy

    import blender_addon
    from scenes import both_engines, render_exr

    out_dir = argv[0]
    blender_addon.register()
    scene = build(bpy)
    both_engines(scene)
    for engine in ("GRIDWALK", "CYCLES"):
        scene.render.engine = engine
        for film in ("opaque", "transparent"):
            scene.render.film_transparent = film == "transparent"
            render_exr(scene, os.path.join(out_dir, f"{engine.lower()}_{film}.exr"))
    with open(os.path.join(out_dir, "info.json"), "w") as f:
        json.dump({"blender": list(bpy.app.version)}, f)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
