"""Geometry Nodes scattering at the scale people use it (test_b01): two carriers, each
instancing its own hidden source cube on the points of a Mesh Line, every instance turned
and scaled by a Random Value node. With 6,000 instances each, the export's mesh instances
span more than one block of matrix rows (MeshCollector's ROW_BLOCK of 8,192).

scatter_scene returns the triangle count and, for every 97th instance the depsgraph lists,
its world-space corners: its matrix (mathutils) applied to its mesh's vertices, read here
apart from the export's own code."""
import bpy

from scenes import cube_object, geometry_group, link, reset


def _scatter_group(name, source, count, seed, variant="object"):
    """Instances of `source` (an object; a collection for the variants "collection" and
    "picked") on `count` points, turned and scaled at random (see carrier_scene)."""
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if bpy.app.version >= (4, 0, 0):
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        if variant == "mixed":
            group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    else:
        group.outputs.new("NodeSocketGeometry", "Geometry")
        if variant == "mixed":
            group.inputs.new("NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    output = nodes.new("NodeGroupOutput")
    points = nodes.new("GeometryNodeMeshLine")
    points.inputs["Count"].default_value = count
    points.inputs["Offset"].default_value = (0.01, 0.003, 0.0)
    if variant in ("collection", "picked"):
        info = nodes.new("GeometryNodeCollectionInfo")
        info.inputs["Collection"].default_value = source
        info.inputs["Separate Children"].default_value = variant == "picked"
    elif variant == "primitive":
        info = nodes.new("GeometryNodeMeshIcoSphere")
        info.inputs["Radius"].default_value, info.inputs["Subdivisions"].default_value = 0.1, 2
    else:
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
    made = info.outputs.get("Instances") or info.outputs.get("Mesh") or info.outputs["Geometry"]
    links.new(made, on_points.inputs["Instance"])
    links.new(turn.outputs[0], on_points.inputs["Rotation"])
    links.new(size.outputs[1], on_points.inputs["Scale"])
    if variant == "picked":
        pick = nodes.new("FunctionNodeRandomValue")
        pick.data_type = "INT"
        pick.inputs[5].default_value, pick.inputs["Seed"].default_value = 1, seed + 2     # (the INT Max)
        on_points.inputs["Pick Instance"].default_value = True
        links.new(pick.outputs["Value"], on_points.inputs["Instance Index"])
    result = on_points.outputs["Instances"]
    if variant == "mixed":      # the carrier's own mesh beside the copies
        join = nodes.new("GeometryNodeJoinGeometry")
        links.new(nodes.new("NodeGroupInput").outputs[0], join.inputs[0])
        links.new(result, join.inputs[0])
        result = join.outputs[0]
    links.new(result, output.inputs[0])
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


CARRIER_VARIANTS = ("object", "primitive", "collection", "picked", "light", "hidden", "far", "mixed")


def carrier_scene(variant="object", count=2000):
    """One Geometry Nodes carrier with `count` copies, each turned and scaled at random, of:
    object      a hidden cube (Object Info, As Instance)
    primitive   an icosphere the node tree makes (Ico Sphere: a geometry set, no object)
    collection  a hidden collection of two cubes (each point lists two instances)
    picked      one of a collection's two cubes at random (Separate Children, Pick Instance)
    light       a point light
    hidden      the cube, the carrier hidden from renders
    far         the cube, the carrier scaled 1e29 (copies beyond 1e30 in world space)
    mixed       the cube, beside the carrier's own mesh (a cube too)
    and a lit plane below, a cube made after the carrier. Returns the variant."""
    from scenes import add_light
    reset()
    floor = link(cube_object("Floor", size=1.0))
    floor.scale, floor.location = (40.0, 40.0, 0.01), (0.0, 0.0, -1.0)
    add_light("Sun", "SUN", (0.0, 0.0, 10.0), energy=2.0)
    if variant in ("collection", "picked"):
        source = bpy.data.collections.new("Sources")
        bpy.context.scene.collection.children.link(source)
        for k, size in enumerate((0.2, 0.1)):
            cube = cube_object(f"Source{k}", size=size)
            cube.location = (0.0, 0.3 * k, 0.0)
            source.objects.link(cube)
        source.hide_render = True
    elif variant == "light":
        source = link(bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT")))
        source.data.energy = 5.0
        source.hide_render = True
    else:
        source = link(cube_object("Source", size=0.2))
        source.hide_render = True
    data = cube_object("CarrierMesh", size=0.5).data if variant == "mixed" else bpy.data.meshes.new("CarrierMesh")
    carrier = link(bpy.data.objects.new("Carrier", data))
    carrier.location = (-10.0, -3.0, 0.0)
    if variant == "far":
        carrier.scale = (1e29, 1e29, 1e29)
    carrier.hide_render = variant == "hidden"
    carrier.modifiers.new("Scatter", "NODES").node_group = _scatter_group("Scatter", source, count, 3, variant)
    after = link(cube_object("After", size=0.3))       # (an object made after the carrier)
    after.location = (2.0, 2.0, 0.0)
    bpy.context.view_layer.update()
    return {"variant": variant}


def volume_output_scene(resolution=(32, 24)):
    """A cube whose Geometry Nodes output its own mesh joined with a Mesh to Volume of it: the
    depsgraph lists a volume instance of the cube besides its mesh."""
    reset(resolution=tuple(resolution))
    cube = link(cube_object("Smoky"))
    group = geometry_group("Smoke")
    nodes, links = group.nodes, group.links
    given, output = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    volume, join = nodes.new("GeometryNodeMeshToVolume"), nodes.new("GeometryNodeJoinGeometry")
    links.new(given.outputs[0], volume.inputs["Mesh"])
    links.new(given.outputs[0], join.inputs[0])
    links.new(volume.outputs[0], join.inputs[0])
    links.new(join.outputs[0], output.inputs[0])
    cube.modifiers.new("Smoke", "NODES").node_group = group
    bpy.context.view_layer.update()
    return {}
