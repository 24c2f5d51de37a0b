"""Test scenes built with bpy (run inside Blender / the bpy module).

Each builder starts from an empty factory scene, adds a camera unless told
not to, and returns a dict of expected values computed with mathutils (an
independent path from the exporter's numpy code).
"""
import math

import bpy
from mathutils import Euler, Matrix, Vector

from blender_addon.scripting import principled_material


def reset(camera=True, resolution=(64, 48), factory=True):
    """An empty scene (factory settings; factory=False keeps the preferences and
    add-ons, as the GUI tests need, and deletes the current scene's objects)."""
    if factory:
        bpy.ops.wm.read_factory_settings(use_empty=True)
    else:
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    if camera:
        cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
        scene.collection.objects.link(cam)
        cam.location = (0.0, -10.0, 0.0)
        cam.rotation_euler = (math.pi / 2, 0.0, 0.0)
        scene.camera = cam
    return scene


def geometry_group(name):
    """A new Geometry Nodes tree with one Geometry input and one Geometry output (3.x and 4.x APIs)."""
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if bpy.app.version >= (4, 0, 0):
        group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        group.inputs.new("NodeSocketGeometry", "Geometry")
        group.outputs.new("NodeSocketGeometry", "Geometry")
    return group


def link(obj, collection=None):
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def cube_object(name="Cube", size=2.0):
    mesh = bpy.data.meshes.new(name)
    h = size / 2
    verts = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    return bpy.data.objects.new(name, mesh)


def world_corners(obj, matrix=None):
    m = matrix if matrix is not None else obj.matrix_world
    return [list(m @ v.co) for v in obj.data.vertices]


def cube_scene():
    reset()
    cube = link(cube_object())
    cube.location = (1.0, 2.0, 3.0)
    cube.rotation_euler = Euler((0.3, 0.2, 0.1))
    cube.scale = (1.0, 2.0, 0.5)
    hidden = link(cube_object("HiddenCube"))
    hidden.hide_render = True
    bpy.context.view_layer.update()
    return {"triangles": 12, "corners": world_corners(cube)}


def suzanne_scene(levels=2):
    reset()
    bpy.ops.mesh.primitive_monkey_add(location=(0.5, 0.0, 0.0))
    obj = bpy.context.object
    obj.data.polygons.foreach_set("use_smooth", [True] * len(obj.data.polygons))
    obj.data.update()
    mod = obj.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = levels
    quads = sum(len(p.vertices) for p in obj.data.polygons)   # level 1: n quads per n-gon
    bpy.context.view_layer.update()
    return {"triangles": 2 * quads * 4 ** (levels - 1), "base_faces": len(obj.data.polygons),
            "center": list(obj.location)}


def instances_scene():
    reset()
    assets = bpy.data.collections.new("Assets")
    bpy.context.scene.collection.children.link(assets)
    cube = link(cube_object("AssetCube", size=1.0), assets)
    cube.location = (0.0, 0.0, 0.5)
    link(cube_object("HiddenAsset", size=1.0), assets).hide_render = True   # not instanced in renders
    bpy.context.view_layer.layer_collection.children["Assets"].exclude = True
    expected = []
    for i, loc in enumerate([(-3.0, 0.0, 0.0), (3.0, 1.0, 0.0)]):
        empty = link(bpy.data.objects.new(f"Instance{i}", None))
        empty.instance_type = "COLLECTION"
        empty.instance_collection = assets
        empty.location = loc
        empty.rotation_euler = (0.0, 0.0, 0.4 * i)
        bpy.context.view_layer.update()
        expected.append(world_corners(cube, empty.matrix_world @ cube.matrix_world))
    return {"triangles": 24, "instances": expected}


def _bar_curve(name):
    """A beveled straight curve: a closed tube along z."""
    curve = bpy.data.curves.new(name, "CURVE")
    curve.dimensions = "3D"
    curve.bevel_depth = 0.3
    spline = curve.splines.new("POLY")
    spline.points.add(1)
    spline.points[0].co = (0.0, 0.0, -1.0, 1.0)
    spline.points[1].co = (0.0, 0.0, 1.0, 1.0)
    return curve


def evaluated_triangles(obj) -> int:
    """Triangles of the object's evaluated geometry, as Blender triangulates it."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    mesh.calc_loop_triangles()
    count = len(mesh.loop_triangles)
    evaluated.to_mesh_clear()
    return count


def curves_scene():
    """Two objects sharing one curve, one of them with an Array modifier; a
    text and a metaball. Each should be exported once, with its own geometry."""
    reset()
    shared = _bar_curve("SharedCurve")
    plain = link(bpy.data.objects.new("PlainBar", shared))
    plain.location = (-4.0, 0.0, 0.0)
    arrayed = link(bpy.data.objects.new("ArrayedBar", shared))
    arrayed.location = (1.0, 0.0, 0.0)
    array = arrayed.modifiers.new("Array", "ARRAY")
    array.count = 3
    array.relative_offset_displace = (3.0, 0.0, 0.0)
    text = bpy.data.curves.new("Text", "FONT")
    text.body = "Gw"
    text.extrude = 0.1
    link(bpy.data.objects.new("Text", text)).location = (0.0, 0.0, 3.0)
    ball = bpy.data.metaballs.new("Ball")
    ball.elements.new()
    link(bpy.data.objects.new("Ball", ball)).location = (0.0, 0.0, -3.0)
    bpy.context.view_layer.update()
    per_object = {obj.name: evaluated_triangles(obj) for obj in bpy.context.scene.objects if obj.type != "CAMERA"}
    return {"triangles": per_object, "plain_x": [-4.3, -3.7], "arrayed_x": [0.7, 1.0 + 2 * 3 * 0.6 + 0.3]}


def hidden_sources_scene():
    """Instances of objects that are themselves disabled in renders: hair
    particles instancing a hidden cube (their emitter hidden too) and, in
    Blender 4+, a Geometry Nodes carrier whose only output is three instances
    of another hidden cube. Blender renders the instances, not the sources."""
    reset()
    leaf = link(cube_object("HiddenLeaf", size=0.3))
    leaf.location = (0.0, 0.0, 6.0)
    leaf.hide_render = True
    emitter = link(cube_object("Emitter", size=4.0))
    emitter.show_instancer_for_render = emitter.show_instancer_for_viewport = False
    system = emitter.modifiers.new("Particles", "PARTICLE_SYSTEM").particle_system
    system.settings.type = "HAIR"
    system.settings.count = 20
    system.settings.hair_length = 1.0
    system.settings.render_type = "OBJECT"
    system.settings.instance_object = leaf
    system.settings.particle_size = 0.3
    system.settings.display_percentage = 100
    expected = {"triangles": 12 * 20, "carrier": None}
    if bpy.app.version >= (4, 0, 0):
        source = link(cube_object("HiddenSource", size=0.8))
        source.location = (0.0, 0.0, 9.0)
        source.hide_render = True
        carrier = link(bpy.data.objects.new("Carrier", bpy.data.meshes.new("CarrierMesh")))
        group = bpy.data.node_groups.new("Scatter", "GeometryNodeTree")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        output = group.nodes.new("NodeGroupOutput")
        points = group.nodes.new("GeometryNodeMeshLine")
        points.inputs["Count"].default_value = 3
        points.inputs["Offset"].default_value = (1.5, 0.0, 0.0)
        info = group.nodes.new("GeometryNodeObjectInfo")
        info.inputs["Object"].default_value = source
        info.inputs["As Instance"].default_value = True
        on_points = group.nodes.new("GeometryNodeInstanceOnPoints")
        group.links.new(points.outputs["Mesh"], on_points.inputs["Points"])
        group.links.new(info.outputs["Geometry"], on_points.inputs["Instance"])
        group.links.new(on_points.outputs["Instances"], output.inputs[0])
        carrier.modifiers.new("Scatter", "NODES").node_group = group
        carrier.location = (-1.5, 0.0, 3.0)
        expected.update(triangles=12 * 23, carrier="Carrier")
    bpy.context.view_layer.update()
    return expected


def plain_world(name, color):
    """A world of one colour, made the scene's: without nodes before Blender 5.0,
    whose worlds always use theirs (the Background node's Color then)."""
    world = bpy.data.worlds.new(name)
    world.color = color
    if bpy.app.version >= (5, 0, 0):
        background = next(n for n in world.node_tree.nodes if n.type == "BACKGROUND")
        background.inputs["Color"].default_value = (*color, 1.0)
        background.inputs["Strength"].default_value = 1.0
    else:
        world.use_nodes = False
    bpy.context.scene.world = world
    return world


def render_exr(scene, path):
    """Render the scene to `path`: a multilayer, uncompressed, 32-bit EXR (tests/blender/exr.py reads it)."""
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):                     # Blender 5.0+
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.exr_codec, settings.color_depth = "NONE", "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def both_engines(scene, aa_samples=4, cycles_samples=16):
    """Settings for comparing GRIDWALK with Cycles: jittered aa_samples^2 anti-aliasing, Cycles on the
    CPU at cycles_samples without denoising, no compositing."""
    scene.render.use_compositing = False
    scene.gridwalk.aa, scene.gridwalk.aa_samples = "JITTERED", aa_samples
    scene.cycles.device, scene.cycles.samples = "CPU", cycles_samples
    scene.cycles.use_denoising = False


def shader_material(name, node_type, inputs=(), socket="Surface", settings=None):
    """A material whose output's `socket` takes one shader node of `node_type`:
    its inputs set from (name, value) pairs, then its properties from `settings`."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    node = nodes.new(node_type)
    for key, value in inputs:
        next(socket_ for socket_ in node.inputs if socket_.name == key).default_value = value
    for key, value in (settings or {}).items():
        setattr(node, key, value)
    mat.node_tree.links.new(node.outputs[0], nodes["Material Output"].inputs[socket])
    return mat


def add_light(name, kind, location=(0, 0, 5), rotation=(0, 0, 0), **props):
    data = bpy.data.lights.new(name, kind)
    for key, value in props.items():
        setattr(data, key, value)
    obj = link(bpy.data.objects.new(name, data))
    obj.location, obj.rotation_euler = location, rotation
    return obj


def lights_scene(nodes=False, portal=False):
    """Every light type; with nodes, the Point light's node tree dims it (an
    Emission of Strength 0.25, Color (1, 1, 0.5)) and the Sphere light's is a
    Blackbody node into the Emission (not read); with portal, the Square light is a
    Portal and the Disk light is hidden from diffuse and glossy rays."""
    reset()
    link(cube_object())
    point = add_light("Point", "POINT", (1, 2, 3), energy=100.0, shadow_soft_size=0.0, color=(1, 0.5, 0.25))
    sphere = add_light("Sphere", "POINT", (0, 0, 4), energy=50.0, shadow_soft_size=0.5)
    if nodes:
        for light, dim in ((point, True), (sphere, False)):
            light.data.use_nodes = True
            emission = next(n for n in light.data.node_tree.nodes if n.type == "EMISSION")
            if dim:
                emission.inputs["Strength"].default_value = 0.25
                emission.inputs["Color"].default_value = (1.0, 1.0, 0.5, 1.0)
            else:
                blackbody = light.data.node_tree.nodes.new("ShaderNodeBlackbody")
                light.data.node_tree.links.new(blackbody.outputs[0], emission.inputs["Color"])
    add_light("Sun", "SUN", (0, 0, 9), (0.5, 0, 0), energy=3.0, angle=math.radians(10))
    spot = add_light("Spot", "SPOT", (2, 0, 5), (0, 0.3, 0), energy=200.0, spot_size=math.radians(60),
                     spot_blend=0.25, shadow_soft_size=0.1)
    if hasattr(spot.data, "use_soft_falloff"):   # (Blender 4.0+; on by default)
        spot.data.use_soft_falloff = False
    square = add_light("Square", "AREA", (0, 3, 5), (0.2, 0, 0), energy=80.0, shape="SQUARE", size=2.0)
    if portal:
        square.data.cycles.is_portal = True
    rect = add_light("Rect", "AREA", (0, -3, 5), energy=60.0, shape="RECTANGLE", size=2.0, size_y=0.5)
    rect.scale = (1.5, 2.0, 1.0)
    disk = add_light("Disk", "AREA", (3, 3, 5), energy=40.0, shape="DISK", size=1.0)
    if portal:
        disk.visible_diffuse = disk.visible_glossy = False
    oval = add_light("Oval", "AREA", (3, -3, 5), energy=40.0, shape="DISK", size=1.0)
    oval.scale = (1.0, 2.0, 1.0)   # a disk scaled unevenly: an ellipse
    ellipse = add_light("Ellipse", "AREA", (-3, 3, 5), energy=40.0, shape="ELLIPSE", size=2.0, size_y=0.5)
    if hasattr(ellipse.data, "cycles") and hasattr(ellipse.data.cycles, "cast_shadow"):   # Blender 3.x: Cycles' own
        ellipse.data.cycles.cast_shadow = False
    else:
        ellipse.data.use_shadow = False
    bpy.context.view_layer.update()
    out = {}
    for obj in bpy.data.objects:
        if obj.type == "LIGHT":
            m = obj.matrix_world
            out[obj.name] = {"position": list(m.translation),
                             "down": list((m.to_3x3() @ Vector((0, 0, -1))).normalized()),
                             "x": list((m.to_3x3() @ Vector((1, 0, 0))).normalized())}
    return {"lights": out}


def near_spot_scene(radius=0.5, resolution=(64, 64)):
    """A grey Diffuse wall facing the camera (orthographic, 2 units across) and a
    spot light 1 unit in front of it pointing at it: 45 degree cone, blend 0.15,
    the given radius, 10 W. No world light."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.data.type = "ORTHO"
    scene.camera.data.ortho_scale = 2.0
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0), rotation=(math.pi / 2, 0, 0))
    wall = bpy.context.object
    wall.data.materials.append(shader_material("Wall", "ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.8, 0.8, 1.0))]))
    add_light("Spot", "SPOT", (0, -1.0, 0), (math.pi / 2, 0, 0), energy=10.0, spot_size=math.radians(45),
              spot_blend=0.15, shadow_soft_size=radius)
    bpy.context.view_layer.update()
    return {}


def near_sphere_scene(height=0.6, soft=True, energy=30.0, mirror=False, resolution=(48, 48)):
    """A white Diffuse floor seen from just above it (orthographic, 3 units across, looking
    down, so the lamp stays out of view) under a point light of radius 0.5 at `height`,
    `energy` W, Soft Falloff on or off (Blender 4.0+; before, always soft). No world light.
    mirror: the floor is a sharp mirror (a Glossy BSDF of Roughness 0) seen from (0, -2.5, 1.2),
    62 degrees down, the lamp's reflection in the middle of the view."""
    scene = reset(resolution=tuple(resolution))
    cam = scene.camera
    if mirror:
        cam.location, cam.rotation_euler = (0.0, -2.5, 1.2), (math.radians(62), 0.0, 0.0)
        cam.data.lens = 30.0
    else:
        cam.data.type = "ORTHO"
        cam.data.ortho_scale = 3.0
        cam.data.clip_start = 0.001
        cam.location, cam.rotation_euler = (0.0, 0.0, 0.02), (0.0, 0.0, 0.0)
    bpy.ops.mesh.primitive_plane_add(size=40.0, location=(0, 0, 0))
    floor = bpy.context.object
    shader = ("ShaderNodeBsdfGlossy", [("Color", (0.8, 0.8, 0.8, 1.0)), ("Roughness", 0.0)]) if mirror else \
        ("ShaderNodeBsdfDiffuse", [("Color", (0.8, 0.8, 0.8, 1.0))])
    floor.data.materials.append(shader_material("Floor", *shader))
    lamp = add_light("Bulb", "POINT", (0, 0, height), energy=energy, shadow_soft_size=0.5)
    if hasattr(lamp.data, "use_soft_falloff"):
        lamp.data.use_soft_falloff = soft
    bpy.context.view_layer.update()
    return {}


def camera_scene(fit="AUTO", resolution=(640, 480), dof=True, focus_object=False, focus_bone=False, ortho=False,
                 unit_scale=1.0, stand_in=None, parent_scale=None):
    """A cube before a 50 mm camera on a 36 x 24 sensor, shifted; stand_in "EMPTY", "SPOT" or
    "POINT": an Empty, a spot light of a 60 degree cone or a point light in the camera's place is
    the active camera instead; parent_scale: the camera, turned 30 degrees about Z, is the child
    of an Empty of that scale (an uneven one shears it)."""
    scene = reset(resolution=resolution)
    scene.unit_settings.scale_length = unit_scale
    link(cube_object())
    cam = scene.camera
    if ortho:
        cam.data.type = "ORTHO"
    cam.data.lens = 50.0
    cam.data.sensor_width, cam.data.sensor_height = 36.0, 24.0
    cam.data.sensor_fit = fit
    cam.data.shift_x, cam.data.shift_y = 0.1, -0.05
    cam.data.dof.use_dof = dof
    cam.data.dof.aperture_fstop = 2.8
    cam.data.dof.focus_distance = 7.5
    if focus_object:
        target = link(bpy.data.objects.new("Focus", None))
        target.location = (2.0, 4.0, 1.0)     # 14 units in front of the camera along +y
        cam.data.dof.focus_object = target
    if focus_bone:                              # an armature 12 units in front, its bone's head 18
        rig = link(bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig")))
        bpy.context.view_layer.objects.active = rig
        bpy.ops.object.mode_set(mode="EDIT")
        bone = rig.data.edit_bones.new("Head")
        bone.head, bone.tail = (0.0, 6.0, 0.0), (0.0, 6.0, 1.0)
        bpy.ops.object.mode_set(mode="OBJECT")
        rig.location = (1.0, 2.0, 0.0)
        cam.data.dof.focus_object = rig
        cam.data.dof.focus_subtarget = "Head"
    if parent_scale is not None:
        rig = link(bpy.data.objects.new("CameraRig", None))
        rig.scale = parent_scale
        cam.parent = rig
        cam.rotation_euler.z += math.radians(30.0)
    if stand_in is not None:
        data = None if stand_in == "EMPTY" else bpy.data.lights.new(stand_in.title(), stand_in)
        if stand_in == "SPOT":
            data.spot_size = math.radians(60.0)
        other = link(bpy.data.objects.new("StandIn", data))
        other.location, other.rotation_euler = cam.location, cam.rotation_euler
        scene.camera = other
    bpy.context.view_layer.update()
    return {"eye": list(cam.matrix_world.translation)}


def no_camera_scene():
    reset(camera=False)
    link(cube_object())
    return {}


def materials_scene(world_lights_diffuse=True):
    reset()
    obj = link(cube_object())
    red = bpy.data.materials.new("Red")
    red.use_nodes = True
    bsdf = red.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.8, 0.1, 0.1, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.25
    bsdf.inputs["Roughness"].default_value = 0.3
    bsdf.inputs["IOR"].default_value = 1.5
    glass = bpy.data.materials.new("Glass")
    glass.use_nodes = True
    gb = glass.node_tree.nodes["Principled BSDF"]
    gb.inputs["Transmission Weight" if "Transmission Weight" in gb.inputs else "Transmission"].default_value = 1.0
    gb.inputs["IOR"].default_value = 1.33
    toon = bpy.data.materials.new("Toon")
    toon.use_nodes = True
    nodes = toon.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    shader = nodes.new("ShaderNodeBsdfTranslucent")
    toon.node_tree.links.new(shader.outputs[0], nodes["Material Output"].inputs["Surface"])
    toon.diffuse_color = (0.1, 0.7, 0.2, 1.0)
    holdout = bpy.data.materials.new("Holdout")
    holdout.use_nodes = True
    nodes = holdout.node_tree.nodes
    shader = nodes.new("ShaderNodeHoldout")
    holdout.node_tree.links.new(shader.outputs[0], nodes["Material Output"].inputs["Surface"])
    for mat in (red, glass, toon, holdout):
        obj.data.materials.append(mat)
    # faces 0-1 red, 2-3 glass, 4 toon, 5 holdout
    obj.data.polygons.foreach_set("material_index", [0, 0, 1, 1, 2, 3])
    obj.data.update()
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
    bg.inputs["Strength"].default_value = 0.5
    world.cycles_visibility.diffuse = world_lights_diffuse
    bpy.context.scene.world = world
    bpy.context.view_layer.update()
    return {"face_slots": [0, 0, 1, 1, 2, 3]}


def sphere_scene(shared=False):
    """A ball flagged 'render as sphere' (and a cube); shared: two more objects using its
    mesh, one scaled by 0.5, one whose Displace modifier grows its mesh to radius 1.5."""
    reset()
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(1.0, 2.0, 3.0))
    ball = bpy.context.object
    ball.scale = (2.0, 2.0, 2.0)
    ball.gridwalk.render_as_sphere = True
    link(cube_object())
    centers, radii = [[1.0, 2.0, 3.0]], [2.0]
    if shared:
        for name, location, scale in (("Small", (-4.0, 0.0, 0.0), 0.5), ("Grown", (4.0, 0.0, 0.0), 1.0)):
            other = link(bpy.data.objects.new(name, ball.data))
            other.location, other.scale = location, (scale,) * 3
            other.gridwalk.render_as_sphere = True
            centers.append(list(location))
            radii.append(scale)
        other.modifiers.new("Displace", "DISPLACE").strength = 1.0   # (no texture: + 0.5 along the normals)
        radii[-1] = 1.5
    bpy.context.view_layer.update()
    return {"center": centers[0], "radius": radii[0], "centers": centers, "radii": radii}


def _sun_and_grey_world():
    add_light("Sun", "SUN", rotation=(0.6, 0.2, 0.0), energy=3.0)
    plain_world("Grey", (0.1, 0.1, 0.1))
    bpy.context.view_layer.update()


def point_cloud_scene(resolution=(96, 72)):
    """A Geometry Nodes point cloud (Mesh to Points of a 5 x 4 grid facing the
    camera, radius 0.25) on an object scaled 1.5, given the Red material by a
    Set Material node (a point cloud takes one material: the node ignores a
    per-point selection); a sun and a grey world light it."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=5, y_subdivisions=4, size=4, rotation=(math.pi / 2, 0, 0))
    grid = bpy.context.object
    grid.name = "Points"
    grid.location, grid.scale = (0.5, 0.0, 0.2), (1.5, 1.5, 1.5)
    group = geometry_group("ToPoints")
    nodes, links = group.nodes, group.links
    to_points = nodes.new("GeometryNodeMeshToPoints")
    to_points.inputs["Radius"].default_value = 0.25
    links.new(nodes.new("NodeGroupInput").outputs[0], to_points.inputs["Mesh"])
    setter = nodes.new("GeometryNodeSetMaterial")
    setter.inputs["Material"].default_value = principled_material("Red", (0.8, 0.05, 0.05))
    links.new(to_points.outputs[0], setter.inputs["Geometry"])
    links.new(setter.outputs[0], nodes.new("NodeGroupOutput").inputs[0])
    grid.modifiers.new("ToPoints", "NODES").node_group = group
    _sun_and_grey_world()
    centres = [list(grid.matrix_world @ v.co) for v in grid.data.vertices]
    return {"centres": centres, "radius": 0.25 * 1.5}




def _hair_material(parametrization):
    """A Principled Hair BSDF material (Melanin 0.5, Redness 0.4; or Direct
    Coloring orange; or an Absorption Coefficient)."""
    return shader_material(f"Hair{parametrization.title()}", "ShaderNodeBsdfHairPrincipled",
                           [("Melanin", 0.5), ("Melanin Redness", 0.4), ("Color", (0.6, 0.25, 0.05, 1.0)),
                            ("Absorption Coefficient", (0.2, 0.6, 1.5))], settings={"parametrization": parametrization})


def hair_scene(resolution=(96, 72), material=None):
    """A hair curves object (Blender's Curves, as Add > Curves makes): five
    straight strands standing in a row facing the camera, four points each,
    radius 0.12 at the root tapering to 0.03 at the tip, on an object scaled
    1.5; material Brown in its slot (material: a Principled Hair BSDF of that
    parametrization instead); beside it an empty hair object; a sun and a grey
    world light it. Expected:
    each segment's world-space ends and radii, computed with mathutils."""
    reset(resolution=tuple(resolution))
    curves = bpy.data.hair_curves.new("Hair")
    if not hasattr(curves, "add_curves"):        # (Blender 3.x: no Python API to add curves)
        return {"segments": None}
    curves.add_curves([4] * 5)
    for k in range(5):
        for j in range(4):
            point = curves.points[4 * k + j]
            point.position = (-1.6 + 0.8 * k, 0.0, -1.2 + 0.8 * j)
            point.radius = 0.12 - 0.03 * j
    curves.materials.append(principled_material("Brown", (0.4, 0.2, 0.05)) if material is None
                            else _hair_material(material))
    hair = link(bpy.data.objects.new("Hair", curves))
    link(bpy.data.objects.new("EmptyHair", bpy.data.hair_curves.new("Empty")))   # (Add > Curves > Empty Hair)
    hair.location, hair.scale = (0.3, 0.0, 0.1), (1.5, 1.5, 1.5)
    _sun_and_grey_world()
    m = hair.matrix_world
    segments = [[list(m @ Vector(curves.points[4 * k + j].position)), list(m @ Vector(curves.points[4 * k + j + 1].position)),
                 1.5 * curves.points[4 * k + j].radius, 1.5 * curves.points[4 * k + j + 1].radius]
                for k in range(5) for j in range(3)]
    return {"segments": segments}


def particle_hair_scene(resolution=(96, 72), random=0.0, children=False, instanced=False, spiral=False,
                        virtual_parents=0.0):
    """Particle hair, as Blender made hair before Curves objects: a 3 x 1 plane
    at z = -1.5, scaled 1.25, growing 40 strands of length 2 (Hair Length is in
    world units) from its faces (random: the emission's random factor, which tilts them;
    children: 3 interpolated children per strand, in the viewport and the
    render); Hair Shape radius scale 0.16, root 1, tip 0.4, shape 0.3, tip not
    closed; material Brown in slot 0, Red in slot 1, which the settings name.
    Beside it a cube whose particle system's modifier is off for both the
    viewport and the render (its hair shows in neither). instanced: the plane
    shows its hair but not itself (Show Instancer off), and a collection
    instance repeats both 5 m behind it. spiral: a Spiral kink (whose extra
    steps Blender gives children only); virtual_parents: that share of the
    children hidden as virtual parents (their paths have no keys). A sun and a
    grey world light it. Expected: the plane's height and extent in world space, the scale,
    the strand count and keys per strand in the viewport and in a render."""
    reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_plane_add(size=1, location=(0.0, 0.0, -1.5))
    plane = bpy.context.object
    plane.name = "Fur"
    plane.data.transform(Matrix.Diagonal((3.0, 1.0, 1.0, 1.0)))
    plane.scale = (1.25, 1.25, 1.25)
    plane.data.materials.append(principled_material("Brown", (0.4, 0.2, 0.05)))
    plane.data.materials.append(principled_material("Red", (0.8, 0.05, 0.05)))
    settings = plane.modifiers.new("Hair", "PARTICLE_SYSTEM").particle_system.settings
    settings.type, settings.count, settings.hair_length = "HAIR", 40, 2.0
    settings.use_advanced_hair, settings.factor_random = True, random
    settings.radius_scale, settings.root_radius, settings.tip_radius = 0.16, 1.0, 0.4
    settings.shape, settings.use_close_tip, settings.material = 0.3, False, 2
    if spiral:
        settings.kink, settings.kink_extra_steps = "SPIRAL", 4
    if children:
        settings.child_type, settings.rendered_child_count = "INTERPOLATED", 3
        settings.virtual_parents = virtual_parents
        # (the viewport's Display Amount: child_nbr before Blender 4.x renamed it)
        setattr(settings, "child_percent" if hasattr(settings, "child_percent") else "child_nbr", 3)
    off = link(cube_object("HairOff", size=0.5))
    off.location = (2.5, 0.0, 1.5)
    modifier = off.modifiers.new("Hair", "PARTICLE_SYSTEM")
    modifier.particle_system.settings.type = "HAIR"
    modifier.show_viewport = modifier.show_render = False
    if instanced:
        plane.show_instancer_for_render = plane.show_instancer_for_viewport = False
        fur = bpy.data.collections.new("Fur")
        fur.objects.link(plane)
        empty = link(bpy.data.objects.new("FurInstance", None))
        empty.instance_type, empty.instance_collection, empty.location = "COLLECTION", fur, (0.0, 5.0, 0.0)
    _sun_and_grey_world()
    strands = 40 * (3 if children else 1)
    return {"z": -1.5, "half_extent": [1.5 * 1.25, 0.5 * 1.25], "scale": 1.25, "strands": strands,
            "keys_viewport": (1 << settings.display_step) + 1, "keys_render": (1 << settings.render_step) + 1}


def showcase_scene(resolution=(96, 72), fresh=True):
    """Meshes with a modifier, a collection instanced twice, an analytic sphere,
    three kinds of light: the scene the render tests compare with Cycles.
    fresh=False builds into the current scene (already reset())."""
    if fresh:
        reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_monkey_add(location=(-1.2, 0.0, 0.3), rotation=(0.0, 0.0, 0.5))
    monkey = bpy.context.object
    mod = monkey.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = 1
    assets = bpy.data.collections.new("Assets")
    bpy.context.scene.collection.children.link(assets)
    link(cube_object("AssetCube", size=0.8), assets)
    bpy.context.view_layer.layer_collection.children["Assets"].exclude = True
    for i, loc in enumerate([(1.3, 0.0, 1.0), (1.6, 1.0, -1.2)]):
        empty = link(bpy.data.objects.new(f"Instance{i}", None))
        empty.instance_type, empty.instance_collection = "COLLECTION", assets
        empty.location, empty.rotation_euler = loc, (0.3, 0.2 * i, 0.5)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(0.3, 1.5, -1.0), segments=64, ring_count=32)
    bpy.context.object.gridwalk.render_as_sphere = True
    monkey.data.materials.append(principled_material("Red", (0.8, 0.15, 0.1), Roughness=0.4))
    add_light("Key", "POINT", (-3, -6, 5), energy=600.0, shadow_soft_size=0.0)
    add_light("Sun", "SUN", (0, 0, 9), (0.6, 0.2, 0), energy=1.0)
    add_light("Fill", "AREA", (4, -4, 2), (1.2, 0, 0.8), energy=150.0, shape="SQUARE", size=1.0)
    bpy.context.view_layer.update()
    return {}


def empty_scene():
    """A camera and a light, nothing to see."""
    reset()
    add_light("Key", "POINT", (0, -5, 5), energy=100.0)
    return {}


def nan_scene():
    """A cube with one vertex at NaN (corrupt geometry)."""
    reset()
    cube = link(cube_object())
    co = [c for v in cube.data.vertices for c in v.co]
    co[0] = float("nan")
    cube.data.vertices.foreach_set("co", co)
    cube.data.update()
    add_light("Key", "POINT", (0, -5, 5), energy=100.0)
    return {}


CAMERA_KINDS = ("perspective", "orthographic", "panoramic", "mirrored", "pixel_aspect", "clipped", "far",
                "portrait_auto", "portrait_horizontal", "fisheye_equidistant", "fisheye_equisolid",
                "fisheye_polynomial", "mirror_ball", "cubemap_face", "central_cylindrical", "mirrored_panoramic",
                "mirrored_fisheye_equisolid", "mirrored_mirror_ball")
# Blender's panorama type of each panoramic kind but "panoramic" (equirectangular), and its settings
PANORAMA_KINDS = {
    "fisheye_equidistant": ("FISHEYE_EQUIDISTANT", dict(fisheye_fov=2.6), dict(shift_x=0.05)),
    "fisheye_equisolid": ("FISHEYE_EQUISOLID", dict(fisheye_fov=3.0, fisheye_lens=10.5), dict(shift_y=-0.05)),
    # (Blender's coefficients, a 50 mm lens on a 36 mm sensor, cut at 0.3 radians off the axis)
    "fisheye_polynomial": ("FISHEYE_LENS_POLYNOMIAL", dict(fisheye_fov=0.6),
                           dict(sensor_fit="VERTICAL", sensor_height=24.0)),
    "mirror_ball": ("MIRRORBALL", {}, {}),
    "cubemap_face": ("EQUIANGULAR_CUBEMAP_FACE", {}, dict(shift_x=-0.1)),
    "central_cylindrical": ("CENTRAL_CYLINDRICAL",
                            dict(central_cylindrical_range_u_min=-1.2, central_cylindrical_range_u_max=1.5,
                                 central_cylindrical_range_v_min=-0.8, central_cylindrical_range_v_max=0.6,
                                 central_cylindrical_radius=1.3), {}),
}


def has_panorama(kind) -> bool:
    """Whether this Blender has the panorama type of camera kind `kind` (Central
    Cylindrical came in 4.3)."""
    return kind != "central_cylindrical" or bpy.app.version >= (4, 3)
FAR = (1e7, 1e7, 0.0)       # whole numbers: exact in float32 (spacing 1 at 1e7)


def camera_kinds_scene(kind="perspective", resolution=(128, 96), far_offset=FAR, sky=None):
    """Cubes, a sphere and a ground plane seen by one kind of camera (the
    CAMERA_KINDS): the scene the camera tests compare with Cycles. "far"
    moves everything 1e7 from the origin and keeps only geometry with whole
    coordinates, which float32 holds exactly there. sky: a world colour
    (the pictures': a fisheye's black corners show against it)."""
    far = kind == "far"
    mirrored = kind.startswith("mirrored_")     # a mirrored panorama: "mirrored_" + a panoramic kind
    kind = kind[len("mirrored_"):] if mirrored else kind
    portrait = kind.startswith("portrait")      # a tall image: AUTO fits the sensor to the height
    scene = reset(resolution=(101, 101) if far else tuple(resolution)[::-1] if portrait else tuple(resolution))
    offset = Vector(far_offset if far else (0.0, 0.0, 0.0))
    cam = scene.camera
    cam.location = offset + Vector((0.0, -10.0, 3.0))
    cam.rotation_euler = (math.radians(76), 0.0, math.radians(12 if far else 0))
    data = cam.data
    data.lens = 35.0
    if kind == "perspective":
        data.sensor_fit, data.sensor_height = "VERTICAL", 24.0
        data.shift_x, data.shift_y = 0.12, -0.08
    elif kind == "orthographic":
        data.type, data.ortho_scale = "ORTHO", 9.0
        data.shift_x, data.shift_y = 0.1, 0.05
    elif kind == "panoramic":
        data.type = "PANO"
        pano = data if hasattr(data, "panorama_type") else data.cycles      # Blender 4.x / 3.x
        pano.panorama_type = "EQUIRECTANGULAR"
        pano.longitude_min, pano.longitude_max = -1.2, 2.0
        pano.latitude_min, pano.latitude_max = -0.6, 0.9
    elif kind in PANORAMA_KINDS:
        data.type = "PANO"
        pano = data if hasattr(data, "panorama_type") else data.cycles      # Blender 4.x / 3.x
        pano_type, settings, lens = PANORAMA_KINDS[kind]
        pano.panorama_type = pano_type
        for name, value in settings.items():
            setattr(pano, name, value)
        for name, value in lens.items():
            setattr(data, name, value)
    if kind == "mirrored" or mirrored:
        cam.scale = (-1.0, 1.0, 1.0)
    if kind == "pixel_aspect":
        scene.render.pixel_aspect_x = 2.0
    elif kind == "portrait_auto":
        data.shift_x = -0.1
    elif kind == "portrait_horizontal":
        data.sensor_fit, data.sensor_width = "HORIZONTAL", 30.0
        data.shift_y = 0.1
    elif kind == "clipped":
        data.clip_start, data.clip_end = 8.8, 14.0
    elif far:
        # Cycles starts its rays at clip_start along each ray in float32: 1e7 from
        # the origin that point snaps to whole units, moving the rays off their
        # line by up to clip_start (0.1 by default: most of a pixel here)
        data.clip_start = 1e-3
    for name, loc, size, spin in (("Left", (-3.0, 0.0, 0.0), 2.0, 0.0), ("Back", (2.0, 4.0, 1.0), 2.0, 0.4),
                                  ("Far", (1.0, 12.0, 1.0), 4.0, 0.0)):
        cube = link(cube_object(name, size))
        cube.location = offset + Vector(loc)
        cube.rotation_euler = (0.0, 0.0, 0.0 if far else spin)
    ground = link(bpy.data.objects.new("Ground", bpy.data.meshes.new("Ground")))
    ground.data.from_pydata([(-5, -4, -1), (5, -4, -1), (5, 7, -1), (-5, 7, -1)], [], [(0, 1, 2, 3)])
    ground.location = offset
    if not far:
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(0.6, -2.0, -0.1), segments=48, ring_count=24)
    add_light("Key", "SUN", offset + Vector((0, 0, 9)), (0.5, 0.2, 0), energy=3.0)
    if sky is not None:
        plain_world("Sky", tuple(sky))
    bpy.context.view_layer.update()
    return {}


def bokeh_scene(blades=6, rotation=0.3, ratio=1.5, resolution=(96, 96)):
    """A glowing sphere far behind the focus of a wide-open lens, on black: its
    image is the aperture's shape (test_b43). blades 0: a round aperture."""
    scene = reset(resolution=tuple(resolution))
    cam = scene.camera
    cam.location, cam.rotation_euler = (0.0, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)    # looking along +y
    data = cam.data
    data.lens, data.sensor_width, data.sensor_fit = 50.0, 36.0, "HORIZONTAL"
    dof = data.dof
    dof.use_dof, dof.focus_distance, dof.aperture_fstop = True, 1.0, 0.1            # aperture radius 0.25
    dof.aperture_blades, dof.aperture_rotation, dof.aperture_ratio = blades, rotation, ratio
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0.0, 20.0, 0.0), segments=32, ring_count=16)
    glow = principled_material("Glow", (0.0, 0.0, 0.0), **{"Emission Strength": 10.0})
    glow.node_tree.nodes["Principled BSDF"].inputs[
        "Emission Color" if bpy.app.version >= (4, 0, 0) else "Emission"].default_value = (1.0, 1.0, 1.0, 1.0)
    bpy.context.active_object.data.materials.append(glow)
    plain_world("Black", (0.0, 0.0, 0.0))
    return {}


def uv_sphere_object(name, radius=1.0, segments=32, rings=16):
    """A smooth UV sphere built with bmesh (no operator: works in GUI timers too)."""
    import bmesh
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius)
    bm.to_mesh(mesh)
    bm.free()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    return bpy.data.objects.new(name, mesh)


def viewport_scene(resolution=(480, 270), factory=True):
    """Three coloured objects well apart on a dark world, lit from behind the
    camera (their shadows fall behind them, out of sight): the GUI viewport
    tests move "Sphere" and check that the image changes only around it.
    "Near" and "Far" are equal cubes at the same height, 6 units apart in
    depth: the same size in an orthographic front view, not in perspective."""
    scene = reset(resolution=tuple(resolution), factory=factory)
    scene.camera.location = (1.0, -14.0, 4.0)
    scene.camera.rotation_euler = (math.radians(76), 0.0, math.radians(4))
    for name, loc, color in (("Near", (-3.0, 0.0, 0.0), (0.8, 0.2, 0.1)), ("Far", (3.0, 6.0, 0.0), (0.1, 0.3, 0.8))):
        cube = link(cube_object(name, 2.0))
        cube.location = loc
        cube.data.materials.append(principled_material(name, color, Roughness=0.6))
    sphere = link(uv_sphere_object("Sphere", 1.0))
    sphere.location = (0.5, 2.0, 0.0)
    sphere.data.materials.append(principled_material("Green", (0.2, 0.7, 0.2), Roughness=0.5))
    add_light("Key", "SUN", (0, -20, 20), (math.radians(40), 0, math.radians(5)), energy=3.0)
    plain_world("World", (0.05, 0.05, 0.06))
    bpy.context.view_layer.update()
    return {}


from gltf_scenes import gltf_model_scene  # noqa: E402,F401
from glossy_scenes import dielectric_scene, panel_floor_scene, rough_metal_scene, shader_mix_scene  # noqa: E402,F401
from light_scenes import chrome_ball_scene, lit_wall_scene, mirrored_light_scene, wide_sun_scene  # noqa: E402,F401
from material_scenes import (alpha_mask_scene, bad_materials_scene, checker_scene, coloured_glass_scene, cutout_scene,  # noqa: E402,F401
                             emission_mirror_scene, nodeless_material_scene, png_alpha_scene,
                             normal_map_scene, rough_glass_scene,
                             emission_panel_scene, environment_scene, fog_box_scene, mix_shaders_scene, node_states_scene, pane_shadow_scene,
                             principled_sphere_scene, roughness_map_scene, texture_links_scene,
                             sunny_monkey_scene, unread_settings_scene, world_shadow_scene)
from procedural_scenes import checker_on_shapes_scene, procedural_checker_scene, procedural_gradient_scene  # noqa: E402,F401,E501
from noise_scenes import noise_bump_scene, procedural_noise_scene  # noqa: E402,F401
from voronoi_scenes import voronoi_scene  # noqa: E402,F401
from pattern_scenes import pattern_scene  # noqa: E402,F401
from scatter_scenes import carrier_scene, scatter_scene, volume_output_scene  # noqa: E402,F401
from catcher_scenes import shadow_catcher_scene  # noqa: E402,F401
from attribute_scenes import attribute_scene  # noqa: E402,F401
from object_info_scenes import object_info_scene  # noqa: E402,F401
from group_scenes import group_edge_scene, node_group_scene  # noqa: E402,F401
from sky_scenes import sky_scene  # noqa: E402,F401
from texture_scenes import (bump_scene, emission_map_scene, mapped_texture_scene, node_chain_scene,  # noqa: E402,F401
                            tinted_by_attribute_scene)
from udim_scenes import udim_scene  # noqa: E402,F401

BUILDERS = {name[:-6]: fn for name, fn in globals().items() if name.endswith("_scene")}
