"""Hair curves objects (Blender's Curves: the hair of Add > Curves, Geometry
Nodes' curves) -> cone frusta, the core's "c" primitive.

Cycles renders each curve as a round tube whose radius follows the points'
`radius` attribute (0.005 where there is none, Cycles' width for such
curves). Each pair of consecutive points becomes one open cone frustum from
one point to the next, with their radii: the polyline through the control
points (Catmull-Rom and poly curves pass through them; Bezier handles and
NURBS weights are not read, so those are approximated by their control
polygon). Positions go through matrix_world, radii times its largest axis
scale. Segments of zero length (in float32) or with both radii 0 are left
out, as are segments whose radii differ by more than 2^20 times their length
(the core refuses those); non-finite
positions or radii, or points beyond +-MAX_COORDINATE, skip the object with
a warning. The material is the object's slot the curve's `material_index`
names (slot 0 where there is none).
"""
from __future__ import annotations

import numpy as np

from ._matrix import transform_points
from .point_clouds import array_digest, attribute_values

DEFAULT_RADIUS = 0.005   # a curve point without a radius attribute, as Cycles renders it


class ConeSet:
    """One hair object instance's cone frusta in world space."""

    def __init__(self, name, base, apex, base_radius, apex_radius, materials):
        self.name = name
        self.base, self.apex = base, apex
        self.base_radius, self.apex_radius, self.materials = base_radius, apex_radius, materials

    def __len__(self):
        return len(self.base_radius)

    def digest(self) -> bytes:
        return array_digest(self.base, self.apex, self.base_radius, self.apex_radius, self.materials)


def read_curves(curves) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(positions (n, 3) float64, radii (n,), offsets (curves + 1,), material slots per curve)."""
    n, m = len(curves.points), len(curves.curves)
    if n == 0 or m == 0:   # (an empty hair object: Blender lists one offset but holds none)
        return np.zeros((0, 3)), np.zeros(0), np.zeros(1, np.int32), np.zeros(0, np.int32)
    attributes = curves.attributes
    positions = attribute_values(attributes, "position", "vector", "FLOAT_VECTOR", "POINT", n, 3, np.float32)
    if positions is None:
        positions = np.zeros((n, 3), np.float32)
    radii = attribute_values(attributes, "radius", "value", "FLOAT", "POINT", n, 1, np.float32)
    if radii is None:
        radii = np.full(n, DEFAULT_RADIUS, np.float32)
    offsets = np.empty(m + 1, np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    slots = attribute_values(attributes, "material_index", "value", "INT", "CURVE", m, 1, np.int32)
    if slots is None:
        slots = np.zeros(m, np.int32)
    return positions.astype(np.float64), radii.astype(np.float64), offsets, slots


def cone_set(obj, matrix, lookup, max_coordinate) -> tuple[ConeSet | None, str | None, bool]:
    """(cones, why the object is skipped, whether its scale is non-uniform) of an
    evaluated Curves object; lookup maps its material slots to material indices."""
    positions, radii, offsets, slots = read_curves(obj.data)
    if not (np.isfinite(positions).all() and np.isfinite(radii).all()):
        return None, "its curves have non-finite positions or radii (NaN or Inf)", False
    scales = np.linalg.norm(matrix[:3, :3], axis=0)
    return polyline_cones(obj.name, transform_points(matrix, positions), radii * scales.max(), offsets, slots,
                          lookup, max_coordinate, scales)


def polyline_cones(name, world, r, offsets, slots, lookup, max_coordinate, scales) -> tuple[ConeSet | None, str | None, bool]:
    """Cones along polylines: world (n, 3) float64 points and r (n,) world radii,
    curve k's points offsets[k]:offsets[k + 1], its material slot slots[k];
    scales: the object's axis scales (whether they differ is returned)."""
    r = np.maximum(r, 0.0)
    counts = np.diff(offsets)
    # Segment i joins point i and i + 1 where both belong to one curve: every
    # point but each curve's last starts one.
    curve_of_point = np.repeat(np.arange(len(counts)), counts)
    starts = np.ones(len(world), bool)
    starts[offsets[1:][counts > 0] - 1] = False
    first = np.nonzero(starts)[0]
    # (in the core's float32, whose rounding can make a short segment's ends coincide)
    base, apex = world[first].astype(np.float32), world[first + 1].astype(np.float32)
    rb, ra = r[first].astype(np.float32), r[first + 1].astype(np.float32)
    height = np.linalg.norm(apex.astype(np.float64) - base, axis=1)
    keep = (height > 0) & ((rb > 0) | (ra > 0)) & (np.abs(ra.astype(np.float64) - rb) <= 2.0 ** 20 * height)
    base, apex, rb, ra, first = base[keep], apex[keep], rb[keep], ra[keep], first[keep]
    reach = max(np.abs(world).max(initial=0.0) + r.max(initial=0.0), 0.0)
    if not reach <= max_coordinate:
        return None, f"its curves lie beyond +-{max_coordinate:g} in world space", False
    materials = lookup[np.clip(slots[curve_of_point[first]], 0, len(lookup) - 1)].astype(np.int32)
    non_uniform = bool(scales.max() - scales.min() > 1e-4 * scales.max())
    return ConeSet(name, base, apex, rb, ra, materials), None, non_uniform


def segment_count(obj) -> int:
    """The cones a Curves object will give at most (for the memory estimate)."""
    data = obj.data
    return max(len(data.points) - len(data.curves), 0) if data is not None else 0
