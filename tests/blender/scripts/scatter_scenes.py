"""Geometry Nodes scattering at the scale people use it (test_b01): two carriers, each
instancing its own hidden source cube on the points of a Mesh Line, every instance turned
and scaled by a Random Value node. With 6,000 instances each, the export's mesh instances
span more than one block of matrix rows (MeshCollector's ROW_BLOCK of 8,192).

scatter_scene returns the triangle count and, for every 97th instance the depsgraph lists,
its world-space corners: its matrix (mathutils) applied to its mesh's vertices, read here
apart from the export's own code."""
import bpy

from scenes import cube_object, link, reset


def _scatter_group(name, source, count, seed):
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if bpy.app.version >= (4, 0, 0):
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        group.outputs.new("NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    output = nodes.new("NodeGroupOutput")
    points = nodes.new("GeometryNodeMeshLine")
    points.inputs["Count"].default_value = count
    points.inputs["Offset"].default_value = (0.01, 0.003, 0.0)
    info = nodes.new("GeometryNodeObjectInfo")
    info.inputs["Object"].default_value = source
    info.inputs["As Instance"].default_value = True
    turn = nodes.new("FunctionNodeRandomValue")
    turn.data_type = "FLOAT_VECTOR"
    turn.inputs["Max"].default_value = (3.0, 3.0, 3.0)
    turn.inputs["Seed"].default_value = seed
    size = nodes.new("FunctionNodeRandomValue")
    size.inputs[2].default_value, size.inputs[3].default_value = 0.5, 2.0    # (the FLOAT Min and Max)
    size.inputs["Seed"].default_value = seed + 1
    on_points = nodes.new("GeometryNodeInstanceOnPoints")
    links.new(points.outputs["Mesh"], on_points.inputs["Points"])
    links.new(info.outputs["Geometry"], on_points.inputs["Instance"])
    links.new(turn.outputs[0], on_points.inputs["Rotation"])
    links.new(size.outputs[1], on_points.inputs["Scale"])
    links.new(on_points.outputs["Instances"], output.inputs[0])
    return group


def scatter_scene(count=6000):
    reset()
    carriers = []
    for k, (size, z) in enumerate(((0.2, 0.0), (0.08, 2.0))):
        source = link(cube_object(f"Source{k}", size=size))
        source.hide_render = True
        carrier = link(bpy.data.objects.new(f"Carrier{k}", bpy.data.meshes.new(f"CarrierMesh{k}")))
        carrier.location = (-30.0, -9.0, z)
        carrier.modifiers.new("Scatter", "NODES").node_group = _scatter_group(f"Scatter{k}", source, count, 7 * k)
        carriers.append(carrier.name)
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    instances, sampled = 0, []
    for inst in depsgraph.object_instances:
        if not (inst.is_instance and inst.parent is not None and inst.parent.original.name in carriers):
            continue
        if instances % 97 == 0:
            matrix = inst.matrix_world.copy()
            sampled.append([list(matrix @ v.co) for v in inst.object.data.vertices])
        instances += 1
    return {"triangles": 12 * instances, "instances": instances, "sampled_corners": sampled}
