"""The adaptive grid lists a primitive only in the cells it meets (a separating-axis test of
the triangle, the distance of a sphere's centre), not in every cell its bounding box overlaps:
a sloped or diagonal triangle's box holds many cells it never enters, and rays crossing those
cells would test it for nothing. The listing must lose no hit (brute force decides, including
rays that graze the primitives and rays along cell faces) and must be exact enough that rays away
from the primitives test nothing (the test counts say so)."""
import numpy as np
import pytest

import gridwalk as gw


def settings(**kw):
    return gw.RenderSettings(threads=1, **kw)


def diagonal_slivers(rng, n=60):
    """n thin triangles, each along the whole diagonal of the unit cube (their bounding boxes are
    the whole cube), a little apart; and 4000 specks in the cube, so that the grid is fine."""
    a = rng.normal(0, 2e-3, (n, 3))
    tri = np.stack([a, a + 1.0, a + 1.0 + rng.normal(0, 5e-3, (n, 3))], 1)
    specks = rng.uniform(0, 1, (4000, 1, 3)) + rng.normal(0, 4e-3, (4000, 3, 3))
    v = np.vstack([tri.reshape(-1, 3), specks.reshape(-1, 3)]).astype(np.float32)
    return v, np.arange(len(v)).reshape(-1, 3)


def brute_force_agrees(sc, o, d, spawned=False):
    got = sc.intersect(o, d, spawned=spawned, settings=settings())
    want = sc.intersect(o, d, spawned=spawned, settings=gw.RenderSettings(accel="none"))
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    occ = sc.occluded(o, d, spawned=spawned, settings=settings())
    assert np.array_equal(occ, sc.occluded(o, d, spawned=spawned, settings=gw.RenderSettings(accel="none")))
    return got


@pytest.mark.parametrize("seed", [1, 2])
def test_rays_near_and_along_diagonal_triangles_find_brute_force_hits(seed):
    rng = np.random.default_rng(seed)
    v, t = diagonal_slivers(rng)
    sc = gw.Scene(vertices=v, triangles=t)
    n = 4000
    # Rays aimed at points of the slivers (their edges and corners included), rays along the
    # diagonal beside them, and random rays.
    k = rng.integers(0, 60, n)
    w = rng.dirichlet([1, 1, 1], n) * np.where(rng.random((n, 1)) < 0.3, rng.random((n, 3)) < 0.5, 1)
    w /= np.maximum(w.sum(1, keepdims=True), 1e-12)
    target = np.einsum("nk,nkj->nj", w, v[t[k]])
    o = target + rng.normal(size=(n, 3)) * 2
    along = rng.normal(0, 3e-3, (n, 3)) - 0.5
    o = np.vstack([o, along, rng.uniform(-0.2, 1.2, (n, 3))]).astype(np.float32)
    d = np.vstack([target - o[:n], np.ones((n, 3)) + rng.normal(0, 1e-4, (n, 3)), rng.normal(size=(n, 3))])
    got = brute_force_agrees(sc, o, d.astype(np.float32))
    assert np.isfinite(got.t[:n]).mean() > 0.9   # (the aimed rays do reach the slivers)


def test_rays_away_from_diagonal_triangles_do_not_test_them():
    rng = np.random.default_rng(3)
    v, t = diagonal_slivers(rng)
    sc = gw.Scene(vertices=v, triangles=t)
    # Rays across the cube in a plane x + y + z = const far from the diagonal's points on it
    # (the diagonal crosses that plane at (c, c, c); these rays pass at least 0.3 from it).
    n = 2000
    c = rng.uniform(0.3, 0.7, n)
    u = np.array([1, -1, 0]) / np.sqrt(2)
    w = np.array([1, 1, -2]) / np.sqrt(6)
    ang = rng.uniform(0, 2 * np.pi, n)
    off = 0.35 * (np.cos(ang)[:, None] * u + np.sin(ang)[:, None] * w)
    o = (c[:, None] + off - 2 * u).astype(np.float32)
    d = np.tile(u, (n, 1)).astype(np.float32)
    # Keep the rays whose closest approach to the diagonal line stays above 0.3.
    p = o.astype(np.float64)
    s = -np.einsum("ij,ij->i", p - c[:, None], d)
    closest = p + s[:, None] * d - c[:, None]
    keep = np.linalg.norm(closest, axis=1) > 0.3
    o, d = o[keep], d[keep]
    hits = brute_force_agrees(sc, o, d)
    slivers = hits.prim[np.isfinite(hits.t)] < 60
    assert not slivers.any()
    # The 60 slivers' boxes cover every cell; listed by box, every cell such a ray crosses would
    # hold the 44 that are not in the grid's list of large primitives (16 at most). Listed where
    # they are, the rays test the specks, as without the slivers, and at most that list.
    specks = gw.Scene(vertices=v[180:], triangles=t[:-60])
    extra = (hits.stats["prim_tests"] - specks.intersect(o, d, settings=settings()).stats["prim_tests"]) / len(o)
    assert extra <= 16 + 2, extra


def test_rays_grazing_spheres_among_specks_find_brute_force_hits():
    # Spheres of many sizes among specks (so that cells are small beside some spheres and large
    # beside others); rays aimed just inside and just outside their silhouettes.
    rng = np.random.default_rng(4)
    centers = rng.uniform(0, 10, (300, 3))
    radii = rng.uniform(0.05, 1.5, 300)
    specks = rng.uniform(0, 10, (6000, 1, 3)) + rng.normal(0, 0.01, (6000, 3, 3))
    sc = gw.Scene(sphere_centers=centers, sphere_radii=radii,
                  vertices=specks.reshape(-1, 3).astype(np.float32), triangles=np.arange(18000).reshape(-1, 3))
    n = 4000
    i = rng.integers(0, 300, n)
    o = rng.uniform(-5, 15, (n, 3))
    to_c = centers[i] - o
    dist = np.linalg.norm(to_c, axis=1, keepdims=True)
    side = np.cross(to_c, rng.normal(size=(n, 3)))
    side /= np.linalg.norm(side, axis=1, keepdims=True)
    # A point at (1 +- 1e-3) radius from the centre, across the ray's line of sight.
    target = centers[i] + side * radii[i, None] * (1 + rng.choice([-1e-3, 1e-3, 0.0], (n, 1)))
    got = brute_force_agrees(sc, o.astype(np.float32), (target - o).astype(np.float32))
    assert (got.kind == 2).sum() > n // 4   # (many of them do hit spheres)
