"""PLY mesh reader (ascii, binary_little_endian, binary_big_endian), as scanners and tools write it.

Read here, in bounded chunks (ply_header.py, ply_body.py), without plyfile:

* `vertex`: x, y, z (any numeric type: float, double or integers), optional
  nx, ny, nz normals (normalised; used for smooth shading) and red, green,
  blue colours (also diffuse_red/green/blue; integers scaled by their type's
  maximum, floats as they are);
* `face`: a list of vertex indices named `vertex_indices` or `vertex_index`,
  any signed or unsigned integer type from 8 to 32 bits for the count and the
  indices. Faces with more than three corners are triangulated: a fan where
  the face is convex (over 32 corners: clipped in rounds), ear clipping where
  it is not (gridwalk.io.triangulate);
* `tristrips`: the same list, each record one or more triangle strips with
  -1 between them (in an unsigned type, its maximum, where that is no vertex
  index); the winding alternates along a strip and the degenerate triangles
  that stitch strips together are dropped. A file may have both faces and
  strips: both are read.
* other elements (edges, materials, ...) and other properties are skipped.

Memory: what the header declares is checked before the body is read: the
file must be large enough for it, and the memory estimate of loading and
rendering the mesh (gridwalk.memory, at the default 512 x 512) must fit in
memory.default_limit(); the body is then read a chunk at a time into the
output arrays, so a file larger than memory can be read when its mesh fits.
Strips declare no triangle count: before a chunk of strip records becomes
triangles, the estimate is checked again with its indices as triangles.

Refused, with the file, element, record and what was expected: NaN, infinite
or beyond-float32 coordinates or normals of vertices a face uses (a vertex no
face uses may hold them: scanners' organised grids mark missing points with
NaN), and such colours; a vertex used by a face beyond +-1e30 (the core's
limit); faces with fewer than 3 corners; indices outside the vertex array; a
file shorter than its header says. A zero-length normal (a degenerate face's,
as MeshLab writes it) is kept as 0 and takes no part in the interpolated
shading normal; a face whose three normals are 0 gets its geometric normal.

Vertex colours: the core has one Material per triangle, not colours per
vertex. Each triangle gets the mean of its three vertex colours (taken as
sRGB, as Blender's PLY importer does, and averaged in linear light), and the
means are quantised in sRGB to the finest of 8, 7, 6, 5 or 4 bits per channel
that gives at most MAX_COLOURS distinct colours. Each distinct colour becomes
one Material (the grey material's kd, ks and shininess with that colour), so
the material table stays bounded for a scan of any size. A colour that varies
across a triangle is flattened to its mean (a per-vertex colour attribute in
the core would keep it).

PLY holds no camera or lights: `load_ply` frames the used vertices with
`default_view`. Without colours the mesh gets one grey material (kd 0.8,
ks 0.2, shininess 40).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..image import srgb_to_linear
from . import triangulate
from .common import SceneFileError, core_refusal, open_scene_file, scene_kwargs
from .ply_body import Body
from .ply_header import Element, Header, read_header

_INDEX_NAMES = ("vertex_indices", "vertex_index")
_COLOUR_NAMES = (("red", "green", "blue"), ("diffuse_red", "diffuse_green", "diffuse_blue"))
_F32_MAX = float(np.finfo(np.float32).max)
_STRIP_BYTES = 128              # peak bytes per index of a chunk becoming triangles, beside the 12 kept (138 measured)
CORE_LIMIT = 1e30               # the core refuses primitives beyond +-1e30
MAX_COLOURS = 4096
GREY = dict(kd=0.8, ks=0.2, shininess=40.0)
BACKGROUND = (0.1, 0.1, 0.1)


@dataclass
class PlyMesh:
    """A triangle mesh from a PLY file.

    vertices (N, 3) float32; triangles (M, 3) int32 (those of the faces
    first, then those of the strips); normals (N, 3) float32 unit vectors or
    None (a zero-length normal stays 0); colors (N, 3) float32 as stored in the file, in [0, 1], or None.
    """
    vertices: np.ndarray
    triangles: np.ndarray
    normals: np.ndarray | None
    colors: np.ndarray | None
    origin: object = None       # triangle index -> "element 'face' record k" (for messages)


def load_ply(path) -> dict:
    """Read a PLY mesh into keyword arguments for `gridwalk.Scene`, with the
    camera and lights of `default_view`, and one grey material or (with
    vertex colours) one material per quantised colour."""
    mesh = load_ply_mesh(path)
    used = np.unique(mesh.triangles)
    camera, lights = default_view(mesh.vertices[used])
    if mesh.colors is None:
        from ..model import Material
        materials = [Material(color=(0.8, 0.8, 0.8), **GREY)]
        triangle_materials = np.zeros(len(mesh.triangles), dtype=np.int32)
    else:
        materials, triangle_materials = colour_materials(mesh.colors, mesh.triangles)
    kwargs = scene_kwargs(
        vertices=mesh.vertices, triangles=mesh.triangles, normals=mesh.normals,
        triangle_materials=triangle_materials, materials=materials,
        lights=lights, camera=camera, background=BACKGROUND)
    refusal = core_refusal(kwargs)
    if refusal:
        name, index, rest = refusal
        where = mesh.origin(index) if name.startswith("triangle") else name
        raise SceneFileError(f"{path}: {where}: {rest}")
    return kwargs


def load_ply_mesh(path) -> PlyMesh:
    """Read a PLY file's triangle mesh; malformed files raise SceneFileError."""
    path = Path(path)
    header = read_header(path)
    vertex, lists = _plan(header)
    reader = _Reader(header, vertex, lists)
    with open_scene_file(path) as f:
        f.seek(header.body_start)
        body = reader.body = Body(f, header)
        for e in header.elements:
            if e is vertex:
                reader.vertices(body, e)
            elif e in lists:
                reader.lists(body, e, lists[e])
            else:
                body.skip(e)
    return reader.mesh()


def _plan(h: Header):
    """Check what the header declares; the vertex element and {element: list name}."""
    path = h.path
    vertex = h.element("vertex")
    if vertex is None or any(vertex.get(c) is None or vertex.get(c).is_list for c in "xyz"):
        raise SceneFileError(f"{path}: no 'vertex' element with x, y and z properties")
    listed = [p.name for p in vertex.properties if p.is_list]
    if listed:                                 # (its records are read as fixed-size rows)
        raise SceneFileError(f"{path}:{vertex.line}: element 'vertex' has list properties "
                             f"({', '.join(repr(n) for n in listed)}); Gridwalk reads vertex elements of "
                             f"single values only (positions, normals, colours, UVs)")
    if vertex.count >= 2 ** 31:
        raise SceneFileError(f"{path}: element 'vertex' declares {vertex.count} records; the core "
                             f"indexes at most 2^31 - 1 vertices")
    lists = {}
    for e in h.elements:
        if e.name not in ("face", "tristrips"):
            continue
        p = next((e.get(n) for n in _INDEX_NAMES if e.get(n) is not None), None)
        if p is None or not p.is_list or p.type[0] == "f":
            raise SceneFileError(f"{path}:{e.line}: element {e.name!r} has no 'vertex_indices' (or "
                                 f"'vertex_index') list of integers")
        lists[e] = p.name
    if not lists:
        raise SceneFileError(f"{path}: no 'face' or 'tristrips' element: the file holds points "
                             f"only, nothing to render")
    need = sum(e.count * e.min_record_bytes(h.ascii) for e in h.elements)
    body = h.file_size - h.body_start
    if need - h.ascii > body:                  # the last ASCII line may lack its newline
        counts = ", ".join(f"{e.count} {e.name}" for e in h.elements)
        raise SceneFileError(f"{path}: the header declares {counts} records, at least {need} bytes, "
                             f"but only {body} bytes follow it (truncated?)")
    _check_memory(h, vertex, lists)
    return vertex, lists


def _check_memory(h: Header, vertex: Element, lists: dict, strip_triangles: int = 0, pending: int = 0) -> None:
    """Refuse a mesh whose estimated memory (the reader's arrays and the
    render's, gridwalk.memory) exceeds memory.default_limit(): up front from
    the header's counts, and again while strips are read (their triangles are
    known only from their lists): `strip_triangles` kept so far, and at most
    `pending` more from the chunk about to become triangles."""
    from .. import memory
    faces = sum(e.count for e in lists if e.name == "face") + strip_triangles + pending
    normals = all(vertex.get(c) is not None for c in ("nx", "ny", "nz"))
    colours = any(all(vertex.get(c) is not None for c in names) for names in _COLOUR_NAMES)
    est = memory.estimate(triangles=faces, vertices=vertex.count, normals=normals, width=512, height=512)
    reading = vertex.count * 12 * (1 + normals + colours) + faces * 3 * 4 + pending * _STRIP_BYTES
    limit = memory.default_limit()
    if limit is not None and est.total + reading > limit:
        what = "faces" if not pending else "faces and strip triangles (up to the record read)"
        raise SceneFileError(
            f"{h.path}: the header declares {vertex.count:,} vertices and {faces:,} {what}: reading and "
            f"rendering them needs an estimated {memory.format_bytes(est.total + reading)} of memory "
            f"(reader {memory.format_bytes(reading)}, {est.breakdown()}), more than the limit of "
            f"{memory.format_bytes(limit)} ({memory.DEFAULT_FRACTION:.0%} of physical memory)")


class _Reader:
    """The arrays of load_ply_mesh, filled chunk by chunk."""

    def __init__(self, h: Header, vertex: Element, lists: dict):
        self.h, self.n, self.vertex, self.body = h, vertex.count, vertex, None
        self.lists_of = lists
        self.xyz = np.empty((self.n, 3), np.float32)
        self.invalid = []                 # arrays of vertices with a non-finite (or beyond float32) coordinate or normal
        self.normals = self.colours = None
        if all(vertex.get(c) is not None for c in ("nx", "ny", "nz")):
            self.normals = np.empty((self.n, 3), np.float32)
        self.colour_names = next((n for n in _COLOUR_NAMES if all(vertex.get(c) for c in n)), None)
        if self.colour_names:
            self.colours = np.empty((self.n, 3), np.float32)
            kind = vertex.get(self.colour_names[0]).type
            self.colour_scale = float(np.iinfo(kind).max) if kind[0] in "iu" else 1.0
        self.faces = []                   # (element, corner chunks, count chunks)
        self.strips = []                  # (element, triangles, triangles per record)

    def vertices(self, body: Body, e: Element):
        names = ["x", "y", "z"] + (["nx", "ny", "nz"] if self.normals is not None else [])
        names += list(self.colour_names or ())
        for first, cols in body.scalars(e, names):
            n = len(cols["x"])
            for out, keys, what in ((self.xyz, "xyz", "coordinate"),
                                    (self.normals, ("nx", "ny", "nz"), "normal"),
                                    (self.colours, self.colour_names, "colour")):
                if out is None:
                    continue
                block = np.column_stack([cols[k] for k in keys]).astype(np.float64)
                bad = ~(np.abs(block) <= _F32_MAX).all(axis=1)
                if what == "colour" and bad.any():
                    k = int(np.argmax(bad))
                    body.fail(e, first + k, f"the {what} {_show(block[k])} is NaN, infinite or beyond "
                                            f"the float32 range")
                if bad.any():
                    # (coordinates and normals: only those of vertices a face uses must be
                    # valid, _check_used; a scanner's organised grid holds NaN placeholders)
                    self.invalid.append(first + np.nonzero(bad)[0])
                if what == "colour":
                    block = np.clip(block / self.colour_scale, 0.0, 1.0)
                if what == "normal":   # (scaled by its largest component first: a tiny normal's squares underflow)
                    largest = np.abs(block).max(axis=1)
                    ok = largest > 0
                    block[ok] /= largest[ok, None]
                    block[ok] /= np.linalg.norm(block[ok], axis=1)[:, None]
                with np.errstate(over="ignore", invalid="ignore"):   # (beyond float32: inf, checked if used)
                    out[first:first + n] = block

    def lists(self, body: Body, e: Element, name: str):
        prop = e.get(name)
        restart = -1
        if prop.type[0] == "u" and np.iinfo(prop.type).max >= self.n:
            restart = np.iinfo(prop.type).max          # -1 as written to an unsigned type
        corners, counts, per_record = [], [], []
        strip_total = sum(len(t) for _, tris, _ in self.strips for t in tris)
        for first, items, c in body.lists(e, name):
            if items.dtype.kind == "f":
                bad = ~np.isfinite(items) | (items != np.round(items))
                if bad.any():
                    k = self._record_of(c, int(np.argmax(bad)))
                    body.fail(e, first + k, f"{name} holds {items[bad][0]:g}; expected integer vertex "
                                            f"indices")
            items = items.astype(np.int64)
            strips = e.name == "tristrips"
            is_restart = ((items == -1) | (items == restart)) if strips else np.zeros(len(items), bool)
            bad = ~is_restart & ((items < 0) | (items >= self.n))
            if bad.any():
                k = self._record_of(c, int(np.argmax(bad)))
                body.fail(e, first + k, f"uses vertex index {items[bad][0]}, but there are {self.n} "
                                        f"vertices (0 to {self.n - 1})")
            if strips:                     # a chunk's n items give at most n triangles
                _check_memory(self.h, self.vertex, self.lists_of, strip_total, len(items))
                tris, records = self._strips(items, is_restart, c)
                strip_total += len(tris)
                corners.append(tris)
                per_record.append(np.bincount(records, minlength=len(c)))
                continue
            if len(c) and c.min() < 3:
                k = int(np.argmax(c < 3))
                body.fail(e, first + k, f"a face of {c[k]} corners; a face needs at least 3")
            corners.append(items.astype(np.int32))
            counts.append(c.astype(np.int64))
        if e.name == "tristrips":
            self.strips.append((e, corners, per_record))
        else:
            self.faces.append((e, corners, counts))

    @staticmethod
    def _record_of(counts, item):
        return int(np.searchsorted(np.cumsum(counts), item, side="right"))

    @staticmethod
    def _strips(items, is_restart, counts):
        """Triangles of a chunk of strip records (a record boundary ends a strip)."""
        ends = np.cumsum(counts)
        stream = np.insert(items, ends[:-1], -1)
        cut = np.insert(is_restart, ends[:-1], True)
        record = np.repeat(np.arange(len(counts)), counts + 1)[:len(stream)]
        tris, start = triangulate.strips(stream, cut, positions=True)
        return tris.astype(np.int32), record[start]

    def mesh(self) -> PlyMesh:
        triangles, origins = [], []
        for e, corners, counts in self.faces:
            corners = np.concatenate(corners) if corners else np.empty(0, np.int32)
            counts = np.concatenate(counts) if counts else np.empty(0, np.int64)
            if len(counts) and np.all(counts == 3):
                triangles.append(corners.reshape(-1, 3))
            elif len(counts):
                triangles.append(self._polygons(e, corners, counts))
            origins.append((e, np.cumsum(counts - 2)))
        for e, tris, per_record in self.strips:
            triangles.append(np.concatenate(tris) if tris else np.empty((0, 3), np.int32))
            origins.append((e, np.cumsum(np.concatenate(per_record)) if per_record else np.zeros(0, int)))
        triangles = np.concatenate(triangles) if triangles else np.empty((0, 3), np.int32)
        if not len(triangles):
            raise SceneFileError(f"{self.h.path}: the mesh has no triangles (no faces, or only "
                                 f"degenerate strips)")
        origin = _Origin(origins, self.body)
        self._check_used(triangles, origin)
        return PlyMesh(self.xyz, np.ascontiguousarray(triangles, np.int32), self.normals,
                       self.colours, origin)

    def _polygons(self, e, corners, counts, block=1 << 20):
        """Triangles of faces of any size, `block` faces at a time (bounded memory)."""
        out, ends = [], np.cumsum(counts)
        for lo in range(0, len(counts), block):
            hi = min(lo + block, len(counts))
            a, b = (ends[lo - 1] if lo else 0), ends[hi - 1]
            chunk = corners[a:b]
            try:
                local, _ = triangulate.polygons(self.xyz[chunk].astype(np.float64), counts[lo:hi])
            except triangulate.TooManyCorners as err:
                raise SceneFileError(f"{self.h.path}: element {e.name!r} record {lo + err.polygon}: "
                                     f"a face of {err}") from None
            out.append(chunk[local])
        return np.concatenate(out)

    def _check_used(self, triangles, origin):
        """Normals and coordinates of the vertices the triangles use. Vertices
        no face uses may hold anything (they are set to 0); a used vertex's
        zero-length normal stays 0, and takes no part in the shading normals
        interpolated across its faces (a face whose three normals are all 0 is
        shaded by its own geometric normal)."""
        used = np.zeros(self.n, dtype=bool)
        used[triangles.reshape(-1)] = True
        if self.invalid:
            invalid = np.concatenate(self.invalid).astype(np.int64)
            bad = invalid[used[invalid]]
            if len(bad):
                v = int(bad.min())
                what, values = (("coordinate", self.xyz[v]) if not np.isfinite(self.xyz[v]).all()
                                else ("normal", self.normals[v]))
                t = int(np.argmax((triangles == v).any(axis=1)))
                raise SceneFileError(f"{self.h.path}: {self.body.where(self.vertex, v)}: the {what} "
                                     f"{_show(values)} is NaN, infinite or beyond the float32 range "
                                     f"(used by {origin(t)})")
            self.xyz[invalid] = 0.0
            if self.normals is not None:
                self.normals[invalid] = 0.0
        far = used & ~(np.abs(self.xyz) <= CORE_LIMIT).all(axis=1)
        if far.any():
            v = int(np.argmax(far))
            t = int(np.argmax((triangles == v).any(axis=1)))
            raise SceneFileError(f"{self.h.path}: {self.body.where(self.vertex, v)}: the coordinate "
                                 f"{_show(self.xyz[v])} lies beyond +-1e30, the core's limit (used by "
                                 f"{origin(t)})")
        if self.normals is not None:
            length = np.linalg.norm(self.normals.astype(np.float64), axis=1)
            ok = length > 0
            self.normals[ok] = (self.normals[ok] / length[ok, None]).astype(np.float32)


class _Origin:
    """Triangle index -> the element and record it comes from."""

    def __init__(self, parts, body):
        self.parts, self.body = parts, body   # [(element, cumulative triangles per record)]

    def __call__(self, t: int) -> str:
        for e, ends in self.parts:
            if len(ends) and t < ends[-1]:
                return self.body.where(e, int(np.searchsorted(ends, t, side="right")))
            t -= int(ends[-1]) if len(ends) else 0
        return f"triangle {t}"


def _show(v) -> str:
    return "(" + ", ".join(f"{x:g}" for x in np.asarray(v, dtype=np.float64)) + ")"


def colour_materials(colors, triangles) -> tuple[list, np.ndarray]:
    """(materials, triangle_materials) for per-vertex sRGB `colors` in [0, 1]:
    see the module docstring."""
    from ..model import Material
    # (float colours outside [0, 1] clipped: a negative one is no light, and
    # the quantisation below packs levels of [0, 1])
    linear = srgb_to_linear(np.clip(np.nan_to_num(np.asarray(colors, dtype=np.float64)), 0.0, 1.0))
    mean = (linear[triangles[:, 0]] + linear[triangles[:, 1]] + linear[triangles[:, 2]]) / 3.0
    srgb = _linear_to_srgb(mean)
    for bits in (8, 7, 6, 5, 4):
        levels = (1 << bits) - 1
        q = np.rint(srgb * levels).astype(np.int64)
        keys, index = np.unique((q[:, 0] << (2 * bits)) | (q[:, 1] << bits) | q[:, 2], return_inverse=True)
        if len(keys) <= MAX_COLOURS:
            break
    rgb = np.stack([keys >> (2 * bits), (keys >> bits) & levels, keys & levels], axis=1) / levels
    materials = [Material(color=tuple(float(c) for c in row), **GREY) for row in srgb_to_linear(rgb)]
    return materials, index.astype(np.int32).reshape(-1)


def _linear_to_srgb(c):
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * np.maximum(c, 0.0) ** (1 / 2.4) - 0.055)


def default_view(vertices, up=(0.0, 0.0, 1.0)):
    """A camera and lights that frame `vertices` (any (N, 3) array).

    The camera looks at the bounding box centre from a diagonal above it, at
    a distance where the box's bounding sphere fits a 40 degree field of view
    (512 x 512). A white key light (0.8) sits just above and beside the camera,
    a fill light (0.3) on the opposite side; like NFF lights they are meant
    without distance falloff.
    """
    from ..model import Camera, Light
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo)) / 2 or 1.0
    up = np.asarray(up, dtype=np.float64) / np.linalg.norm(up)
    side = np.cross(up, (1.0, 0.0, 0.0) if abs(up[0]) < 0.9 else (0.0, 1.0, 0.0))
    side /= np.linalg.norm(side)
    front = np.cross(up, side)
    view_dir = side + front + 0.6 * up
    view_dir /= np.linalg.norm(view_dir)
    fov = 40.0
    distance = 1.1 * radius / math.sin(math.radians(fov / 2))
    eye = centre + distance * view_dir
    key = eye + 0.3 * distance * (up + side)
    fill_dir = front - side + 0.3 * up
    fill = centre + distance * fill_dir / np.linalg.norm(fill_dir)
    camera = Camera(eye=_floats(eye), target=_floats(centre), up=_floats(up), fov=fov,
                    width=512, height=512)
    lights = [Light(position=_floats(key), color=(0.8, 0.8, 0.8)),
              Light(position=_floats(fill), color=(0.3, 0.3, 0.3))]
    return camera, lights


def _floats(vector) -> tuple:
    return tuple(float(c) for c in vector)
