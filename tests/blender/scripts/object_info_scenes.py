"""Tiles whose material reads the Object Info node (test_b52; render_scene.py and
export_dump.py build them by name)."""
import math

import bpy
import numpy as np

from scenes import geometry_group, link, reset, shader_material

# Tile names: ASCII, a numbered duplicate's and UTF-8 (Cycles hashes a name's bytes for Random)
NAMES = ("Tile", "Tile.001", "Stone", "Brick", "Ünïcode", "Zebra", "Moss", "Tile.002", "Ash", "Oak", "Pine", "Élan")


def _tile_mesh():
    mesh = bpy.data.meshes.new("TileMesh")
    mesh.from_pydata([(-0.6, -0.6, 0.0), (0.6, -0.6, 0.0), (0.6, 0.6, 0.0), (-0.6, 0.6, 0.0)], [], [(0, 1, 2, 3)])
    return mesh


def _material(output, ramp, divide, attribute):
    """Emission whose Color is Object Info's `output` (with attribute, an Attribute node's of that
    type named "tint"; Location x 0.2 + 0.5 by two Mix nodes), divided by `divide` when given,
    through a three-stop Color Ramp with ramp."""
    mat = shader_material("ByObject", "ShaderNodeEmission", [("Strength", 1.0)])
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    if attribute:
        node = nodes.new("ShaderNodeAttribute")
        node.attribute_type, node.attribute_name = attribute, "tint"
    else:
        node = nodes.new("ShaderNodeObjectInfo")
    source = node.outputs[output]
    if output == "Location":             # (x, y, z) x 0.2 + 0.5: each tile's place as a colour
        for blend, value in (("MULTIPLY", 0.2), ("ADD", 0.5)):
            mix = nodes.new("ShaderNodeMixRGB")
            mix.blend_type, mix.inputs["Fac"].default_value = blend, 1.0
            mix.inputs["Color2"].default_value = (value, value, value, 1.0)
            links.new(source, mix.inputs["Color1"])
            source = mix.outputs["Color"]
    if divide:
        math_node = nodes.new("ShaderNodeMath")
        math_node.operation = "DIVIDE"
        math_node.inputs[1].default_value = divide
        links.new(source, math_node.inputs[0])
        source = math_node.outputs[0]
    if ramp:
        colour_ramp = nodes.new("ShaderNodeValToRGB")
        stops = colour_ramp.color_ramp.elements
        stops[0].position, stops[0].color = 0.2, (0.1, 0.2, 0.9, 1.0)
        stops[1].position, stops[1].color = 0.8, (0.9, 0.5, 0.1, 1.0)
        stops.new(0.5).color = (0.2, 0.8, 0.3, 1.0)
        links.new(source, colour_ramp.inputs["Fac"])
        source = colour_ramp.outputs["Color"]
    links.new(source, nodes["Emission"].inputs["Color"])
    return mat


def _group(name):
    return geometry_group(name)


def _points(mat):
    """A point cloud (Geometry Nodes' Mesh to Points of a tile's corners) of material `mat`."""
    group = _group("ToPoints")
    nodes, links = group.nodes, group.links
    to_points = nodes.new("GeometryNodeMeshToPoints")
    to_points.inputs["Radius"].default_value = 0.1
    links.new(nodes.new("NodeGroupInput").outputs[0], to_points.inputs["Mesh"])
    setter = nodes.new("GeometryNodeSetMaterial")
    setter.inputs["Material"].default_value = mat
    links.new(to_points.outputs[0], setter.inputs["Geometry"])
    links.new(setter.outputs[0], nodes.new("NodeGroupOutput").inputs[0])
    dots = link(bpy.data.objects.new("Dots", _tile_mesh()))
    dots.location = (0.0, -2.0, -2.0)
    dots.modifiers.new("ToPoints", "NODES").node_group = group


def _carrier(source, rows, columns, spacing, tint):
    """A Geometry Nodes carrier: `source` (as an instance, half its size) on the points of a
    rows x columns grid, facing the camera; tint: with a random colour "tint" stored on each."""
    group = _group("Tiles")
    nodes, links = group.nodes, group.links
    grid = nodes.new("GeometryNodeMeshGrid")
    grid.inputs["Size X"].default_value, grid.inputs["Size Y"].default_value = spacing * (columns - 1), \
        spacing * (rows - 1)
    grid.inputs["Vertices X"].default_value, grid.inputs["Vertices Y"].default_value = columns, rows
    info = nodes.new("GeometryNodeObjectInfo")
    info.inputs["Object"].default_value = source
    info.inputs["As Instance"].default_value = True
    on_points = nodes.new("GeometryNodeInstanceOnPoints")
    on_points.inputs["Scale"].default_value = (0.5, 0.5, 0.5)
    links.new(grid.outputs["Mesh"], on_points.inputs["Points"])
    links.new(info.outputs.get("Instances") or info.outputs["Geometry"], on_points.inputs["Instance"])
    result = on_points.outputs["Instances"]
    if tint:
        colour = nodes.new("FunctionNodeRandomValue")
        colour.data_type = "FLOAT_VECTOR"
        store = nodes.new("GeometryNodeStoreNamedAttribute")
        store.data_type, store.domain = "FLOAT_VECTOR", "INSTANCE"
        store.inputs["Name"].default_value = "tint"
        links.new(result, store.inputs["Geometry"])
        links.new(colour.outputs[0], store.inputs["Value"] if "Value" in store.inputs else store.inputs[3])
        result = store.outputs[0]
    links.new(result, nodes.new("NodeGroupOutput").inputs[0])
    carrier = link(bpy.data.objects.new("Carrier", bpy.data.meshes.new("CarrierMesh")))
    carrier.rotation_euler = (math.pi / 2, 0.0, 0.0)
    carrier.modifiers.new("Tiles", "NODES").node_group = group
    return carrier


# Each tile's custom property "tint" (an Attribute node of the Object or Instancer type reads it),
# by k % 5: a colour, a number, a whole number, none (black), a boolean
TINTS = (lambda rng: tuple(rng.uniform(0.05, 1.0, 3)), lambda rng: float(rng.uniform(0.1, 0.9)), lambda rng: 1,
         None, lambda rng: True)


def object_info_scene(output="Random", layout="objects", ramp=False, divide=0.0, sphere=False, points=False,
                      attribute="", second="", copies=8, resolution=(96, 72)):
    """Square tiles facing the camera, their Emission Color Object Info's `output` (Random,
    Color, Alpha, Object Index; `divide`: through a Math Divide by it; ramp: a Color Ramp):
      objects     12 tile objects sharing one mesh (NAMES), 4 x 3, each with its own Viewport
                  Display colour (Color, Alpha) and Pass Index
      collection  6 such tiles in a collection outside the scene, shown twice, side by side, by
                  two Empties instancing it
      copies      `copies` x `copies` Geometry Nodes copies of one hidden tile (8: the bulk path's 64)
      particles   a plane (not rendered) emitting the tile at its four corners (a particle system
                  with "tint" on its settings, red, and on the emitter, green)
    sphere: the tiles are 'Render as sphere' (a sphere has no corner colours: rendered as meshes);
    points: a point cloud of the same material below them. attribute ("OBJECT", "INSTANCER"): an
    Attribute node of that type named "tint" in Object Info's place (output: Color or Fac), each
    tile with a "tint" property (TINTS), the left Empty with one of its own, the copies with a
    random "tint" stored on each (Geometry Nodes' instance domain). second="attribute": the tiles'
    mesh has a second material slot reading the render Color Attribute."""
    reset(resolution=tuple(resolution))
    mat = _material(output, ramp, divide, attribute)
    mesh = _tile_mesh()
    mesh.materials.append(mat)
    if second == "attribute":
        other = shader_material("ByColour", "ShaderNodeEmission", [("Strength", 1.0)])
        colours = other.node_tree.nodes.new("ShaderNodeVertexColor")
        other.node_tree.links.new(colours.outputs["Color"], other.node_tree.nodes["Emission"].inputs["Color"])
        mesh.materials.append(other)
    rng = np.random.default_rng(5)

    def tile(name, location, collection=None, index=0):
        obj = link(bpy.data.objects.new(name, mesh), collection)
        obj.location, obj.rotation_euler = location, (math.pi / 2, 0.0, 0.0)
        obj.color = (*rng.uniform(0.05, 1.0, 3), rng.uniform(0.1, 1.0))
        obj.pass_index = index
        tint = TINTS[index % len(TINTS)]
        if tint is not None:
            obj["tint"] = tint(rng)
        if sphere:
            obj.gridwalk.render_as_sphere = True
        return obj

    if layout == "objects":
        for k, name in enumerate(NAMES):
            tile(name, (-2.25 + 1.5 * (k % 4), 0.0, 1.5 - 1.5 * (k // 4)), index=k + 1)
    elif layout == "collection":
        tiles = bpy.data.collections.new("Tiles")           # (not in the scene: shown by its instances)
        for k, name in enumerate(NAMES[:6]):
            tile(name, (-0.75 + 1.5 * (k % 2), 0.0, 1.5 - 1.5 * (k // 2)), tiles, index=k + 1)
        for x in (-1.5, 1.5):
            empty = link(bpy.data.objects.new(f"Shelf{x:+.0f}", None))
            empty.instance_type, empty.instance_collection = "COLLECTION", tiles
            empty.location = (x, 0.0, 0.0)
            if x < 0:
                empty["tint"] = (0.7, 0.7, 0.1)
    elif layout == "particles":
        source = tile("Tile", (0.0, 40.0, 0.0), index=3)       # (behind the camera's view: its copies show)
        source.scale = (0.5, 0.5, 0.5)
        bpy.ops.mesh.primitive_plane_add(size=3.0, rotation=(math.pi / 2, 0, 0))
        emitter = bpy.context.object
        emitter["tint"] = (0.1, 0.9, 0.1)
        emitter.modifiers.new("Scatter", "PARTICLE_SYSTEM")
        settings = emitter.particle_systems[0].settings
        settings.count, settings.frame_start, settings.frame_end, settings.lifetime = 4, 1, 1, 100
        settings.emit_from, settings.use_emit_random, settings.physics_type = "VERT", False, "NO"
        settings.render_type, settings.instance_object = "OBJECT", source
        emitter.show_instancer_for_render = False
        settings["tint"] = (0.9, 0.1, 0.1)
        bpy.context.scene.frame_set(1)
    else:
        source = tile("Tile", (0.0, 0.0, 0.0), index=3)
        source.rotation_euler = (0.0, 0.0, 0.0)
        source.hide_render = True
        _carrier(source, copies, copies, 0.7, bool(attribute))
    if points:
        _points(mat)
    bpy.context.view_layer.update()
    return {"output": output, "layout": layout}
