"""Meshes and their instances -> triangle and sphere arrays.

Every mesh entry of depsgraph.object_instances (curves, surfaces, text and
metaballs come as the mesh instances Blender evaluates them to; collection,
particle and Geometry Nodes instances included, each with its own
matrix_world) is evaluated with its modifiers (`to_mesh()`), triangulated
through loop_triangles and read with foreach_get into numpy. A mesh is read
once and reused by all its instances (mesh_cache.MeshCache; the viewport keeps
it between updates). Objects hidden for render are skipped, and instances
whose instancer is (`renders`). What an instance's object, instancer and
visibility decide is worked out once per kind of instance (`instance_key`,
`InstancePlan`), so that the tenth thousand Geometry Nodes instance of a mesh
costs the reading of its matrix, a few microseconds. In Blender 4.3 and later a
Geometry Nodes carrier's copies skip even that: their matrices are read from
the carrier's instances component in bulk (carrier_instances.py, add_block).

Shading normals come from Blender's normals domain:
  FACE   (all faces flat)            -> no normals (the core uses geometric normals)
  POINT  (all smooth, no sharp edge) -> per-vertex normals, vertices shared
  CORNER (mixed / custom normals)    -> per-corner normals, one vertex per corner
If any mesh in the scene needs normals, flat meshes get their face normals per
corner, since the core takes one normal per vertex.

An object with "Render as sphere" becomes one analytic sphere: centre =
matrix_world @ (centre of its local bounding box), radius = (largest local
half extent) * (largest axis scale of matrix_world). A point cloud object
becomes one sphere per point (point_clouds.py), a hair curves object one cone
frustum per segment (hair.py).

Bad input never reaches the core: an instance whose transform or vertex
coordinates are not finite, or lie beyond +-MAX_COORDINATE in world space, is
skipped and named in a warning (the grid's arithmetic overflows float32 beyond
that). Objects without faces (vertices and edges only) and zero-area
triangles are named in warnings too. count_geometry() counts triangles and
vertices from the evaluated meshes without reading their arrays, for the
memory estimate made before the export.
"""
from __future__ import annotations

import math

import numpy as np

from gridwalk.mesh_checks import zero_area_count

from .assemble import assemble_triangles, mirror_flags
from ._matrix import finite, to_numpy
from .hair import cone_set, segment_count
from .instance_values import is_instance_layer, part_values, row_value
from .object_info import display_color
from .particle_hair import hair_systems, particle_cone_sets, particle_segment_count
from .point_clouds import point_count, point_set

MAX_COORDINATE = 1e30       # larger world coordinates are refused (float32 extents overflow)


class MeshData:
    """One evaluated mesh in object space (float32 / int32 arrays)."""

    def __init__(self, co, triangles, normals, material_slot, uvs=None, colors=None):
        self.co = co                   # (V, 3) positions; one per corner for CORNER meshes
        self.uvs = uvs                 # (T, 3, 2) corner UVs, or None (not asked for, or no UV map)
        self.colors = colors           # (T, 3, 3) corner colours (linear RGB), or None
        self.generated = None          # (T, 3, 3) corner Generated coordinates, or None (not asked for)
        self.object_coords = None      # (T, 3, 3) corner Object coordinates (object space), or None
        self.object_normals = None     # (T, 3, 3) corner shading normals (object space), or None
        self.triangles = triangles     # (T, 3) indices into co
        self.normals = normals         # (V, 3) shading normals or None (flat)
        self.material_slot = material_slot   # (T,) material slot index
        self.missing_uv_layer = None   # a UV map a material names that the mesh lacks (its render one was read)
        self.missing_color_layer = None  # the colour attribute a material reads that the mesh lacks ("": any)
        flat = co.reshape(-1)      # NaN propagates through max / min; Inf shows in them
        top, bottom = (float(flat.max()), float(flat.min())) if flat.size else (0.0, 0.0)
        self.finite = math.isfinite(top) and math.isfinite(bottom)
        self.extent = max(abs(top), abs(bottom)) if self.finite else math.inf   # largest |coordinate|
        self.degenerate = zero_area_count(co, triangles) if self.finite else 0
        if normals is not None and not np.isfinite(normals.reshape(-1).sum()):
            self.normals = np.nan_to_num(normals, nan=0.0, posinf=0.0, neginf=0.0)  # the core falls back
        # Corners whose UV or colour is NaN or Inf (the core refuses them): read as 0, and counted
        self.non_finite_corners = 0
        for name in ("uvs", "colors"):
            values = getattr(self, name)
            if values is not None and not np.isfinite(values.reshape(-1).sum()):
                bad = ~np.isfinite(values)
                self.non_finite_corners += int(bad.any(axis=-1).sum())
                setattr(self, name, np.where(bad, np.float32(0.0), values))




def _get(collection, attr, count, width, dtype):
    out = np.empty(count * width, dtype=dtype)
    if count:
        collection.foreach_get(attr, out)
    return out.reshape(count, width) if width > 1 else out


def _attribute(mesh, name, prop, count, width, dtype):
    """A generic attribute's values (the fast foreach_get path), or None if absent."""
    attributes = getattr(mesh, "attributes", None)
    attribute = attributes.get(name) if attributes is not None else None
    if attribute is None or len(attribute.data) != count:
        return None
    return _get(attribute.data, prop, count, width, dtype)


def _positions(mesh, n_verts):
    co = _attribute(mesh, "position", "vector", n_verts, 3, np.float32)      # Blender 3.5+
    return co if co is not None else _get(mesh.vertices, "co", n_verts, 3, np.float32)


def _corner_verts(mesh, n_loops):
    verts = _attribute(mesh, ".corner_vert", "value", n_loops, 1, np.int32)  # Blender 3.6+
    return verts if verts is not None else _get(mesh.loops, "vertex_index", n_loops, 1, np.int32)


def _material_slots(mesh, tris, n_tris):
    tri_polys = getattr(mesh, "loop_triangle_polygons", None)              # Blender 3.6+
    if tri_polys is None:
        return _get(tris, "material_index", n_tris, 1, np.int32)
    if mesh.attributes.get("material_index") is None:
        return np.zeros(n_tris, np.int32)
    per_face = _attribute(mesh, "material_index", "value", len(mesh.polygons), 1, np.int32)
    return per_face[_get(tri_polys, "value", n_tris, 1, np.int32)]


def _domain(mesh, tris, n_tris) -> str:
    domain = getattr(mesh, "normals_domain", None)          # Blender 4.1+
    if domain is not None:
        return domain
    smooth = _get(tris, "use_smooth", n_tris, 1, bool)
    if not smooth.any():
        return "FACE"
    if getattr(mesh, "has_custom_normals", False) or getattr(mesh, "use_auto_smooth", False):
        return "CORNER"
    return "POINT" if smooth.all() else "CORNER"


def _vertex_normals(mesh, n_verts):
    if hasattr(mesh, "vertex_normals"):                     # Blender 3.5+: fast path
        return _get(mesh.vertex_normals, "vector", n_verts, 3, np.float32)
    return _get(mesh.vertices, "normal", n_verts, 3, np.float32)


def _corner_normals(mesh, n_loops):
    if hasattr(mesh, "corner_normals"):                     # Blender 4.1+
        return _get(mesh.corner_normals, "vector", n_loops, 3, np.float32)
    mesh.calc_normals_split()                               # Blender <= 4.0
    return _get(mesh.loops, "normal", n_loops, 3, np.float32)


def _corner_uvs(mesh, layer_name: str, n_loops):
    """(corners, 2) UVs of the named layer (else the active render one), or None without UV maps."""
    layers = mesh.uv_layers
    if not len(layers):
        return None
    layer = layers.get(layer_name) if layer_name else None
    if layer is None:
        layer = next((l for l in layers if l.active_render), None) or layers.active or layers[0]
    if hasattr(layer, "uv"):                                    # Blender 3.5+
        return _get(layer.uv, "vector", n_loops, 2, np.float32)
    return _get(layer.data, "uv", n_loops, 2, np.float32)


# A generic attribute's data type -> (its foreach_get field, values per element): what the
# Attribute node's Color output gives of it, as Cycles does (a number on all three channels,
# a 2D vector with 0 for z)
ATTRIBUTE_VALUES = {"FLOAT": ("value", 1, np.float32), "INT": ("value", 1, np.int32), "BOOLEAN": ("value", 1, bool),
                    "INT8": ("value", 1, np.int32),    # (Blender 4.x; Cycles reads a 2D whole number as nothing)
                    "FLOAT_VECTOR": ("vector", 3, np.float32), "FLOAT2": ("vector", 2, np.float32),
                    "FLOAT_COLOR": ("color", 4, np.float32), "BYTE_COLOR": ("color", 4, np.float32)}


def _corner_colors(mesh, layer_name: str, n_loops, n_verts):
    """((corners, 3) linear RGB, missing): the named colour attribute ("": the
    render one), or a generic attribute of that name (an Attribute node's: a
    number, vector or colour on points, faces or corners, as its Color output
    reads it). Where the mesh has no such attribute, black, as Cycles reads a
    missing attribute, and `missing` is the name asked for ("" for the render
    one); else missing is None. (None, None) where Blender has no colour
    attributes API."""
    attributes = getattr(mesh, "color_attributes", None)       # Blender 3.2+
    if attributes is None:
        return None, None
    attr = attributes.get(layer_name) if layer_name else None
    if attr is None and not layer_name and len(attributes):
        index = getattr(attributes, "render_color_index", 0)
        attr = attributes[index] if 0 <= index < len(attributes) else attributes[0]
    if attr is None and layer_name:
        attr = mesh.attributes.get(layer_name)
    field, width, dtype = ATTRIBUTE_VALUES.get(getattr(attr, "data_type", ""), (None, 0, None))
    sizes = {"POINT": n_verts, "CORNER": n_loops, "FACE": len(mesh.polygons)}
    domain = getattr(attr, "domain", "")
    if field is None or domain not in sizes or len(attr.data) != sizes[domain]:
        return np.zeros((n_loops, 3), np.float32), layer_name
    count = sizes[domain]
    values = _get(attr.data, field, count, width, dtype).reshape(count, width).astype(np.float32)
    rgb = np.repeat(values, 3, axis=1) if width == 1 else np.zeros((count, 3), np.float32)
    if width > 1:
        rgb[:, :min(width, 3)] = values[:, :3]
    if domain == "POINT":
        rgb = rgb[_corner_verts(mesh, n_loops)]
    elif domain == "FACE":     # (each corner its face's value, wherever Blender keeps its loops)
        starts = _get(mesh.polygons, "loop_start", count, 1, np.int32).reshape(-1)
        totals = _get(mesh.polygons, "loop_total", count, 1, np.int32).reshape(-1)
        face = np.repeat(np.arange(count), totals)
        offsets = np.arange(len(face)) - np.repeat(np.cumsum(totals) - totals, totals)
        per_loop = np.zeros((n_loops, 3), np.float32)
        per_loop[np.repeat(starts, totals) + offsets] = rgb[face]
        rgb = per_loop
    return np.ascontiguousarray(rgb, np.float32), None


def generated_coordinates(co, texspace):
    """Blender's Generated coordinates of object-space points: the mesh's texture
    space (location L, size S: half its extent) mapped to [0, 1], (co - L) / (2 S)
    + 1/2, as Cycles computes them (an axis of size 0 gives 1/2)."""
    location, size = (np.asarray(v, np.float64) for v in texspace)
    factor = np.divide(0.5, size, out=np.zeros(3), where=size != 0)
    return ((co - location) * factor + 0.5).astype(np.float32)


def texture_space(mesh) -> tuple:
    """(location, size) of a mesh's texture space (Blender 4.0+ and 3.x names)."""
    location = getattr(mesh, "texture_space_location", None) or getattr(mesh, "texspace_location")
    size = getattr(mesh, "texture_space_size", None) or getattr(mesh, "texspace_size")
    return tuple(location), tuple(size)


def read_mesh(mesh, uv_layer=None, color_layer=None, texspace=None, object_coords=False,
              object_normals=False) -> MeshData:
    """Triangulate an evaluated mesh into numpy arrays (no per-element Python loops).

    Uses Blender's own triangulation (loop_triangles) and, where Blender has
    them, the generic attributes, whose foreach_get is much faster than the
    per-element RNA collections (~0.3 s for 1M triangles). Corner UVs and
    colours are read only when a material needs them (uv_layer / color_layer
    not None; "" = the active render layer; uv_layer may also be a tuple of
    each material slot's layer, MaterialTable.layers); corner Generated
    coordinates where texspace (texture_space) is given, corner Object
    coordinates (the positions) where object_coords is, corner normals in
    object space (Normal coordinates) where object_normals is.
    """
    if hasattr(mesh, "calc_loop_triangles"):
        mesh.calc_loop_triangles()
    tris = mesh.loop_triangles
    n_tris, n_verts, n_loops = len(tris), len(mesh.vertices), len(mesh.loops)
    co = _positions(mesh, n_verts)
    tri_loops = _get(tris, "loops", n_tris, 3, np.int32)
    slots = _material_slots(mesh, tris, n_tris)
    domain = _domain(mesh, tris, n_tris) if n_tris else "FACE"
    uvs = colors = None
    missing = None
    if isinstance(uv_layer, tuple):   # each slot's material its own UV map
        uvs, missing = _slot_uvs(mesh, uv_layer, slots, tri_loops, n_loops)
    elif uv_layer is not None:
        corner = _corner_uvs(mesh, uv_layer, n_loops)
        uvs = None if corner is None else corner[tri_loops]
        missing = uv_layer if uv_layer and mesh.uv_layers.get(uv_layer) is None else None
    missing_colors = None
    if color_layer is not None:
        corner, missing_colors = _corner_colors(mesh, color_layer, n_loops, n_verts)
        colors = None if corner is None else corner[tri_loops]
    if domain == "CORNER":
        data = MeshData(co[_corner_verts(mesh, n_loops)], tri_loops, _corner_normals(mesh, n_loops), slots,
                        uvs, colors)
    else:
        tri_verts = _corner_verts(mesh, n_loops)[tri_loops]
        normals = _vertex_normals(mesh, n_verts) if domain == "POINT" else None
        data = MeshData(co, tri_verts, normals, slots, uvs, colors)
    if texspace is not None:
        # Blender's undeformed positions (each vertex before deforming modifiers and
        # shape keys, as Cycles takes Generated coordinates; where the depsgraph kept
        # none, the positions themselves)
        orco = _get(mesh.vertices, "undeformed_co", n_verts, 3, np.float32)
        if domain == "CORNER":
            orco = orco[_corner_verts(mesh, n_loops)]
        data.generated = generated_coordinates(orco, texspace)[data.triangles]
    if object_coords:
        data.object_coords = data.co[data.triangles]
    if object_normals:
        data.object_normals = corner_normals(data)
    if uvs is not None:
        data.missing_uv_layer = missing
    data.missing_color_layer = missing_colors
    return data


def corner_normals(data: MeshData) -> np.ndarray:
    """(T, 3, 3) float32 each corner's shading normal in object space: its smooth
    normal where the mesh has them, else its face's (by its winding; 0 for a face
    of no area, which the core reads as the zero vector)."""
    if data.normals is not None:
        return np.ascontiguousarray(data.normals[data.triangles], np.float32)
    corners = data.co[data.triangles].astype(np.float64)
    face = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(face, axis=1, keepdims=True)
    face = np.divide(face, length, out=np.zeros_like(face), where=length > 0)
    return np.repeat(face[:, None, :], 3, axis=1).astype(np.float32)


def _slot_uvs(mesh, layers, slots, tri_loops, n_loops):
    """((T, 3, 2) corner UVs, each triangle's from the UV map its slot's
    material names (layers[slot]; the render one where it names none), a
    named map the mesh lacks or None); (None, None) without UV maps."""
    if not len(mesh.uv_layers):
        return None, None
    slot = np.clip(slots, 0, len(layers) - 1)
    uvs = np.empty(tri_loops.shape + (2,), np.float32)
    missing = None
    for name in sorted({layer or "" for layer in layers}):
        which = np.isin(slot, [k for k, layer in enumerate(layers) if (layer or "") == name])
        uvs[which] = _corner_uvs(mesh, name, n_loops)[tri_loops[which]]
        if name and mesh.uv_layers.get(name) is None and which.any():
            missing = missing or name
    return uvs, missing


def _quoted(names) -> str:
    return ", ".join(f"'{name}'" for name in sorted(names))


def object_key(obj) -> tuple:
    """What tells an evaluated object apart within one export: the addresses of
    the object, its original and its data. (The depsgraph lists Geometry Nodes
    and particle instances through a few temporary objects, which differ from
    one another only in these.)"""
    return obj.as_pointer(), obj.original.as_pointer(), obj.data.as_pointer() if obj.data is not None else 0


def _in_order(blocks) -> list:
    """The blocks of mesh instances (matrices, plans, instance numbers, own values) in
    the order of their numbers: blocks read in bulk (add_block) and instances read again come
    after those read first, but take their places among them."""
    if not blocks:
        return blocks
    seqs = np.concatenate([b[2] for b in blocks])
    if not (np.diff(seqs) < 0).any():
        return blocks
    order = np.argsort(seqs, kind="stable")
    columns = [np.concatenate([b[k] for b in blocks])[order] for k in range(4)]
    return [tuple(c[i:i + ROW_BLOCK] for c in columns) for i in range(0, len(seqs), ROW_BLOCK)]


def instance_key(inst, obj=None) -> tuple:
    """What decides how an object instance renders, but for its matrix: object_key(), its
    instancer's address and its show flags. Geometry Nodes and particles list tens of
    thousands of instances under a few of these."""
    obj = inst.object if obj is None else obj
    parent = inst.parent if inst.is_instance else None
    data = obj.data
    return (obj.as_pointer(), obj.original.as_pointer(), data.as_pointer() if data is not None else 0,
            parent.as_pointer() if parent is not None else 0, inst.show_self,
            bool(getattr(inst, "show_particles", True)))


def renders(inst, particles: bool = False) -> bool:
    """Whether a depsgraph object instance is geometry that the render shows
    (particles: whether its particle systems show, which they can while the
    emitter itself does not: the particle settings' Show Emitter off).

    Meshes, point clouds and hair curves only: Blender lists the evaluated geometry of a curve, surface,
    text or metaball as a mesh instance whose parent is the object itself,
    beside the object, whose data is the unevaluated datablock that every
    object using it shares (exporting both gave each such object twice, and
    objects sharing a curve one another's modifiers' geometry). An instance
    shows when its instancer does: the source of particle and Geometry Nodes
    instances is usually hidden in renders, and Blender renders them all the
    same (the depsgraph of a final render holds no hidden object itself)."""
    obj = inst.object
    if particles:
        if obj.type != "MESH" or not getattr(inst, "show_particles", True):
            return False
    elif obj.type not in ("MESH", "POINTCLOUD", "CURVES") or not inst.show_self:
        return False
    return shown(inst, obj)


def shown(inst, obj) -> bool:
    """Whether the render shows a depsgraph object instance by its object's and instancer's
    Disable in Renders (renders(); lights too)."""
    if not inst.is_instance or inst.parent is None:
        return not obj.original.hide_render
    parent = inst.parent.original
    if parent.hide_render:
        return False
    # A member of an instanced collection that is itself hidden in renders:
    # the final render's depsgraph leaves it out, the viewport's lists it.
    return not (obj.original.hide_render and getattr(parent, "instance_type", "") == "COLLECTION")


# Object settings the Whitted core does not model (every ray sees every
# object): (property, the value that asks for something else, what it is called).
# (Shadow Catcher was one: it is rendered now, Material.shadow_catcher.)
IGNORED_VISIBILITY = ()
# An object's Visibility that its materials carry (gridwalk.Material's fields of the same names).
RAY_VISIBILITY = ("visible_camera", "visible_glossy", "visible_transmission", "visible_shadow")


def as_sphere(obj) -> bool:
    settings = getattr(obj.original, "gridwalk", None)
    return settings is not None and settings.render_as_sphere


def read_object_mesh(obj, layers=(None, None)) -> MeshData | None:
    """The evaluated object's mesh (modifiers applied), read into arrays;
    layers = (uv layer, colour layer[, corner points]) as MaterialTable.layers
    gives them. The Generated coordinates take the texture space of the
    object's mesh before its modifiers and its undeformed positions, as Cycles
    does (read_mesh)."""
    uv, color, points = (tuple(layers) + ((),))[:3]
    color = None if is_instance_layer(color) else color   # (filled per instance: instance_values.py)
    generated = "generated" in points
    texspace = texture_space(obj.data) if generated and getattr(obj, "type", "") == "MESH" else None
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        if generated and texspace is None:
            texspace = texture_space(mesh)
        return read_mesh(mesh, uv, color, texspace, "object" in points, "normal" in points)
    finally:
        obj.to_mesh_clear()


def hidden_from(obj) -> tuple[str, ...]:
    """The RAY_VISIBILITY fields the object turns off (Object > Visibility > Ray Visibility)."""
    source = getattr(obj, "original", None) or obj
    return tuple(field for field in RAY_VISIBILITY if getattr(source, field, True) is False)


def matte_names(obj) -> tuple[str, str, int]:
    """(object, asset, pass index) of an evaluated object's primitives: the
    names Cryptomatte gives them, its original's name and that of its topmost
    parent, as Blender hashes them (the ID's name, without a library), and
    its Pass Index (the Object Index pass)."""
    source = getattr(obj, "original", None) or obj
    top = source
    while getattr(top, "parent", None) is not None:
        top = top.parent
    return source.name, top.name, int(getattr(source, "pass_index", 0))


ROW_BLOCK = 8192    # mesh instances' matrices gathered as Python rows before they become one numpy block
NO_VALUE = (math.nan,) * 3   # a row's own value where its plan's applies (instance_values.py)


class InstancePlan:
    """What every instance of one instance_key (object, original, data, instancer, show
    flags) becomes. Set when the plan is made: renders (whether the render shows it),
    flags (holdout, hidden_from fields, shadow catcher), name (the object's name in warnings), hair
    (whether its particle hair renders). Set at its first instance with a finite matrix
    (as the export read objects before: none of a skipped object's materials, mesh or
    warnings): kind ("mesh", "sphere", "shapes" or "none", a mesh without triangles),
    known (what MeshCollector._source read, with matte_names() last), names (its
    Cryptomatte names), index (its place among the mesh plans, -1 for other kinds), info (the
    colour layer of one value per instance its materials read, instance_values.py, or None)
    and info_value (that layer's value for every instance, where not their own); unread:
    whether instances read one by one miss their copy's own value (a Geometry Nodes instance
    attribute); parent: the instancer (None: the object itself is no instance); particles: the
    particle settings that instance it (None: none)."""
    __slots__ = ("renders", "flags", "name", "hair", "kind", "known", "names", "index", "info", "info_value",
                 "unread", "parent", "particles")

    def __init__(self, renders, flags, name, hair, parent=None, particles=None):
        self.renders, self.flags, self.name, self.hair = renders, flags, name, hair
        self.kind, self.known, self.names, self.index = None, None, None, -1
        self.info, self.info_value, self.unread = None, (0.0, 0.0, 0.0), False
        self.parent, self.particles = parent, particles


class MeshCollector:
    """Gathers world-space triangles and spheres over all object instances.

    cache: a mesh_cache.MeshCache; meshes it holds are not read again (the
    viewport keeps one between updates; a final render starts empty)."""

    def __init__(self, materials, cache, view_layer=None, render: bool = True):
        self.materials = materials
        self.cache = cache
        self.render = render           # a final render's depsgraph (else the viewport's): which hair shows
        self.view_layer = view_layer   # (whose collections may set objects to Holdout)
        self._flag_cache = {}          # original object address -> (holdout, hidden_from fields, catcher)
        self.used = set()          # the cache entries this export used
        self.parts = []            # (cache key, MeshData, matrix, slot->material lookup)
        self.part_matrices = np.zeros((0, 4, 4))   # after finish(): every part's matrix, (P, 4, 4) (parts' are its rows)
        self.part_values = None    # after finish(): each part's value (instance_values.py), (P, 3) float32, where a material reads one
        # (carrier, attribute) Geometry Nodes instance attributes that copies read one by one did not read
        self.unread_instance_attributes = set()
        self._part_plans = np.zeros(0, np.int64)   # after finish(): each part's plan (InstancePlan.index)
        self.spheres = []          # (centre, radius, material index)
        self.point_sets = []       # point_clouds.PointSet per point cloud instance
        self.cone_sets = []        # hair.ConeSet per hair curves instance
        self.non_uniform_spheres = []
        self.invalid = {}          # object name -> why it was skipped
        self.faceless = set()      # mesh objects without faces
        self.instancers = set()    # objects that instance others (a Geometry Nodes carrier's own mesh may be empty)
        self.ignored = {}          # IGNORED_VISIBILITY label -> names of the objects that set it
        self.visibility_read = set()   # the objects whose settings were read for `ignored`
        self.degenerate = {}       # object name -> (zero-area triangles, triangles)
        self.without_uvs = set()   # textured objects whose mesh has no UV map
        self.missing_uv_layers = {}  # object name -> the UV map its material names and its mesh lacks
        self.mixed_uv_maps = {}      # (object name, material name) -> the UV maps its textures read (the first read)
        self.missing_color_layers = {}  # object name -> the colour attribute its material reads and its mesh lacks
        self.non_finite_corners = {}  # object name -> corners whose UV or colour was NaN or Inf (read as 0)
        self.textured_spheres = set()  # 'Render as sphere' objects with image textures (a sphere has no UVs)
        self.mesh_spheres = set()      # 'Render as sphere' objects rendered as meshes: a texture reads Generated or per instance
        self.emissive_shapes = set()   # spheres, point clouds and hair with an emissive material (they light nothing)
        self.info_shapes = set()       # point clouds and hair whose material reads a value per instance (black)
        self.layout = None         # after arrays(): per part, where its vertices and triangles went (Placement)
        # Cryptomatte's names (object, its top parent: the asset) of each part, sphere and point or cone set
        self.part_names, self.sphere_names, self.set_names = [], [], {}
        self._sources = {}         # (object, original, data addresses) -> what _source() read of it
        self._lookups = {}         # material lookup bytes -> the one array the parts share
        self._hair = {}            # object_key -> whether it has hair particle systems to render
        self._shape_notes = {}     # material lookup (slots' indices) -> (whether it emits, whether it reads a value per instance)
        self._sphere_bounds = {}   # evaluated mesh address -> (local centre, half size) of 'render as sphere' objects
        self._plans = {}           # add_instance's memo -> InstancePlan
        self._mesh_plans = []      # the plans of mesh kind, by InstancePlan.index
        # mesh instances' rows since the last block, their plans, numbers and own values (instance_values.py)
        self._rows, self._row_plans, self._row_seqs, self._row_values = [], [], [], []
        # ((K, 4, 4) matrices, plan indices, instance numbers, (K, 3) own values) of mesh instances, in order
        self._blocks = []
        self._seq = 0              # add_instance calls so far (the order _skip keeps)
        self._skip_rank = {}       # object name -> the rank of the reason `invalid` holds

    def add_instance(self, inst, obj=None):
        """One entry of depsgraph.object_instances (any type: what is not rendered geometry is
        passed over); obj: its object, if read already (each read makes a new Python object).

        What an instance's object, instancer and visibility decide is worked out once per
        instance_key and kept (InstancePlan): Geometry Nodes and particles list tens of
        thousands of instances of a few of those. A mesh instance then costs its matrix,
        read as a row into a block; finish() checks the rows' bounds and makes the parts."""
        obj = inst.object if obj is None else obj
        plan = self._memo_plan(inst, obj, instance_key(inst, obj))
        self._seq += 1
        if plan.renders:
            self._add_geometry(plan, inst, obj)
        if plan.hair:
            self._add_particle_hair(inst, obj)

    def _add_geometry(self, plan, inst, obj):
        """A rendered instance's own geometry under its matrix: a mesh's row (parts come in
        finish()), a sphere, or a point or cone set; or why it is skipped."""
        m = inst.matrix_world
        row = m[0][:] + m[1][:] + m[2][:] + m[3][:]
        if plan.index >= 0 and plan.known[3].finite:
            # A mesh read already (the ten-thousandth copy of a scattered stone): its
            # row alone; _flush_rows checks the block's rows are finite, all at once.
            self._add_row(row, plan, None if plan.info is None else row_value(plan, inst, obj, row[3:12:4]))
            return
        if not finite(row):
            self._skip(plan.name, "its transform is not finite (NaN or Inf)")
            return
        if plan.known is None:
            self._resolve(plan, obj)
        if plan.kind == "sphere":
            self._add_sphere(obj.name, plan.known[2], row, plan.known[1], plan.names)
        elif plan.kind == "shapes":
            read, sets = (point_set, self.point_sets) if obj.type == "POINTCLOUD" else (cone_set, self.cone_sets)
            lookup = plan.known[1]
            matrix = np.array(row, dtype=np.float64).reshape(4, 4)
            self._add_shapes(obj.name, lookup, *read(obj, matrix, lookup, MAX_COORDINATE), sets, plan.names)
        elif plan.kind == "mesh" and not plan.known[3].finite:
            self._skip(plan.name, "its mesh has non-finite vertex coordinates (NaN or Inf)")
        elif plan.kind == "mesh":
            self._add_row(row, plan, None if plan.info is None else row_value(plan, inst, obj, row[3:12:4]))

    def _add_row(self, row, plan, value):
        """A mesh instance's matrix (16 floats) into the rows of the next block, with its own
        value (instance_values.row_value; None: its plan's)."""
        self._rows.append(row)
        self._row_plans.append(plan.index)
        self._row_seqs.append(self._seq)
        self._row_values.append(NO_VALUE if value is None else value)
        if plan.unread:
            self.unread_instance_attributes.add((plan.parent.name, plan.info.name))
        if len(self._rows) >= ROW_BLOCK:
            self._flush_rows()

    def _memo_plan(self, inst, obj, memo) -> InstancePlan:
        plan = self._plans.get(memo)
        if plan is None:
            plan = self._plans[memo] = self._plan(inst, obj)
        return plan

    def plan_of(self, inst, obj, memo) -> InstancePlan:
        """The plan of the instances whose instance_key is memo (add_instance's), its object
        read where it renders (carrier_instances: a carrier's first copy of a reference)."""
        plan = self._memo_plan(inst, obj, memo)
        if plan.renders and plan.known is None:
            self._resolve(plan, obj)
        return plan

    def next_seq(self) -> int:
        """An instance number for an instance read elsewhere (carrier_instances), as add_instance counts."""
        self._seq += 1
        return self._seq

    def count_from(self, seq: int):
        """Numbers the next instance `seq` (one read again under the number it had first)."""
        self._seq = seq - 1

    def add_block(self, matrices, which, seqs, values=None):
        """Mesh instances read elsewhere (carrier_instances), after those read so far: their
        (K, 4, 4) float64 matrices, plans (InstancePlan.index, resolved) and instance numbers;
        values: (K, 3) each copy's own value, NaN where its plan's applies (instance_values.py),
        or None for none."""
        self._flush_rows()
        self._append_block(matrices, which, seqs, np.full((len(seqs), 3), np.nan) if values is None else values)

    def _plan(self, inst, obj) -> InstancePlan:
        """What an instance of this object, instancer and visibility becomes (add_instance)."""
        if inst.is_instance and inst.parent is not None:
            self.instancers.add(inst.parent.name)
        hair = renders(inst, particles=True) and self._has_hair(obj)
        if not renders(inst):
            return InstancePlan(False, None, obj.name, hair)
        source = obj.original
        if source.name not in self.visibility_read:   # once per object, not per instance (particles: millions)
            self.visibility_read.add(source.name)
            for prop, value, label in IGNORED_VISIBILITY:
                if getattr(source, prop, not value) == value:
                    self.ignored.setdefault(label, set()).add(source.name)
        system = getattr(inst, "particle_system", None) if inst.is_instance else None
        return InstancePlan(True, self._flags(inst), obj.name, hair, inst.parent if inst.is_instance else None,
                            system.settings if system is not None else None)

    def _resolve(self, plan, obj):
        """Reads what the plan's object becomes (its materials, mesh or shape), at its first
        instance with a finite matrix."""
        memo = object_key(obj) + plan.flags
        known = self._sources.get(memo)
        if known is None:
            known = self._sources[memo] = (*self._source(obj, plan.flags), matte_names(obj))
        plan.kind, plan.known, plan.names = known[0], known, known[-1]
        if plan.kind == "mesh" and is_instance_layer(known[4][1]):
            plan.info = known[4][1]
            plan.info_value = plan.info.plan_value(plan.parent, obj, display_color(plan.parent, obj), plan.particles)
            plan.unread = plan.info.unread_by_rows(plan.parent)
        if plan.kind == "mesh":
            plan.index = len(self._mesh_plans)
            self._mesh_plans.append(plan)

    def _skip(self, name, why, rank=None):
        """Names an object in the warnings as skipped, for `why`. Of several reasons for one
        name, the one met last in the order the instances came is kept (rank: (instance
        number, 0 for its geometry or 1 for its particle hair); now, by default)."""
        rank = (self._seq, 0) if rank is None else rank
        if rank >= self._skip_rank.get(name, (-1, 0)):
            self._skip_rank[name] = rank
            self.invalid[name] = why

    def _flush_rows(self):
        """The matrices read since the last flush, as one block: (K, 4, 4) float64, their
        plans' indices, their instance numbers. A row that is not finite is named in the
        warnings (as _add_geometry names the first instance of a mesh) and left out."""
        if self._rows:
            matrices = np.array(self._rows, dtype=np.float64).reshape(-1, 4, 4)
            which, seqs = np.array(self._row_plans, dtype=np.int64), np.array(self._row_seqs, dtype=np.int64)
            values = np.array(self._row_values, dtype=np.float64).reshape(-1, 3)
            self._rows, self._row_plans, self._row_seqs, self._row_values = [], [], [], []
            self._append_block(matrices, which, seqs, values)

    def _append_block(self, matrices, which, seqs, values):
        finite_rows = np.isfinite(matrices).all(axis=(1, 2))
        if not finite_rows.all():
            for k, seq in zip(which[~finite_rows].tolist(), seqs[~finite_rows].tolist()):
                self._skip(self._mesh_plans[k].name, "its transform is not finite (NaN or Inf)", (seq, 0))
            matrices, which, seqs = matrices[finite_rows], which[finite_rows], seqs[finite_rows]
            values = values[finite_rows]
        if len(matrices):
            self._blocks.append((matrices, which, seqs, values))

    def finish(self, should_stop=None) -> bool:
        """Turns the mesh instances read so far into parts, in the order they came, block by
        block: each instance whose mesh's vertices lie beyond +-MAX_COORDINATE under its
        matrix is named in the warnings instead. Called once, after the last add_instance;
        False when should_stop() said stop (asked before each block)."""
        self._flush_rows()
        plans = self._mesh_plans
        extents = np.array([p.known[3].extent for p in plans], np.float64)
        noted = set()
        blocks, self._blocks = _in_order(self._blocks), []
        kept, kept_plans, kept_values = [], [], []
        for matrices, which, seqs, values in blocks:
            if should_stop is not None and should_stop():
                return False
            # |matrix @ p| <= (largest row sum of |linear part|) * extent + largest |translation|
            # for |p|inf <= extent
            with np.errstate(over="ignore"):
                linear = np.abs(matrices[:, :3, :3]).sum(axis=2).max(axis=1)
                inside = linear * extents[which] + np.abs(matrices[:, :3, 3]).max(axis=1) <= MAX_COORDINATE
            for k, seq in zip(which[~inside].tolist(), seqs[~inside].tolist()):
                self._skip(plans[k].name, f"its vertices lie beyond +-{MAX_COORDINATE:g} in world space", (seq, 0))
            kept.append(matrices[inside])
            kept_plans.append(which[inside])
            kept_values.append(values[inside])
        # Every part's matrix is a row of one (P, 4, 4) array (assemble_triangles and
        # _instances take them from it, not one by one).
        self.part_matrices = np.concatenate(kept) if kept else np.zeros((0, 4, 4))
        which = np.concatenate(kept_plans) if kept_plans else np.zeros(0, np.int64)
        for k in dict.fromkeys(which.tolist()):   # (each mesh once, in the order it first came)
            if k not in noted:
                noted.add(k)
                self._note_mesh(plans[k])
        self._part_plans = which
        self.part_values = part_values(plans, which, np.concatenate(kept_values) if kept_values else np.zeros((0, 3)))
        which = which.tolist()
        heads = [(p.known[2], p.known[3], p.known[1]) for p in plans]   # (key, MeshData, lookup) per plan
        self.parts.extend((heads[k][0], heads[k][1], m, heads[k][2]) for k, m in zip(which, self.part_matrices))
        self.part_names.extend([plans[k].names for k in which])
        return True

    def _source(self, obj, flags=(False, (), False)) -> tuple:
        """(kind, material lookup, ...) of an evaluated object: "shapes" (a point cloud or
        hair curves), "sphere" (+ (its local bounds' centre, half size, whether it is
        textured)), "mesh" (+ cache key, MeshData, uv/colour layers, whether it is a mesh
        object, [whether its warnings were noted]), or "none" (a mesh without triangles)."""
        lookup = np.asarray(self.materials.slot_indices(obj, *flags), dtype=np.int32)
        lookup = self._lookups.setdefault(lookup.tobytes(), lookup)   # one array per lookup: chunks compare by `is`
        kind = obj.type
        sphere = kind not in ("POINTCLOUD", "CURVES") and as_sphere(obj)
        layers = self.materials.layers(lookup)
        if sphere and (layers[2] or is_instance_layer(layers[1])):
            sphere = False                 # (an analytic sphere has no Generated coordinates nor corner colours)
            self.mesh_spheres.add(obj.name)
        if kind in ("POINTCLOUD", "CURVES"):
            self._note_shapes(obj.name, lookup)
            return "shapes", lookup
        if sphere:
            self._note_shapes(obj.name, lookup)
            # (objects sharing one evaluated mesh share its local bounds: read once, not per
            # object; 820 balls of one mesh spent most of their export here)
            data_key = obj.data.as_pointer() if obj.data is not None else None
            bounds = self._sphere_bounds.get(data_key) if data_key is not None else None
            if bounds is None:
                corners = [tuple(c) for c in obj.bound_box]
                lo, hi = [min(c[a] for c in corners) for a in range(3)], [max(c[a] for c in corners) for a in range(3)]
                bounds = ([(l + h) / 2.0 for l, h in zip(lo, hi)], max(h - l for l, h in zip(lo, hi)) / 2.0)
                if data_key is not None:
                    self._sphere_bounds[data_key] = bounds
            return "sphere", lookup, (*bounds, layers[0] is not None)
        key, data = self.cache.mesh(obj, layers)
        self.used.add(key)
        if layers[0] is not None:
            for material, maps in self.materials.mixed_uv_maps(lookup, obj.data):
                self.mixed_uv_maps[(obj.name, material)] = maps
        if data is None or not len(data.triangles):
            # (curves without bevel are paths, and a mesh that had faces before
            # its modifiers took them all is what they were set up to do: no mistakes)
            original = obj.original
            if original.type == "MESH" and not (original.data is not None and len(original.data.polygons)):
                self.faceless.add(obj.name)
            return "none", lookup
        return "mesh", lookup, key, data, layers, obj.original.type == "MESH", [False]

    def _flags(self, inst) -> tuple:
        """(holdout, hidden_from fields, shadow catcher) of an instance: its object's; for an instance
        (Geometry Nodes, particles, a collection instance) the instancer's Holdout, the visibility
        both turn off and a Shadow Catcher either sets, as Cycles takes them."""
        holdout, hidden, catcher = self._object_flags(inst.object)
        parent = inst.parent if inst.is_instance else None
        if parent is not None:
            parent_holdout, parent_hidden, parent_catcher = self._object_flags(parent)
            holdout, hidden = parent_holdout, tuple(sorted(set(hidden) | set(parent_hidden)))
            catcher = catcher or parent_catcher
        return holdout, hidden, catcher

    def _object_flags(self, obj) -> tuple:
        """(whether the object is a holdout: its own Visibility > Holdout, or a collection's in the
        view layer; the visibility fields it turns off; whether it is a Shadow Catcher), read once
        per object."""
        key = obj.original.as_pointer()   # (the depsgraph lists instances through reused temporary objects)
        found = self._flag_cache.get(key)
        if found is None:
            source = obj.original
            try:
                holdout = bool(source.holdout_get(view_layer=self.view_layer)) if self.view_layer is not None \
                    else bool(getattr(source, "is_holdout", False))
            except (AttributeError, TypeError, RuntimeError):
                holdout = bool(getattr(source, "is_holdout", False))
            catcher = bool(getattr(source, "is_shadow_catcher", False))
            found = self._flag_cache[key] = (holdout, tuple(sorted(hidden_from(obj))), catcher)
        return found

    def _add_sphere(self, name, bounds, flat, lookup, names):
        """One 'Render as sphere' instance: its bounds' centre under the matrix (row by
        row, as transform_points sums), its half size times the largest axis scale
        (plain floats: a sphere costs a few microseconds, not numpy's per-call cost)."""
        (px, py, pz), half, textured = bounds
        centre = [flat[r] * px + flat[r + 1] * py + flat[r + 2] * pz + flat[r + 3] for r in (0, 4, 8)]
        scales = [math.sqrt(flat[c] * flat[c] + flat[c + 4] * flat[c + 4] + flat[c + 8] * flat[c + 8])
                  for c in (0, 1, 2)]
        radius = half * max(scales)
        if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in (*centre, radius)):
            self._skip(name, f"its sphere lies outside +-{MAX_COORDINATE:g} or is not finite")
            return
        if max(scales) - min(scales) > 1e-4 * max(scales):
            self.non_uniform_spheres.append(name)
        self.spheres.append((np.array(centre), radius, int(lookup[0])))
        self.sphere_names.append(names)
        if textured:
            self.textured_spheres.add(name)

    def _note_mesh(self, plan):
        """What a mesh itself is worth a warning for, once per object and mesh (with a rendered instance)."""
        _, lookup, key, data, layers, from_mesh, noted = plan.known[:7]
        if noted[0]:
            return
        noted[0] = True
        name = plan.name
        if data.degenerate and from_mesh:
            # (a NURBS surface's, text's or metaball's tessellation has zero-area triangles at
            # its poles and seams by design: nothing the user can or should fix)
            self.degenerate[name] = (data.degenerate, len(data.triangles))
        if layers[0] is not None and data.uvs is None:
            self.without_uvs.add(name)
        if data.missing_uv_layer:
            self.missing_uv_layers[name] = data.missing_uv_layer
        if data.missing_color_layer is not None:
            self.missing_color_layers[name] = data.missing_color_layer
        if data.non_finite_corners:
            self.non_finite_corners[name] = data.non_finite_corners

    def _has_hair(self, obj) -> bool:
        """Whether the object has hair particle systems to render (particle_hair.py), read once per object."""
        memo = object_key(obj)
        if memo not in self._hair:
            self._hair[memo] = bool(hair_systems(obj, self.render))
        return self._hair[memo]

    def _note_shapes(self, name, lookup):
        """What the warnings say of a sphere, point cloud or hair of the materials `lookup`: that
        it emits light yet lights nothing, that a value per instance reads black on it (spheres
        read it as meshes: _source)."""
        key = tuple(lookup.tolist())
        found = self._shape_notes.get(key)
        if found is None:    # (one answer per set of slots: 820 balls of one material ask it 820 times)
            found = self._shape_notes[key] = (
                any(self.materials.materials[int(i)].emits_light for i in set(lookup.tolist())),
                is_instance_layer(self.materials.layers(lookup)[1]))
        if found[0]:
            self.emissive_shapes.add(name)
        if found[1]:
            self.info_shapes.add(name)

    def _add_particle_hair(self, inst, obj):
        """The instance's hair particle systems as cones (its emitter shows them: renders(particles=True))."""
        if not np.isfinite(to_numpy(inst.matrix_world)).all():
            self._skip(obj.name, "its transform is not finite (NaN or Inf)", (self._seq, 1))
            return
        lookup = np.asarray(self.materials.slot_indices(obj, *self._flags(inst)), dtype=np.int32)
        self._note_shapes(obj.name, lookup)
        names = matte_names(obj)
        for found in particle_cone_sets(inst, lookup, MAX_COORDINATE, self.render):
            self._add_shapes(obj.name, lookup, *found, self.cone_sets, names, phase=1)

    def _add_shapes(self, name, lookup, found, why, non_uniform, sets, names, phase=0):
        """Keeps a point or cone set read from an object (or why it was skipped; phase: 1 for
        particle hair, as _skip ranks it)."""
        if why is not None:
            self._skip(name, why, (self._seq, phase))
        elif len(found):
            sets.append(found)
            self.set_names[id(found)] = names
            if non_uniform:
                self.non_uniform_spheres.append(name)
            if self.materials.layers(lookup)[0] is not None:
                self.textured_spheres.add(name)

    def without_faces(self) -> set[str]:
        """The mesh objects without faces that instance nothing either."""
        return self.faceless - self.instancers

    def warnings(self) -> list[str]:
        out = [f"Skipped object '{name}': {why}" for name, why in sorted(self.invalid.items())]
        for label, names in sorted(self.ignored.items()):
            out.append(f"{label} is not supported (every ray sees the object): "
                       + _quoted(names))
        if self.without_faces():
            out.append("Objects without faces (only vertices or edges) are not rendered: "
                       + _quoted(self.without_faces()))
        for name, (zero, total) in sorted(self.degenerate.items()):
            out.append(f"Object '{name}': {zero} of {total} triangles have zero area and are invisible")
        for name, layer in sorted(self.missing_uv_layers.items()):
            out.append(f"Object '{name}' has no UV map '{layer}', which its material's UV Map node names: "
                       "its render UV map is used instead (Cycles reads UV (0, 0) there)")
        for (name, material), maps in sorted(self.mixed_uv_maps.items()):
            out.append(f"Object '{name}': the textures of material '{material}' read the UV maps "
                       f"{', '.join(repr(m) for m in maps)}: every texture of a material reads one, "
                       f"{maps[0]!r}")
        for name, layer in sorted(self.missing_color_layers.items()):
            what = f"colour attribute '{layer}'" if layer else "colour attribute"
            out.append(f"Object '{name}' has no {what}, which its material's Color Attribute node reads: "
                       "black there, as in Cycles")
        if self.without_uvs:
            out.append("Objects with image textures but no UV map show each texture's corner at UV (0, 0): "
                       + _quoted(self.without_uvs))
        for name, count in sorted(self.non_finite_corners.items()):
            out.append(f"Object '{name}': {count} triangle corners have a non-finite UV or colour (NaN or Inf), "
                       "read as 0")
        if self.emissive_shapes:
            out.append("Emissive spheres, point clouds and hair are seen but light nothing (only emissive "
                       "meshes light the scene): " + _quoted(self.emissive_shapes))
        if self.textured_spheres:
            out.append("Objects rendered as spheres or tubes ('Render as sphere', point clouds, hair) have no UV map, "
                       "so each image texture shows one texel: " + _quoted(self.textured_spheres))
        if self.mesh_spheres:
            out.append("'Render as sphere' objects whose textures read Generated, Object or Position coordinates, "
                       "Object Info or an Object or Instancer attribute are rendered as their meshes: "
                       + _quoted(self.mesh_spheres))
        if self.info_shapes:
            out.append("Object Info and Object or Instancer attributes are not read on point clouds and hair "
                       "(they read black): " + _quoted(self.info_shapes))
        if self.unread_instance_attributes:
            out.append("Geometry Nodes instance attributes were not read for copies read one by one (before "
                       "Blender 4.3, or where a carrier's copies could not be read in bulk; their instancer's and "
                       "object's properties were): " + ", ".join(f"{a!r} of {c!r}" for c, a in
                                                                 sorted(self.unread_instance_attributes)))
        if self.non_uniform_spheres:
            names = ", ".join(sorted(set(self.non_uniform_spheres)))
            out.append("Objects rendered as spheres or tubes ('Render as sphere', point clouds, hair) with non-uniform scale "
                       f"use their largest axis ({names})")
        return out

    def arrays(self) -> dict:
        """Scene keyword arrays: vertices, triangles, normals, triangle_materials, spheres."""
        out, self.layout = assemble_triangles(self.parts, self.cache, self.part_matrices, self.part_values)
        out.update(self._instances())
        self.cache.prune(self.used)
        sets = self.point_sets
        out["sphere_centers"] = np.concatenate(
            [np.array([s[0] for s in self.spheres], np.float64).reshape(-1, 3)] + [p.centres for p in sets]
        ).astype(np.float32)
        out["sphere_radii"] = np.concatenate(
            [np.array([s[1] for s in self.spheres], np.float64)] + [p.radii for p in sets]).astype(np.float32)
        out["sphere_materials"] = self._shape_materials(np.concatenate(
            [np.array([s[2] for s in self.spheres], np.int32)] + [p.materials for p in sets]).astype(np.int32))
        if self.cone_sets:
            joined = lambda field, shape: np.concatenate([getattr(c, field).reshape(shape) for c in self.cone_sets])
            out.update(cylinder_base=joined("base", (-1, 3)).astype(np.float32),
                       cylinder_apex=joined("apex", (-1, 3)).astype(np.float32),
                       cylinder_base_radius=joined("base_radius", -1).astype(np.float32),
                       cylinder_apex_radius=joined("apex_radius", -1).astype(np.float32),
                       cylinder_materials=self._shape_materials(joined("materials", -1).astype(np.int32)))
        return out

    def _instances(self) -> dict:
        """gridwalk.Scene's instance_triangles / instance_meshes / instance_matrices:
        every part, its mesh the pair (mesh entry, mirrored or not), since the
        parts of one entry mirrored alike have their corners in one order
        (assemble.corner_order); none where no entry repeats. After
        assemble_triangles (self.layout)."""
        if len(self.parts) < 2:
            return {}
        matrices = self.part_matrices
        entries = {}
        entry = np.array([entries.setdefault(plan.known[2], len(entries)) for plan in self._mesh_plans], np.int64)
        # (each part's mesh entry, from its plan's; numbered below in the order they first come)
        pairs = entry[self._part_plans] * 2 + mirror_flags(matrices)
        _, first, inverse = np.unique(pairs, return_index=True, return_inverse=True)
        if len(first) == len(self.parts):
            return {}
        rank = np.empty(len(first), np.int32)
        rank[np.argsort(first, kind="stable")] = np.arange(len(first), dtype=np.int32)
        meshes = rank[inverse.reshape(-1)]
        triangles = np.array([(p.triangle_start, p.triangle_count) for p in self.layout], np.int64)
        return {"instance_triangles": triangles, "instance_meshes": meshes, "instance_matrices": matrices}

    def primitive_names(self, arrays) -> tuple[list, np.ndarray]:
        """(names, index): the distinct (object, asset, pass index) of matte_names()
        and, per primitive of `arrays` (triangles, spheres, cylinders, in the
        core's order), the index of its names (-1: none, such as the world-only
        scene's placeholder triangle). After arrays()."""
        table, index_of = [], {}

        def index(names):
            if names not in index_of:
                index_of[names] = len(table)
                table.append(names)
            return index_of[names]
        n_tris = len(arrays["triangles"])
        tris = np.full(n_tris, -1, np.int32)
        if self.layout:
            starts = np.array([p.triangle_start for p in self.layout], np.int64)
            counts = np.array([p.triangle_count for p in self.layout], np.int64)
            which = np.array([index(n) for n in self.part_names], np.int32)
            order = np.argsort(starts, kind="stable")
            tris[:int(counts.sum())] = np.repeat(which[order], counts[order])
        shapes = [np.array([index(n) for n in self.sphere_names], np.int32).reshape(-1)]
        shapes += [np.full(len(p.radii), index(self.set_names[id(p)]), np.int32) for p in self.point_sets]
        shapes += [np.full(len(c.base_radius), index(self.set_names[id(c)]), np.int32) for c in self.cone_sets]
        return table, np.concatenate([tris] + shapes)

    def _shape_materials(self, indices):
        """The spheres' or cylinders' material indices, each without textures at
        Generated coordinates (MaterialTable.shape_material)."""
        remap = {i: self.materials.shape_material(i) for i in np.unique(indices).tolist()}
        if all(k == v for k, v in remap.items()):
            return indices
        return np.array([remap[i] for i in indices.tolist()], np.int32)


def count_geometry(depsgraph) -> dict:
    """Triangles, vertices and spheres the export will produce, from the evaluated
    meshes' sizes (no arrays are read): for the memory estimate.

    Triangles per mesh = corners - 2 * faces (loop_triangles' count). Vertices:
    shared for smooth (POINT) and flat meshes, one per corner otherwise, three
    per triangle for flat meshes in a scene that needs normals (as exported).
    Non-mesh geometry (curves, text, metaballs) is converted to count it.
    copies / copied_triangles: the instances of a mesh seen before, and their
    triangles (what the instanced grid does not build over).
    """
    per_mesh, triangles, spheres, cylinders, flat, any_normals = {}, 0, 0, 0, [0, 0], False
    vertices = copies = copied = 0
    render = getattr(depsgraph, "mode", "RENDER") == "RENDER"
    known = {}          # instance_key -> (particle hair cones, kind or None (not rendered), mesh key)
    for inst in depsgraph.object_instances:
        memo = instance_key(inst)
        facts = known.get(memo)
        if facts is None:
            obj = inst.object
            kind = obj.type if obj.type in ("POINTCLOUD", "CURVES") else "SPHERE" if as_sphere(obj) else "MESH"
            hair = particle_segment_count(obj, render) if renders(inst, particles=True) else 0
            facts = known[memo] = (hair, kind if renders(inst) else None,
                                   (obj.original.name_full, obj.data.as_pointer() if obj.data else 0))
        cylinders += facts[0]
        kind, key = facts[1:]
        if kind is None:
            continue
        if kind == "POINTCLOUD":
            spheres += point_count(inst.object)
            continue
        if kind == "CURVES":
            cylinders += segment_count(inst.object)
            continue
        if kind == "SPHERE":
            spheres += 1
            continue
        if key not in per_mesh:
            per_mesh[key] = _mesh_counts(inst.object)
        else:
            copies += 1                # (a copy of a mesh seen before: Scene's instance arrays declare it)
            copied += per_mesh[key][0]
        tris, verts, domain = per_mesh[key]
        triangles += tris
        if domain == "FACE":
            flat[0] += tris
            flat[1] += verts
        else:
            vertices += verts
            any_normals = any_normals or tris > 0
    vertices += 3 * flat[0] if any_normals else flat[1]
    return {"triangles": triangles, "vertices": vertices, "spheres": spheres, "cylinders": cylinders,
            "normals": any_normals, "copies": copies, "copied_triangles": copied}


def _mesh_counts(obj) -> tuple[int, int, str]:
    """(triangles, exported vertices, normals domain) of an evaluated object's mesh."""
    if obj.type == "MESH" and obj.data is not None:
        return _counts(obj.data)
    mesh = obj.to_mesh()
    try:
        return _counts(mesh) if mesh is not None else (0, 0, "FACE")
    finally:
        obj.to_mesh_clear()


def _counts(mesh) -> tuple[int, int, str]:
    corners, faces = len(mesh.loops), len(mesh.polygons)
    domain = getattr(mesh, "normals_domain", "CORNER")          # Blender 4.1+; else the larger count
    verts = len(mesh.vertices) if domain in ("POINT", "FACE") else corners
    return max(0, corners - 2 * faces), verts, domain
