"""Scenes about what lights look like (render_scene.py builds them by name)."""
import math

import bpy

from blender_addon.scripting import principled_material
from scenes import add_light, plain_world, reset, shader_material

# Each kind of light that a sharp mirror shows by its shape, 8 units in front of the mirror,
# facing it, behind the camera: (Blender light type, its settings).
MIRRORED_LIGHTS = {
    "rect": ("AREA", {"shape": "RECTANGLE", "size": 2.0, "size_y": 1.0, "energy": 20.0}),
    "disk": ("AREA", {"shape": "DISK", "size": 1.5, "energy": 20.0}),
    "ellipse": ("AREA", {"shape": "ELLIPSE", "size": 2.4, "size_y": 0.8, "energy": 20.0}),
    "sphere": ("POINT", {"shadow_soft_size": 0.3, "energy": 20.0}),
    "sun": ("SUN", {"angle": math.radians(10.0), "energy": 0.1}),
    "point": ("POINT", {"shadow_soft_size": 0.0, "energy": 20.0}),
    "spot": ("SPOT", {"shadow_soft_size": 0.3, "energy": 20.0, "spot_size": math.radians(60.0), "spot_blend": 0.5}),
}


def mirrored_light_scene(light="rect", roughness=0.0, resolution=(64, 48)):
    """A mirror (Principled, Metallic 1, the given Roughness) 6 units in front of the camera,
    facing it, filling the view; one light of MIRRORED_LIGHTS behind the camera, shining at
    the mirror along the view, seen only in the mirror. A black world."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0, -6, 0), (math.pi / 2, 0, 0)
    bpy.ops.mesh.primitive_plane_add(size=12.0, location=(0, 0, 0), rotation=(math.pi / 2, 0, 0))
    mirror = bpy.context.object
    mirror.data.materials.append(principled_material("Mirror", (1.0, 1.0, 1.0), Metallic=1.0, Roughness=roughness))
    kind, settings = MIRRORED_LIGHTS[light]
    add_light("Light", kind, (0.3, -8.0, 0.2), (math.pi / 2, 0, 0), **settings)
    bpy.context.view_layer.update()
    return {}



def lit_wall_scene(light="rect", resolution=(64, 48)):
    """A grey diffuse wall (Principled, Roughness 1) filling the view, lit by one light of
    MIRRORED_LIGHTS 3 units in front of it, facing it."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0, -6, 0), (math.pi / 2, 0, 0)
    bpy.ops.mesh.primitive_plane_add(size=12.0, location=(0, 0, 0), rotation=(math.pi / 2, 0, 0))
    bpy.context.object.data.materials.append(principled_material("Wall", (0.8, 0.8, 0.8), Roughness=1.0))
    kind, settings = MIRRORED_LIGHTS[light]
    add_light("Light", kind, (0.3, -3.0, 0.2), (math.pi / 2, 0, 0), **settings)
    bpy.context.view_layer.update()
    return {}


def chrome_ball_scene(resolution=(128, 96), glass=False, hide=()):
    """A chrome ball (Principled, Metallic 1, Roughness 0, rendered as a sphere; glass: Principled
    Transmission 1, IOR 1.5 instead) on a grey floor under a rectangle light in front of it and
    above, which the ball reflects; hide: the light's Ray Visibility switched off for these of
    "diffuse", "glossy", "transmission"."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0, -6, 2.0), (math.radians(75), 0, 0)
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    bpy.context.object.data.materials.append(principled_material("Floor", (0.5, 0.5, 0.5), Roughness=1.0))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0, 0, 1.0))
    ball = bpy.context.object
    ball.gridwalk.render_as_sphere = True
    bpy.ops.object.shade_smooth()
    ball.data.materials.append(
        principled_material("Glass", (1.0, 1.0, 1.0), Roughness=0.0, IOR=1.5, Transmission=1.0) if glass else
        principled_material("Chrome", (0.9, 0.9, 0.9), Metallic=1.0, Roughness=0.0))
    softbox = add_light("Softbox", "AREA", (1.5, -3.0, 4.0), (math.radians(40), 0, math.radians(25)),
                        shape="RECTANGLE", size=2.0, size_y=1.0, energy=100.0)
    for kind in hide:
        setattr(softbox, f"visible_{kind}", False)
    bpy.context.view_layer.update()
    return {}


def wide_sun_scene(angle_degrees=120.0, resolution=(48, 36)):
    """A grey diffuse floor (Diffuse BSDF 0.8) filling an orthographic view from above, under a sun
    straight down of the given angular diameter, Strength 1, in a black world."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0, 0, 5), (0, 0, 0)
    scene.camera.data.type, scene.camera.data.ortho_scale = "ORTHO", 4.0
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    bpy.context.object.data.materials.append(shader_material("Floor", "ShaderNodeBsdfDiffuse",
                                                             [("Color", (0.8, 0.8, 0.8, 1.0))]))
    add_light("Sun", "SUN", (0, 0, 10), (0, 0, 0), energy=1.0, angle=math.radians(angle_degrees))
    plain_world("Black", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}

