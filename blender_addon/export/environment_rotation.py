"""The rotation of a world's Environment Texture: its Vector input.

Artists turn an HDRI (to place its sun) with a Mapping node between a Texture
Coordinate's Generated output (in a world: the view direction) and the
texture's Vector. The image is then looked up along R d for a ray direction d
(gridwalk.World.environment_rotation, row-major): R = Rz Ry Rx of the Mapping's
Rotation (Euler XYZ, as Blender composes it) for the Point, Vector and Normal
types, its inverse for the Texture type. A uniform Scale changes no direction;
a Location (Point type) or a non-uniform Scale does, and is ignored with a
warning, as is any other Vector source (the image is then not turned).
"""
from __future__ import annotations

import math

import numpy as np

from .node_links import _source, input_value

IDENTITY = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)


def euler_xyz(rx: float, ry: float, rz: float) -> np.ndarray:
    """Blender's XYZ Euler rotation as a matrix: Rz @ Ry @ Rx."""
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return z @ y @ x


def _generated(socket) -> bool:
    """Whether the socket is unlinked or fed by a Texture Coordinate's Generated output
    (in a world both give the ray direction)."""
    src, out = _source(socket)
    return src is None or (src.type == "TEX_COORD" and out.name == "Generated")


def environment_rotation(env) -> tuple[tuple, str | None]:
    """(row-major R as 9 floats, a problem to warn about or None) for an Environment or Sky
    Texture node. (A Sky Texture with its sun's disc has no Vector input: Blender makes the
    socket unavailable, and Cycles reads no link to it.)"""
    socket = next((s for s in env.inputs if s.identifier == "Vector"), None)
    if socket is None or not getattr(socket, "enabled", True) or _generated(socket):
        return IDENTITY, None
    mapping, _ = _source(socket)
    ignored = "the environment is not rotated"
    if mapping.type != "MAPPING":
        return IDENTITY, f"the environment's Vector from {mapping.bl_idname} is not read ({ignored})"
    kind = getattr(mapping, "vector_type", "POINT")
    linked = [name for name in ("Location", "Rotation", "Scale") if name in mapping.inputs
              and _source(mapping.inputs[name])[0] is not None]
    if linked or not _generated(mapping.inputs["Vector"]):
        what = ", ".join(linked) if linked else "Vector"
        return IDENTITY, f"the environment's Mapping node has a linked {what}, which is not read ({ignored})"
    rotation = euler_xyz(*input_value(mapping.inputs["Rotation"])[:3])
    if kind == "TEXTURE":
        rotation = rotation.T
    notes = []
    scale = np.asarray(input_value(mapping.inputs["Scale"])[:3], float) if "Scale" in mapping.inputs else np.ones(3)
    if np.ptp(np.abs(scale)) > 1e-6 * np.abs(scale).max() or np.any(scale <= 0):
        notes.append(f"its Scale {tuple(round(float(v), 4) for v in scale)}")
    if kind in ("POINT", "TEXTURE") and "Location" in mapping.inputs and \
            np.any(np.asarray(input_value(mapping.inputs["Location"])[:3], float) != 0):
        notes.append("its Location")
    problem = None
    if notes:
        problem = f"the environment's Mapping node turns it; {' and '.join(notes)} are ignored"
    return tuple(float(v) for v in rotation.ravel()), problem
