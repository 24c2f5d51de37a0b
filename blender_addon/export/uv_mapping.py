"""The texture coordinates an image or procedural texture node reads: its Vector input.

An Image Texture looks up the (x, y) of the vector it is given. Unlinked,
that vector is the mesh's active render UV map, (u, v, 0) (a procedural
texture's: the object's Generated coordinates); a UV Map node gives a named
layer, a Texture Coordinate node's UV output the active render one, its
Generated and Object outputs those coordinates (gridwalk.Texture.coordinates),
its Normal, Camera, Window and Reflection outputs those the core computes at
each hit (from the object-space normals, the camera that renders and the ray;
in the viewport, the view's camera, as in Cycles), and a Geometry node's
Position output the world point ("position"), its Normal, True Normal and
Incoming outputs those vectors at the hit, in world space. Where the
Texture Coordinate node names another object, its Object output is the world
point in that object's space: "position" under the inverse of the object's
world matrix (read at each export: in the viewport, moving that object
exports again, and the pattern follows it). Mapping nodes between them and the texture (any number, chained) move
the vector by an affine map of 3-space, as Blender defines them:
  Point:   R (S p) + L
  Texture: R^T (p - L) / S   (a zero component of S gives 0: Blender's safe divide)
  Vector:  R (S p)
with R = Rz Ry Rx of the node's Rotation (Euler XYZ), S its Scale and L its
Location. Since the UV map's z is 0, the composition restricted to (u, v) ->
(x, y) is a 2 x 3 affine map, an image's gridwalk.Texture.uv_transform;
a procedural texture (or an image at other coordinates) takes the whole 3 x 4 map,
gridwalk.Texture.vector_transform. A Mapping whose
own Vector is unlinked maps that input's value, as Cycles does: the texture
then shows one texel everywhere. A Location, Rotation or Scale fed by a Value
node (a float, as every axis) or a Combine XYZ of constants takes that value.

Not read, each named in the material's warning: the Normal type (it
normalises, which is not affine: the node is passed over), Location,
Rotation or Scale inputs fed by other nodes (their own values are used), any
other source of coordinates (a Vector Math node...: the node's own
default, the UV map or Generated, is used: the Texture Coordinate node's
From Instancer among them, and the Object output of an object whose
transform has no inverse), and a map beyond float range
(likewise).
"""
from __future__ import annotations

import numpy as np

from .environment_rotation import euler_xyz
from .node_links import _source, input_value, node_key

IDENTITY = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0)
FLOAT_MAX = float(np.finfo(np.float32).max)   # the core keeps float32
UV_SOURCES = {"UVMAP": None, "TEX_COORD": "UV"}   # node type -> the output that is a UV map (None: any)
# The Texture Coordinate node's outputs the core computes at each hit from its normal, the ray
# and the camera (gridwalk.Texture.coordinates "normal", "camera", "window", "reflection")
VIEW_OUTPUTS = ("Normal", "Camera", "Window", "Reflection")
# ... and the Geometry node's outputs it computes likewise (its Position is "position")
GEOMETRY_OUTPUTS = {"Normal": "geometry_normal", "True Normal": "true_normal", "Incoming": "incoming"}
# The coordinates read from per-corner arrays of the triangles (spheres and cylinders have none)
CORNER_COORDINATES = ("generated", "object", "position", "normal")
VECTOR_IDENTITY = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)


def constant_vector(socket, problems, where):
    """The 3 numbers a vector input takes: its own value, a Value node's (on every
    axis, as Blender converts a float), or a Combine XYZ's of constant inputs; for
    any other node its own value, with a note in `problems`."""
    src, _ = _source(socket)
    if src is None:
        return np.asarray(input_value(socket)[:3], np.float64)
    if src.type == "VALUE":
        return np.full(3, float(src.outputs[0].default_value))
    if src.type == "COMBXYZ" and all(_source(s)[0] is None for s in src.inputs[:3]):
        return np.array([float(input_value(s)) for s in src.inputs[:3]])
    problems.append(f"{socket.name} of {where} ({src.bl_idname}: its own value is used)")
    return np.asarray(socket.default_value[:3], np.float64)


def mapping_affine(node, folds_zero: bool = True) -> tuple[np.ndarray, list[str]]:
    """(4 x 4 affine matrix of 3-space, problems) of one Mapping node. folds_zero: a Scale of
    (0, 0, 0) gives the zero vector, Location and all, as Cycles folds such a Mapping
    (ConstantFolder::fold_mapping) unless all its inputs are constants, which it evaluates."""
    kind = getattr(node, "vector_type", "POINT")
    out, problems = np.eye(4), []
    if kind not in ("POINT", "TEXTURE", "VECTOR"):
        return out, problems + [f"{node.name!r} of type {kind.title()} (passed over)"]
    where = repr(node.name)
    rotation = euler_xyz(*constant_vector(node.inputs["Rotation"], problems, where))
    scale = constant_vector(node.inputs["Scale"], problems, where)
    location = np.zeros(3) if kind == "VECTOR" else constant_vector(node.inputs["Location"], problems, where)
    if folds_zero and not np.any(scale):
        out[:3] = 0.0
    elif kind == "TEXTURE":
        inverse = np.divide(1.0, scale, out=np.zeros(3), where=scale != 0)
        out[:3, :3] = inverse[:, None] * rotation.T
        out[:3, 3] = -out[:3, :3] @ location
    else:
        out[:3, :3] = rotation * scale[None, :]
        out[:3, 3] = location
    return out, problems


# Texture nodes whose unlinked Vector is the zero vector in Cycles (the others take Generated
# coordinates, or an image the UV map).
ZERO_VECTOR_NODES = ("TEX_WHITE_NOISE",)


def vector_source(node, default: str = "uv") -> tuple[str, str, np.ndarray, list[str]]:
    """(coordinates "uv" | "generated" | "object" | "position" | "normal" | "camera" | "window" |
    "reflection" | "geometry_normal" | "true_normal" | "incoming" | "constant", UV layer ("" the active render
    one), the Mapping nodes' 4 x 4 affine map, problems to warn about) of a texture node's
    Vector input; unlinked, the `default` coordinates (the zero vector for ZERO_VECTOR_NODES).
    "constant": the map's translation is the point everywhere (an unlinked Vector at the
    chain's end, its value)."""
    vector = node.inputs.get("Vector")
    problems, layer, coordinates = [], "", default
    mappings, socket, seen = [], vector, set()
    while socket is not None:
        src, out = _source(socket)
        if src is None:
            if socket is not vector or node.type in ZERO_VECTOR_NODES:   # (a constant: a Mapping's unlinked Vector)
                coordinates = "constant"
                end = np.zeros((4, 4))
                end[:3, 3] = np.asarray(input_value(socket)[:3], np.float64) if socket is not vector else 0.0
                end[3, 3] = 1.0
                mappings.append(end)
            break
        if src.type == "MAPPING" and node_key(src) not in seen:
            seen.add(node_key(src))
            mappings.append(src)
            socket = src.inputs["Vector"]
            continue
        if src.type in ("UVMAP", "TEX_COORD") and getattr(src, "from_instancer", False) and \
                out.name in ("UV", "Generated"):
            problems.append(f"Vector of {node.name!r} ({src.bl_idname}'s From Instancer: the instancer's "
                            f"coordinates are not read; the object's own {out.name} is used)")
        if src.type in UV_SOURCES and UV_SOURCES[src.type] in (None, out.name):
            layer, coordinates = (src.uv_map if src.type == "UVMAP" else ""), "uv"
        elif src.type == "TEX_COORD" and (out.name == "Generated" or
                                          out.name == "Object" and getattr(src, "object", None) is None):
            coordinates = out.name.lower()
        elif src.type == "TEX_COORD" and out.name == "Object":
            # another object's Object coordinates: the world point in that object's space
            world = np.array(src.object.matrix_world, np.float64)
            if not (np.all(np.isfinite(world)) and abs(np.linalg.det(world[:3, :3])) > 1e-30):
                problems.append(f"Vector of {node.name!r} (the Object coordinates of {src.object.name!r}, whose "
                                f"transform cannot be inverted (a scale of 0): {_NAMES[default]} is used)")
                mappings = []
                break
            coordinates = "position"
            mappings.append(np.linalg.inv(world))
        elif src.type == "NEW_GEOMETRY" and out.name == "Position":
            coordinates = "position"
        elif src.type == "TEX_COORD" and out.name in VIEW_OUTPUTS:
            coordinates = out.name.lower()
        elif src.type == "NEW_GEOMETRY" and out.name in GEOMETRY_OUTPUTS:
            coordinates = GEOMETRY_OUTPUTS[out.name]
        else:
            problems.append(f"Vector of {node.name!r} ({src.bl_idname} {out.name}: only UV maps, the Texture "
                            f"Coordinate node's outputs and the Geometry node's Position, Normal, True Normal "
                            f"and Incoming, through Mapping nodes, are read; {_NAMES[default]} is used)")
            mappings = []
        break
    # (Cycles evaluates Mappings of constants as they are, and folds a Scale of 0 to zero elsewhere)
    affine = np.eye(4)
    for step in mappings:
        if isinstance(step, np.ndarray):
            affine = affine @ step
        else:
            matrix, notes = mapping_affine(step, folds_zero=coordinates != "constant")
            affine, problems = affine @ matrix, problems + notes
    if not all(abs(x) <= FLOAT_MAX for x in affine[:3].reshape(-1)):          # (NaN fails too)
        problems.append(f"Vector of {node.name!r} (its Mapping is beyond float range: {_NAMES[default]} is used)")
        affine, coordinates, layer = np.eye(4), default, ""
    return coordinates, layer, affine, problems


_NAMES = {"uv": "the UV map", "generated": "Generated"}


def texture_fields(node, default: str = "uv", image: bool = True) -> tuple[str | None, dict, list[str]]:
    """(UV layer the texture reads, or None where it reads Generated or Object coordinates
    or one constant point (its coordinates "uv", unread, under a map of no linear part);
    its gridwalk.Texture coordinate fields; problems) of an Image (image) or
    procedural texture node: an image on the UV map takes a 2 x 3 uv_transform,
    anything else the coordinates and a 3 x 4 vector_transform."""
    coordinates, layer, affine, problems = vector_source(node, default)
    if coordinates == "constant":
        # (one point everywhere: no coordinates are read, the map's translation is the point)
        affine[:3, :3] = 0.0
        coordinates, layer = "uv", None
    if image and coordinates == "uv":
        # (u, v, 0, 1) -> (x, y): rows x and y, columns u, v and the translation
        return layer, {"uv_transform": tuple(float(affine[r, c]) for r in (0, 1) for c in (0, 1, 3))}, problems
    fields = {"coordinates": coordinates, "vector_transform": tuple(float(x) for x in affine[:3].reshape(-1))}
    return (layer if coordinates == "uv" else None), fields, problems
