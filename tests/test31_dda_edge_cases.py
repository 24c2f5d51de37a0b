"""Grid traversal edge cases: axis-parallel rays with +0/-0 components, origins
on cell boundaries and on the grid's faces and corners, rays grazing along
faces, degenerate scenes, huge extents with tiny triangles, and NaN/Inf rays.
In every case both grids (the seed's uniform grid and the adaptive grid, at
every level) must report exactly what brute force reports."""
import time

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls
from meshes import icosphere, random_rays


GRIDS = ("grid", "adaptive")


def assert_grid_equals_brute_force(sc, o, d, **kw):
    """Both grids against brute force; returns the uniform grid's hits."""
    n = sc.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    out = {}
    for accel in GRIDS:
        g = out[accel] = sc.intersect(o, d, settings=gw.RenderSettings(accel=accel, **kw))
        bad = (np.isfinite(g.t) != np.isfinite(n.t)) | (np.isfinite(n.t) & (g.t != n.t))
        assert not bad.any(), (f"{accel}: {bad.sum()} rays differ, e.g. o={o[bad][0]}, d={d[bad][0]}, "
                               f"{g.t[bad][0]} vs {n.t[bad][0]}")
    return out["grid"]


def cube_grid_scene():
    """A lattice of axis-aligned cubes: many faces lie exactly on cell boundaries."""
    V, F = [], []
    box = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32)
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    for i in range(4):
        for j in range(4):
            for k in range(2):
                F.append(faces + len(V) * 8)
                V.append(box + np.array([2 * i, 2 * j, 2 * k], np.float32))
    return gw.Scene(vertices=np.concatenate(V), triangles=np.concatenate(F).astype(np.int32))


def axis_rays(points):
    dirs = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            for zero in (0.0, -0.0):
                d = np.full(3, zero, np.float32)
                d[axis] = sign
                dirs.append(d)
    o = np.repeat(points, len(dirs), axis=0).astype(np.float32)
    d = np.tile(np.array(dirs), (len(points), 1)).astype(np.float32)
    return o, d


def test_axis_parallel_rays_with_signed_zeros():
    sc = cube_grid_scene()
    rng = np.random.default_rng(1)
    pts = np.concatenate([rng.uniform(-1, 8, (300, 3)),                         # anywhere
                          np.round(rng.uniform(-1, 8, (300, 3)) * 2) / 2])     # on faces, edges and corners
    o, d = axis_rays(pts)
    g = assert_grid_equals_brute_force(sc, o, d)
    assert np.isfinite(g.t).sum() > 500


def test_origins_on_cell_boundaries_and_grid_faces_and_corners():
    sc = cube_grid_scene()
    lo, hi = sc.bounds
    res = np.array(sc.grid_info(gw.RenderSettings(accel="grid"))["resolution"])
    ticks = [np.linspace(lo[a], hi[a], res[a] + 1) for a in range(3)]   # (about) the uniform grid's cell boundaries
    rng = np.random.default_rng(2)
    pts = np.stack([rng.choice(t, 2000) for t in ticks], -1)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    pts = np.concatenate([pts, corners])
    d = rng.normal(size=(len(pts), 3))
    assert_grid_equals_brute_force(sc, pts.astype(np.float32), d.astype(np.float32))
    o, d = axis_rays(pts[:300])
    assert_grid_equals_brute_force(sc, o, d)


def test_rays_grazing_along_faces():
    sc = cube_grid_scene()
    rng = np.random.default_rng(3)
    n = 20000
    o = rng.uniform(-1, 8, (n, 3))
    o[:, 2] = rng.choice([0.0, 1.0, 2.0, 3.0], n)      # in the planes of the cubes' top/bottom faces
    d = rng.normal(size=(n, 3))
    d[:, 2] = 0.0
    assert_grid_equals_brute_force(sc, o.astype(np.float32), d.astype(np.float32))


def test_one_primitive_and_all_primitives_in_one_cell():
    one = gw.Scene(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]])
    assert one.grid_info()["cells"] >= 1
    o, d = random_rays(5000, [0, 0, 0], [1, 1, 0], seed=4)
    assert_grid_equals_brute_force(one, o, d)
    single_sphere = gw.Scene(sphere_centers=[[3, 3, 3]], sphere_radii=[0.0])   # zero radius: a point
    assert_grid_equals_brute_force(single_sphere, o, d)
    rng = np.random.default_rng(5)
    cluster = rng.normal(0, 1e-3, (3000, 3))
    V = np.concatenate([cluster, [[100, 100, 100], [101, 100, 100], [100, 101, 100]]]).astype(np.float32)
    F = np.arange(len(V), dtype=np.int32).reshape(-1, 3)
    sc = gw.Scene(vertices=V, triangles=F)
    o, d = random_rays(20000, [-0.01] * 3, [0.01] * 3, seed=6)
    assert_grid_equals_brute_force(sc, o, d)


def test_duplicate_and_zero_area_triangles():
    V, F = icosphere(2)
    points = np.repeat(V[:5], 3, axis=0)                       # three identical vertices: zero area
    line = np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2]], np.float32)   # collinear: zero area
    V2 = np.concatenate([V, points, line]).astype(np.float32)
    extra = np.arange(len(V), len(V2), dtype=np.int32).reshape(-1, 3)
    F2 = np.concatenate([F, F[:50], extra])                    # 50 duplicated triangles
    sc = gw.Scene(vertices=V2, triangles=F2)
    o, d = random_rays(30000, [-1.2] * 3, [1.2] * 3, seed=7)
    g = assert_grid_equals_brute_force(sc, o, d)
    assert np.isfinite(g.t).sum() > 1000


def test_huge_extent_with_tiny_triangles():
    # Tiny triangles (1e-4) where float32 can still resolve them, inside a
    # scene whose extent (1e6) makes every grid cell enormous next to them.
    rng = np.random.default_rng(8)
    n = 4000
    c = rng.uniform(-10, 10, (n, 1, 3))
    V = (c + rng.normal(0, 1e-4, (n, 3, 3))).reshape(-1, 3).astype(np.float32)
    V = np.concatenate([V, [[-1e6, -1e6, 0], [1e6, -1e6, 0], [0, 1e6, 0]]]).astype(np.float32)
    F = np.arange(len(V), dtype=np.int32).reshape(-1, 3)
    sc = gw.Scene(vertices=V, triangles=F)
    # Aim rays straight at the tiny triangles (their centroids) from random far points.
    target = V[: 3 * n].reshape(n, 3, 3).mean(1)
    o = rng.uniform(-100, 100, (n, 3))
    g = assert_grid_equals_brute_force(sc, o.astype(np.float32), (target - o).astype(np.float32))
    assert np.isfinite(g.t).sum() > 0.9 * n


def test_nan_and_inf_rays_are_misses_and_do_not_slow_the_batch():
    sc = gw.Scene(**balls(3))
    lo, hi = sc.bounds
    o, d = random_rays(200_000, lo, hi, seed=9)
    bad_o, bad_d = o.copy(), d.copy()
    k = np.arange(0, len(o), 7)
    bad_d[k[0::4], 0] = np.nan
    bad_o[k[1::4], 1] = np.inf
    bad_d[k[2::4]] = 0.0                         # zero direction
    bad_d[k[3::4], 2] = -np.inf
    t0 = time.perf_counter(); good = sc.intersect(o, d, settings=gw.RenderSettings(threads=1)); t_good = time.perf_counter() - t0
    t0 = time.perf_counter(); mixed = sc.intersect(bad_o, bad_d, settings=gw.RenderSettings(threads=1)); t_mixed = time.perf_counter() - t0
    assert not np.isfinite(mixed.t[k]).any() and np.all(mixed.prim[k] == -1) and np.all(mixed.kind[k] == 0)
    rest = np.setdiff1d(np.arange(len(o)), k)
    assert np.array_equal(mixed.t[rest], good.t[rest])
    assert t_mixed < 2.0 * t_good + 0.05
    nan_t = sc.intersect(o[:10], d[:10], tmin=np.nan)
    assert not np.isfinite(nan_t.t).any()
    assert sc.occluded(bad_o[k], bad_d[k]).sum() == 0
