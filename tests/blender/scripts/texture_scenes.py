"""Scenes about where a texture lands (render_scene.py and export_dump.py build them by name)."""
import math

import bpy
import numpy as np

from blender_addon.scripting import principled_material
from material_scenes import _filled_image
from scenes import add_light, plain_world, reset, shader_material

# Mapping nodes from the UV map to the image, the first applied first:
# (vector type, location, rotation in radians, scale)
TURNED = ((0.3, -0.2, 0.0), (0.0, 0.0, math.radians(30.0)), (2.5, 1.5, 1.0))
MAPPINGS = {
    "none": [],
    "point": [("POINT", *TURNED)],
    "texture": [("TEXTURE", *TURNED)],
    "vector": [("VECTOR", *TURNED)],
    # turned about every axis, moved along z too: the second map sees the first's z
    "chain": [("POINT", (0.1, 0.0, 0.4), (0.5, 0.0, 0.2), (1.5, 2.0, 1.0)),
              ("TEXTURE", (0.1, 0.2, 0.7), (0.3, 0.2, 0.5), (0.5, 2.0, 3.0))],
}


CONSTANT = (0.6, 0.3, 0.0)      # the first Mapping's own Vector where nothing feeds it


def _mapping(nodes, kind, location, rotation, scale):
    node = nodes.new("ShaderNodeMapping")
    node.vector_type = kind
    if kind in ("POINT", "TEXTURE"):       # (the other types have no Location input)
        node.inputs["Location"].default_value = location
    node.inputs["Rotation"].default_value = rotation
    node.inputs["Scale"].default_value = scale
    return node


def mapped_texture_scene(chain="point", source="coordinates", extension="REPEAT", valued=False,
                         resolution=(96, 72)):
    """A plane filling the view, its Emission shader's Color an 8 x 8 image of random 8-bit colours
    read through the Mapping nodes MAPPINGS[chain] from `source`: "coordinates" (a Texture
    Coordinate's UV), "uvmap" (a UV Map node naming the plane's layer) or "constant" (the
    first Mapping's Vector unlinked, set to CONSTANT), the image's `extension` as given; valued: a
    Value node of 3 feeds the first map's Scale instead. chain "unread": a Normal-type Mapping and a
    Point one whose Scale a Texture Coordinate node's Object output gives. Returns the maps (as
    applied), the constant vector they map (None: the UV map) and the image's pixels."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.0, rotation=(math.pi / 2, 0, 0))
    plane = bpy.context.object
    pixels = np.random.default_rng(5).integers(0, 256, (8, 8, 4)) / 255.0
    pixels[..., 3] = 1.0
    image = _filled_image("Random", pixels, float_buffer=False)
    mat = shader_material("Mapped", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation, tex.extension = image, "Linear", extension
    links.new(tex.outputs["Color"], nodes["Emission"].inputs["Color"])
    maps = MAPPINGS.get(chain, [])
    chained = [_mapping(nodes, *m) for m in maps]
    if valued:
        value = nodes.new("ShaderNodeValue")
        value.outputs[0].default_value = 3.0
        links.new(value.outputs[0], chained[0].inputs["Scale"])
        maps = [(*maps[0][:3], (3.0, 3.0, 3.0)), *maps[1:]]
    if chain == "unread":
        chained = [_mapping(nodes, "NORMAL", *TURNED), _mapping(nodes, "POINT", *TURNED)]
        links.new(nodes.new("ShaderNodeTexCoord").outputs["Object"], chained[1].inputs["Scale"])
    for a, b in zip(chained, chained[1:]):
        links.new(a.outputs["Vector"], b.inputs["Vector"])
    if chained:
        links.new(chained[-1].outputs["Vector"], tex.inputs["Vector"])
    first = chained[0].inputs["Vector"] if chained else tex.inputs["Vector"]
    if source == "constant":
        first.default_value = CONSTANT
    elif source == "coordinates":
        links.new(nodes.new("ShaderNodeTexCoord").outputs["UV"], first)
    elif source == "uvmap":
        uv = nodes.new("ShaderNodeUVMap")
        uv.uv_map = plane.data.uv_layers[0].name
        links.new(uv.outputs["UV"], first)
    plane.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {"maps": maps, "start": CONSTANT if source == "constant" else None, "pixels": pixels.tolist()}


def _node(nodes, kind, inputs=(), **settings):
    """A new node of `kind`: its settings, then its inputs by identifier (or index) to values."""
    node = nodes.new(kind)
    for key, value in settings.items():
        setattr(node, key, value)
    for key, value in inputs:
        socket = node.inputs[key] if isinstance(key, int) else next(s for s in node.inputs if s.identifier == key)
        socket.default_value = value
    return node


# Chains from the image to the Emission shader's Color, each a list of
# (output to take, node type, inputs set, settings, input the chain enters);
# the first step takes the image's Color or Alpha output.
CHAINS = {
    "tint": ("Color", [("Result", "ShaderNodeMix", [("Factor_Float", 0.8), ("B_Color", (0.9, 0.5, 0.2, 1.0))],
                        {"data_type": "RGBA", "blend_type": "MULTIPLY"}, "A_Color")]),
    "green": ("Color", [("Green", "ShaderNodeSeparateColor", [], {}, "Color"),
                        ("Value", "ShaderNodeMath", [(1, 0.7)], {"operation": "MULTIPLY"}, 0),
                        ("Value", "ShaderNodeMath", [(1, 0.1)], {"operation": "ADD", "use_clamp": True}, 0)]),
    "invert": ("Color", [("Color", "ShaderNodeInvert", [("Fac", 0.75)], {}, "Color"),
                         ("Result", "ShaderNodeMix", [("Factor_Float", 0.3), ("A_Color", (0.2, 0.4, 0.9, 1.0))],
                          {"data_type": "RGBA", "blend_type": "MIX"}, "B_Color")]),
    "luminance": ("Color", [("Value", "ShaderNodeMath", [(0, 1.0)], {"operation": "SUBTRACT"}, 1)]),
    "alpha": ("Alpha", [("Value", "ShaderNodeMath", [(1, 1.5), (2, 0.1)], {"operation": "MULTIPLY_ADD"}, 0),
                        ("Result", "ShaderNodeMix", [("Factor_Float", 0.5), ("B_Float", 0.2)],
                         {"data_type": "FLOAT"}, "A_Float")]),
    "legacy": ("Color", [("Color", "ShaderNodeMixRGB", [("Fac", 1.0), ("Color2", (0.5, 0.9, 0.7, 1.0))],
                          {"blend_type": "MULTIPLY"}, "Color1"),
                         ("R", "ShaderNodeSeparateRGB", [], {}, "Image")]),
    "divide": ("Color", [("Value", "ShaderNodeMath", [(1, 2.0)], {"operation": "DIVIDE"}, 0)]),
    # a factor beyond 1 where its clamp is off; a float mix's Clamp Result (Color mode's only)
    "overdrive": ("Color", [("Result", "ShaderNodeMix", [("Factor_Float", 1.5), ("B_Color", (0.2, 0.3, 0.1, 1.0))],
                             {"data_type": "RGBA", "blend_type": "MIX", "clamp_factor": False}, "A_Color")]),
    "float_clamp": ("Alpha", [("Result", "ShaderNodeMix", [("Factor_Float", 0.5), ("B_Float", 3.0)],
                               {"data_type": "FLOAT", "clamp_result": True}, "A_Float")]),
    "unread": ("Color", [("Color", "ShaderNodeGamma", [("Gamma", 2.2)], {}, "Color")]),   # (not a map the export folds)
    "linked_fac": ("Color", [("Color", "ShaderNodeInvert", [], {}, "Color")]),    # (its Fac: the image's alpha)
}


def node_chain_scene(chain="tint", resolution=(48, 36)):
    """A plane filling the view, its Emission shader's Color fed by an 8 x 8 image of random
    8-bit colours and alphas through the nodes CHAINS[chain]."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.0, rotation=(math.pi / 2, 0, 0))
    plane = bpy.context.object
    pixels = np.random.default_rng(9).integers(0, 256, (8, 8, 4)) / 255.0
    mat = shader_material("Chained", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = _filled_image("Random", pixels, float_buffer=False), "Closest"
    output, steps = CHAINS[chain]
    socket = tex.outputs[output]
    for take, kind, inputs, settings, into in steps:
        node = _node(nodes, kind, inputs, **settings)
        target = node.inputs[into] if isinstance(into, int) else next(s for s in node.inputs if s.identifier == into)
        links.new(socket, target)
        socket = next(s for s in node.outputs if s.name == take and s.enabled)
    links.new(socket, nodes["Emission"].inputs["Color"])
    if chain == "linked_fac":
        links.new(tex.outputs["Alpha"], socket.node.inputs["Fac"])
    plane.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {}


def emission_map_scene(resolution=(64, 48)):
    """A 3 x 3 panel facing the camera above a grey floor, in a black world with no lamp: its
    Principled BSDF is black and rough, its Emission Color a 4 x 4 image of random 8-bit colours,
    Emission Strength 3. The floor is lit by the panel alone; the camera looks down at it."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.location, scene.camera.rotation_euler = (0, -9, 4), (math.radians(70), 0, 0)
    bpy.ops.mesh.primitive_plane_add(size=3.0, location=(0, 0, 0.7), rotation=(math.pi / 2, 0, 0))
    panel = bpy.context.object
    pixels = np.random.default_rng(11).integers(0, 256, (4, 4, 4)) / 255.0
    pixels[..., 3] = 1.0
    mat = principled_material("Screen", (0.0, 0.0, 0.0), Roughness=1.0)
    nodes = mat.node_tree.nodes
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = _filled_image("Glow", pixels, float_buffer=False), "Closest"
    bsdf = nodes["Principled BSDF"]
    colour = bsdf.inputs["Emission Color"] if "Emission Color" in bsdf.inputs else bsdf.inputs["Emission"]
    mat.node_tree.links.new(tex.outputs["Color"], colour)
    bsdf.inputs["Emission Strength"].default_value = 3.0
    panel.data.materials.append(mat)
    bpy.ops.mesh.primitive_plane_add(size=30.0, location=(0, 0, -1.0))
    bpy.context.object.data.materials.append(principled_material("Floor", (0.8, 0.8, 0.8), Roughness=1.0))
    plain_world("World", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


def bump_scene(distance=0.3, invert=False, strength=1.0, scale=1.0, tilt=None, resolution=(96, 48)):
    """A grey plane (7 x 7, Diffuse BSDF) facing the camera, its Normal from a Bump node whose Height is a
    float image of 4 sine stripes across u (Non-Color), lit by a sun from the side (45 degrees
    from +x): the stripes' slopes facing the sun are brighter. scale: the object's scale (its mesh
    7 / scale across: the same plane in the world). tilt: a Tangent Space Normal Map of one
    normal, leaning `tilt` degrees along u, feeds the Bump's own Normal."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.0 / scale, rotation=(math.pi / 2, 0, 0))
    plane = bpy.context.object
    plane.scale = (scale, scale, scale)
    u = (np.arange(64) + 0.5) / 64
    height = 0.5 + 0.5 * np.sin(2 * math.pi * 4 * u)
    pixels = np.ones((4, 64, 4))
    pixels[..., :3] = height[None, :, None]
    mat = shader_material("Bumpy", "ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.8, 0.8, 1.0))])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = _filled_image("Height", pixels, float_buffer=True, non_color=True)
    bump = nodes.new("ShaderNodeBump")
    bump.invert = invert
    bump.inputs["Distance"].default_value, bump.inputs["Strength"].default_value = distance, strength
    links.new(tex.outputs["Color"], bump.inputs["Height"])
    links.new(bump.outputs["Normal"], nodes["Diffuse BSDF"].inputs["Normal"])
    if tilt is not None:
        lean = np.ones((2, 2, 4))
        lean[..., :3] = (0.5 + 0.5 * math.sin(math.radians(tilt)), 0.5, 0.5 + 0.5 * math.cos(math.radians(tilt)))
        image = nodes.new("ShaderNodeTexImage")
        image.image = _filled_image("Lean", lean, float_buffer=True, non_color=True)
        nmap = nodes.new("ShaderNodeNormalMap")
        links.new(image.outputs["Color"], nmap.inputs["Color"])
        links.new(nmap.outputs["Normal"], bump.inputs["Normal"])
    plane.data.materials.append(mat)
    add_light("Sun", "SUN", (0, -5, 0), (math.radians(90), 0, math.radians(45)), energy=3.0)
    plain_world("World", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


def tinted_by_attribute_scene(legacy=False, resolution=(48, 36)):
    """A plane filling the view, its Emission Color an 8 x 8 image of random 8-bit colours times a
    colour attribute "Tint" (red, green, blue and white at its corners) through a Mix node
    (Multiply, factor 1; legacy: a MixRGB), as Blender's glTF importer wires vertex colours."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.0, rotation=(math.pi / 2, 0, 0))
    plane = bpy.context.object
    tint = plane.data.color_attributes.new("Tint", "FLOAT_COLOR", "CORNER")
    corners = [(1.0, 0.2, 0.2, 1.0), (0.2, 1.0, 0.2, 1.0), (0.2, 0.2, 1.0, 1.0), (1.0, 1.0, 1.0, 1.0)]
    for i, loop in enumerate(plane.data.loops):
        tint.data[i].color = corners[loop.vertex_index % 4]
    pixels = np.random.default_rng(4).integers(0, 256, (8, 8, 4)) / 255.0
    pixels[..., 3] = 1.0
    mat = shader_material("Tinted", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = _filled_image("Random", pixels, float_buffer=False), "Closest"
    attribute = nodes.new("ShaderNodeVertexColor")
    attribute.layer_name = "Tint"
    if legacy:
        mix = _node(nodes, "ShaderNodeMixRGB", [("Fac", 1.0)], blend_type="MULTIPLY")
        a, b = mix.inputs["Color1"], mix.inputs["Color2"]
    else:
        mix = _node(nodes, "ShaderNodeMix", [("Factor_Float", 1.0)], data_type="RGBA", blend_type="MULTIPLY")
        a, b = (next(s for s in mix.inputs if s.identifier == i) for i in ("A_Color", "B_Color"))
    links.new(tex.outputs["Color"], a)
    links.new(attribute.outputs["Color"], b)
    links.new(next(s for s in mix.outputs if s.enabled), nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {}
