"""Scene layouts that are hard for grids, as numpy triangle meshes (bench_layouts.py): a building
of floors, walls and furniture; a stack of floor quads; a blind of slats; a terrain; grass on a
plane; a soup of small triangles; clusters far apart; long thin slivers in every direction.
Each function takes a numpy Generator and a scale (1 for the documented sizes) and returns
(vertices, triangles, eye, target)."""
from __future__ import annotations

import numpy as np

from gridwalk.scenes import icosphere

CUBE_FACES = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4], [2, 6, 3], [3, 6, 7],
                       [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
CUBE_CORNERS = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)


def boxes(lo, hi):
    """Triangles of axis-aligned boxes [lo, hi] (k, 3 each)."""
    lo, hi = np.atleast_2d(lo).astype(float), np.atleast_2d(hi).astype(float)
    v = (lo[:, None] + CUBE_CORNERS[None] * (hi - lo)[:, None]).reshape(-1, 3)
    t = (CUBE_FACES[None] + 8 * np.arange(len(lo))[:, None, None]).reshape(-1, 3)
    return v, t


def join(parts):
    vs, ts, offset = [], [], 0
    for v, t in parts:
        vs.append(v)
        ts.append(np.asarray(t) + offset)
        offset += len(v)
    return np.vstack(vs), np.vstack(ts)


def building(rng, scale=1.0, floors=10):
    """Ten floors (or `floors`) of 20 x 20 m: a slab, three outer walls, six inner walls across the
    floor, and furniture (tables as boxes, 1,280-triangle balls); the camera on the second floor
    (z = 4.5 m)."""
    size, h = 20.0, 3.0
    props = max(2, int(40 * scale))
    ball_v, ball_t = icosphere(3, dtype=np.float64)
    parts = []
    for k in range(floors):
        z = k * h
        lo = [(-size / 2, -size / 2, z - 0.2), (-size / 2 - 0.1, -size / 2, z), (size / 2 - 0.1, -size / 2, z),
              (-size / 2, size / 2 - 0.1, z)]
        hi = [(size / 2, size / 2, z), (-size / 2 + 0.1, size / 2, z + h - 0.2), (size / 2 + 0.1, size / 2, z + h - 0.2),
              (size / 2, size / 2 + 0.1, z + h - 0.2)]
        for i in range(6):
            x = rng.uniform(-size / 2, size / 2)
            across_x = i % 2 == 1
            lo.append((x - 0.05, -size / 2, z) if across_x else (-size / 2, x - 0.05, z))
            hi.append((x + 0.05, size / 2, z + h - 0.2) if across_x else (size / 2, x + 0.05, z + h - 0.2))
        for i in range(props):
            p = rng.uniform(-size / 2 + 1, size / 2 - 1, 2)
            if i % 2:
                parts.append((ball_v * 0.4 + (p[0], p[1], z + 0.5), ball_t))
            else:
                lo.append((p[0] - 0.5, p[1] - 0.3, z))
                hi.append((p[0] + 0.5, p[1] + 0.3, z + 0.8))
        parts.append(boxes(lo, hi))
    v, t = join(parts)
    return v, t, (0.0, -9.5, 4.5), (0.0, 5.0, 4.0)


def stacked_floors(rng, scale=1.0):
    """1,000 horizontal 2 x 2 quads at random heights (a stack of floors or shelves, nothing else)."""
    n = max(10, int(1000 * scale))
    z = rng.uniform(-1, 1, n)
    xy = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)
    v = np.zeros((n, 4, 3))
    v[:, :, :2] = xy
    v[:, :, 2] = z[:, None]
    k = 4 * np.arange(n)[:, None]
    t = np.concatenate([k + [0, 1, 2], k + [0, 2, 3]])
    return v.reshape(-1, 3), t, (3.0, -3.0, 2.0), (0.0, 0.0, 0.0)


def blind(rng, scale=1.0):
    """300 slats 2 m long, 10 cm deep and 2 mm thick, stacked 1 cm apart, seen from the front."""
    n = max(10, int(300 * scale))
    z = np.arange(n) * 0.01
    lo = np.stack([np.full(n, -1.0), np.full(n, -0.05), z], 1)
    hi = np.stack([np.full(n, 1.0), np.full(n, 0.05), z + 0.002], 1)
    v, t = boxes(lo, hi)
    return v, t, (0.3, -2.5, 2.0), (0.0, 0.0, 1.5)


def terrain(rng, scale=1.0):
    """A 300 x 300 heightfield (180,000 triangles) of 2 x 2 m, 0.6 m of relief."""
    k = max(8, int(300 * np.sqrt(scale)))
    x, y = np.meshgrid(np.linspace(-1, 1, k + 1), np.linspace(-1, 1, k + 1))
    z = 0.3 * np.sin(3 * x) * np.cos(4 * y) + 0.05 * rng.normal(size=x.shape)
    v = np.stack([x, y, z], -1).reshape(-1, 3)
    i = np.arange(k * (k + 1)).reshape(k, k + 1)[:, :k].ravel()
    t = np.concatenate([np.stack([i, i + 1, i + k + 2], 1), np.stack([i, i + k + 2, i + k + 1], 1)])
    return v, t, (0.0, -3.0, 1.5), (0.0, 0.0, 0.0)


def grass(rng, scale=1.0):
    """200,000 blades (one triangle each, 5-30 cm tall) on a 40 x 40 m plane."""
    n, size = max(100, int(200_000 * scale)), 20.0
    base = rng.uniform(-size / 2, size / 2, (n, 2))
    v = np.zeros((3 * n, 3))
    v[0::3, :2] = base
    v[1::3, :2] = base + [0.01, 0]
    v[2::3, :2] = base + rng.normal(0, 0.03, (n, 2))
    v[2::3, 2] = rng.uniform(0.05, 0.3, n)
    plane = np.array([[-size, -size, 0], [size, -size, 0], [size, size, 0], [-size, size, 0]], float)
    v, t = join([(v, np.arange(3 * n).reshape(-1, 3)), (plane, [[0, 1, 2], [0, 2, 3]])])
    return v, t, (0.0, -6.0, 1.5), (0.0, 0.0, 0.0)


def specks(rng, n, half, spread):
    """n triangles with a corner uniform in [-half, half]^3 and the others `spread` (a standard
    deviation) from it: (vertices, triangles)."""
    a = rng.uniform(-half, half, (n, 3))
    v = np.stack([a, a + rng.normal(0, spread, (n, 3)), a + rng.normal(0, spread, (n, 3))], 1).reshape(-1, 3)
    return v, np.arange(3 * n).reshape(-1, 3)


def soup(rng, scale=1.0):
    """200,000 small random triangles in a cube."""
    v, t = specks(rng, max(100, int(200_000 * scale)), 1.0, 0.02)
    return v, t, (3.0, -3.0, 2.0), (0.0, 0.0, 0.0)


def far_clusters(rng, scale=1.0):
    """50 clusters of 2,000 small triangles each, 1 m across, spread over 2 km."""
    k, per = 50, max(10, int(2000 * scale))
    parts = []
    for _ in range(k):
        v, t = specks(rng, per, 0.5, 0.01)
        parts.append((v + rng.uniform(-1000, 1000, 3), t))
    v, t = join(parts)
    return v, t, (0.0, -3000.0, 800.0), (0.0, 0.0, 0.0)


def slivers(rng, scale=1.0):
    """20,000 long thin triangles (about 1.6 m long, 2 mm wide) in random directions."""
    n = max(100, int(20_000 * scale))
    a = rng.uniform(-1, 1, (n, 3))
    v = np.stack([a, a + rng.normal(0, 1, (n, 3)), a + rng.normal(0, 0.002, (n, 3))], 1).reshape(-1, 3)
    return v, np.arange(3 * n).reshape(-1, 3), (3.0, -3.0, 2.0), (0.0, 0.0, 0.0)


def fan_disk(rng, scale=1.0):
    """A disk of 20,000 segments (10 m across) triangulated as a fan from its centre, as a large
    n-gon cap comes, with 50 boxes standing on it: every triangle meets the centre."""
    n = max(16, int(20_000 * scale))
    a = 2 * np.pi * np.arange(n) / n
    rim = np.stack([5 * np.cos(a), 5 * np.sin(a), np.zeros(n)], 1)
    disk_v = np.concatenate([[[0.0, 0.0, 0.0]], rim])
    disk_t = np.stack([np.zeros(n, int), 1 + np.arange(n), 1 + (np.arange(n) + 1) % n], 1)
    centres = rng.uniform(-3, 3, (50, 2))
    size = rng.uniform(0.1, 0.5, (50, 1))
    lo = np.concatenate([centres - size, np.zeros((50, 1))], 1)
    hi = np.concatenate([centres + size, 2 * size], 1)
    v, t = join([(disk_v, disk_t), boxes(lo, hi)])
    return v, t, (0.0, -8.0, 5.0), (0.0, 0.0, 0.0)


def tilted_stack(rng, scale=1.0):
    """1,000 parallel 2 x 2 quads tilted 45 degrees about x, 2 mm apart along their normal (a stack
    no axis-aligned cut separates: each spans the scene's box on every axis)."""
    n = max(10, int(1000 * scale))
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    turned = corners @ np.array([[1, 0, 0], [0, c, s], [0, -s, c]])
    normal = np.array([0.0, -s, c])
    v = turned[None] + (0.002 * np.arange(n))[:, None, None] * normal
    k = 4 * np.arange(n)[:, None]
    t = np.concatenate([k + [0, 1, 2], k + [0, 2, 3]])
    return v.reshape(-1, 3), t, (3.0, -3.0, 2.0), (0.0, 0.0, 0.0)


def big_triangles(rng, scale=1.0):
    """1,000 triangles with corners uniform in a 2 m cube, crossing each other (large panels or
    cards at random angles: each spans most of the scene on every axis)."""
    n = max(10, int(1000 * scale))
    return rng.uniform(-1, 1, (3 * n, 3)), np.arange(3 * n).reshape(-1, 3), (3.0, -3.0, 2.0), (0.0, 0.0, 0.0)


def far_terrain(rng, scale=1.0):
    """terrain()'s 2 m heightfield 1e5 from the origin, where floats are 0.008 apart: a scene a few
    dozen coordinate paddings across (the uniform grid serves it)."""
    v, t, eye, target = terrain(rng, scale)
    at = np.array([1e5, -7e4, 3e4])
    return v + at, t, tuple(np.add(eye, at)), tuple(np.add(target, at))


def camera_test(make, n, spread, seed):
    """The layout `make` as a gridwalk Scene (its documented size), with n rays from its eye towards
    its target, each direction moved by up to `spread` per axis: (scene, origins, directions)."""
    import gridwalk as gw

    v, t, eye, target = make(np.random.default_rng(0))
    scene = gw.Scene(vertices=v.astype(np.float32), triangles=t.astype(np.int32))
    rng = np.random.default_rng(seed)
    o = np.tile(np.float32(eye), (n, 1))
    d = (rng.uniform(-spread, spread, (n, 3)) + np.subtract(target, eye)).astype(np.float32)
    return scene, o, d


LAYOUTS = {"building": ("A building: 10 floors, walls, furniture", building),
           "stacked_floors": ("1,000 stacked floor quads", stacked_floors),
           "blind": ("A blind of 300 slats", blind),
           "terrain": ("A 300 x 300 terrain", terrain),
           "grass": ("200k grass blades on a plane", grass),
           "soup": ("200k random small triangles", soup),
           "far_clusters": ("50 clusters 2 km apart", far_clusters),
           "slivers": ("20k long thin slivers", slivers),
           "fan_disk": ("A 20,000-gon disk as a fan, 50 boxes", fan_disk),
           "tilted_stack": ("1,000 quads stacked at 45 degrees", tilted_stack),
           "big_triangles": ("1,000 big triangles crossing", big_triangles),
           "far_terrain": ("A 2 m terrain 1e5 from the origin", far_terrain)}
