"""Test scenes for materials and the world (issue 13), built with bpy.

Imported by scenes.py, whose BUILDERS list every *_scene function: render
them with render_scene.py. Images are generated or filled in memory (no files
are read), except the missing one of bad_materials_scene.
"""
import math
import os
import pathlib
import tempfile

import bpy
import numpy as np

from blender_addon.scripting import principled_material
from scenes import add_light, link, plain_world, reset, shader_material


def _plane(name, size, location=(0, 0, 0), rotation=(0, 0, 0)):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    obj = bpy.context.object
    obj.name = name
    return obj


def _image_node(mat, image, socket="Base Color", output="Color", interpolation="Linear", uv_map=None,
                extension="REPEAT"):
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation, tex.extension = image, interpolation, extension
    links.new(tex.outputs[output], nodes["Principled BSDF"].inputs[socket])
    if uv_map is not None:
        uv = nodes.new("ShaderNodeUVMap")
        uv.uv_map = uv_map
        links.new(uv.outputs["UV"], tex.inputs["Vector"])
    return tex


def _filled_image(name, pixels, float_buffer, non_color=False):
    """A packed image holding `pixels` ((h, w, 4) in [0, 1] for 8-bit, row 0 at
    the BOTTOM, Blender's order). The colour space is set first: setting it
    later reloads the image and loses the pixels."""
    h, w = pixels.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=float_buffer)
    if non_color:
        img.colorspace_settings.name = "Non-Color"
    img.pixels.foreach_set(np.ascontiguousarray(pixels, np.float32).reshape(-1))
    img.pack()
    return img


def checker_scene(resolution=(64, 48)):
    """A UV-mapped plane facing the camera with Blender's generated colour grid
    (an 8-bit sRGB image) on its Base Color, lit by a sun from the camera's side."""
    reset(resolution=tuple(resolution))
    plane = _plane("Plane", 7.0, rotation=(math.pi / 2, 0, 0))
    img = bpy.data.images.new("Grid", 256, 256)
    img.generated_type = "COLOR_GRID"
    mat = principled_material("Textured", (0.8, 0.8, 0.8), Roughness=1.0)
    _image_node(mat, img)
    plane.data.materials.append(mat)
    add_light("Sun", "SUN", (0, -5, 0), (math.pi / 2, 0, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {}


def principled_sphere_scene(resolution=(64, 48), material=True):
    """A smooth sphere alone under a point light, in a black world (direct light
    only, so Cycles and the Whitted core see the same light): a default
    Principled BSDF, or no material at all (Blender 5.0 renders that as one)."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=1.5)
    sphere = bpy.context.object
    bpy.ops.object.shade_smooth()
    if material:
        sphere.data.materials.append(principled_material("Default", (0.8, 0.8, 0.8)))
    add_light("Key", "POINT", (2, -4, 3), energy=600.0, shadow_soft_size=0.0)
    bpy.context.scene.world = None
    bpy.context.view_layer.update()
    return {}


def node_states_scene(resolution=(32, 24)):
    """Six planes whose materials use node states Cycles honours: an output
    for EEVEE only (active, green) beside one for Cycles (red); an Image
    Texture node that is muted; a muted link from an Image Texture (these two
    leave Base Color at its own value, blue); a UV Map node naming a layer
    the plane does not have; a muted Mix node passing its unlinked A (red),
    which Cycles reads as black; RGB nodes linked to Base Color and (as
    their luminance) to Roughness; a reroute from a muted Image Texture and a
    loop of two reroutes (both black Base Color in Cycles 4.5, unlike the
    muted Image Texture linked directly); a material whose output's Surface is
    unlinked and one without an output (both black in Cycles). The world's Background reaches its output
    through a reroute, and its Color through a muted link (its own value
    counts); its Strength comes through a muted Math node from a linked Value
    node."""
    reset(resolution=tuple(resolution))
    img = bpy.data.images.new("Grid", 16, 16)
    img.generated_type = "COLOR_GRID"
    targets = principled_material("Targets", (0.0, 0.8, 0.0))
    tree = targets.node_tree
    tree.nodes["Material Output"].target = "EEVEE"
    cycles_out = tree.nodes.new("ShaderNodeOutputMaterial")
    cycles_out.target = "CYCLES"
    red = tree.nodes.new("ShaderNodeBsdfPrincipled")
    red.inputs["Base Color"].default_value = (0.8, 0.0, 0.0, 1.0)
    tree.links.new(red.outputs[0], cycles_out.inputs["Surface"])
    muted_node = principled_material("MutedNode", (0.1, 0.1, 0.8))
    _image_node(muted_node, img).mute = True
    muted_link = principled_material("MutedLink", (0.1, 0.1, 0.8))
    _image_node(muted_link, img)
    muted_link.node_tree.nodes["Principled BSDF"].inputs["Base Color"].links[0].is_muted = True
    missing_map = principled_material("MissingMap", (0.5, 0.5, 0.5))
    _image_node(missing_map, img, uv_map="Missing")              # a UV map the plane does not have
    muted_mix = principled_material("MutedMix", (0.1, 0.1, 0.8))
    mix = muted_mix.node_tree.nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    colour_a = next(i for i in mix.inputs if i.identifier == "A_Color")     # (3.x: inputs["A"] is the float one)
    colour_a.default_value = (1.0, 0.0, 0.0, 1.0)
    mix.mute = True
    result = next(o for o in mix.outputs if o.identifier == "Result_Color")
    muted_mix.node_tree.links.new(result, muted_mix.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    constants = principled_material("Constants", (0.1, 0.1, 0.8))
    ctree = constants.node_tree
    rgb = ctree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.2, 0.7, 0.3, 1.0)
    ctree.links.new(rgb.outputs[0], ctree.nodes["Principled BSDF"].inputs["Base Color"])
    grey = ctree.nodes.new("ShaderNodeRGB")       # a colour into a float input: its luminance
    grey.outputs[0].default_value = (0.5, 0.25, 1.0, 1.0)
    ctree.links.new(grey.outputs[0], ctree.nodes["Principled BSDF"].inputs["Roughness"])
    rerouted = []                      # a reroute from a muted Image Texture, and a loop of reroutes
    for name in ("RerouteMuted", "RerouteLoop"):
        mat = principled_material(name, (0.1, 0.1, 0.8))
        tree = mat.node_tree
        first, second = tree.nodes.new("NodeReroute"), tree.nodes.new("NodeReroute")
        tree.links.new(first.outputs[0], tree.nodes["Principled BSDF"].inputs["Base Color"])
        if name == "RerouteMuted":
            tex = tree.nodes.new("ShaderNodeTexImage")
            tex.image, tex.mute = img, True
            tree.links.new(tex.outputs["Color"], first.inputs[0])
        else:
            tree.links.new(second.outputs[0], first.inputs[0])
            tree.links.new(first.outputs[0], second.inputs[0])        # (Blender marks this link invalid)
        rerouted.append(mat)
    unlinked = principled_material("NoSurfaceLink", (0.1, 0.9, 0.1))   # Cycles renders both black
    for link in list(unlinked.node_tree.links):
        unlinked.node_tree.links.remove(link)
    no_output = principled_material("NoOutput", (0.1, 0.9, 0.1))
    no_output.node_tree.nodes.remove(no_output.node_tree.nodes["Material Output"])
    materials = (targets, muted_node, muted_link, missing_map, muted_mix, constants, *rerouted, unlinked, no_output)
    for i, mat in enumerate(materials):
        _plane(mat.name, 1.0, (2.0 * i - 4.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(mat)
    world = bpy.data.worlds.new("NodeStates")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    background.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
    background.inputs["Strength"].default_value = 5.0
    reroute = nodes.new("NodeReroute")
    links.new(background.outputs[0], reroute.inputs[0])
    links.new(reroute.outputs[0], nodes["World Output"].inputs["Surface"])
    rgb = nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (1.0, 0.0, 1.0, 1.0)
    links.new(rgb.outputs[0], background.inputs["Color"]).is_muted = True
    value = nodes.new("ShaderNodeValue")
    value.outputs[0].default_value = 2.0
    math_node = nodes.new("ShaderNodeMath")
    math_node.operation = "MULTIPLY"
    math_node.inputs[1].default_value = 100.0
    links.new(value.outputs[0], math_node.inputs[0])
    links.new(math_node.outputs[0], background.inputs["Strength"])
    math_node.mute = True                                          # passes the Value node's 2
    bpy.context.scene.world = world
    bpy.context.view_layer.update()
    return {"names": [m.name for m in materials]}


def roughness_map_scene(resolution=(64, 48), value=128, textured=True):
    """A glossy plane under a point light; its roughness comes from a Non-Color
    8-bit image of constant `value` (textured) or is set to value / 255."""
    reset(resolution=tuple(resolution))
    plane = _plane("Plane", 7.0, rotation=(math.pi / 2 - 0.3, 0, 0))
    mat = principled_material("Glossy", (0.2, 0.3, 0.8), Roughness=value / 255.0)
    if textured:
        px = np.full((8, 8, 4), value / 255.0)
        px[..., 3] = 1.0
        img = _filled_image("Roughness", px, float_buffer=False, non_color=True)
        _image_node(mat, img, "Roughness")
    plane.data.materials.append(mat)
    add_light("Key", "POINT", (0, -6, 3), energy=800.0, shadow_soft_size=0.0)
    bpy.context.view_layer.update()
    return {}


def sky_pixels(w=64, h=32):
    """An HDR equirectangular sky: colour varies with longitude, brightness with latitude."""
    lon = (np.arange(w) + 0.5) / w * 2 * np.pi
    lat = ((np.arange(h) + 0.5) / h - 0.5) * np.pi         # row 0 = bottom (Blender's order)
    px = np.ones((h, w, 4))
    px[..., 0] = 0.2 + 1.5 * (0.5 + 0.5 * np.cos(lon))[None, :]
    px[..., 1] = 0.2 + 1.5 * (0.5 + 0.5 * np.sin(lon))[None, :]
    px[..., 2] = 0.3 + 2.0 * np.clip(np.sin(lat), 0, 1)[:, None]
    return px


def _diffuse_material(name):
    return shader_material(name, "ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.8, 0.8, 1.0))])


def environment_scene(resolution=(64, 48), broken=False, eight_bit_alpha=None, matte=False, turn=None):
    """A mirror sphere in an HDR environment (a float image on an Environment Texture);
    broken: a few of its pixels are +Inf and NaN, as broken HDR files hold;
    eight_bit_alpha: an 8-bit sRGB image instead, of this alpha in its right half;
    matte: the sphere is a grey Diffuse BSDF, lit by the environment alone;
    turn: (x, y, z) degrees, a Mapping node (Point) from the Generated
    coordinates turns the environment."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=2.5, segments=64, ring_count=32)
    sphere = bpy.context.object
    sphere.data.polygons.foreach_set("use_smooth", [True] * len(sphere.data.polygons))
    sphere.data.update()
    sphere.data.materials.append(_diffuse_material("Matte") if matte else
                                 principled_material("Mirror", (1.0, 1.0, 1.0), Metallic=1.0, Roughness=0.0))
    world = bpy.data.worlds.new("Sky")
    bpy.context.scene.world = world
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes = world.node_tree.nodes
    env = nodes.new("ShaderNodeTexEnvironment")
    sky = sky_pixels()
    if broken:
        sky[16, 10:14, :3] = np.inf
        sky[5, 3, 0] = np.nan
    if eight_bit_alpha is not None:
        sky = np.clip(sky, 0.0, 1.0)
        sky[:, sky.shape[1] // 2:, 3] = eight_bit_alpha
    env.image = _filled_image("SkyHDR", sky, float_buffer=eight_bit_alpha is None)
    world.node_tree.links.new(env.outputs["Color"], nodes["Background"].inputs["Color"])
    if turn is not None:
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = tuple(math.radians(a) for a in turn)
        coords = nodes.new("ShaderNodeTexCoord")
        world.node_tree.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        world.node_tree.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    bpy.context.view_layer.update()
    return {}


def emission_mirror_scene(resolution=(64, 48)):
    """A mirror facing the camera; a green emissive sphere behind the camera
    (out of view) is seen only in the mirror. No lights."""
    reset(resolution=tuple(resolution))
    mirror = _plane("Mirror", 6.0, rotation=(math.pi / 2, 0, 0))
    mirror.data.materials.append(principled_material("Mirror", (1.0, 1.0, 1.0), Metallic=1.0, Roughness=0.0))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=2.0, location=(0, -14, 0))
    glow = bpy.context.object
    mat = principled_material("Glow", (0.0, 0.0, 0.0))
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Emission Color" if "Emission Color" in bsdf.inputs else "Emission"].default_value = (0, 1, 0, 1)
    bsdf.inputs["Emission Strength"].default_value = 3.0
    glow.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {}


def fog_box_scene(resolution=(48, 36)):
    """A red cube behind a large box whose material is a Principled Volume with
    no surface (thin fog); a sun lights it."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_cube_add(size=1.5, location=(0, 2, 0))
    bpy.context.object.data.materials.append(principled_material("Red", (0.8, 0.05, 0.05)))
    bpy.ops.mesh.primitive_cube_add(size=6.0, location=(0, 0, 0))
    fog = bpy.context.object
    fog.data.materials.append(shader_material("Fog", "ShaderNodeVolumePrincipled", [("Density", 0.01)], "Volume"))
    add_light("Sun", "SUN", rotation=(0.5, 0.3, 0.0), energy=3.0)
    bpy.context.view_layer.update()
    return {}


def emission_panel_scene(resolution=(64, 48)):
    """A 2 x 2 Emission plane (strength 4, warm white) 1.5 above the middle of
    a grey Diffuse floor, facing it; no lamps, a black world. The camera looks
    down at the floor from the front."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.location = (0.0, -7.0, 5.0)
    scene.camera.rotation_euler = (math.radians(55), 0.0, 0.0)
    floor = _plane("Floor", 12.0)
    floor.data.materials.append(_diffuse_material("Floor"))
    panel = _plane("Panel", 2.0, location=(0, 0, 1.5), rotation=(math.pi, 0, 0))
    panel.data.materials.append(shader_material("Panel", "ShaderNodeEmission",
                                                [("Color", (1.0, 0.8, 0.6, 1.0)), ("Strength", 4.0)]))
    plain_world("Black", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


def world_shadow_scene(resolution=(64, 48)):
    """A nearly black Diffuse ball (radius 1) resting on a grey Diffuse floor
    under a plain white world, no lamps: the world's light alone, blocked by
    the ball around its contact point (its own bounce light is negligible)."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.location = (0.0, -6.0, 6.0)
    scene.camera.rotation_euler = (math.radians(45), 0.0, 0.0)
    _plane("Floor", 20.0).data.materials.append(_diffuse_material("Floor"))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0, 0, 1.0), segments=48, ring_count=24)
    ball = bpy.context.object
    ball.data.polygons.foreach_set("use_smooth", [True] * len(ball.data.polygons))
    ball.data.materials.append(shader_material("Ball", "ShaderNodeBsdfDiffuse", [("Color", (0.02, 0.02, 0.02, 1.0))]))
    plain_world("White", (1.0, 1.0, 1.0))
    bpy.context.view_layer.update()
    return {}


def sunny_monkey_scene(resolution=(96, 72)):
    """Suzanne (subdivided, smooth, red) on a grey floor under an HDR sky with a
    sun (3 x 3 texels 3,000 times brighter than the blue sky, 46 degrees up),
    beside a blue Emission panel; no lamps."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.location = (0, -7, 3.5)
    scene.camera.rotation_euler = (math.radians(68), 0, 0)
    _plane("Floor", 20.0).data.materials.append(principled_material("Floor", (0.7, 0.7, 0.7), Roughness=0.8))
    bpy.ops.mesh.primitive_monkey_add(location=(0, 0, 1))
    monkey = bpy.context.object
    monkey.modifiers.new("Subdivision", "SUBSURF").levels = 2
    monkey.data.polygons.foreach_set("use_smooth", [True] * len(monkey.data.polygons))
    monkey.data.materials.append(principled_material("Red", (0.8, 0.1, 0.05), Roughness=0.4))
    panel = _plane("Panel", 1.5, location=(2.2, 0.5, 1.8), rotation=(0, math.radians(-120), 0))
    panel.data.materials.append(shader_material("Glow", "ShaderNodeEmission",
                                                [("Color", (0.3, 0.6, 1.0, 1.0)), ("Strength", 8.0)]))
    h, w = 128, 256
    up = ((np.arange(h) + 0.5) / h > 0.5)[:, None]              # row 0 at the bottom
    px = np.ones((h, w, 4), np.float32)
    for c, level in enumerate((0.35, 0.5, 0.9)):
        px[..., c] = np.where(up, level, 0.15 * level)
    px[95:98, 160:163, :3] = 3000.0
    world = bpy.data.worlds.new("SunnySky")
    scene.world = world
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    env.image = _filled_image("SunnySky", px, float_buffer=True)
    world.node_tree.links.new(env.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    bpy.context.view_layer.update()
    return {}


NORMAL_BANDS = 8   # normal_map_scene's stripes across the plane


def normal_map_scene(resolution=(96, 48), strength=1.0, tilt=30.0, sphere=False, mirror=False):
    """A plane facing the camera whose Diffuse BSDF's Normal comes from a
    Tangent Space Normal Map node fed by a Non-Color 8-bit image: NORMAL_BANDS
    vertical stripes whose normals lean `tilt` degrees to one side and the other
    along the UV's u (the plane's x), lit by a sun from the left. sphere: a
    smooth low-poly UV sphere instead (16 x 8), its map one colour (every
    normal leaning `tilt` degrees along u): the tangents' interpolation over
    its faces decides the shading. mirror: the object's x scale is -1 (its
    winding and its UVs' orientation are mirrored in world space)."""
    import mathutils
    reset(resolution=tuple(resolution))
    if sphere:
        bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=2.0)
        plane = bpy.context.object
        bpy.ops.object.shade_smooth()
    else:
        plane = _plane("Plane", 7.0, rotation=(math.pi / 2, 0, 0))
    if mirror:
        plane.scale.x = -1.0
    mat = shader_material("Bumpy", "ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.8, 0.8, 1.0))])
    shader = next(n for n in mat.node_tree.nodes if n.type == "BSDF_DIFFUSE")
    lean = math.radians(tilt)
    px = np.ones((4, 8 * NORMAL_BANDS, 4))
    for band in range(NORMAL_BANDS):
        side = 1.0 if band % 2 or sphere else -1.0
        px[:, 8 * band:8 * band + 8, :3] = 0.5 + 0.5 * np.array([side * math.sin(lean), 0.0, math.cos(lean)])
    img = _filled_image("Normals", px, float_buffer=False, non_color=True)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = img, "Closest"
    nmap = nodes.new("ShaderNodeNormalMap")
    nmap.inputs["Strength"].default_value = strength
    links.new(tex.outputs["Color"], nmap.inputs["Color"])
    links.new(nmap.outputs["Normal"], shader.inputs["Normal"])
    plane.data.materials.append(mat)
    travel = mathutils.Vector((0.8, 0.6, 0.0)).normalized()          # from the left, towards the plane
    sun = add_light("Sun", "SUN", (0, -5, 0), energy=3.0, angle=0.0)
    sun.rotation_euler = travel.to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.world = None
    bpy.context.view_layer.update()
    return {}


def pane_shadow_scene(pane="glass", resolution=(64, 64), light="sun"):
    """A white floor seen from straight above (orthographic) and a pane 2 units
    above it, lit by a slanted sun: the pane's shadow falls at x = -2, y = 0,
    pixel column 16, row 32. pane: glass (Transmission 1), alpha (Alpha 0.5) or opaque.
    light="area": a 3 x 3 area light 5 units above the centre instead, whose
    penumbra spreads 2 units around the pane's shadow below it."""
    reset(resolution=tuple(resolution))
    cam = bpy.context.scene.camera
    cam.location, cam.rotation_euler = (0, 0, 10), (0, 0, 0)
    cam.data.type, cam.data.ortho_scale = "ORTHO", 8.0
    floor = _plane("Floor", 20.0)
    floor.data.materials.append(principled_material("White", (0.8, 0.8, 0.8), Roughness=1.0))
    glass = _plane("Pane", 1.0, location=(0, 0, 2))
    inputs = {"glass": {"Transmission": 1.0, "Roughness": 0.0, "IOR": 1.45}, "alpha": {"Alpha": 0.5},
              "opaque": {}}[pane]
    glass.data.materials.append(principled_material("Pane", (0.8, 0.8, 0.8), **inputs))
    if light == "area":
        add_light("Area", "AREA", (0, 0, 5), energy=400.0, size=3.0)
    else:
        add_light("Sun", "SUN", (0, 0, 5), (0, math.pi / 4, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {}


def rough_glass_scene(resolution=(128, 96), roughness=0.4):
    """Two glass spheres (Principled BSDF, Transmission 1, IOR 1.45; left
    Roughness 0, right `roughness`) in front of a wall of 16 vertical stripes,
    white and nearly black, lit by a sun; the camera looks through the spheres
    at the wall."""
    reset(resolution=tuple(resolution))
    white = principled_material("StripeWhite", (0.8, 0.8, 0.8), Roughness=1.0)
    black = principled_material("StripeBlack", (0.02, 0.02, 0.02), Roughness=1.0)
    for k in range(16):
        stripe = _plane(f"Stripe{k}", 1.0, location=(-3.75 + 0.5 * k, 3.0, 0.0), rotation=(math.pi / 2, 0, 0))
        stripe.scale = (0.5, 8.0, 1.0)
        stripe.data.materials.append(white if k % 2 else black)
    for x, rough in ((-1.1, 0.0), (1.1, roughness)):
        bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(x, 0.0, 0.0), segments=64, ring_count=32)
        sphere = bpy.context.object
        for polygon in sphere.data.polygons:
            polygon.use_smooth = True
        sphere.data.materials.append(principled_material(f"Glass{rough:g}", (1.0, 1.0, 1.0), Transmission=1.0,
                                                         Roughness=rough, IOR=1.45))
    add_light("Sun", "SUN", (0, -5, 5), (math.pi / 4, 0, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {}


def coloured_glass_scene(resolution=(96, 72)):
    """Two green glass spheres against a grey world, seen straight on: left a Glass BSDF
    (Color (0.1, 0.9, 0.1)), right a Principled BSDF of that Base Color with Transmission 1,
    both sharp, IOR 1.45; under them a white floor that their shadows fall on, lit by a sun."""
    reset(resolution=tuple(resolution))
    scene = bpy.context.scene
    scene.camera.location, scene.camera.rotation_euler = (0, -6, 0.6), (math.radians(84), 0, 0)
    plain_world("Grey", (0.5, 0.5, 0.5))
    floor = _plane("Floor", 12.0, location=(0.0, 0.0, -1.0))
    floor.data.materials.append(principled_material("Floor", (0.8, 0.8, 0.8), Roughness=1.0))
    green = (0.1, 0.9, 0.1)
    glass = shader_material("GreenGlass", "ShaderNodeBsdfGlass", [("Color", (*green, 1.0)), ("Roughness", 0.0),
                                                                   ("IOR", 1.45)])
    principled = principled_material("GreenTransmission", green, Transmission=1.0, Roughness=0.0, IOR=1.45)
    for x, material in ((-1.2, glass), (1.2, principled)):
        bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(x, 0.0, 0.0), segments=64, ring_count=32)
        sphere = bpy.context.object
        for polygon in sphere.data.polygons:
            polygon.use_smooth = True
        sphere.data.materials.append(material)
    add_light("Sun", "SUN", (0, 0, 5), (math.radians(-35), 0, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {}


def _png(path, pixels, colour_type):
    """Writes an 8-bit PNG of `pixels` ((h, w, channels) bytes, row 0 at the top): colour
    type 6 (RGBA) or 4 (grey + alpha), as image editors save them."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    h, w = pixels.shape[:2]
    rows = b"".join(b"\x00" + pixels[y].astype(np.uint8).tobytes() for y in range(h))
    header = struct.pack(">IIBBBBB", w, h, 8, colour_type, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows))
                     + chunk(b"IEND", b""))


def png_alpha_scene(resolution=(96, 32)):
    """Three emissive planes side by side under an orthographic camera, each showing a PNG of
    grey 128 at alpha 153 through an Emission shader, the Alpha output unused: a file saved as
    RGBA, a file saved as grey + alpha, and that grey + alpha image packed into the .blend. Cycles
    associates the RGBA file and the packed image (0.5 x 0.6 in sRGB) and leaves the grey + alpha
    file as stored. A black world. (The files lie in Blender's session folder, gone at exit.)"""
    reset(resolution=tuple(resolution))
    cam = bpy.context.scene.camera.data
    cam.type, cam.ortho_scale = "ORTHO", 12.0
    folder = pathlib.Path(bpy.app.tempdir)
    for name, x, colour_type, px, pack in (("RGBA", -4.0, 6, [128, 128, 128, 153], False),
                                           ("GreyAlpha", 0.0, 4, [128, 153], False),
                                           ("GreyAlphaPacked", 4.0, 4, [128, 153], True)):
        path = folder / f"{name}.png"
        _png(path, np.tile(np.array(px, np.uint8), (4, 4, 1)), colour_type)
        img = bpy.data.images.load(str(path))
        if pack:
            img.pack()
        mat = shader_material(name, "ShaderNodeEmission")
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = img
        links.new(tex.outputs["Color"], next(n for n in nodes if n.type == "EMISSION").inputs["Color"])
        _plane(name, 3.5, location=(x, 0, 0), rotation=(math.pi / 2, 0, 0)).data.materials.append(mat)
    plain_world("Black", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


def alpha_mask_scene(operation="LESS_THAN", cutoff=0.5, resolution=(64, 16)):
    """An orthographic camera filling its view with a plane whose Principled BSDF (black, emitting
    white) takes its Alpha as Blender's glTF importer builds Alpha Mode Mask: an image's Alpha (a
    ramp from 0 at the left to 1 at the right, 64 texels, Closest) through a Math node comparing it
    with `cutoff` (Less Than, then 1 - that; Greater Than: its own output), over a black world."""
    reset(resolution=tuple(resolution))
    cam = bpy.context.scene.camera.data
    cam.type, cam.ortho_scale = "ORTHO", 4.0
    px = np.ones((4, 64, 4))
    px[..., 3] = (np.arange(64)[None, :] + 0.5) / 64
    img = _filled_image("Mask", px, float_buffer=False)
    plane = _plane("Masked", 4.0, rotation=(math.pi / 2, 0, 0))
    plane.scale = (1.0, 0.25, 1.0)
    mat = principled_material("Masked", (0.0, 0.0, 0.0))
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes["Principled BSDF"]
    emission = next(s for s in bsdf.inputs if s.name in ("Emission Color", "Emission"))
    emission.default_value = (1.0, 1.0, 1.0, 1.0)
    if "Emission Strength" in bsdf.inputs:
        bsdf.inputs["Emission Strength"].default_value = 1.0
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = img, "Closest"
    compare = nodes.new("ShaderNodeMath")
    compare.operation = operation
    compare.inputs[1].default_value = cutoff
    links.new(tex.outputs["Alpha"], compare.inputs[0])
    out = compare.outputs[0]
    if operation == "LESS_THAN":
        invert = nodes.new("ShaderNodeMath")
        invert.operation = "SUBTRACT"
        invert.inputs[0].default_value = 1.0
        links.new(out, invert.inputs[1])
        out = invert.outputs[0]
    links.new(out, bsdf.inputs["Alpha"])
    plane.data.materials.append(mat)
    plain_world("Black", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


def cutout_scene(resolution=(64, 32)):
    """Two emissive planes side by side under an orthographic camera, textured
    with one 8 x 8 8-bit image whose left half is opaque and right half a
    quarter opaque, in a grey world. Left, "Cutout": a Mix Shader of a
    Transparent BSDF and an Emission, Fac from the image's Alpha (the Color
    is then straight: Cycles divides it by alpha again). Right, "Dangling":
    the Emission alone, the Alpha output linked to a Math node that reaches
    nothing (the Color is associated, as with the Alpha output unlinked)."""
    reset(resolution=tuple(resolution))
    cam = bpy.context.scene.camera.data
    cam.type, cam.ortho_scale = "ORTHO", 8.0
    px = np.random.default_rng(1).random((8, 8, 4))
    px[..., 3] = np.where(np.arange(8)[None, :] < 4, 1.0, 0.25)
    img = _filled_image("Leaves", px, float_buffer=False)
    for name, x in (("Cutout", -2.0), ("Dangling", 2.0)):
        mat = bpy.data.materials.new(name)
        if bpy.app.version < (5, 0, 0):
            mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        for node in [n for n in nodes if n.type != "OUTPUT_MATERIAL"]:
            nodes.remove(node)
        emission, tex = nodes.new("ShaderNodeEmission"), nodes.new("ShaderNodeTexImage")
        tex.image, tex.interpolation = img, "Closest"
        links.new(tex.outputs["Color"], emission.inputs["Color"])
        surface = emission.outputs[0]
        if name == "Cutout":
            mix, clear = nodes.new("ShaderNodeMixShader"), nodes.new("ShaderNodeBsdfTransparent")
            links.new(tex.outputs["Alpha"], mix.inputs[0])
            links.new(clear.outputs[0], mix.inputs[1])
            links.new(emission.outputs[0], mix.inputs[2])
            surface = mix.outputs[0]
        else:
            links.new(tex.outputs["Alpha"], nodes.new("ShaderNodeMath").inputs[0])
        links.new(surface, nodes["Material Output"].inputs["Surface"])
        _plane(name, 4.0, location=(x, 0, 0), rotation=(math.pi / 2, 0, 0)).data.materials.append(mat)
    world = bpy.data.worlds.new("Grey")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    bpy.context.scene.world = world
    bpy.context.view_layer.update()
    return {}


def mix_shaders_scene(resolution=(32, 24)):
    """Planes whose surface is a Mix Shader: a Transparent BSDF first with Fac
    0.3 (alpha 0.3), second (alpha 0.7), second with a linked Fac, tinted,
    beside a Principled BSDF whose own Alpha is 0.5, a Mix of two other
    shaders (not read: the viewport colour), and first with Fac from a Math
    node (not read: Fac's own value)."""
    reset(resolution=tuple(resolution))
    img = _filled_image("Mask", np.full((4, 4, 4), 0.5), float_buffer=False)
    cases = ("ClearFirst", "ClearSecond", "LinkedFacSecond", "Tinted", "OwnAlpha", "TwoShaders", "FacFromMath")
    for i, name in enumerate(cases):
        mat = principled_material(name, (0.2, 0.4, 0.6), Alpha=0.5 if name == "OwnAlpha" else 1.0)
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        mix = nodes.new("ShaderNodeMixShader")
        mix.inputs[0].default_value = 0.3
        other = nodes.new("ShaderNodeBsdfDiffuse" if name == "TwoShaders" else "ShaderNodeBsdfTransparent")
        if name == "Tinted":
            other.inputs["Color"].default_value = (1.0, 0.5, 0.5, 1.0)
        first, second = (nodes["Principled BSDF"], other) if "Second" in name else (other, nodes["Principled BSDF"])
        links.new(first.outputs[0], mix.inputs[1])
        links.new(second.outputs[0], mix.inputs[2])
        if name == "LinkedFacSecond":
            tex = nodes.new("ShaderNodeTexImage")
            tex.image = img
            links.new(tex.outputs["Alpha"], mix.inputs[0])
        if name == "FacFromMath":              # a node the export does not read: Fac's own 0.3
            links.new(nodes.new("ShaderNodeMath").outputs[0], mix.inputs[0])
        links.new(mix.outputs[0], nodes["Material Output"].inputs["Surface"])
        _plane(name, 1.0, (2.0 * i - 5.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(mat)
    bpy.context.view_layer.update()
    return {"names": list(cases)}


def _file_image(name, path):
    """An image datablock reading `path`, as a .blend that points at a file would have it."""
    img = bpy.data.images.new(name, 4, 4)
    img.source, img.filepath = "FILE", path
    img.reload()
    return img


def nodeless_material_scene(resolution=(32, 24)):
    """A plane whose material has no nodes (Use Nodes off, as bpy.data.materials.new makes one
    before Blender 5.0), its viewport colour (0.2, 0.4, 0.6), Metallic 1 and Roughness 0.2."""
    reset(resolution=tuple(resolution))
    plane = _plane("Plain", 4.0, rotation=(math.pi / 2, 0, 0))
    mat = bpy.data.materials.new("NoNodes")
    if getattr(mat, "use_nodes", False):
        mat.use_nodes = False
    mat.diffuse_color, mat.metallic, mat.roughness = (0.2, 0.4, 0.6, 1.0), 1.0, 0.2
    plane.data.materials.append(mat)
    add_light("Sun", "SUN", (0, -5, 0), (math.pi / 2, 0, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {"use_nodes": bool(getattr(mat, "use_nodes", True)) and mat.node_tree is not None}


def bad_materials_scene(resolution=(48, 36)):
    """Six planes, each with one problem: a missing image file, a 0 x 0 image,
    a 16k x 16k image, a textured mesh without UVs, a node Gridwalk does
    not understand (a Sky Texture on Base Color), and an image sequence."""
    reset(resolution=tuple(resolution))
    missing = _file_image("MissingImage", "/nonexistent/gridwalk_missing_texture.png")
    # (in Blender's session folder, which scripting.leave removes at exit)
    zero_file = os.path.join(tempfile.mkdtemp(prefix="gridwalk_", dir=bpy.app.tempdir), "zero_size.png")
    open(zero_file, "wb").close()          # a file Blender cannot decode: a 0 x 0 image
    zero = _file_image("ZeroSizeImage", zero_file)
    small = bpy.data.images.new("SmallImage", 4, 4)
    huge = bpy.data.images.new("HugeImage", 16384, 16384)
    frames = bpy.data.images.new("Frames", 4, 4)
    frames.source, frames.filepath = "SEQUENCE", "/nonexistent/gridwalk_frame_0001.png"
    cases = {"MissingFile": missing, "ZeroSize": zero, "Huge": huge, "NoUVs": small, "Sky": None,
             "Sequence": frames}
    for i, (name, image) in enumerate(cases.items()):
        plane = _plane(name, 1.5, location=(-4 + 2 * i, 0, 0), rotation=(math.pi / 2, 0, 0))
        mat = principled_material(name, (0.5, 0.5, 0.5))
        if name == "Sky":
            sky = mat.node_tree.nodes.new("ShaderNodeTexSky")
            mat.node_tree.links.new(sky.outputs["Color"], mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
        else:
            _image_node(mat, image)
        if name == "NoUVs":
            while plane.data.uv_layers:
                plane.data.uv_layers.remove(plane.data.uv_layers[0])
        plane.data.materials.append(mat)
    add_light("Sun", "SUN", (0, -5, 0), (math.pi / 2, 0, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {}


def _uv_layer(mesh, name, offset, scale=1.0):
    """A new UV layer holding the first layer's UVs * scale + offset."""
    first = mesh.uv_layers[0]
    uv = np.empty(2 * len(first.data), np.float32)
    first.data.foreach_get("uv", uv)
    layer = mesh.uv_layers.new(name=name)
    layer.data.foreach_set("uv", uv * scale + offset)
    return layer


def texture_links_scene(resolution=(32, 24), mixed_maps=False, from_instancer=False, odd_space=False):
    """Four planes whose materials use each linked input the exporter reads:
      ByNode: a UV Map node picks layer "Second" (UVs in [0.25, 0.75]) although
        "UVMap" renders; the 8-bit sRGB image "Shared" on Base Color, Closest,
        Clip; a float image on Roughness.
      ByRender: no UV Map node, so the active render layer "Render" (UVs in
        [3, 4]) although "UVMap" is active for editing; "Shared" again (Linear,
        Extend) on Base Color, its Alpha output on Alpha, a Non-Color 8-bit
        image on Metallic.
      Painted: a Color Attribute node reading "Paint" (not the render one).
      Lamp: an Emission shader, Color (1, 0.5, 0.25) x Strength 4.
    mixed_maps: a fifth plane, Mixed, whose Base Color image reads the render UV map (its
    Vector unlinked; UVs in [0, 1]) and whose Roughness image reads "Second" through a UV Map
    node (UVs in [0.25, 0.75]), as Blender's glTF importer builds a model with two UV sets.
    from_instancer: ByNode's UV Map nodes take From Instancer (which the export does not read).
    odd_space: the 8-bit image "MetalMap" takes a colour space the core does not decode (the
    first of Display P3, Filmic Log, AgX Log that this Blender has); returns its name."""
    reset(resolution=tuple(resolution))
    shared = _filled_image("Shared", np.full((4, 4, 4), 0.5), float_buffer=False)
    metal = _filled_image("MetalMap", np.full((8, 8, 4), 0.75), float_buffer=False, non_color=True)
    rough = _filled_image("RoughHDR", np.full((2, 2, 4), 0.25), float_buffer=True)
    space = None
    if odd_space:
        names = metal.colorspace_settings.bl_rna.properties["name"].enum_items.keys()
        space = next(name for name in ("Display P3", "Filmic Log", "AgX Log") if name in names)
        metal.colorspace_settings.name = space

    by_node = _plane("ByNode", 1.0, location=(-3, 0, 0), rotation=(math.pi / 2, 0, 0))
    _uv_layer(by_node.data, "Second", 0.25, 0.5)
    mat = principled_material("ByNode", (0.5, 0.5, 0.5))
    _image_node(mat, shared, interpolation="Closest", extension="CLIP", uv_map="Second")
    _image_node(mat, rough, "Roughness", uv_map="Second")
    if from_instancer:
        for node in mat.node_tree.nodes:
            if node.type == "UVMAP":
                node.from_instancer = True
    by_node.data.materials.append(mat)

    by_render = _plane("ByRender", 1.0, location=(-1, 0, 0), rotation=(math.pi / 2, 0, 0))
    _uv_layer(by_render.data, "Render", 3.0).active_render = True
    by_render.data.uv_layers.active = by_render.data.uv_layers["UVMap"]
    mat = principled_material("ByRender", (0.5, 0.5, 0.5))
    _image_node(mat, shared, extension="EXTEND")
    _image_node(mat, shared, "Alpha", output="Alpha", extension="EXTEND")
    _image_node(mat, metal, "Metallic", extension="EXTEND")
    by_render.data.materials.append(mat)

    painted = _plane("Painted", 1.0, location=(1, 0, 0), rotation=(math.pi / 2, 0, 0))
    for name, rgba in (("Other", (1.0, 0.0, 0.0, 1.0)), ("Paint", (0.2, 0.6, 0.9, 1.0))):
        attr = painted.data.color_attributes.new(name, "FLOAT_COLOR", "CORNER")
        attr.data.foreach_set("color", np.tile(np.array(rgba, np.float32), len(attr.data)))
    painted.data.color_attributes.active_color = painted.data.color_attributes["Other"]
    if hasattr(painted.data.color_attributes, "render_color_index"):
        painted.data.color_attributes.render_color_index = 0        # "Other" renders by default
    mat = principled_material("Painted", (0.5, 0.5, 0.5))
    node = mat.node_tree.nodes.new("ShaderNodeVertexColor")
    node.layer_name = "Paint"
    mat.node_tree.links.new(node.outputs["Color"], mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    painted.data.materials.append(mat)
    # The same material on meshes without "Paint": one with no colour attribute, one with another
    # (Cycles reads a missing attribute as black)
    _plane("Unpainted", 1.0, location=(5, 0, 0), rotation=(math.pi / 2, 0, 0)).data.materials.append(mat)
    other = _plane("OtherPaint", 1.0, location=(7, 0, 0), rotation=(math.pi / 2, 0, 0))
    attr = other.data.color_attributes.new("Col", "FLOAT_COLOR", "CORNER")
    attr.data.foreach_set("color", np.tile(np.array((1.0, 0.0, 0.0, 1.0), np.float32), len(attr.data)))
    other.data.materials.append(mat)

    lamp = _plane("Lamp", 1.0, location=(3, 0, 0), rotation=(math.pi / 2, 0, 0))
    mat = principled_material("Lamp", (0.5, 0.5, 0.5))
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    emission.inputs["Strength"].default_value = 4.0
    mat.node_tree.links.new(emission.outputs["Emission"], nodes["Material Output"].inputs["Surface"])
    lamp.data.materials.append(mat)
    if mixed_maps:
        mixed = _plane("Mixed", 1.0, location=(9, 0, 0), rotation=(math.pi / 2, 0, 0))
        _uv_layer(mixed.data, "Second", 0.25, 0.5)
        mat = principled_material("Mixed", (0.5, 0.5, 0.5))
        _image_node(mat, shared)
        _image_node(mat, rough, "Roughness", uv_map="Second")
        mixed.data.materials.append(mat)
    add_light("Sun", "SUN", (0, -5, 0), (math.pi / 2, 0, 0), energy=3.0)
    bpy.context.view_layer.update()
    return {"space": space}


def unread_settings_scene(override=False):
    """Settings the export reads or warns about (found by an exploration
    against Cycles): a Box-projected image (read since: test_b50), an object whose two materials
    name different UV maps (the second the first shrunk to [0.25, 0.75]), a plane with a NaN UV (one loop: a corner of both its triangles), a Principled
    BSDF with a coat and a sheen, a world hidden from camera rays; with override, the view layer's Material Override (grey)."""
    reset(resolution=(32, 24))
    img = bpy.data.images.new("Grid", 16, 16)
    img.generated_type = "COLOR_GRID"
    box = principled_material("Box", (0.5, 0.5, 0.5))
    _image_node(box, img).projection = "BOX"
    _plane("Boxed", 1.0, (-2.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(box)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=3, y_subdivisions=3, size=1.0, location=(0.0, 0.0, 0.0),
                                    rotation=(math.pi / 2, 0, 0))
    two = bpy.context.object                   # faces alternating between the two materials
    two.name = "TwoMaps"
    second = two.data.uv_layers.new(name="Second")
    for loop in second.data:                   # the first map shrunk about its centre
        loop.uv = (0.25 + 0.5 * loop.uv[0], 0.25 + 0.5 * loop.uv[1])
    for name, layer in (("FirstMap", "UVMap"), ("SecondMap", "Second")):
        mat = principled_material(name, (0.5, 0.5, 0.5))
        _image_node(mat, img, uv_map=layer)
        two.data.materials.append(mat)
    two.data.polygons.foreach_set("material_index", [i % 2 for i in range(len(two.data.polygons))])
    nan_uv = _plane("NanUV", 1.0, (2.0, 0.0, 0.0), (math.pi / 2, 0, 0))
    nan_uv.data.materials.append(box)
    nan_uv.data.uv_layers.active.data[0].uv = (float("nan"), 0.5)
    layers = principled_material("Layers", (0.5, 0.5, 0.5))       # a coat and a sheen (3.x: Clearcoat, Sheen)
    bsdf = layers.node_tree.nodes["Principled BSDF"]
    for names, value in ((("Coat Weight", "Clearcoat"), 0.5), (("Sheen Weight", "Sheen"), 1.0)):
        bsdf.inputs[next(n for n in names if n in bsdf.inputs)].default_value = value
    _plane("Layered", 1.0, (4.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(layers)
    tinted = principled_material("Tinted", (0.5, 0.5, 0.5))       # inputs without a term, named too
    bsdf = tinted.node_tree.nodes["Principled BSDF"]
    tint = bsdf.inputs["Specular Tint"]
    tint.default_value = (1.0, 0.2, 0.2, 1.0) if hasattr(tint.default_value, "__len__") else 0.5
    bsdf.inputs["Anisotropic"].default_value = 0.9
    bsdf.inputs["Emission Strength"].default_value = -2.0
    bsdf.inputs[next(n for n in ("Emission Color", "Emission") if n in bsdf.inputs)].default_value = (1, 1, 1, 1)
    _plane("TintedPlane", 1.0, (4.0, 2.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(tinted)
    rough = shader_material("RoughDiffuse", "ShaderNodeBsdfDiffuse", [("Color", (0.5, 0.5, 0.5, 1.0)), ("Roughness", 0.6)])
    _plane("RoughPlane", 1.0, (6.0, 2.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(rough)
    bumpy = principled_material("Bumpy", (0.5, 0.5, 0.5))            # Sky -> Bump -> Normal (a Sky Texture is not read)
    nodes, node_links = bumpy.node_tree.nodes, bumpy.node_tree.links
    bump = nodes.new("ShaderNodeBump")
    node_links.new(nodes.new("ShaderNodeTexSky").outputs[0], bump.inputs["Height"])
    node_links.new(bump.outputs["Normal"], nodes["Principled BSDF"].inputs["Normal"])
    _plane("Bumped", 1.0, (6.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(bumpy)
    displaced = shader_material("Displaced", "ShaderNodeBsdfDiffuse", [("Color", (0.5, 0.5, 0.5, 1.0))])
    nodes, node_links = displaced.node_tree.nodes, displaced.node_tree.links     # Noise -> Displacement -> output
    shift = nodes.new("ShaderNodeDisplacement")
    node_links.new(nodes.new("ShaderNodeTexNoise").outputs[0], shift.inputs["Height"])
    node_links.new(shift.outputs[0], displaced.node_tree.get_output_node("CYCLES").inputs["Displacement"])
    _plane("DisplacedPlane", 1.0, (8.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(displaced)
    object_space = principled_material("ObjectSpace", (0.5, 0.5, 0.5))   # Image -> Normal Map (Object Space) -> Normal
    nodes, node_links = object_space.node_tree.nodes, object_space.node_tree.links
    nmap = nodes.new("ShaderNodeNormalMap")
    nmap.space = "OBJECT"
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = _filled_image("ObjectNormals", np.full((2, 2, 4), 0.5), float_buffer=False, non_color=True)
    node_links.new(tex.outputs["Color"], nmap.inputs["Color"])
    node_links.new(nmap.outputs["Normal"], nodes["Principled BSDF"].inputs["Normal"])
    _plane("ObjectSpaceMapped", 1.0, (10.0, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(object_space)
    for name, colour in (("FlatNormalMap", (0.5, 0.5, 1.0, 1.0)), ("TiltedNormalMap", (0.8, 0.5, 0.9, 1.0))):
        unlinked = principled_material(name, (0.5, 0.5, 0.5))           # Normal Map with an unlinked Color -> Normal
        nmap = unlinked.node_tree.nodes.new("ShaderNodeNormalMap")
        nmap.inputs["Color"].default_value = colour
        unlinked.node_tree.links.new(nmap.outputs["Normal"], unlinked.node_tree.nodes["Principled BSDF"].inputs["Normal"])
        x = 12.0 if name == "FlatNormalMap" else 14.0
        _plane(name + "Plane", 1.0, (x, 0.0, 0.0), (math.pi / 2, 0, 0)).data.materials.append(unlinked)
    world = bpy.data.worlds.new("Hidden")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
    world.cycles_visibility.camera = False
    bpy.context.scene.world = world
    if override:
        bpy.context.view_layer.material_override = principled_material("Override", (0.3, 0.3, 0.3))
    bpy.context.view_layer.update()
    return {}
