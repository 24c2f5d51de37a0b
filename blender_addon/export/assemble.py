"""Instances of meshes -> the scene's world-space triangle arrays.

Each instance (a part: mesh cache key, MeshData, matrix, material lookup) is
its mesh under its matrix. Instances of one mesh (Geometry Nodes and particle
instances come by the thousand) are transformed together, as one stack of
matrices, in chunks (chunks()): 90,000 instances of an 80-triangle icosphere
took about 50 us each one at a time, the numpy calls' overhead, and a few
microseconds each in chunks. A lone instance is a chunk of one, through the
same code. The scene's arrays list the chunks in turn: each mesh's instances
together, the meshes in the order they first appear.

A mirroring matrix (negative determinant) lists its triangles with their
corners reversed, so that their winding still faces out in world space
(Cycles flips such an object's normals), for transmission, normal maps and
flat meshes' normals.
"""
from __future__ import annotations

import zlib

import numpy as np

from ._matrix import cross, normalized, transform_normals, transform_points
from .instance_values import is_instance_layer

CHUNK_VERTICES = 1 << 18    # vertices per chunk at most (float64 temporaries of 6 MiB, up to 6 times that for flat corners)
CHUNK_INSTANCES = 256       # instances per chunk on average (chunks())
REVERSED = [0, 2, 1]


def mirrors(matrix) -> bool:
    """Whether the transform mirrors (a negative scale): see the module's note."""
    return bool(mirror_flags(np.asarray(matrix, np.float64)[None])[0])


def mirror_flags(matrices) -> np.ndarray:
    """mirrors() of each of a (K, 4, 4) stack."""
    return np.linalg.det(matrices[:, :3, :3]) < 0


def corner_order(matrix):
    """The order of a triangle's corners in world space (mirrors())."""
    return REVERSED if mirrors(matrix) else [0, 1, 2]


def _ordered(per_triangle, flips):
    """(K, T, 3, ...) corners of each instance in its world-space order (per_triangle: (T, 3, ...))."""
    if not flips.any():
        return np.broadcast_to(per_triangle, (len(flips),) + per_triangle.shape)
    return np.where(flips.reshape((-1,) + (1,) * per_triangle.ndim), per_triangle[:, REVERSED], per_triangle)


def world_chunk(data, matrices, flat_corners: bool):
    """K instances of one mesh in world space: (vertices (K V, 3) float32,
    triangles (K T, 3) int32 numbered from the chunk's first vertex, normals
    (K V, 3) float32 or None, mirror flags (K,)). flat_corners: a flat mesh in
    a scene that needs normals gets unshared corners with its face normals."""
    k = len(matrices)
    flips = mirror_flags(matrices)
    world = transform_points(matrices, data.co)                    # (K, V, 3) float64
    if flat_corners:
        corners = np.take(world, data.triangles.reshape(-1), axis=1).reshape(k, -1, 3, 3)
        if flips.any():
            corners = np.where(flips[:, None, None, None], corners[:, :, REVERSED], corners)
        n = normalized(cross(corners[:, :, 1] - corners[:, :, 0], corners[:, :, 2] - corners[:, :, 0]))
        count = corners.shape[0] * corners.shape[1]
        return (corners.reshape(-1, 3).astype(np.float32), np.arange(count * 3, dtype=np.int32).reshape(-1, 3),
                np.repeat(n.reshape(-1, 3).astype(np.float32), 3, axis=0), flips)
    tris = _ordered(data.triangles, flips)                         # (K, T, 3)
    vertices = data.co.shape[0]
    tris = tris + (np.arange(k, dtype=np.int32) * vertices)[:, None, None]
    normals = None
    if data.normals is not None:
        normals = transform_normals(matrices, data.normals.astype(np.float64)).reshape(-1, 3).astype(np.float32)
    return world.reshape(-1, 3).astype(np.float32), tris.reshape(-1, 3).astype(np.int32, copy=False), normals, flips


class Placement:
    """Where one part's arrays lie in the assembled scene arrays, and how they
    were made (flat: unshared corners with face normals): what a later move of
    the instance needs (gridwalk.InstanceMove)."""

    def __init__(self, vertex_start: int, triangle_start: int, triangle_count: int, flat: bool, normals: bool):
        self.vertex_start, self.triangle_start, self.triangle_count = vertex_start, triangle_start, triangle_count
        self.flat, self.normals = flat, normals


def chunks(parts) -> list[list[int]]:
    """The parts' indices in chunks: each mesh entry's parts (the meshes in the order
    they first appear, each one's parts in theirs), cut after every part whose
    matrix's CRC-32 is 0 modulo CHUNK_INSTANCES, and before CHUNK_VERTICES would
    be passed. The cuts follow the matrices, not the positions, so that adding
    or deleting an instance changes only its own chunk (the others stay cached)."""
    by_mesh = {}
    for i, part in enumerate(parts):
        by_mesh.setdefault(part[0], []).append(i)
    out = []
    for indices in by_mesh.values():
        cap = max(1, CHUNK_VERTICES // max(parts[indices[0]][1].co.shape[0], 1))
        chunk = []
        for i in indices:
            chunk.append(i)
            if len(chunk) >= cap or zlib.crc32(parts[i][2].tobytes()) % CHUNK_INSTANCES == 0:
                out.append(chunk)
                chunk = []
        if chunk:
            out.append(chunk)
    return out


def _materials(parts, chunk):
    """The chunk's triangles' material indices (one tile where its parts share a lookup)."""
    data = parts[chunk[0]][1]
    lookups = [parts[i][3] for i in chunk]
    slots = data.material_slot
    if all(lookup is lookups[0] or np.array_equal(lookup, lookups[0]) for lookup in lookups):
        one = lookups[0][np.clip(slots, 0, len(lookups[0]) - 1)]
        return np.tile(one, len(chunk))
    return np.concatenate([lookup[np.clip(slots, 0, len(lookup) - 1)] for lookup in lookups])


# Per-corner points a texture may read (gridwalk.Scene's arrays), and the value
# of corners whose mesh has none (a mesh whose materials read none of them).
CORNER_POINTS = {"generated": 0.5, "object_coords": 0.0, "object_normals": 0.0}


def _corner_values(data, name, flips, fill):
    """The chunk's corner UVs, colours or points (CORNER_POINTS) in world-space corner order, (K T, 3, C)."""
    values = getattr(data, name)
    if values is None:
        return np.full((len(flips) * len(data.triangles), 3, fill[1]), fill[0], np.float32)
    return _ordered(values, flips).reshape((-1,) + values.shape[1:])


def _reads_instance_values(key) -> bool:
    """Whether the parts of mesh cache key `key` (MeshCache.key: its last item the layers) read a value
    per instance (instance_values.py)."""
    layers = key[-1] if isinstance(key, tuple) and key and isinstance(key[-1], tuple) else ()
    return len(layers) > 1 and is_instance_layer(layers[1])


def assemble_triangles(parts, cache, matrices=None, values=None) -> tuple[dict, list[Placement]]:
    """(Scene arrays (vertices, triangles, normals, triangle_materials, uvs,
    colours), each part's Placement) of the parts (cache key, MeshData,
    matrix, material lookup); each chunk's world-space arrays come from
    cache.world_chunk (reused while its matrices are unchanged). matrices:
    the parts' matrices as one (P, 4, 4) float64 array, if the caller has
    it (MeshCollector.finish), else stacked here. values: each part's value
    ((P, 3), MeshCollector.part_values), the corner colours of the parts whose
    materials read one value per instance (instance_values.py), or None."""
    if not parts:
        return {"vertices": np.zeros((0, 3), np.float32), "triangles": np.zeros((0, 3), np.int32),
                "normals": None, "triangle_materials": np.zeros(0, np.int32)}, []
    if matrices is None:
        matrices = np.stack([part[2] for part in parts])
    matrices = np.asarray(matrices, np.float64)
    meshes = list({id(part[1]): part[1] for part in parts}.values())   # (each MeshData once)
    need_normals = any(data.normals is not None for data in meshes)
    need_uvs = any(data.uvs is not None for data in meshes)
    info = values is not None and any(_reads_instance_values(part[0]) for part in parts)
    need_colors = info or any(data.colors is not None for data in meshes)
    points = [name for name in CORNER_POINTS if any(getattr(data, name) is not None for data in meshes)]
    vertices, triangles, normals, materials, uvs, colors = [], [], [], [], [], []
    corner_points = {name: [] for name in points}
    layout = [None] * len(parts)
    offset = triangle_offset = 0
    for chunk in chunks(parts):
        key, data = parts[chunk[0]][:2]
        flat = need_normals and data.normals is None
        world, tris, nrm, flips = cache.world_chunk(key, data, matrices[chunk], flat)
        per_vertices, per_triangles = world.shape[0] // len(chunk), len(data.triangles)
        for j, i in enumerate(chunk):
            layout[i] = Placement(offset + j * per_vertices, triangle_offset + j * per_triangles, per_triangles,
                                  flat, need_normals)
        triangle_offset += len(tris)
        vertices.append(world)
        triangles.append(tris + np.int32(offset) if offset else tris)
        if need_normals:
            normals.append(nrm)
        materials.append(_materials(parts, chunk))
        if need_uvs:
            uvs.append(_corner_values(data, "uvs", flips, (0.0, 2)))
        if info and _reads_instance_values(key):        # (each part's triangles its own value at every corner)
            per_part = np.asarray(values, np.float32)[chunk]
            colors.append(np.repeat(per_part, per_triangles * 3, axis=0).reshape(-1, 3, 3))
        elif need_colors:
            colors.append(_corner_values(data, "colors", flips, (1.0, 3)))
        for name in points:
            corner_points[name].append(_corner_values(data, name, flips, (CORNER_POINTS[name], 3)))
        offset += world.shape[0]
    out = {"vertices": np.concatenate(vertices), "triangles": np.concatenate(triangles).astype(np.int32, copy=False),
           "normals": np.concatenate(normals) if need_normals else None,
           "triangle_materials": np.concatenate(materials).astype(np.int32, copy=False)}
    if need_uvs:
        out["uvs"] = np.concatenate(uvs)
    if need_colors:
        out["colors"] = np.concatenate(colors)
    for name in points:
        out[name] = np.concatenate(corner_points[name])
    return out, layout
