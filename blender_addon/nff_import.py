"""File > Import > NFF (.nff): an NFF scene as Blender objects.

The file is read by `gridwalk.io.read_nff` (the core's own reader, so the
layouts it reads, the parsing and the errors are the same; a malformed file
becomes an error report).
The values come from nff_convert.py, which explains how each inverts the
exporter. The import adds a collection named after the file holding:

  "<name> polygons"   one mesh of every p / pp polygon (n-gons, concave ones
                      too; pp normals as custom normals, smooth shading), a
                      material slot each
  "<name> sphere k"   unit UV spheres scaled by the radius, "Render as Sphere"
  "<name> cones"      one open mesh of every c cone / cylinder (tessellated)
  "<name> light k"    point lights (power: see nff_convert.py)
  "<name> camera"     made the scene camera; the render resolution is set
and gives the scene a new world with the NFF background colour.
"""
from __future__ import annotations

from pathlib import Path

import dataclasses

import bpy
from bpy.props import IntProperty, StringProperty
from bpy_extras.io_utils import ImportHelper
from mathutils import Matrix

ALIASES = {"Transmission Weight": ("Transmission",), "Specular IOR Level": ("Specular",),
           "Emission Color": ("Emission",)}     # Blender 3.x names


def _node(tree, kind):
    return next((n for n in tree.nodes if n.type == kind), None)


def make_material(name, material):
    """A Principled BSDF material the exporter turns back into `material`."""
    from .nff_convert import principled_inputs
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    bsdf = _node(mat.node_tree, "BSDF_PRINCIPLED")
    for key, value in principled_inputs(material).items():
        for socket_name in (key, *ALIASES.get(key, ())):
            socket = bsdf.inputs.get(socket_name)
            if socket is not None:
                socket.default_value = value
                break
    mat.diffuse_color = (*material.color, 1.0)        # the viewport's solid colour
    fields = dataclasses.asdict(material)
    fields["color"] = [float(c) for c in material.color]
    mat["gridwalk_material"] = fields                   # exported exactly (export/materials.py)
    mat.metallic, mat.roughness = min(max(material.mirror, 0.0), 1.0), 0.0
    return mat


def make_mesh(name, vertices, corners, starts, materials=(), face_materials=None,
              vertex_normals=None):
    """A mesh from numpy arrays: polygon k uses corners[starts[k]:starts[k+1]]."""
    import numpy as np
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(vertices))
    mesh.vertices.foreach_set("co", np.asarray(vertices, np.float32).reshape(-1))
    mesh.loops.add(len(corners))
    mesh.loops.foreach_set("vertex_index", np.asarray(corners, np.int32))
    mesh.polygons.add(len(starts))
    mesh.polygons.foreach_set("loop_start", np.asarray(starts, np.int32))
    if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:   # Blender < 4.0
        totals = np.diff(np.append(np.asarray(starts), len(corners)))
        mesh.polygons.foreach_set("loop_total", totals.astype(np.int32))
    for mat in materials:
        mesh.materials.append(mat)
    if face_materials is not None and len(starts):
        mesh.polygons.foreach_set("material_index", np.asarray(face_materials, np.int32))
    mesh.update(calc_edges=True)
    # flat unless there are normals (new faces are smooth by default since Blender 4.1)
    mesh.polygons.foreach_set("use_smooth", np.full(len(starts), vertex_normals is not None))
    if vertex_normals is not None:
        if hasattr(mesh, "use_auto_smooth"):          # Blender < 4.1: custom normals need it
            mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(np.asarray(vertex_normals, np.float32).tolist())
    mesh.update()
    return mesh


def _used(indices, materials):
    """(slot materials, slot of each entry) for the materials `indices` use."""
    import numpy as np
    used, slots = np.unique(np.asarray(indices, dtype=np.int64), return_inverse=True)
    return [materials[i] for i in used], slots


def add_polygons(collection, name, kw, polygons, materials):
    """One mesh of the file's polygons as n-gons (gridwalk.io.nff.NffPolygons:
    each polygon's corners are consecutive rows of the Scene's vertices)."""
    import numpy as np
    if not len(polygons.counts):
        return 0
    slot_materials, slots = _used(polygons.materials, materials)
    mesh = make_mesh(f"{name} polygons", kw["vertices"], np.arange(len(kw["vertices"])), polygons.starts,
                     slot_materials, slots, kw["normals"])
    collection.objects.link(bpy.data.objects.new(f"{name} polygons", mesh))
    return len(polygons.counts)


def add_spheres(collection, name, kw, materials, segments=32):
    from .nff_convert import uv_sphere
    vertices, corners, starts = uv_sphere(segments, segments // 2)
    meshes = {}
    for k, (centre, radius, m) in enumerate(zip(kw["sphere_centers"], kw["sphere_radii"],
                                                kw["sphere_materials"])):
        mesh = meshes.get(int(m))
        if mesh is None:
            mesh = meshes[int(m)] = make_mesh(f"{name} sphere {materials[m].name}", vertices,
                                              corners, starts, [materials[m]])
            mesh.polygons.foreach_set("use_smooth", [True] * len(starts))
        obj = bpy.data.objects.new(f"{name} sphere {k}", mesh)
        obj.location = tuple(centre)
        obj.scale = (float(radius),) * 3
        obj.gridwalk.render_as_sphere = True
        collection.objects.link(obj)
    return len(kw["sphere_radii"])


def add_cones(collection, name, kw, materials, segments=32):
    import numpy as np

    from .nff_convert import cone_mesh
    parts = [cone_mesh(b, a, rb, ra, segments) for b, a, rb, ra in zip(
        kw["cylinder_base"], kw["cylinder_apex"], kw["cylinder_base_radius"], kw["cylinder_apex_radius"])]
    keep = [k for k, p in enumerate(parts) if p is not None]
    if not keep:
        return 0
    vertices, normals, corners, starts, face_cone, offset, loops = [], [], [], [], [], 0, 0
    for k in keep:
        v, n, c, s = parts[k]
        vertices.append(v)
        normals.append(n)
        corners.append(c + offset)
        starts.append(s + loops)
        face_cone.append(np.full(len(s), k))
        offset, loops = offset + len(v), loops + len(c)
    face_cone = np.concatenate(face_cone)
    slot_materials, slots = _used(kw["cylinder_materials"][face_cone], materials)
    mesh = make_mesh(f"{name} cones", np.concatenate(vertices), np.concatenate(corners),
                     np.concatenate(starts), slot_materials, slots, np.concatenate(normals))
    collection.objects.link(bpy.data.objects.new(f"{name} cones", mesh))
    return len(keep)


def add_lights(collection, name, lights, distances):
    """Point lights for falloff-free gridwalk lights (power: nff_convert.point_light)."""
    from .nff_convert import point_light
    for k, (light, d0) in enumerate(zip(lights, distances)):
        data = bpy.data.lights.new(f"{name} light {k}", "POINT")
        data.color, data.energy = point_light(light.color, d0)
        data.shadow_soft_size = 0.0          # a point, as in NFF: hard shadows
        data["nff_intensity"] = [float(c) for c in light.color]
        data["nff_reference_distance"] = d0
        obj = bpy.data.objects.new(f"{name} light {k}", data)
        obj.location = tuple(light.position)
        collection.objects.link(obj)
    return len(lights)


def add_camera(scene, collection, name, camera, far=1000.0):
    """The scene camera for a gridwalk.Camera, and the render resolution."""
    from .nff_convert import camera_lens, camera_matrix
    data = bpy.data.cameras.new(f"{name} camera")
    data.sensor_fit = "VERTICAL"
    data.sensor_height, data.lens = camera_lens(camera.fov)
    data.clip_start = max(float(camera.hither), 1e-6)
    data.clip_end = max(far, data.clip_start * 10.0)
    obj = bpy.data.objects.new(f"{name} camera", data)
    obj.matrix_world = Matrix(camera_matrix(camera.eye, camera.target, camera.up).tolist())
    collection.objects.link(obj)
    scene.camera = obj
    render = scene.render
    render.resolution_x, render.resolution_y = int(camera.width), int(camera.height)
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    return obj


def set_world(scene, name, color):
    """A world that camera rays see as the NFF background colour and that
    lights nothing (NFF has no ambient light): Mix Shader(Is Camera Ray,
    black Background, coloured Background), as Cycles users write it."""
    world = bpy.data.worlds.new(f"{name} background")
    world.color = tuple(color)
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    tree = world.node_tree
    for node in list(tree.nodes):
        tree.nodes.remove(node)
    output = tree.nodes.new("ShaderNodeOutputWorld")
    mix = tree.nodes.new("ShaderNodeMixShader")
    path = tree.nodes.new("ShaderNodeLightPath")
    dark, seen = tree.nodes.new("ShaderNodeBackground"), tree.nodes.new("ShaderNodeBackground")
    dark.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    seen.inputs["Color"].default_value = (*color, 1.0)
    seen.inputs["Strength"].default_value = 1.0
    tree.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    tree.links.new(dark.outputs["Background"], mix.inputs[1])
    tree.links.new(seen.outputs["Background"], mix.inputs[2])
    tree.links.new(mix.outputs["Shader"], output.inputs["Surface"])
    scene.world = world


def import_nff(context, filepath, segments=32) -> dict:
    """Read `filepath` and add it to the context's scene; returns the counts.
    Raises gridwalk.io.SceneFileError, another ValueError (the core's checks of
    the scene) or OSError, always before anything is added."""
    import numpy as np
    from gridwalk.io import read_nff

    from .nff_convert import reference_distances, scene_bounds
    nff = read_nff(filepath)
    kw = nff.kwargs
    distances = reference_distances(kw)     # builds a gridwalk.Scene: validates everything first
    name = Path(filepath).stem
    scene = context.scene
    collection = bpy.data.collections.new(name)
    scene.collection.children.link(collection)
    materials = [make_material(f"{name} f{k}", m) for k, m in enumerate(kw["materials"])]
    counts = {"polygons": add_polygons(collection, name, kw, nff.polygons, materials),
              "spheres": add_spheres(collection, name, kw, materials, segments),
              "cones": add_cones(collection, name, kw, materials, segments),
              "lights": add_lights(collection, name, kw["lights"], distances)}
    lo, hi = scene_bounds(kw)              # clip end: twice the farthest the scene can be
    far = 2.0 * float(np.linalg.norm((lo + hi) / 2 - kw["camera"].eye) + np.linalg.norm(hi - lo) / 2)
    add_camera(scene, collection, name, kw["camera"], far=max(far, 100.0))
    set_world(scene, name, kw["background"])
    return counts


class GRIDWALK_OT_import_nff(bpy.types.Operator, ImportHelper):
    """Import an NFF (Neutral File Format) scene: meshes, spheres, cones, lights, camera"""
    bl_idname = "import_scene.gridwalk_nff"
    bl_label = "Import NFF"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".nff"
    filter_glob: StringProperty(default="*.nff", options={"HIDDEN"})
    segments: IntProperty(name="Segments", default=32, min=4, max=256, step=4,
                          description="Segments of the sphere and cone meshes "
                                      "(a multiple of 4 keeps spheres exact)")

    def execute(self, context):
        from . import dependencies
        try:
            dependencies.import_gridwalk()
        except ImportError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        try:
            counts = import_nff(context, self.filepath, max(4, self.segments // 4 * 4))
        except (ValueError, OSError) as exc:   # gridwalk.io.SceneFileError is a ValueError
            self.report({"ERROR"}, f"NFF import failed: {exc}")
            return {"CANCELLED"}
        self.report({"INFO"}, "NFF: " + ", ".join(f"{v} {k}" for k, v in counts.items()))
        return {"FINISHED"}


def menu_func(self, context):
    self.layout.operator(GRIDWALK_OT_import_nff.bl_idname, text="NFF (.nff)")


def register():
    bpy.utils.register_class(GRIDWALK_OT_import_nff)
    bpy.types.TOPBAR_MT_file_import.append(menu_func)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(menu_func)
    bpy.utils.unregister_class(GRIDWALK_OT_import_nff)
