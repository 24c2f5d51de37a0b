"""A shadow catcher scene (render_scene.py and export_dump.py build it by name)."""
import math

import bpy

from scenes import add_light, cube_object, link, plain_world, reset, shader_material


def shadow_catcher_scene(world=0.0, resolution=(96, 72), instanced=False):
    """A 12 x 12 floor set to Shadow Catcher under a red cube (its corner 1 above the floor) and a
    sun 40 degrees from overhead, behind the cube; the camera looks down at them from the front. world: the grey
    of the world, whose light fills the shadow (and, on an opaque film, what the floor shows).
    instanced: the floor is a Geometry Nodes copy of a hidden plane, its carrier the catcher."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.location, scene.camera.rotation_euler = (0.0, -9.0, 6.0), (math.radians(58.0), 0.0, 0.0)
    floor = link(cube_object("Floor", size=1.0))
    floor.scale, floor.location = (12.0, 12.0, 0.02), (0.0, 0.0, -0.01)
    floor.data.materials.append(shader_material("FloorGrey", "ShaderNodeBsdfDiffuse",
                                                [("Color", (0.6, 0.6, 0.6, 1.0))]))
    if instanced:
        carrier = link(bpy.data.objects.new("Carrier", bpy.data.meshes.new("CarrierMesh")))
        group = bpy.data.node_groups.new("Place", "GeometryNodeTree")
        if bpy.app.version >= (4, 0, 0):
            group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        else:
            group.outputs.new("NodeSocketGeometry", "Geometry")
        info = group.nodes.new("GeometryNodeObjectInfo")
        info.inputs["Object"].default_value = floor
        info.inputs["As Instance"].default_value = True
        info.transform_space = "RELATIVE"          # (the floor where it lies, scaled)
        group.links.new(info.outputs["Geometry"], group.nodes.new("NodeGroupOutput").inputs[0])
        carrier.modifiers.new("Place", "NODES").node_group = group
        carrier.is_shadow_catcher = True
        floor.hide_render = True
    else:
        floor.is_shadow_catcher = True
    cube = link(cube_object("Cube", size=1.6))
    cube.location, cube.rotation_euler = (0.3, 0.5, 1.0), (0.0, 0.0, math.radians(30.0))
    cube.data.materials.append(shader_material("Red", "ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.1, 0.1, 1.0))]))
    add_light("Sun", "SUN", (0.0, 0.0, 8.0), (math.radians(40.0), 0.0, math.radians(150.0)), energy=3.0, angle=0.0)
    plain_world("World", (world, world, world))
    bpy.context.view_layer.update()
    return {"world": world}
