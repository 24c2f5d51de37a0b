"""Mesh attributes an Attribute node reads (render_scene.py and export_dump.py build them by name)."""
import math

import bpy
import numpy as np

from scenes import reset, shader_material

ATTRIBUTES = {   # name -> (data type, domain)
    "face_value": ("FLOAT", "FACE"), "point_vector": ("FLOAT_VECTOR", "POINT"),
    "corner_colour": ("BYTE_COLOR", "CORNER"), "face_int": ("INT", "FACE"), "missing": (None, None),
    "face_int8": ("INT8", "FACE"), "point_int2": ("INT32_2D", "POINT"),     # (Blender 4.x+)
}


def attribute_scene(attribute="face_value", output="Color", ramp=False, resolution=(96, 72)):
    """A 6 x 6-face grid filling the view, its Emission Color an Attribute node's `output` of the
    generic attribute `attribute` (ATTRIBUTES), filled with values from a seeded generator;
    ramp: through a Color Ramp of three stops (blue, green, orange)."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=7, y_subdivisions=7, size=7.0, rotation=(math.pi / 2, 0, 0))
    grid = bpy.context.object
    mesh = grid.data
    name = attribute
    data_type, domain = ATTRIBUTES[name]
    rng = np.random.default_rng(11)
    if data_type is not None:
        attr = mesh.attributes.new(name, data_type, domain)
        n = len(attr.data)
        if data_type == "FLOAT":
            attr.data.foreach_set("value", rng.random(n).astype(np.float32))
        elif data_type in ("INT", "INT8"):
            attr.data.foreach_set("value", rng.integers(0, 2, n).astype(np.int32))
        elif data_type == "INT32_2D":
            attr.data.foreach_set("value", rng.integers(0, 2, 2 * n).astype(np.int32))
        elif data_type == "FLOAT_VECTOR":
            attr.data.foreach_set("vector", rng.random(3 * n).astype(np.float32))
        else:
            colours = rng.random((n, 4)).astype(np.float32)
            colours[:, 3] = 1.0
            attr.data.foreach_set("color", colours.reshape(-1))
    mat = shader_material("ByAttribute", "ShaderNodeEmission", [("Strength", 1.0)])
    node = mat.node_tree.nodes.new("ShaderNodeAttribute")
    node.attribute_name = name
    source = node.outputs[output]
    if ramp:
        colour_ramp = mat.node_tree.nodes.new("ShaderNodeValToRGB")
        stops = colour_ramp.color_ramp.elements
        stops[0].position, stops[0].color = 0.2, (0.1, 0.2, 0.9, 1.0)
        stops[1].position, stops[1].color = 0.8, (0.9, 0.5, 0.1, 1.0)
        stops.new(0.5).color = (0.2, 0.8, 0.3, 1.0)
        mat.node_tree.links.new(source, colour_ramp.inputs["Fac"])
        source = colour_ramp.outputs["Color"]
    mat.node_tree.links.new(source, mat.node_tree.nodes["Emission"].inputs["Color"])
    mesh.materials.append(mat)
    bpy.context.view_layer.update()
    return {"name": name}
