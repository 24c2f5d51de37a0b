"""PLY mesh reader (ascii, binary_little_endian, binary_big_endian).

The body is read by the `plyfile` package; the header is checked here first,
so that a header whose declared element counts need more bytes than the file
holds (say `element vertex 4000000000` in a 1 kB file) is rejected before
anything is allocated. Supported content: a `vertex` element with x, y, z
(optional nx, ny, nz normals and red, green, blue colours) and a `face` element
with a `vertex_indices` (or `vertex_index`) list; faces with more than three
corners are fan-triangulated (they are assumed convex). Also rejected: NaN,
infinite or beyond-float32 coordinates and normals, zero-length normals, faces
with fewer than 3 corners and indices outside the vertex array.

PLY holds no camera, lights or materials: `load_ply` frames the mesh with
`default_view` and gives it one grey material (kd 0.8, ks 0.2, shininess 40).
Vertex colours are not used for shading; `load_ply_mesh` returns them.
"""
from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..model import Camera, Light, Material
from .common import SceneFileError, fan_triangulate, scene_kwargs

_SIZES = {"char": 1, "int8": 1, "uchar": 1, "uint8": 1, "short": 2, "int16": 2,
          "ushort": 2, "uint16": 2, "int": 4, "int32": 4, "uint": 4, "uint32": 4,
          "float": 4, "float32": 4, "double": 8, "float64": 8}
_INTEGER_TYPES = {name for name in _SIZES if not name.startswith(("float", "double"))}
_FORMATS = ("ascii", "binary_little_endian", "binary_big_endian")
_MAX_HEADER = 1 << 20
_INDEX_NAMES = ("vertex_indices", "vertex_index")
_F32_MAX = float(np.finfo(np.float32).max)
BACKGROUND = (0.1, 0.1, 0.1)


@dataclass
class PlyMesh:
    """A triangle mesh from a PLY file.

    vertices (N, 3) float32; triangles (M, 3) int32; normals (N, 3) float32
    unit vectors or None; colors (N, 3) float32 RGB in [0, 1] or None.
    """
    vertices: np.ndarray
    triangles: np.ndarray
    normals: np.ndarray | None
    colors: np.ndarray | None


def load_ply(path) -> dict:
    """Read a PLY mesh into keyword arguments for `gridwalk.Scene`, with the
    camera and lights of `default_view` and one grey material."""
    mesh = load_ply_mesh(path)
    camera, lights = default_view(mesh.vertices)
    return scene_kwargs(
        vertices=mesh.vertices, triangles=mesh.triangles, normals=mesh.normals,
        triangle_materials=np.zeros(len(mesh.triangles), dtype=np.int32),
        materials=[Material(color=(0.8, 0.8, 0.8), kd=0.8, ks=0.2, shininess=40.0)],
        lights=lights, camera=camera, background=BACKGROUND)


def load_ply_mesh(path) -> PlyMesh:
    """Read a PLY file's triangle mesh; malformed files raise SceneFileError."""
    # Imported here, not at the top: gridwalk.io (the NFF reader) must import
    # where plyfile is absent, e.g. in Blender, whose add-on bundles only gridwalk.
    import plyfile

    path = Path(path)
    _check_header(path)
    try:
        ply = plyfile.PlyData.read(str(path))
    except (plyfile.PlyParseError, ValueError, OverflowError, EOFError, IndexError) as err:
        raise SceneFileError(f"{path}: {err}") from None
    vertex = ply["vertex"].data
    vertices = np.column_stack([vertex[c] for c in "xyz"]).astype(np.float64)
    _require_finite(path, vertices, "coordinate")
    face = ply["face"].data
    faces = face[next(n for n in _INDEX_NAMES if n in face.dtype.names)]
    triangles = _triangulate(path, faces, len(vertices))
    names = vertex.dtype.names
    normals = colors = None
    if all(c in names for c in ("nx", "ny", "nz")):
        normals = np.column_stack([vertex[c] for c in ("nx", "ny", "nz")]).astype(np.float64)
        _require_finite(path, normals, "normal")
        length = np.linalg.norm(normals, axis=1)
        if not length.all():
            bad = int(np.argmin(length))
            raise SceneFileError(f"{path}: vertex {bad} has a zero-length normal")
        normals = (normals / length[:, None]).astype(np.float32)
    if all(c in names for c in ("red", "green", "blue")):
        rgb = np.column_stack([vertex[c] for c in ("red", "green", "blue")])
        scale = np.iinfo(rgb.dtype).max if rgb.dtype.kind in "iu" else 1.0
        colors = (rgb / scale).astype(np.float32)
    return PlyMesh(vertices.astype(np.float32), triangles, normals, colors)


def default_view(vertices, up=(0.0, 0.0, 1.0)) -> tuple[Camera, list[Light]]:
    """A camera and lights that frame `vertices` (any (N, 3) array).

    The camera looks at the bounding box centre from a diagonal above it, at
    a distance where the box's bounding sphere fits a 40 degree field of view
    (512 x 512). A white key light (0.8) sits just above and beside the camera,
    a fill light (0.3) on the opposite side; like NFF lights they are meant
    without distance falloff.
    """
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


def _require_finite(path, values, what):
    bad = ~(np.abs(values) <= _F32_MAX).all(axis=1)
    if bad.any():
        raise SceneFileError(f"{path}: vertex {int(np.argmax(bad))} has a NaN, infinite or "
                             f"out-of-float32-range {what}")


def _triangulate(path, faces, n_vertices) -> np.ndarray:
    counts = np.fromiter(map(len, faces), dtype=np.int64, count=len(faces))
    if not len(counts):
        raise SceneFileError(f"{path}: the mesh has no faces")
    if counts.min() < 3:
        k = int(np.argmax(counts < 3))
        raise SceneFileError(f"{path}: face {k} has {counts[k]} corners; a face needs at least 3")
    flat = np.concatenate(list(faces)).astype(np.int64)
    bad = (flat < 0) | (flat >= n_vertices)
    if bad.any():
        at = int(np.argmax(bad))
        face = int(np.searchsorted(np.cumsum(counts), at, side="right"))
        raise SceneFileError(f"{path}: face {face} uses vertex index {flat[at]}, "
                             f"but there are {n_vertices} vertices")
    corners, _ = fan_triangulate(counts)
    return flat[corners].astype(np.int32)


def _check_header(path: Path) -> None:
    """Check the header, and that the body is large enough for what it declares."""
    fmt, elements, body = _read_header(path)
    props = {name: p for name, _, p in elements}
    vertex, face = props.get("vertex", {}), props.get("face", {})
    if not all(vertex.get(c) in _SIZES for c in "xyz"):
        raise SceneFileError(f"{path}: no 'vertex' element with scalar x, y, z properties")
    index = next((face[n] for n in _INDEX_NAMES if n in face), None)
    if not (isinstance(index, tuple) and index[2] in _INTEGER_TYPES):
        raise SceneFileError(f"{path}: no 'face' element with an integer 'vertex_indices' list")
    need = 0
    for name, count, p in elements:
        if not p:
            raise SceneFileError(f"{path}: element {name!r} has no properties")
        if fmt == "ascii":       # each value takes at least a digit and a separator
            need += count * 2 * len(p)
        else:                    # each scalar its size; each list at least its count
            need += count * sum(_SIZES[t[1] if isinstance(t, tuple) else t] for t in p.values())
    if need - (fmt == "ascii") > body:       # the last ascii line may lack its newline
        counts = ", ".join(f"{count} {name}" for name, count, _ in elements)
        raise SceneFileError(f"{path}: the header declares {counts} records, at least {need} "
                             f"bytes, but only {body} bytes follow it (truncated?)")


def _read_header(path: Path):
    """Parse the header: (format, [[element, count, {property: type}]], body bytes).

    A scalar property's type is its type name; a list's is ("list", count
    type, item type). Only the first 1 MiB is read.
    """
    with open(path, "rb") as f:
        head = f.read(_MAX_HEADER)
        size = os.fstat(f.fileno()).st_size

    def fail(message, lineno=None):
        raise SceneFileError(f"{path}:{lineno}: {message}" if lineno else f"{path}: {message}")

    end = re.search(rb"(?m)^end_header[ \t\r]*\n", head)
    if not head.startswith(b"ply") or end is None:
        fail("not a PLY file, or a truncated one (no 'ply' ... 'end_header' header in "
             "the first 1 MiB)")
    fmt, elements = None, []
    header = head[:end.start()].decode("ascii", "replace").splitlines()
    for lineno, line in enumerate(header[1:], 2):
        tokens = line.split()
        if not tokens or tokens[0] in ("comment", "obj_info"):
            continue
        if tokens[0] == "format":
            if len(tokens) != 3 or tokens[1] not in _FORMATS or tokens[2] != "1.0":
                fail(f"unsupported format line {line!r}", lineno)
            fmt = tokens[1]
        elif tokens[0] == "element":
            if len(tokens) != 3 or not tokens[2].isdecimal():
                fail(f"expected 'element <name> <count>', got {line!r}", lineno)
            elements.append([tokens[1], int(tokens[2]), {}])
        elif tokens[0] == "property" and elements:
            if len(tokens) == 5 and tokens[1] == "list":
                if tokens[2] not in _INTEGER_TYPES or tokens[3] not in _SIZES:
                    fail(f"list count type must be an integer type (and item type known), "
                         f"got {line!r}", lineno)
                elements[-1][2][tokens[4]] = ("list", tokens[2], tokens[3])
            elif len(tokens) == 3 and tokens[1] in _SIZES:
                elements[-1][2][tokens[2]] = tokens[1]
            else:
                fail(f"bad property line {line!r}", lineno)
        else:
            fail(f"unexpected header line {line!r}", lineno)
    if fmt is None:
        fail("the header has no 'format' line")
    return fmt, elements, size - end.end()
