"""Materials built from node groups (test_b53; render_scene.py and export_dump.py build them by name)."""
import math

import bpy

from scenes import reset, shader_material


def _group(name, inputs, outputs):
    """An empty shader node group with (name, socket type[, default]) inputs and (name, socket type) outputs,
    its Group Input and Group Output nodes."""
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for spec in inputs:
        _socket(group, spec[0], "INPUT", spec[1], spec[2] if len(spec) > 2 else None)
    for spec in outputs:
        _socket(group, spec[0], "OUTPUT", spec[1], None)
    return group, group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")


def _socket(group, name, in_out, kind, default):
    if bpy.app.version >= (4, 0, 0):
        socket = group.interface.new_socket(name, in_out=in_out, socket_type=kind)
    else:
        socket = (group.inputs if in_out == "INPUT" else group.outputs).new(kind, name)
    if default is not None:
        socket.default_value = default


def _checker_ramp(nodes, links, scale_from=None):
    """A Checker (Generated coordinates) through a two-stop Color Ramp: its Color output."""
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 4.0
    if scale_from is not None:
        links.new(scale_from, checker.inputs["Scale"])
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.95, 0.8, 0.2, 1.0)
    ramp.color_ramp.elements[1].color = (0.05, 0.1, 0.4, 1.0)
    links.new(checker.outputs["Fac"], ramp.inputs["Fac"])
    return ramp.outputs["Color"]


def node_group_scene(variant="shader", resolution=(96, 72)):
    """A square filling the view, its material's Emission colour made by node groups:
      shader    the Surface a group holding an Emission whose Color and Strength are the group's
                inputs: Color linked from a Checker through a Color Ramp outside, Strength 1.5 unlinked
      texture   the Emission Color a group holding the Checker and its ramp, its Scale from the
                group's input (unlinked: 7)
      nested    a group holding a group (the Checker and ramp), times the outer group's Gain (0.6)
      twice     the texture group in two materials, Scale 3 (left half) and 9 (right half)
      constant  a group passing its Color input (unlinked, orange) to its output"""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.5, rotation=(math.pi / 2, 0, 0))
    plane = bpy.context.object
    mat = shader_material("Grouped", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    emission = nodes["Emission"]
    place = nodes.new("ShaderNodeGroup")
    if variant == "shader":
        group, gin, gout = _group("Glow", [("Color", "NodeSocketColor", (1, 1, 1, 1)),
                                           ("Strength", "NodeSocketFloat", 1.0)], [("Shader", "NodeSocketShader")])
        inner = group.nodes.new("ShaderNodeEmission")
        group.links.new(gin.outputs["Color"], inner.inputs["Color"])
        group.links.new(gin.outputs["Strength"], inner.inputs["Strength"])
        group.links.new(inner.outputs[0], gout.inputs["Shader"])
        place.node_tree = group
        place.inputs["Strength"].default_value = 1.5
        links.new(_checker_ramp(nodes, links), place.inputs["Color"])
        links.new(place.outputs["Shader"], nodes["Material Output"].inputs["Surface"])
    elif variant in ("texture", "twice"):
        group, gin, gout = _group("Pattern", [("Scale", "NodeSocketFloat", 5.0)], [("Color", "NodeSocketColor")])
        group.links.new(_checker_ramp(group.nodes, group.links, gin.outputs["Scale"]), gout.inputs["Color"])
        place.node_tree = group
        place.inputs["Scale"].default_value = 7.0 if variant == "texture" else 3.0
        links.new(place.outputs["Color"], emission.inputs["Color"])
        if variant == "twice":               # the right half: a second material, the group at Scale 9
            plane.scale.x, plane.location.x = 0.5, -1.875
            bpy.ops.mesh.primitive_plane_add(size=7.5, rotation=(math.pi / 2, 0, 0), location=(1.875, 0, 0))
            right = bpy.context.object
            right.scale.x = 0.5
            other = mat.copy()
            other.node_tree.nodes["Group"].inputs["Scale"].default_value = 9.0
            right.data.materials.append(other)
    elif variant == "nested":
        inner_group, _, inner_out = _group("Inner", [], [("Color", "NodeSocketColor")])
        inner_group.links.new(_checker_ramp(inner_group.nodes, inner_group.links), inner_out.inputs["Color"])
        group, gin, gout = _group("Outer", [("Gain", "NodeSocketFloat", 0.6)], [("Color", "NodeSocketColor")])
        held = group.nodes.new("ShaderNodeGroup")
        held.node_tree = inner_group
        scale = group.nodes.new("ShaderNodeMixRGB")
        scale.blend_type = "MULTIPLY"
        scale.inputs["Fac"].default_value = 1.0
        group.links.new(held.outputs["Color"], scale.inputs["Color1"])
        group.links.new(gin.outputs["Gain"], scale.inputs["Color2"])
        group.links.new(scale.outputs["Color"], gout.inputs["Color"])
        place.node_tree = group
        links.new(place.outputs["Color"], emission.inputs["Color"])
    else:
        group, gin, gout = _group("Pass", [("Color", "NodeSocketColor", (0.2, 0.2, 0.2, 1))],
                                  [("Color", "NodeSocketColor")])
        group.links.new(gin.outputs["Color"], gout.inputs["Color"])
        place.node_tree = group
        place.inputs["Color"].default_value = (0.9, 0.45, 0.1, 1.0)
        links.new(place.outputs["Color"], emission.inputs["Color"])
    plane.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {"variant": variant}


def group_edge_scene(variant="twice_through", resolution=(48, 36)):
    """Node-group chains whose reading is easy to get wrong (test_b53's export checks):
      twice_through  an RGB node through the same pass-through group twice into the Emission Color
      narrowed       a red RGB node into a group's number input passed to its colour output (Cycles
                     shows that number's grey: not followed, the group is named in a warning)
      world          the world's Background Color from the same pass-through group, fed the RGB node"""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=7.5, rotation=(math.pi / 2, 0, 0))
    plane = bpy.context.object
    mat = shader_material("Edges", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    rgb = nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.9, 0.5, 0.1, 1.0)
    if variant == "world":
        world = bpy.context.scene.world = bpy.data.worlds.new("Grouped")
        world.use_nodes = True
        tree = world.node_tree
        group, gin, gout = _group("Through", [("Color", "NodeSocketColor", (0.1, 0.1, 0.1, 1))],
                                  [("Color", "NodeSocketColor")])
        group.links.new(gin.outputs["Color"], gout.inputs["Color"])
        place = tree.nodes.new("ShaderNodeGroup")
        place.node_tree = group
        colour = tree.nodes.new("ShaderNodeRGB")
        colour.outputs[0].default_value = (0.9, 0.5, 0.1, 1.0)
        tree.links.new(colour.outputs[0], place.inputs["Color"])
        tree.links.new(place.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    elif variant == "twice_through":
        group, gin, gout = _group("Through", [("Color", "NodeSocketColor", (0.1, 0.1, 0.1, 1))],
                                  [("Color", "NodeSocketColor")])
        group.links.new(gin.outputs["Color"], gout.inputs["Color"])
        first, second = nodes.new("ShaderNodeGroup"), nodes.new("ShaderNodeGroup")
        first.node_tree = second.node_tree = group
        links.new(rgb.outputs[0], first.inputs["Color"])
        links.new(first.outputs["Color"], second.inputs["Color"])
        links.new(second.outputs["Color"], nodes["Emission"].inputs["Color"])
    else:
        group, gin, gout = _group("Narrow", [("Fac", "NodeSocketFloat", 0.5)], [("Color", "NodeSocketColor")])
        group.links.new(gin.outputs["Fac"], gout.inputs["Color"])
        place = nodes.new("ShaderNodeGroup")
        place.node_tree = group
        links.new(rgb.outputs[0], place.inputs["Fac"])
        links.new(place.outputs["Color"], nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {"variant": variant}
