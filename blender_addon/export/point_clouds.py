"""Point cloud objects -> analytic spheres.

Cycles renders every point of a point cloud (Geometry Nodes' Mesh to Points,
Points, Distribute Points on Faces realized as points, a Point Cloud object)
as a sphere of the point's radius; the core has that primitive, so each point
becomes one sphere: centre = matrix_world @ position, radius = the point's
`radius` attribute (Blender's 0.01 where there is none) times the largest axis
scale of matrix_world (a sphere stays a sphere: a non-uniformly scaled cloud
is warned). The material is the object's slot `material_index` names (slot 0
where there is none), as for meshes. Points of radius 0 or less are left out,
as Cycles shows nothing for them; non-finite positions or radii, or points
beyond +-MAX_COORDINATE, skip the object with a warning.
"""
from __future__ import annotations

import hashlib

import numpy as np

from ._matrix import transform_points

DEFAULT_RADIUS = 0.01   # a point without a radius attribute (Blender's PointCloud default)


def attribute_values(attributes, name, prop, data_type, domain, count, width, dtype):
    """An attribute's values, or None where the geometry has none of that type and domain."""
    attribute = attributes.get(name)
    if attribute is None or attribute.data_type != data_type or attribute.domain != domain \
            or len(attribute.data) != count:
        return None
    out = np.empty(count * width, dtype)
    if count:
        attribute.data.foreach_get(prop, out)
    return out.reshape(count, width) if width > 1 else out


def read_points(cloud) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions (n, 3) float64, radii (n,), material slots (n,) int32) in object space."""
    n = len(cloud.points)
    attributes = cloud.attributes
    positions = attribute_values(attributes, "position", "vector", "FLOAT_VECTOR", "POINT", n, 3, np.float32)
    if positions is None:
        positions = np.empty((n, 3), np.float32)
        if n:
            cloud.points.foreach_get("co", positions.reshape(-1))
    radii = attribute_values(attributes, "radius", "value", "FLOAT", "POINT", n, 1, np.float32)
    if radii is None:
        radii = np.full(n, DEFAULT_RADIUS, np.float32)
    slots = attribute_values(attributes, "material_index", "value", "INT", "POINT", n, 1, np.int32)
    if slots is None:
        slots = np.zeros(n, np.int32)
    return positions.astype(np.float64), radii.astype(np.float64), slots


class PointSet:
    """One point cloud instance's spheres in world space."""

    def __init__(self, name, centres, radii, materials):
        self.name, self.centres, self.radii, self.materials = name, centres, radii, materials

    def __len__(self):
        return len(self.radii)

    def digest(self) -> bytes:
        return array_digest(self.centres, self.radii, self.materials)


def array_digest(*arrays) -> bytes:
    """A short hash of the arrays' bytes (the viewport compares exports by it)."""
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.digest()


def point_set(obj, matrix, lookup, max_coordinate) -> tuple[PointSet | None, str | None, bool]:
    """(spheres, why the object is skipped, whether its scale is non-uniform) of an
    evaluated point cloud object; lookup maps its material slots to material indices."""
    positions, radii, slots = read_points(obj.data)
    if not (np.isfinite(positions).all() and np.isfinite(radii).all()):
        return None, "its points have non-finite positions or radii (NaN or Inf)", False
    keep = radii > 0
    positions, radii, slots = positions[keep], radii[keep], slots[keep]
    scales = np.linalg.norm(matrix[:3, :3], axis=0)
    centres = transform_points(matrix, positions)
    radii = radii * scales.max()
    reach = np.abs(centres).max(initial=0.0) + radii.max(initial=0.0)
    if not reach <= max_coordinate:
        return None, f"its points lie beyond +-{max_coordinate:g} in world space", False
    materials = lookup[np.clip(slots, 0, len(lookup) - 1)].astype(np.int32)
    non_uniform = bool(scales.max() - scales.min() > 1e-4 * scales.max())
    return PointSet(obj.name, centres, radii, materials), None, non_uniform


def point_count(obj) -> int:
    """The spheres a point cloud object will give at most (for the memory estimate)."""
    return len(obj.data.points) if obj.data is not None else 0
