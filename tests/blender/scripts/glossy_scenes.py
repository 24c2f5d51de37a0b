"""Scenes about glossy surfaces (render_scene.py builds them by name)."""
import math

import bpy

from blender_addon.scripting import principled_material
from scenes import add_light, cube_object, link, plain_world, reset, shader_material, uv_sphere_object

ROUGH_METALS = (0.2, 0.35, 0.5, 0.8)     # left to right


def sphere_row(name, roughnesses, color, **inputs):
    """Spheres of radius 0.8 at x = -3, -1, 1, 3 (y = z = 0), a Principled BSDF of the colour, the
    inputs and each of the roughnesses, left to right."""
    for i, roughness in enumerate(roughnesses):
        sphere = link(uv_sphere_object(f"{name}{roughness}", 0.8, segments=64, rings=32))
        sphere.location = (-3.0 + 2.0 * i, 0.0, 0.0)
        sphere.data.materials.append(principled_material(f"{name}{roughness}", color, Roughness=roughness, **inputs))


def row_view(resolution):
    """A fresh scene of `resolution` whose camera looks along +y at the row of spheres (sphere_row)
    orthographically, 8 units wide."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0.0, -10.0, 0.0), (math.radians(90), 0.0, 0.0)
    scene.camera.data.type, scene.camera.data.ortho_scale = "ORTHO", 8.0
    return scene


def rough_metal_scene(resolution=(160, 40), lit="sun"):
    """A row of copper-coloured metal spheres (Principled Metallic 1, the Blender's default
    distribution: Multiscatter GGX from 4.0, GGX before) of the ROUGH_METALS roughnesses, seen
    head on by an orthographic camera 8 units wide: lit "sun" (a sun 0.05 radians wide from the
    upper left, a black world) or "world" (a grey world of 0.5, no lamp)."""
    row_view(resolution)
    sphere_row("Metal", ROUGH_METALS, (0.9, 0.6, 0.3), Metallic=1.0)
    if lit == "sun":
        plain_world("Black", (0.0, 0.0, 0.0))
        add_light("Sun", "SUN", (0, -5, 5), (math.radians(60), 0, math.radians(-30)), energy=2.0, angle=0.05)
    else:
        plain_world("Grey", (0.5, 0.5, 0.5))
    bpy.context.view_layer.update()
    return {}


DIELECTRICS = (0.0, 0.2, 0.5, 0.8)       # left to right


def dielectric_scene(resolution=(160, 40), lit="world"):
    """Dark grey (0.05) dielectric spheres (Principled Metallic 0, the default IOR and specular) of
    the DIELECTRICS roughnesses, seen head on by an orthographic camera 8 units wide: lit "world"
    (a grey world of 0.5, no lamp: all but the diffuse is the world's reflection, bright at the
    rims) or "floor" (the spheres on a black dielectric floor of roughness 0.1 that reflects
    them, a white backdrop lit by a sun, a black world; the camera looks down 15 degrees, the
    image half as high as wide)."""
    scene = row_view(resolution)
    sphere_row("Dielectric", DIELECTRICS, (0.05, 0.05, 0.05))
    if lit == "world":
        plain_world("Grey", (0.5, 0.5, 0.5))
    else:
        floor = link(cube_object("Floor", 1.0))
        floor.scale, floor.location = (12.0, 12.0, 0.01), (0.0, 0.0, -0.81)
        floor.data.materials.append(principled_material("Floor", (0.0, 0.0, 0.0), Roughness=0.1))
        panel = link(cube_object("Backdrop", 1.0))
        panel.scale, panel.location = (12.0, 0.01, 6.0), (0.0, 3.0, 0.0)
        panel.data.materials.append(principled_material("Backdrop", (0.8, 0.8, 0.8), Roughness=1.0))
        plain_world("Black", (0.0, 0.0, 0.0))
        add_light("Sun", "SUN", (0, -5, 5), (math.radians(50), 0, math.radians(-20)), energy=3.0, angle=0.05)
        # (looking down by 15 degrees: the floor's lower half of the image holds the reflections)
        scene.camera.location, scene.camera.rotation_euler = (0.0, -10.0, 2.68), (math.radians(75), 0.0, 0.0)
        scene.render.resolution_y = resolution[0] // 2
    bpy.context.view_layer.update()
    return {}


def panel_floor_scene(resolution=(96, 72), floor="metal"):
    """A small Emission panel (0.3 x 0.3, strength 60, facing down) 1.5 above a 40 x 40 floor of
    Roughness 0.3: "metal" (Principled Metallic 1, light grey) or "dielectric" (Metallic 0,
    grey); no lamps, a black world. The camera looks down 20 degrees at where the floor mirrors
    the panel: its highlight is the panel seen through the floor's GGX lobe. floor "lamp": a
    1 x 1 m area light (200 W) in the panel's place over the metal at Roughness 0.15, no panel:
    the lamp's reflection with GGX's glow around it."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0.0, -3.0, 1.5), (math.radians(70), 0.0, 0.0)
    ground = link(cube_object("Floor", 1.0))
    ground.scale, ground.location = (40.0, 40.0, 0.01), (0.0, 0.0, -0.005)
    metal = floor in ("metal", "lamp")
    colour = (0.9, 0.9, 0.9) if metal else (0.3, 0.3, 0.3)
    ground.data.materials.append(principled_material("Floor", colour, Roughness=0.15 if floor == "lamp" else 0.3,
                                                     Metallic=1.0 if metal else 0.0))
    if floor == "lamp":
        add_light("Lamp", "AREA", (0.0, 2.0, 1.5), (0.0, 0.0, 0.0), shape="SQUARE", size=1.0, energy=200.0)
        plain_world("Black", (0.0, 0.0, 0.0))
        bpy.context.view_layer.update()
        return {}
    mesh = bpy.data.meshes.new("Panel")
    h = 0.15
    mesh.from_pydata([(-h, -h, 0.0), (h, -h, 0.0), (h, h, 0.0), (-h, h, 0.0)], [], [(0, 3, 2, 1)])
    mesh.update()
    panel = link(bpy.data.objects.new("Panel", mesh))
    panel.location = (0.0, 2.0, 1.5)
    panel.data.materials.append(shader_material("Panel", "ShaderNodeEmission", [("Strength", 60.0)]))
    plain_world("Black", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


# The shader mixes of shader_mix_scene, left to right (blender_addon/export/shader_mix.py).
SHADER_MIXES = ("constant", "fresnel", "layer_weight", "emission")


def _mix_material(kind):
    """A Mix Shader of a Diffuse BSDF and a Glossy BSDF: by Fac 0.3 (a red diffuse, a light blue
    glossy of roughness 0.3), by a Fresnel node of IOR 1.5 (blue, white glossy of roughness 0.2)
    or a Layer Weight's Fresnel of Blend 0.3 (green, roughness 0.1); or an Add Shader of a grey
    diffuse and an orange Emission of strength 0.5."""
    mat = bpy.data.materials.new(f"Mix_{kind}")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.remove(nodes["Principled BSDF"])
    out = nodes["Material Output"].inputs["Surface"]
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    if kind == "emission":
        diffuse.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
        glow = nodes.new("ShaderNodeEmission")
        glow.inputs["Color"].default_value, glow.inputs["Strength"].default_value = (1.0, 0.5, 0.2, 1.0), 0.5
        add = nodes.new("ShaderNodeAddShader")
        links.new(diffuse.outputs[0], add.inputs[0])
        links.new(glow.outputs[0], add.inputs[1])
        links.new(add.outputs[0], out)
        return mat
    color, gloss, roughness = {"constant": ((0.8, 0.2, 0.1), (0.6, 0.8, 1.0), 0.3),
                               "fresnel": ((0.1, 0.3, 0.8), (1.0, 1.0, 1.0), 0.2),
                               "layer_weight": ((0.2, 0.7, 0.2), (1.0, 1.0, 1.0), 0.1)}[kind]
    diffuse.inputs["Color"].default_value = (*color, 1.0)
    glossy = nodes.new("ShaderNodeBsdfGlossy")
    glossy.inputs["Color"].default_value = (*gloss, 1.0)
    glossy.inputs["Roughness"].default_value = roughness
    mix = nodes.new("ShaderNodeMixShader")
    if kind == "constant":
        mix.inputs[0].default_value = 0.3
    elif kind == "fresnel":
        fresnel = nodes.new("ShaderNodeFresnel")
        fresnel.inputs["IOR"].default_value = 1.5
        links.new(fresnel.outputs["Fac"], mix.inputs[0])
    else:
        weight = nodes.new("ShaderNodeLayerWeight")
        weight.inputs["Blend"].default_value = 0.3
        links.new(weight.outputs["Fresnel"], mix.inputs[0])
    links.new(diffuse.outputs[0], mix.inputs[1])
    links.new(glossy.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], out)
    return mat


def shader_mix_scene(resolution=(160, 40), lit="sun"):
    """Spheres of the SHADER_MIXES materials in a row, seen head on by an orthographic camera 8
    units wide: lit "sun" (as rough_metal_scene's, a dark grey world) or "world" (a grey world of
    0.5, no lamp)."""
    row_view(resolution)
    for i, kind in enumerate(SHADER_MIXES):
        sphere = link(uv_sphere_object(f"Mix_{kind}", 0.8, segments=64, rings=32))
        sphere.location = (-3.0 + 2.0 * i, 0.0, 0.0)
        sphere.data.materials.append(_mix_material(kind))
    if lit == "sun":
        plain_world("Dark", (0.05, 0.05, 0.05))
        add_light("Sun", "SUN", (0, -5, 5), (math.radians(60), 0, math.radians(-30)), energy=2.0, angle=0.05)
    else:
        plain_world("Grey", (0.5, 0.5, 0.5))
    bpy.context.view_layer.update()
    return {}
