"""Scenes about glossy surfaces (render_scene.py builds them by name)."""
import math

import bpy

from blender_addon.scripting import principled_material
from scenes import add_light, link, plain_world, reset, uv_sphere_object

ROUGH_METALS = (0.2, 0.35, 0.5, 0.8)     # left to right


def rough_metal_scene(resolution=(160, 40), lit="sun"):
    """A row of copper-coloured metal spheres (Principled Metallic 1, the Blender's default
    distribution: Multiscatter GGX from 4.0, GGX before) of the ROUGH_METALS roughnesses, seen
    head on by an orthographic camera 8 units wide: lit "sun" (a sun 0.05 radians wide from the
    upper left, a black world) or "world" (a grey world of 0.5, no lamp)."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0.0, -10.0, 0.0), (math.radians(90), 0.0, 0.0)
    scene.camera.data.type, scene.camera.data.ortho_scale = "ORTHO", 8.0
    for i, roughness in enumerate(ROUGH_METALS):
        sphere = link(uv_sphere_object(f"Metal{roughness}", 0.8, segments=64, rings=32))
        sphere.location = (-3.0 + 2.0 * i, 0.0, 0.0)
        sphere.data.materials.append(principled_material(f"Metal{roughness}", (0.9, 0.6, 0.3), Metallic=1.0,
                                                         Roughness=roughness))
    if lit == "sun":
        plain_world("Black", (0.0, 0.0, 0.0))
        add_light("Sun", "SUN", (0, -5, 5), (math.radians(60), 0, math.radians(-30)), energy=2.0, angle=0.05)
    else:
        plain_world("Grey", (0.5, 0.5, 0.5))
    bpy.context.view_layer.update()
    return {}
