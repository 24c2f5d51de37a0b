"""A demo scene built by script (no download), rendered headless with GRIDWALK.

    blender -b --python blender_addon/demo.py -- demo.png [WIDTH HEIGHT]
    .venv-bpy45/bin/python blender_addon/demo.py demo.png          (bpy from PyPI)

Uses the installed Gridwalk add-on if it is enabled, else registers this
folder. Builds: a floor, Suzanne with a Subdivision modifier, a glass sphere
and a mirror sphere rendered as analytic spheres, a collection of cubes
instanced three times, a sun, an area light and a point light with a radius,
and a camera with depth of field. build_demo_scene() is also used for the
documentation screenshot.
"""
import importlib
import math
import os
import sys

if __package__ in (None, ""):    # run as a script: the repository root holds the blender_addon package
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from blender_addon.scripting import principled_material, run_main  # noqa: E402


def _register_addon():
    import bpy
    try:
        bpy.context.scene.render.engine = "GRIDWALK"
        return
    except TypeError:
        pass
    here = os.path.dirname(os.path.abspath(__file__))
    importlib.import_module(os.path.basename(here)).register()


def _add(bpy, op, material=None, sphere=False, **kwargs):
    op(**kwargs)
    obj = bpy.context.object
    if material is not None:
        obj.data.materials.append(material)
    if sphere:
        obj.gridwalk.render_as_sphere = True
    return obj


def _light(bpy, name, kind, location, rotation=(0, 0, 0), **props):
    data = bpy.data.lights.new(name, kind)
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    obj.location, obj.rotation_euler = location, rotation
    return obj


def build_demo_scene(width=640, height=360, fresh=True):
    """The demo scene; fresh=False builds into the open file (GUI), removing its objects."""
    import bpy
    if fresh:
        bpy.ops.wm.read_homefile(use_empty=True)
    else:
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
    _register_addon()
    scene = bpy.context.scene
    scene.render.engine = "GRIDWALK"
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    mesh = bpy.ops.mesh
    _add(bpy, mesh.primitive_plane_add, principled_material("Floor", (0.55, 0.55, 0.5), Roughness=0.8), size=30)
    monkey = _add(bpy, mesh.primitive_monkey_add, principled_material("Red", (0.8, 0.12, 0.08), Roughness=0.35),
                  location=(0, 0, 1.0), rotation=(0.35, 0, 0.4))
    monkey.modifiers.new("Subdivision", "SUBSURF").render_levels = 2
    monkey.modifiers["Subdivision"].levels = 2
    for poly in monkey.data.polygons:
        poly.use_smooth = True
    _add(bpy, mesh.primitive_uv_sphere_add, principled_material("Glass", (1, 1, 1), Transmission=1.0, IOR=1.5,
                                                       Roughness=0.0), sphere=True, radius=0.8, location=(2.2, -1.2, 0.8))
    _add(bpy, mesh.primitive_uv_sphere_add, principled_material("Mirror", (0.9, 0.9, 0.9), Metallic=1.0, Roughness=0.0),
         sphere=True, radius=1.0, location=(-2.6, 1.0, 1.0))
    cubes = bpy.data.collections.new("Cubes")
    scene.collection.children.link(cubes)
    blue = principled_material("Blue", (0.1, 0.25, 0.8), Roughness=0.5)
    for i in range(3):
        cube = _add(bpy, mesh.primitive_cube_add, blue, size=0.5, location=(0.7 * i, 0, 0.25))
        for coll in cube.users_collection:
            coll.objects.unlink(cube)
        cubes.objects.link(cube)
    bpy.context.view_layer.layer_collection.children["Cubes"].exclude = True
    for i, (x, y, rz) in enumerate([(-1.5, -2.5, 0.3), (1.5, 2.5, -0.5), (3.5, 1.0, 1.2)]):
        empty = bpy.data.objects.new(f"Cubes.{i}", None)
        empty.instance_type, empty.instance_collection = "COLLECTION", cubes
        empty.location, empty.rotation_euler = (x, y, 0), (0, 0, rz)
        scene.collection.objects.link(empty)
    _light(bpy, "Sun", "SUN", (0, 0, 10), (0.7, 0.1, 0.6), energy=2.5, angle=math.radians(3))
    _light(bpy, "Area", "AREA", (-3, -4, 5), (0.7, 0, -0.6), energy=600.0, shape="RECTANGLE", size=2.0, size_y=1.0)
    _light(bpy, "Point", "POINT", (3, -3, 3), energy=300.0, shadow_soft_size=0.3)
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.location, cam.rotation_euler = (0.5, -9.5, 3.6), (math.radians(74), 0, 0)
    cam.data.lens = 35
    cam.data.dof.use_dof, cam.data.dof.aperture_fstop, cam.data.dof.focus_distance = True, 4.0, 9.5
    scene.camera = cam
    world = bpy.data.worlds.new("World")
    world.color = (0.2, 0.3, 0.45)
    scene.world = world
    settings = scene.gridwalk
    settings.aa, settings.aa_samples = "JITTERED", 2
    settings.shadow, settings.shadow_samples = "AREA", 2
    settings.dof_samples, settings.glossy_samples = 2, 2
    return scene


def main(argv):
    import bpy
    out = os.path.abspath(argv[0] if argv else "demo.png")
    size = [int(v) for v in argv[1:3]] if len(argv) >= 3 else [640, 360]
    scene = build_demo_scene(*size)
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)
    print("wrote", out)


if __name__ == "__main__":
    run_main(main)
