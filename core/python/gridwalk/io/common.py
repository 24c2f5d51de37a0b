"""Pieces shared by the scene readers and generators."""
from __future__ import annotations

import numpy as np


class SceneFileError(ValueError):
    """A scene file is malformed. The message names the file and, where one
    applies, the line (NFF) or header line (PLY) and what was expected."""


# Geometry keywords of gridwalk.Scene: dtype and shape of one row.
_ARRAYS = {
    "vertices": (np.float32, (3,)), "triangles": (np.int32, (3,)),
    "triangle_materials": (np.int32, ()),
    "sphere_centers": (np.float32, (3,)), "sphere_radii": (np.float32, ()),
    "sphere_materials": (np.int32, ()),
    "cylinder_base": (np.float32, (3,)), "cylinder_apex": (np.float32, (3,)),
    "cylinder_base_radius": (np.float32, ()), "cylinder_apex_radius": (np.float32, ()),
    "cylinder_materials": (np.int32, ()),
}


def scene_kwargs(*, materials, lights, camera, background, normals=None, **arrays) -> dict:
    """Keyword arguments for gridwalk.Scene with every geometry key present:
    given arrays converted to float32 / int32, absent ones empty; normals
    (per vertex, float32) stay None unless given."""
    unknown = set(arrays) - set(_ARRAYS)
    if unknown:
        raise TypeError(f"not a Scene array: {sorted(unknown)}")
    kwargs = {}
    for key, (dtype, row) in _ARRAYS.items():
        value = arrays.get(key)
        kwargs[key] = (np.empty((0, *row), dtype) if value is None
                       else np.ascontiguousarray(value, dtype=dtype).reshape(-1, *row))
    kwargs["normals"] = None if normals is None else np.ascontiguousarray(normals, np.float32)
    kwargs.update(materials=list(materials), lights=list(lights), camera=camera,
                  background=tuple(float(c) for c in background))
    return kwargs


def fan_triangulate(counts) -> tuple[np.ndarray, np.ndarray]:
    """Fan-triangulate polygons stored one after another.

    counts[k] is the vertex count (>= 3) of polygon k; its corners are the
    positions starts[k] .. starts[k] + counts[k] - 1 of the concatenated
    corner list. Returns (triangles, polygon): (T, 3) int64 corner positions
    (s, s+j, s+j+1 for j = 1 .. n-2) and the polygon of each triangle.
    """
    counts = np.asarray(counts, dtype=np.int64)
    starts = np.cumsum(counts) - counts
    ntri = counts - 2
    polygon = np.repeat(np.arange(len(counts)), ntri)
    j = np.arange(ntri.sum()) - np.repeat(np.cumsum(ntri) - ntri, ntri) + 1
    first = starts[polygon]
    return np.stack([first, first + j, first + j + 1], axis=1), polygon
