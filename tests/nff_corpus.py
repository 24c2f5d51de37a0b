"""A generated NFF corpus: every entity of the NFF text, and SPD-like scenes at
small sizes, written in several layouts. Nothing here is copied from a file.

A scene is a list of entities (word, numbers); a polygon is ("p", rows) or
("pp", rows) with one row of 3 (or 6) numbers per vertex. `write(scene,
layout)` gives the file text:

  spd        as today's SPD generators (libpr2.c) write it: the view block one
             item per line, a cone on ONE line "c bx by bz br ax ay az ar",
             polygons "p n" then one vertex per line
  spec       as the NFF text shows it: a cone as "c" then a base line and an
             apex line
  one_line   every entity on one line, polygons included
  stream     the whole file on one line
  scrambled  random line breaks (LF or CRLF), tabs, runs of spaces and form
             feeds between any two tokens, comments on lines of their own and
             after numbers (holding a U+2028, a U+0085 and a form feed),
             seeded

The generators follow the logic of SPD's generators (balls, gears, rings,
tree, tetra, mount, sombrero) at small sizes, written here from their
descriptions: the primitives they place, not their code.
"""
from __future__ import annotations

import math
import random

import numpy as np

from gridwalk.scenes import _sphereflake

SKY = (0.078, 0.361, 0.753)
LAYOUTS = ("spd", "spec", "one_line", "stream", "scrambled")


def fmt(x: float) -> str:
    return f"{x:g}"


# -- entities -------------------------------------------------------------------------
def view(eye, target, up, angle, hither=1.0, res=(512, 512)):
    return [("v", []), ("from", list(eye)), ("at", list(target)), ("up", list(up)),
            ("angle", [angle]), ("hither", [hither]), ("resolution", list(res))]


def colour(rgb, kd, ks, shine, t=0.0, ior=0.0):
    return ("f", [*rgb, kd, ks, shine, t, ior])


def phong_power(angle_degrees: float) -> float:
    """SPD's highlight exponent for a highlight half-width angle (log 0.5 / log cos)."""
    a = math.radians(angle_degrees)
    if a <= 0:
        return 100000.0
    return 1.0 if a >= math.pi / 2 else math.log(0.5) / math.log(math.cos(a))


def cone(base, base_r, apex, apex_r):
    return ("c", [*base, base_r, *apex, apex_r])


def sphere(centre, r):
    return ("s", [*centre, r])


def polygon(points, normals=None):
    if normals is None:
        return ("p", [list(map(float, p)) for p in points])
    return ("pp", [[*map(float, p), *map(float, n)] for p, n in zip(points, normals)])


# -- layouts ------------------------------------------------------------------------
def _lines(entity, layout):
    word, values = entity
    if word == "#":
        return ["# a comment: every entity of the NFF text follows"]
    if word in ("p", "pp"):
        rows = [" ".join(map(fmt, r)) for r in values]
        if layout == "one_line":
            return [f"{word} {len(values)} " + " ".join(rows)]
        return [f"{word} {len(values)}"] + rows
    if word == "c" and layout == "spec":
        return ["c", " ".join(map(fmt, values[:4])), " ".join(map(fmt, values[4:]))]
    return [" ".join([word, *map(fmt, values)])]


def write(scene, layout: str, seed: int = 0) -> str:
    if layout in ("spd", "spec", "one_line"):
        return "".join(line + "\n" for e in scene for line in _lines(e, layout))
    return relayout([t for e in scene if e[0] != "#" for line in _lines(e, "spd") for t in line.split()],
                    layout, seed)


def relayout(tokens, layout: str, seed: int = 0) -> str:
    """The tokens of an NFF file (no comments) in the stream or scrambled layout."""
    if layout == "stream":
        return " ".join(tokens) + "\n"
    rng = random.Random(seed)
    out = ["# scrambled \u2028 layout \u0085 with\x0c odd separators\r\n"]
    for t in tokens:
        out.append(t)
        r = rng.random()
        if r < 0.3:
            out.append(rng.choice(["\n", "\r\n", " # note \u2028 \x0c\x1c\n"]))
            if rng.random() < 0.2:
                out.append("#\tcomment line \u0085\n")
        else:
            out.append(rng.choice([" ", "  ", "\t", " \t ", " \x0c ", "\x0b"]))
    return "".join(out) + "\n"


# -- the scenes --------------------------------------------------------------------------
def every_entity():
    """Each entity of the NFF text at least once, in both of its forms where it has two."""
    return [("#", None), *view((0, -9, 3), (0, 0, 0.6), (0, 0, 1), 35, 0.01, (64, 48)),
            ("b", [0.1, 0.2, 0.3]), ("l", [3, -4, 6]), ("l", [-3, -4, 5, 0.9, 0.8, 0.7]),
            sphere((2.2, 0, 0.5), 0.5), colour((0.9, 0.3, 0.2), 0.7, 0.2, 20),
            cone((-2, 0, 0), 0.5, (-2, 0, 1.5), -0.5), cone((0, 0, 0), 0.7, (0, 0, 1.6), 0),
            polygon([(-1, -1, -0.01), (1, -1, -0.01), (1.5, 1, -0.01), (0, 2, -0.01), (-1.5, 1, -0.01)]),
            colour((0.2, 0.5, 0.9), 0.6, 0.1, 10, 0.5, 1.3),
            polygon([(1, -2, 0), (2, -2, 0), (2, -2, 1), (1, -2, 1)],
                    [(0, -1, 0.2), (0.3, -1, 0.2), (0.3, -1, 0), (0, -1, 0)]),
            sphere((-0.5, 1, 2), -0.3)]


def balls(size=1):
    centres, radii = _sphereflake(size)
    return [("b", list(SKY)), *view((2.1, 1.3, 1.7), (0, 0, 0), (0, 0, 1), 45, 0.01),
            ("l", [4, 3, 2]), ("l", [1, -4, 4]), ("l", [-3, 1, 5]),
            colour((1, 0.75, 0.33), 0.8, 0, phong_power(0)),
            polygon([(12, 12, -0.5), (-12, 12, -0.5), (-12, -12, -0.5), (12, -12, -0.5)]),
            colour((1, 0.9, 0.7), 0.5, 0.5, phong_power(45), 0, 1),
            *(sphere(c, r) for c, r in zip(centres, radii))]


def _rotation_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _rotation_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def gears(size=1, teeth=12):
    """size^3 gears: each a concave polygon outline of 4 points per tooth on
    top and bottom, and a quad per outline edge around the side."""
    scene = [("b", list(SKY)), *view((-1.1, -2.1, 2.6), (0, 0, 0), (0, 0, 1), 45),
             *(("l", list(p)) for p in ((2, 4, 4), (-2, 4, 3), (2, -2.5, 2.5), (-1, -4, 2))),
             colour((1, 0.85, 0.7), 0.3, 0.6, phong_power(37)),
             polygon([(2, 2, 0), (-2, 2, 0), (-2, -2, 0), (2, -2, 0)])]
    outer = 1.0 / (size - (size - 1) * 0.05)
    thick = min(0.1, 1.0 / (2 * size))
    step = 2 * math.pi / teeth
    for ix, iy, iz in np.ndindex(size, size, size):
        centre = np.array([-1 + outer + ix * outer * 1.9, -1 + outer + iy * outer * 1.9, 1 - iz / size])
        hue = np.array([(ix * 3 + iy * 2 + iz + 1) * 5 / 7, (iy * 3 + iz * 2 + ix + 1) * 3 / 7,
                        (iz * 3 + ix * 2 + iy + 1) * 2 / 7]) % 1 + 0.01
        glass = (ix * 4 + iy * 2 + iz) % 5 == 0
        scene.append(colour(hue / hue.max(), 0.2 if glass else 1.0, 0, 0, 0.8 if glass else 0,
                            1.1 if glass else 0))
        outline = []
        for k in range(teeth):
            a = step * k + (ix + iy + iz) % 2 * step / 2
            for frac, r in ((-0.19, 0.995), (0.19, 0.995), (0.3, 0.9), (0.7, 0.9)):
                outline.append(centre + _rotation_z(a + frac * step) @ (outer * r, 0, 0))
        top = np.array(outline)
        bottom = top - (0, 0, thick)
        scene.append(polygon(top))
        for k in range(len(top)):
            j = (k + 1) % len(top)
            scene.append(polygon([top[k], bottom[k], bottom[j], top[j]]))
        scene.append(polygon(bottom[::-1]))
    return scene


def rings(size=1):
    """Pyramid of objects, each 6 pentagonal rings of 5 cylinders (one-line c)
    and 5 spheres through the edge midpoints of a dodecahedron."""
    radius = 0.07412
    spread = 1 / math.sin(math.pi / 8)
    eye = (-1.0, -spread, 0.5)
    scene = [("b", list(SKY)), *view(eye, (eye[0], eye[1] + 1, eye[2]), (0, 0, 1), 45),
             ("l", [3, -spread, 3]), ("l", [-4, -spread, 1]), ("l", [2, -spread, -4]),
             colour((1, 1, 1), 1, 0, phong_power(0))]
    w = 1.01 * (spread * (size + 1) + spread) * math.tan(math.pi / 8)
    y = spread * (size + 1)
    scene.append(polygon([(w - 1, y, w + 0.5), (-w - 1, y, w + 0.5), (-w - 1, y, -w + 0.5),
                          (w - 1, y, -w + 0.5)]))
    scale = 1 / (1 + radius)
    pentagon = [scale * np.array([math.cos(k * 2 * math.pi / 5), math.sin(k * 2 * math.pi / 5), 0])
                for k in range(5)]
    tilt = _rotation_x(2 * math.acos(math.cos(math.pi / 3) / math.sin(math.pi / 5)))
    points = list(pentagon)
    for k in range(1, 6):
        turn = _rotation_z(math.pi * (2 * (k - 1) + 1) / 5)
        points += [turn @ (tilt @ p) for p in pentagon]
    colours = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 1, 1), (1, 0, 1), (1, 1, 0)]
    for depth in range(size):
        for iz in range(depth + 1):
            for ix in range(depth + 1):
                offset = np.array([2 * ix - depth, spread * (depth + 1), 2 * iz - depth])
                for k in range(30):
                    if k % 5 == 0:
                        scene.append(colour(colours[k // 5], 0.5, 0.2, phong_power(37)))
                    prev = k + 4 if k % 5 == 0 else k - 1
                    scene.append(cone(points[k] + offset, radius, points[prev] + offset, radius))
                    scene.append(sphere(points[k] + offset, radius))
    return scene


def tree(size=2):
    """A branching tree: each branch a cone with a sphere at its tip, two
    children rotated and shrunk from it."""
    scene = [("b", list(SKY)), *view((4.5, 0.4, 2), (0, 0, 1.5), (0, 0, 1), 45),
             *(("l", list(p)) for p in ((-5, 5, 50), (30, -30, 30), (-40, -30, 20))),
             colour((0.2, 0.7, 0.2), 1, 0, phong_power(0)),
             polygon([(50, 50, 0), (-50, 50, 0), (-50, -50, 0), (50, -50, 0)]),
             colour((0.55, 0.4, 0.2), 1, 0, phong_power(0))]
    children = []
    for angle, turn, shrink in ((40, 90, 0.65), (25, 230, 0.70)):
        m = np.eye(4)
        m[:3, :3] = _rotation_z(math.radians(turn)) @ _rotation_x(math.radians(angle)) * shrink
        m[:3, 3] = (0, 0, 1)
        children.append(m)

    def grow(m, width, depth):
        base, tip = m[:3, 3], (m @ (0, 0, 1, 1))[:3]
        scene.append(cone(base, width, tip, width * 0.67))
        scene.append(sphere(tip, width * 0.67))
        for child in children if depth else ():
            grow(m @ child, width * 0.67, depth - 1)
    grow(np.eye(4), 0.15, size)
    return scene


def tetra(size=2):
    """A Sierpinski tetrahedron: each level keeps four half-size copies."""
    scene = [("b", list(SKY)), *view((1.02, -3.18, -2.17), (0, 0, 0.22), (-0.82, -0.82, 0.82), 45),
             ("l", [1.9, -15, -6]), ("l", [2, -18, -5]), colour((1, 0.2, 0.2), 1, 0, phong_power(0))]
    corners = np.array([(1, 1, 1), (-1, -1, 1), (-1, 1, -1), (1, -1, -1)], float) / math.sqrt(3)

    def split(centre, scale, depth):
        if depth == 0:
            pts = centre + corners * scale
            for a, b, c in ((0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)):
                scene.append(polygon([pts[a], pts[b], pts[c]]))
            return
        for k in range(4):
            split(centre + corners[k] * scale / 2, scale / 2, depth - 1)
    split(np.zeros(3), 1.0, size)
    return scene


def mount(size=2, seed=3):
    """A fractal mountain (midpoint displacement of triangles, seeded) with
    four glass spheres over it."""
    rng = np.random.default_rng(seed)
    scene = [("b", list(SKY)), *view((-1.6, 1.6, 1.7), (0, 0, 0), (0, 0, 1), 45, 0.01),
             ("l", [-100, -100, 100]), colour((1, 1, 1), 0.1, 0.1, phong_power(5), 0.9, 1.5),
             *(sphere(c, 0.17) for c in ((-0.8, 0.8, 1.2), (-0.66, 0.66, 0.93), (-0.8, 0.4, 0.9),
                                         (-0.4, 0.8, 0.95))),
             colour((1, 0.5, 0.2), 0.9, 0, phong_power(0))]
    tris = [np.array([(1, 1, 0), (-1, 1, 0), (0, -1, 0)], float),
            np.array([(1, 1, 0), (0, -1, 0), (1, -1, 0)], float)]
    for level in range(size):
        nxt = []
        for a, b, c in tris:
            ab, bc, ca = ((a + b) / 2, (b + c) / 2, (c + a) / 2)
            for m in (ab, bc, ca):
                m[2] += rng.normal() * 0.3 / 2 ** level
            nxt += [np.array(t) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]
        tris = nxt
    scene += [polygon(t) for t in tris]
    return scene


def sombrero(size=8):
    """A height field z = cos(2 pi r) exp(-r) as patches with normals (pp 3)."""
    scene = [("b", list(SKY)), *view((0, 5, -8), (0, 0, 0), (0, 0, 1), 40, 0.01),
             ("l", [10, 10, -10]), colour((1, 0.1, 0.1), 0.8, 0.2, phong_power(10))]
    t = np.linspace(-3, 3, size + 1)
    x, y = np.meshgrid(t, t, indexing="ij")
    r = np.hypot(x, y)
    z = np.cos(2 * math.pi * r) * np.exp(-r)
    dzdr = -2 * math.pi * np.sin(2 * math.pi * r) * np.exp(-r) - z
    with np.errstate(invalid="ignore", divide="ignore"):
        gx, gy = np.nan_to_num(dzdr * x / r), np.nan_to_num(dzdr * y / r)
    p = np.stack([x, y, z], axis=-1)
    n = np.stack([-gx, -gy, np.ones_like(z)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    for i in range(size):
        for j in range(size):
            for tri in (((i, j), (i + 1, j), (i + 1, j + 1)), ((i, j), (i + 1, j + 1), (i, j + 1))):
                scene.append(polygon([p[a] for a in tri], [n[a] for a in tri]))
    return scene


GENERATORS = {"balls": balls, "gears": gears, "rings": rings, "tree": tree, "tetra": tetra,
              "mount": mount, "sombrero": sombrero}


def counts(scene) -> dict:
    """Primitive counts of a scene: spheres, cones, polygons, their triangles."""
    words = [w for w, _ in scene]
    polys = [len(v) for w, v in scene if w in ("p", "pp")]
    return {"spheres": words.count("s"), "cones": words.count("c"), "polygons": len(polys),
            "triangles": sum(n - 2 for n in polys), "lights": words.count("l")}
