"""Reader for Eric Haines' NFF (Neutral File Format), as the SPD writes it.

One entity per line, numbers separated by blanks; blank lines and `#` comment
lines are skipped anywhere:

    v                                  the view block; these lines follow it:
      from x y z | at x y z | up x y z | angle deg | hither d | resolution w h
    b r g b                            background colour (default black)
    l x y z [r g b]                    point light, optional colour
    f r g b Kd Ks Shine T ior          material of the primitives that follow
    c + 2 lines "x y z radius"         cone / cylinder: base line, apex line
    s x y z radius                     sphere
    p n  + n lines "x y z"             convex polygon, fan-triangulated
    pp n + n lines "x y z nx ny nz"    polygon patch with vertex normals

Decisions where the format leaves room:

* Light intensity. NFF.txt says a light without a colour has "a non-zero
  intensity of no particular value" and the SPD README leaves intensities to
  the renderer; the SPD generators themselves write 1/sqrt(#lights) for
  renderers that need one (balls.c, `lscale`). So a light without a colour is
  white with intensity `spd_light_intensity(n_lights)` = 1/sqrt(n_lights); a
  colour given on the line is used as is.
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
* Normals: only `pp` has vertex normals. If a file has a `pp`, the vertices of
  `p` polygons get their polygon's geometric (Newell) normal so `normals`
  covers every vertex; with no `pp`, normals is None. Polygons share no
  vertices; `p` polygons come before `pp` polygons in the arrays.
* The view needs from, at, up and angle; hither defaults to 0, resolution to
  512 x 512 (SPD's).

Malformed input raises SceneFileError naming file, line and what was
expected; nothing is returned half-read.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..model import Camera, Light, Material
from .common import SceneFileError, fan_triangulate, scene_kwargs

_NUMERIC_START = frozenset("0123456789+-.")
_ENTITIES = "v, from, at, up, angle, hither, resolution, b, l, f, c, s, p, pp or #"
_F32_MAX = float(np.finfo(np.float32).max)


def spd_light_intensity(n_lights: int) -> float:
    """Intensity of each of `n_lights` NFF lights that have no colour."""
    return 1.0 / math.sqrt(max(n_lights, 1))


def nff_camera(eye, target, up, angle, width=512, height=512, hither=0.0) -> Camera:
    """Camera for an NFF view; `angle` spans the centres of the outer pixel rows."""
    scale = height / (height - 1) if height > 1 else 1.0
    fov = math.degrees(2.0 * math.atan(math.tan(math.radians(angle) / 2.0) * scale))
    return Camera(eye=tuple(eye), target=tuple(target), up=tuple(up), fov=fov,
                  width=int(width), height=int(height), hither=float(hither))


def load_nff(path) -> dict:
    """Read an NFF file into keyword arguments for `gridwalk.Scene`."""
    path = Path(path)
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SceneFileError(f"{path}: not a text file (byte {err.start} is not UTF-8)") from None
    return _Parser(path, text).parse()


class _Parser:
    def __init__(self, path: Path, text: str):
        self.path = path
        kept = [(n, s) for n, s in enumerate(map(str.strip, text.splitlines()), 1)
                if s and s[0] != "#"]
        self.linenos = [n for n, _ in kept]
        self.lines = [s for _, s in kept]
        self.view, self.background = {}, (0.0, 0.0, 0.0)
        self.lights, self.materials, self.material = [], [], -1
        self.spheres = ([], [], [])                     # row texts, line numbers, materials
        self.polygons = {"p": ([], [], []), "pp": ([], [], [])}  # first row, count, material
        self.cylinders = ([], [])                       # first row, material

    def fail(self, lineno, message):
        where = f"{self.path}:{lineno}" if lineno else f"{self.path}"
        raise SceneFileError(f"{where}: {message}")

    # -- entity lines -------------------------------------------------------
    def parse(self) -> dict:
        lines, n = self.lines, len(self.lines)
        heads = [i for i, s in enumerate(lines) if s[0] not in _NUMERIC_START] + [n]
        if heads[0] != 0:
            self.fail(self.linenos[0], f"expected an entity ({_ENTITIES}), got numbers")
        for i, nxt in zip(heads, heads[1:]):
            kw, *rest = lines[i].split(None, 1)
            rest = rest[0] if rest else ""
            handler = getattr(self, "_e_" + kw, None)
            if handler is None:
                self.fail(self.linenos[i], f"unknown entity {kw!r}; expected {_ENTITIES}")
            need, have = handler(i, kw, rest), nxt - i - 1
            if have > need:
                self.fail(self.linenos[i + 1 + need],
                          f"unexpected numbers after '{kw}' on line {self.linenos[i]}; "
                          f"expected an entity ({_ENTITIES})")
            if have < need:
                end = ("then the file ends: truncated?" if nxt == n
                       else f"then line {self.linenos[nxt]} starts an entity")
                self.fail(self.linenos[i], f"'{kw}' needs {need} lines of numbers below it, "
                                           f"but only {have} follow ({end})")
        return self._scene()

    def _numbers(self, i, kw, rest, counts):
        tokens = rest.split()
        if len(tokens) not in counts:
            want = " or ".join(map(str, counts))
            self.fail(self.linenos[i], f"'{kw}' expects {want} numbers, got {len(tokens)}")
        try:
            values = [float(t) for t in tokens]
        except ValueError:
            self.fail(self.linenos[i], f"'{kw}': bad number in {rest!r}")
        if not all(abs(v) <= _F32_MAX for v in values):
            self.fail(self.linenos[i], f"'{kw}': NaN, infinite or out-of-range number in {rest!r}")
        return values

    def _e_v(self, i, kw, rest):
        if rest:
            self.fail(self.linenos[i], f"'v' takes no numbers, got {rest!r}")
        return 0

    def _e_from(self, i, kw, rest):
        self.view[kw] = self._numbers(i, kw, rest, (3,))
        return 0

    _e_at = _e_up = _e_from

    def _e_angle(self, i, kw, rest):
        (angle,) = self._numbers(i, kw, rest, (1,))
        if not 0.0 < angle < 180.0:
            self.fail(self.linenos[i], f"'angle' must be between 0 and 180 degrees, got {angle}")
        self.view[kw] = angle
        return 0

    def _e_hither(self, i, kw, rest):
        (hither,) = self._numbers(i, kw, rest, (1,))
        if hither < 0:
            self.fail(self.linenos[i], f"'hither' must be >= 0, got {hither}")
        self.view[kw] = hither
        return 0

    def _e_resolution(self, i, kw, rest):
        size = self._numbers(i, kw, rest, (2,))
        if not all(v >= 1 and v == int(v) for v in size):
            self.fail(self.linenos[i], f"'resolution' expects two positive integers, got {rest!r}")
        self.view[kw] = [int(v) for v in size]
        return 0

    def _e_b(self, i, kw, rest):
        self.background = tuple(self._numbers(i, kw, rest, (3,)))
        return 0

    def _e_l(self, i, kw, rest):
        values = self._numbers(i, kw, rest, (3, 6))
        self.lights.append((tuple(values[:3]), tuple(values[3:]) or None))
        return 0

    def _e_f(self, i, kw, rest):
        r, g, b, kd, ks, shine, t, ior = self._numbers(i, kw, rest, (8,))
        if shine < 0:
            self.fail(self.linenos[i], f"'f': Shine must be >= 0, got {shine}")
        if ior <= 0:
            if t > 0:
                self.fail(self.linenos[i], f"'f': a transparent surface needs ior > 0, got {ior}")
            ior = 1.0
        self.materials.append(Material(color=(r, g, b), kd=kd, ks=ks, shininess=shine,
                                       transmittance=t, ior=ior, mirror=ks))
        self.material = len(self.materials) - 1
        return 0

    def _e_s(self, i, kw, rest):
        tails, linenos, mats = self.spheres
        tails.append(rest)
        linenos.append(self.linenos[i])
        mats.append(self.material)
        return 0

    def _e_p(self, i, kw, rest):
        count = int(rest) if rest.isdecimal() else 0
        if count < 3:
            self.fail(self.linenos[i], f"'{kw}' expects a vertex count (an integer >= 3), "
                                       f"got {rest!r}")
        first, counts, mats = self.polygons[kw]
        first.append(i + 1)
        counts.append(count)
        mats.append(self.material)
        return count

    _e_pp = _e_p

    def _e_c(self, i, kw, rest):
        if rest:
            self.fail(self.linenos[i], f"'c' takes no numbers on its line, got {rest!r}")
        self.cylinders[0].append(i + 1)
        self.cylinders[1].append(self.material)
        return 2

    # -- batched numeric rows -------------------------------------------------
    def _rows(self, texts, lineno_of, width, what):
        """Parse rows of exactly `width` finite float32-range numbers."""
        if not texts:
            return np.empty((0, width))
        try:
            rows = np.loadtxt(texts, dtype=np.float64, comments=None, ndmin=2)
        except ValueError:
            rows = None
        if rows is None or rows.shape[1] != width:      # slow path: find the bad line
            parsed = []
            for r, text in enumerate(texts):
                tokens = text.split()
                if len(tokens) != width:
                    self.fail(lineno_of(r), f"{what} expects {width} numbers, got {len(tokens)}")
                try:
                    parsed.append([float(t) for t in tokens])
                except ValueError:
                    self.fail(lineno_of(r), f"{what}: bad number in {text!r}")
            rows = np.array(parsed)
        bad = ~(np.abs(rows) <= _F32_MAX).all(axis=1)
        if bad.any():
            self.fail(lineno_of(int(np.argmax(bad))),
                      f"{what}: NaN, infinite or out-of-range number")
        return rows

    def _block(self, first, count, width, what):
        """The `count` numeric lines below each entity, parsed as one array."""
        first, count = np.asarray(first, dtype=np.int64), np.asarray(count, dtype=np.int64)
        idx = np.repeat(first - (np.cumsum(count) - count), count) + np.arange(count.sum())

        def lineno_of(r):
            return self.linenos[idx[r]]
        return self._rows([self.lines[k] for k in idx], lineno_of, width, what), lineno_of

    def _polygons(self, kind, width):
        first, count, mats = self.polygons[kind]
        rows, lineno_of = self._block(first, count, width, f"'{kind}' vertex line")
        if width == 6:
            length = np.linalg.norm(rows[:, 3:], axis=1)
            if not length.all():
                self.fail(lineno_of(int(np.argmin(length))), "'pp' normal has zero length")
            rows[:, 3:] /= length[:, None]
        triangles, polygon = fan_triangulate(count)
        return rows, triangles, np.asarray(mats, dtype=np.int64)[polygon]

    def _scene(self) -> dict:
        tails, sphere_lines, sphere_mats = self.spheres
        spheres = self._rows(tails, sphere_lines.__getitem__, 4, "'s'")
        p_rows, p_tris, p_mats = self._polygons("p", 3)
        pp_rows, pp_tris, pp_mats = self._polygons("pp", 6)
        cyl, _ = self._block(self.cylinders[0], [2] * len(self.cylinders[0]), 4, "'c' line")
        if not (len(spheres) or len(p_tris) or len(pp_tris) or len(cyl)):
            self.fail(None, "no geometry: expected at least one s, p, pp or c entity")
        missing = [key for key in ("from", "at", "up", "angle") if key not in self.view]
        if missing:
            self.fail(None, f"the view ('v' block) lacks {', '.join(missing)}")

        materials = list(self.materials)
        mats = [np.asarray(sphere_mats, dtype=np.int64), np.concatenate([p_mats, pp_mats]),
                np.asarray(self.cylinders[1], dtype=np.int64)]
        if any(m.size and m.min() < 0 for m in mats):   # primitives before the first 'f'
            materials.insert(0, Material())
            mats = [m + 1 for m in mats]
        gain = spd_light_intensity(len(self.lights))
        view = self.view
        return scene_kwargs(
            vertices=np.concatenate([p_rows, pp_rows[:, :3]]),
            triangles=np.concatenate([p_tris, pp_tris + len(p_rows)]),
            normals=(np.concatenate([_newell_normals(p_rows, self.polygons["p"][1]),
                                     pp_rows[:, 3:]]) if len(pp_rows) else None),
            triangle_materials=mats[1],
            sphere_centers=spheres[:, :3],
            sphere_radii=np.abs(spheres[:, 3]),        # negative: "only the inside is visible"
            sphere_materials=mats[0],
            cylinder_base=cyl[0::2, :3], cylinder_apex=cyl[1::2, :3],
            cylinder_base_radius=np.abs(cyl[0::2, 3]),  # sign dropped, as for spheres
            cylinder_apex_radius=np.abs(cyl[1::2, 3]),
            cylinder_materials=mats[2],
            materials=materials,
            lights=[Light(position=p, color=c or (gain, gain, gain), kind="point")
                    for p, c in self.lights],
            camera=nff_camera(view["from"], view["at"], view["up"], view["angle"],
                              *view.get("resolution", (512, 512)), view.get("hither", 0.0)),
            background=self.background,
        )


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
