"""Scenes with procedural textures (render_scene.py and export_dump.py build them by name)."""
import math

import bpy
import numpy as np

from material_scenes import _filled_image
from scenes import cube_object, link, plain_world, reset, shader_material

# Checker variants: the object, where the Checker's Vector comes from, and what it feeds.
#   plane      a plane facing the camera, the Checker's Vector unlinked (Generated), its Color
#   cube       a cube turned towards the camera: Texture Coordinate Generated -> Mapping (Point, turned,
#              moved, scaled) -> Checker
#   subdivided the cube with a Subdivision modifier (level 2): Generated spans the cube before it
#   uv         the plane, Texture Coordinate UV -> Checker
#   fac        the plane, the Checker's Fac into the Emission's Color (white and black)
#   image      the cube, Texture Coordinate Generated -> Mapping -> an 8 x 8 Image Texture
#   principled the cube, the Checker into a Principled BSDF's Base Color, lit by a sun
#   object     the cube scaled (1.2, 0.8, 1.0), Texture Coordinate Object -> Mapping -> Checker (Scale 1.5)
#   twisted    the cube twisted 60 degrees by a Simple Deform modifier: Generated is taken before it
#   valued     the plane, a Value node (2.0) into the Checker's Scale and an RGB node into its Color1
CHECKER_VARIANTS = ("plane", "cube", "subdivided", "uv", "fac", "image", "principled", "object", "twisted",
                    "valued", "position", "other_object")
# "position": a Geometry node's Position; "other_object": the Object output of a Texture
# Coordinate node naming an empty placed thus (location, rotation, scale)
EMPTY_PLACE = ((0.4, -0.3, 0.2), (0.3, -0.5, 0.6), (0.7, 1.4, 1.1))
VALUE_SCALE, RGB_COLOR = 2.0, (0.2, 0.8, 0.3, 1.0)
COLORS = ((0.9, 0.6, 0.1, 1.0), (0.05, 0.1, 0.4, 1.0))
SCALE = 3.7          # cube edges do not fall on pixel centres
TURN = ((0.2, -0.1, 0.3), (0.3, 0.2, math.radians(25.0)), (1.3, 0.8, 1.1))   # location, rotation, scale


def procedural_checker_scene(variant="plane", resolution=(96, 72), coordinates=None, flat_empty=False,
                             smooth=False, panorama=None, projection=None, blend=0.0):
    """One object seen by the camera at (0, -10, 0), its material's colour a Checker
    Texture (or an image at Generated coordinates) as CHECKER_VARIANTS describes;
    a black world (coordinates: the Texture Coordinate node's output to read instead,
    such as "Reflection", or "Geometry:" and a Geometry node's output; flat_empty:
    "other_object"'s empty scaled to 0 along z; smooth: the object's faces shaded smooth;
    panorama: a panoramic camera kind of scenes.PANORAMA_KINDS, or "equirectangular", 3.2 units
    from the object; projection, blend: the "image" variant's Image Texture Projection and its
    Blend).
    Returns the Checker's settings, the empty's location and the Mapping's."""
    reset(resolution=tuple(resolution))
    if variant in ("plane", "uv", "fac", "valued"):
        bpy.ops.mesh.primitive_plane_add(size=7.0, rotation=(math.pi / 2, 0, 0))
        obj = bpy.context.object
    else:
        obj = link(cube_object("Cube", 3.0))
        obj.rotation_euler = (math.radians(30.0), 0.0, math.radians(35.0))
        if variant == "subdivided":
            obj.modifiers.new("Subdivision", "SUBSURF").levels = 2
        if variant in ("object", "position", "other_object"):
            obj.scale = (1.2, 0.8, 1.0)
        if variant == "twisted":
            twist = obj.modifiers.new("Twist", "SIMPLE_DEFORM")
            twist.deform_method, twist.angle = "TWIST", math.radians(60.0)
    if variant == "principled":
        mat = bpy.data.materials.new("Checkered")
        mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        target = nodes["Principled BSDF"].inputs["Base Color"]
        sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
        sun.data.energy, sun.data.angle = 3.0, 0.0
        sun.rotation_euler = (math.radians(50.0), 0.0, math.radians(-30.0))
        link(sun)
    else:
        mat = shader_material("Checkered", "ShaderNodeEmission", [("Strength", 1.0)])
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        target = nodes["Emission"].inputs["Color"]
    if variant == "image":
        texture = nodes.new("ShaderNodeTexImage")
        pixels = np.random.default_rng(7).integers(0, 256, (8, 8, 4)) / 255.0
        pixels[..., 3] = 1.0
        texture.image, texture.interpolation = _filled_image("Random", pixels, float_buffer=False), "Closest"
        if projection:
            texture.projection, texture.projection_blend = projection, blend
    else:
        texture = nodes.new("ShaderNodeTexChecker")
        texture.inputs["Color1"].default_value, texture.inputs["Color2"].default_value = COLORS
        texture.inputs["Scale"].default_value = SCALE if variant not in ("object", "position", "other_object") else 1.5   # (object space spans 3)
    links.new(texture.outputs["Fac" if variant == "fac" else "Color"], target)
    if variant == "valued":
        value, rgb = nodes.new("ShaderNodeValue"), nodes.new("ShaderNodeRGB")
        value.outputs[0].default_value, rgb.outputs[0].default_value = VALUE_SCALE, RGB_COLOR
        links.new(value.outputs[0], texture.inputs["Scale"])
        links.new(rgb.outputs[0], texture.inputs["Color1"])
    if variant in ("cube", "image", "uv", "object", "position", "other_object"):
        coords = nodes.new("ShaderNodeTexCoord")
        named = coordinates or {"uv": "UV", "object": "Object", "other_object": "Object"}.get(variant, "Generated")
        source = None if named.startswith("Geometry:") else coords.outputs[named]
        if variant == "position":
            source = nodes.new("ShaderNodeNewGeometry").outputs["Position"]
        elif named.startswith("Geometry:"):
            source = nodes.new("ShaderNodeNewGeometry").outputs[named.split(":", 1)[1]]
        if variant == "other_object":
            empty = coords.object = link(bpy.data.objects.new("Empty", None))
            empty.location, empty.rotation_euler, empty.scale = EMPTY_PLACE
            if flat_empty:
                empty.scale.z = 0.0
        if variant != "uv":
            mapping = nodes.new("ShaderNodeMapping")
            mapping.vector_type = "POINT"
            for name, value in zip(("Location", "Rotation", "Scale"), TURN):
                mapping.inputs[name].default_value = value
            links.new(source, mapping.inputs["Vector"])
            source = mapping.outputs["Vector"]
        links.new(source, texture.inputs["Vector"])
    obj.data.materials.append(mat)
    if panorama:
        from scenes import PANORAMA_KINDS
        cam = bpy.context.scene.camera
        cam.location.y = -3.2
        cam.data.type = "PANO"
        pano = cam.data if hasattr(cam.data, "panorama_type") else cam.data.cycles      # Blender 4.x / 3.x
        pano_type, settings, lens = PANORAMA_KINDS.get(panorama, ("EQUIRECTANGULAR", {}, {}))
        pano.panorama_type = pano_type
        for name, value in settings.items():
            setattr(pano, name, value)
        for name, value in lens.items():
            setattr(cam.data, name, value)
    if smooth:
        obj.data.polygons.foreach_set("use_smooth", [True] * len(obj.data.polygons))
        obj.data.update()
    plain_world("World", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {"colors": COLORS, "scale": SCALE, "value_scale": VALUE_SCALE, "rgb": RGB_COLOR,
            "empty_location": EMPTY_PLACE[0], "mapping_location": TURN[0]}


def checker_material():
    """An Emission material whose Color is a Checker Texture at Generated coordinates."""
    mat = shader_material("Checkered", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes = mat.node_tree.nodes
    texture = nodes.new("ShaderNodeTexChecker")
    mat.node_tree.links.new(texture.outputs["Color"], nodes["Emission"].inputs["Color"])
    return mat


def checker_on_shapes_scene(resolution=(96, 72)):
    """hair_scene's strands (where the Python API makes hair curves) and a UV sphere flagged
    'Render as sphere', both with checker_material: shapes without Generated coordinates;
    and a second flagged sphere, Bumpy, whose Principled BSDF's Normal is a Bump node whose
    Height a Checker gives (which reads Generated coordinates too). Returns whether the hair exists."""
    from scenes import hair_scene, uv_sphere_object
    made = hair_scene(resolution=resolution)["segments"] is not None
    mat = checker_material()
    if made:
        bpy.data.hair_curves["Hair"].materials[0] = mat
    ball = link(uv_sphere_object("Ball", 1.0))
    ball.location = (0.0, -2.0, 0.0)
    ball.gridwalk.render_as_sphere = True
    ball.data.materials.append(mat)
    bumpy = link(uv_sphere_object("Bumpy", 1.0))
    bumpy.location = (2.5, -2.0, 0.0)
    bumpy.gridwalk.render_as_sphere = True
    bumped = bpy.data.materials.new("Bumped")
    bumped.use_nodes = True
    nodes = bumped.node_tree.nodes
    bump = nodes.new("ShaderNodeBump")
    bumped.node_tree.links.new(nodes.new("ShaderNodeTexChecker").outputs["Fac"], bump.inputs["Height"])
    bumped.node_tree.links.new(bump.outputs["Normal"], nodes["Principled BSDF"].inputs["Normal"])
    bumpy.data.materials.append(bumped)
    bpy.context.view_layer.update()
    return {"hair": made}


GRADIENTS = ("LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL")


RAMP = ((0.15, (0.9, 0.2, 0.1, 1.0)), (0.5, (0.1, 0.8, 0.2, 1.0)), (0.8, (0.2, 0.3, 1.0, 1.0)))


def emissive_plane(name, resolution):
    """(plane, its material): a new scene with a 7 x 7 plane facing the camera and a material
    `name` of one Emission shader (Strength 1), for the caller to feed and append."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.0, rotation=(math.pi / 2, 0, 0))
    return bpy.context.object, shader_material(name, "ShaderNodeEmission", [("Strength", 1.0)])


def tinted(tree, socket, tint):
    """The Color output of a Mix node (MixRGB) multiplying `socket` by the colour `tint`, factor 1."""
    mix = tree.nodes.new("ShaderNodeMixRGB")
    mix.blend_type, mix.inputs["Fac"].default_value = "MULTIPLY", 1.0
    mix.inputs["Color2"].default_value = tint
    tree.links.new(socket, mix.inputs["Color1"])
    return mix.outputs["Color"]


def procedural_gradient_scene(gradient="LINEAR", resolution=(96, 72), ramp=None):
    """A plane facing the camera, its Emission's Color a Gradient Texture of type `gradient`
    at the plane's Object coordinates through a Mapping node: the ramps from x = 0 to 1
    across the plane (moved and scaled so that both clamped ends show), the spheres and
    the radial one about its centre. ramp: a Color Ramp of the RAMP stops with that
    interpolation between the gradient and the shader; "SHARED": Linear, a fourth stop
    (blue) at the green one's position, a hard edge; "ODD": B-Spline in HSV mode, the
    first stop moved past the others by a script (Blender keeps the stops in that order);
    "FIXED": Linear, its Fac a Value node (0.3) instead of the gradient (one colour);
    "AFTER": Linear, the gradient x 0.8 + 0.1 (a Math node) before it, and after it a
    Separate Color's green x 2 - 0.3 (a clamped Math Multiply Add) into the Color;
    "TINTED": Linear, a Mix multiplying its colour by a tint after it."""
    plane, mat = emissive_plane("Graded", resolution)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    texture = nodes.new("ShaderNodeTexGradient")
    texture.gradient_type = gradient
    mapping = nodes.new("ShaderNodeMapping")
    centred = gradient in ("SPHERICAL", "QUADRATIC_SPHERE", "RADIAL")
    mapping.inputs["Location"].default_value = (0.0, 0.0, 0.0) if centred else (0.5, 0.45, 0.0)
    mapping.inputs["Scale"].default_value = (0.3, 0.3, 0.3) if centred else (0.16, 0.12, 0.16)
    links.new(nodes.new("ShaderNodeTexCoord").outputs["Object"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    if ramp is None:
        links.new(texture.outputs["Color"], nodes["Emission"].inputs["Color"])
    else:
        node = nodes.new("ShaderNodeValToRGB")
        elements = node.color_ramp.elements
        elements[0].position, elements[0].color = RAMP[0]
        elements[1].position, elements[1].color = RAMP[2]
        middle = elements.new(RAMP[1][0])
        middle.color = RAMP[1][1]
        node.color_ramp.interpolation = {"SHARED": "LINEAR", "ODD": "B_SPLINE", "FIXED": "LINEAR", "AFTER": "LINEAR",
                                         "TINTED": "LINEAR"}.get(ramp, ramp)
        if ramp == "SHARED":
            edge = elements.new(RAMP[1][0])
            edge.color = (0.05, 0.1, 0.9, 1.0)
        if ramp == "ODD":
            node.color_ramp.color_mode = "HSV"
            elements[0].position = 0.9
        if ramp == "FIXED":
            value = nodes.new("ShaderNodeValue")
            value.outputs[0].default_value = 0.3
            links.new(value.outputs[0], node.inputs["Fac"])
        elif ramp == "AFTER":
            before = nodes.new("ShaderNodeMath")
            before.operation, before.inputs[1].default_value, before.inputs[2].default_value = "MULTIPLY_ADD", 0.8, 0.1
            links.new(texture.outputs["Fac"], before.inputs[0])
            links.new(before.outputs[0], node.inputs["Fac"])
        else:
            links.new(texture.outputs["Fac"], node.inputs["Fac"])
        color = node.outputs["Color"]
        if ramp == "AFTER":
            split = nodes.new("ShaderNodeSeparateColor" if bpy.app.version >= (3, 3) else "ShaderNodeSeparateRGB")
            after = nodes.new("ShaderNodeMath")
            after.operation, after.use_clamp = "MULTIPLY_ADD", True
            after.inputs[1].default_value, after.inputs[2].default_value = 2.0, -0.3
            links.new(color, split.inputs[0])
            links.new(split.outputs[1], after.inputs[0])
            color = after.outputs[0]
        if ramp == "TINTED":
            color = tinted(mat.node_tree, color, (0.9, 0.5, 0.2, 1.0))
        links.new(color, nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    plain_world("World", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}
