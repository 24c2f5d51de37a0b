"""Reader for Eric Haines' NFF (Neutral File Format), as the SPD tools write and read it.

An NFF file is a stream of entities, each a keyword followed by its numbers.
The NFF text shows the numbers on separate lines; today's SPD generators
(libpr2.c) write a cone on one line, and the SPD's own reader (readnff.c)
reads numbers with scanf, so line breaks are just whitespace. This reader
does the same: any layout of the numbers over lines (one line, many lines,
tabs, CRLF) reads alike. Entities:

    v                                  starts the view; these give its values:
      from x y z | at x y z | up x y z | angle deg | hither d | resolution w h
    b r g b                            background colour (default black)
    l x y z [r g b]                    point light, optional colour
    f r g b Kd Ks Shine T ior          material of the primitives that follow
    c bx by bz br ax ay az ar          cone / cylinder: base and apex, each with a radius
    s x y z radius                     sphere
    p n  x y z (n times)               polygon
    pp n x y z nx ny nz (n times)      polygon patch with vertex normals
    # ...                              a comment, from the # to the end of its line

The file is read in bounded chunks (gridwalk.io.tokens), so memory stays
bounded whatever the file holds; junk is refused at its first bad token.
Errors name the file and line and quote at most a short excerpt.

Decisions where the format leaves room:

* Light intensity. NFF.txt says a light without a colour has "a non-zero
  intensity of no particular value" and the SPD README leaves intensities to
  the renderer; the SPD generators themselves write 1/sqrt(#lights) for
  renderers that need one (balls.c, `lscale`). So a light without a colour is
  white with intensity `spd_light_intensity(n_lights)` = 1/sqrt(n_lights); a
  colour given with it is used as is.
* Field of view. NFF's `angle` spans "from the center of the top pixel row to
  the bottom pixel row". `Camera.fov` spans the image edges, so for an image
  H pixels high fov = 2 atan(tan(angle / 2) * H / (H - 1)): the centre ray of
  the top row is then exactly angle / 2 off the view axis, as in NFF (and as
  SPD's 513 corner rays per 512 pixels). SPD images are square; for other
  shapes the angle is taken as the vertical one.
* A negative radius (s, c) means "only the inside is visible". Gridwalk
  primitives are two-sided, so the absolute radius is kept and the sign dropped.
* `f` -> Material(color, kd, ks, shininess=Shine, transmittance=T, ior,
  mirror=Ks). SPD writes ior 0 for opaque surfaces; with T = 0 it becomes 1.
  Primitives before the first `f` get a default Material().
* Polygons may be concave (SPD's gears are): see gridwalk.io.triangulate.
  Normals: only `pp` has vertex normals. If a file has a `pp`, the vertices
  of `p` polygons get their polygon's geometric (Newell) normal so `normals`
  covers every vertex; with no `pp`, normals is None. Polygons share no
  vertices and keep the file's order.
* The view needs from, at, up and angle; hither defaults to 0, resolution to
  512 x 512 (SPD's). Numbers are plain decimals (no `_`, `nan` or `inf`)
  within the float32 range.
* The scene is checked by the core (gridwalk.Scene) before it is returned:
  what the core refuses (a cone whose base is its apex, a primitive beyond
  +-1e30, a camera looking along its up vector, too many pixels) is reported
  at the line of the entity that causes it.

Malformed input raises SceneFileError; nothing is returned half-read.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import nff_parser, triangulate
from .common import SceneFileError, core_refusal, open_scene_file, scene_kwargs
from .nff_parser import AT, FROM, RESOLUTION, UP, ANGLE, HITHER, V, Parser, Refusal
from .tokens import TokenError, TokenStream, line_of


def spd_light_intensity(n_lights: int) -> float:
    """Intensity of each of `n_lights` NFF lights that have no colour."""
    return 1.0 / math.sqrt(max(n_lights, 1))


def nff_camera(eye, target, up, angle, width=512, height=512, hither=0.0):
    """Camera for an NFF view; `angle` spans the centres of the outer pixel rows."""
    from ..model import Camera
    scale = height / (height - 1) if height > 1 else 1.0
    fov = math.degrees(2.0 * math.atan(math.tan(math.radians(angle) / 2.0) * scale))
    return Camera(eye=tuple(eye), target=tuple(target), up=tuple(up), fov=fov,
                  width=int(width), height=int(height), hither=float(hither))


def nff_resized(camera, width: int, height: int):
    """An NFF camera (nff_camera's) for an image of width x height: the view's
    angle, recovered from the camera's field of view and height, spans the new
    image's outer pixel centres."""
    import dataclasses
    old = camera.height / (camera.height - 1) if camera.height > 1 else 1.0
    angle = math.degrees(2.0 * math.atan(math.tan(math.radians(camera.fov) / 2.0) / old))
    fresh = nff_camera(camera.eye, camera.target, camera.up, angle, width, height, camera.hither)
    return dataclasses.replace(camera, width=fresh.width, height=fresh.height, fov=fresh.fov)


@dataclass
class NffPolygons:
    """The file's p and pp polygons before triangulation, for importers that
    keep n-gons: polygon k has the counts[k] rows of the Scene's `vertices`
    (and `normals`) from starts[k], and material index materials[k]."""
    counts: np.ndarray
    starts: np.ndarray
    materials: np.ndarray


@dataclass
class NffFile:
    """A read NFF file: `kwargs` for gridwalk.Scene, and its polygons."""
    kwargs: dict
    polygons: NffPolygons


def load_nff(path) -> dict:
    """Read an NFF file into keyword arguments for `gridwalk.Scene`."""
    return read_nff(path).kwargs


def read_nff(path) -> NffFile:
    """Read an NFF file: the Scene keywords and the untriangulated polygons."""
    path = Path(path)
    parser = Parser()
    try:
        with open_scene_file(path) as f:
            for tokens, first in TokenStream(f).segments():
                parser.feed(tokens, first)
        parser.finish()
        return _Scene(parser).build()
    except TokenError as err:
        shown = ascii(err.token.decode("latin-1"))
        shown = shown[:60] + "..." if len(shown) > 60 or err.size > len(err.token) else shown
        raise SceneFileError(f"{path}:{err.line}: {err.reason}, {shown}: not an NFF text file, "
                             f"or a damaged one") from None
    except Refusal as err:
        line = line_of(path, err.index) if err.index is not None else None
        message = err.message.replace("{also}", str(line_of(path, err.also)) if err.also is not None else "?")
        raise SceneFileError(f"{path}:{line}: {message}" if line else f"{path}: {message}") from None


_VIEW_ENTITIES = {"eye": FROM, "target": AT, "up": UP, "fov": ANGLE, "width": RESOLUTION,
                  "height": RESOLUTION, "hither": HITHER}
_CORE_WORDS = {"Camera.eye": "'from'", "Camera.target": "'at'", "Camera.up": "'up'",
               "Camera.fov": "the field of view (from 'angle')", "Camera.width": "'resolution' width",
               "Camera.height": "height", "Camera.hither": "'hither'",
               "cylinder_base_radius": "the base radius", "cylinder_apex_radius": "the apex radius",
               "cylinder_apex": "the apex", "cylinder_base": "the base", "sphere_radii": "the radius",
               "sphere_centers": "the centre", "the primitive": "it"}
_CORE_WORD = re.compile("|".join(map(re.escape, _CORE_WORDS)))     # longest names first above


class _Scene:
    """The parsed entities as gridwalk.Scene keywords, checked by the core."""

    def __init__(self, parser: Parser):
        self.p = parser

        def join(chunks, k, width=None):
            if not chunks:
                return np.empty((0, width) if width else 0)
            return np.concatenate([c[k] for c in chunks])
        self.spheres, self.sphere_mat, self.sphere_at = (join(parser.spheres, k, 4) for k in range(3))
        self.cones, self.cone_mat, self.cone_at = (join(parser.cones, k, 8) for k in range(3))
        poly = parser.polygons
        self.corners = join(poly, 0, 3)
        self.normals = join(poly, 1, 3) if parser.patches else None
        self.counts, self.poly_mat, self.poly_at = (join(poly, k).astype(np.int64) for k in (2, 3, 4))
        self.offset = 0

    def build(self) -> NffFile:
        from ..model import Light, Material
        p = self.p
        if not (len(self.spheres) or len(self.counts) or len(self.cones)):
            raise Refusal(None, "no geometry: expected at least one s, p, pp or c entity")
        missing = [nff_parser.NAMES[k] for k in (FROM, AT, UP, ANGLE) if k not in p.view]
        if missing:
            raise Refusal(p.view.get(V, (None, None))[1], f"the view lacks {', '.join(missing)} "
                                                          "(a 'v' block needs from, at, up and angle)")
        try:
            triangles, polygon = triangulate.polygons(self.corners, self.counts)
        except triangulate.TooManyCorners as err:
            raise Refusal(int(self.poly_at[err.polygon]), f"the polygon has {err}") from None
        normals = self._normals() if self.normals is not None else None
        materials = [m for m, _ in p.materials]
        mats = [self.sphere_mat.astype(np.int64), self.poly_mat, self.cone_mat.astype(np.int64)]
        self.offset = int(any(m.size and m.min() < 0 for m in mats))    # primitives before the first f
        if self.offset:
            materials.insert(0, Material())
        sphere_mat, poly_mat, cone_mat = (m + self.offset for m in mats)
        gain = spd_light_intensity(len(p.lights))
        view = {k: v for k, (v, _) in p.view.items()}
        resolution = view.get(RESOLUTION, (512, 512))
        kwargs = scene_kwargs(
            vertices=self.corners, triangles=triangles, normals=normals,
            triangle_materials=poly_mat[polygon],
            sphere_centers=self.spheres[:, :3], sphere_radii=np.abs(self.spheres[:, 3]),  # sign: inside
            sphere_materials=sphere_mat,
            cylinder_base=self.cones[:, 0:3], cylinder_apex=self.cones[:, 4:7],
            cylinder_base_radius=np.abs(self.cones[:, 3]), cylinder_apex_radius=np.abs(self.cones[:, 7]),
            cylinder_materials=cone_mat,
            materials=materials,
            lights=[Light(position=pos, color=c or (gain, gain, gain), kind="point")
                    for pos, c, _ in p.lights],
            camera=nff_camera(view[FROM], view[AT], view[UP], view[ANGLE], *resolution,
                              view.get(HITHER, 0.0)),
            background=p.background[0] if p.background else (0.0, 0.0, 0.0))
        refusal = core_refusal(kwargs)
        if refusal:
            name, index, rest = refusal
            at, what = self._where(name, index)
            text = _reword(rest if rest.startswith("the primitive") else f"{name} {rest}")
            raise Refusal(at, f"{what}: {text}" if what else text)
        counts = self.counts
        return NffFile(kwargs, NffPolygons(counts, np.cumsum(counts) - counts, poly_mat))

    def _normals(self):
        normals = self.normals.copy()
        plain = np.isnan(normals[:, 0])
        length = np.linalg.norm(normals, axis=1)
        zero = ~plain & ~(length > 0)
        if zero.any():
            k = int(np.searchsorted(np.cumsum(self.counts), np.argmax(zero), side="right"))
            raise Refusal(int(self.poly_at[k]), "'pp' has a vertex normal of zero length")
        normals[~plain] /= length[~plain, None]
        normals[plain] = _newell_normals(self.corners, self.counts)[plain]
        return normals

    def _where(self, name: str, index: int | None):
        """(token index, what) of the entity a core error about `name`[index] is about."""
        if name in ("triangles", "triangle_materials"):
            k = np.searchsorted(np.cumsum(self.counts - 2), index, side="right")
            return int(self.poly_at[k]), "polygon"
        if name in ("vertices", "normals"):
            return int(self.poly_at[np.searchsorted(np.cumsum(self.counts), index, side="right")]), "polygon"
        if name.startswith("sphere_"):
            return int(self.sphere_at[index]), "sphere ('s')"
        if name.startswith("cylinder_"):
            return int(self.cone_at[index]), "cone ('c')"
        if name == "lights":
            return self.p.lights[index][2], "light ('l')"
        if name == "materials" and index >= self.offset:
            return self.p.materials[index - self.offset][1], "material ('f')"
        if name.startswith("Camera."):
            view = self.p.view
            return view.get(_VIEW_ENTITIES.get(name[7:]), view.get(V, (None, None)))[1], "view"
        return None, None


def _reword(text: str) -> str:
    """A core error message in the file's words ('at' for Camera.target, ...)."""
    return _CORE_WORD.sub(lambda m: _CORE_WORDS[m[0]], text).replace(" .", " ")


def _newell_normals(vertices, counts):
    """Each polygon's unit normal (Newell's method), repeated for its vertices."""
    counts = np.asarray(counts, dtype=np.int64)
    starts = np.cumsum(counts) - counts
    if not len(vertices):
        return np.empty((0, 3))
    v = vertices - np.repeat(vertices[starts], counts, axis=0)
    nxt = np.arange(len(v)) + 1
    nxt[starts + counts - 1] = starts
    n = np.add.reduceat(np.cross(v, v[nxt]), starts, axis=0)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    # A degenerate polygon's triangles are never hit; any unit normal will do.
    n = np.where(length > 0, n / np.maximum(length, 1e-300), (0.0, 0.0, 1.0))
    return np.repeat(n, counts, axis=0)
