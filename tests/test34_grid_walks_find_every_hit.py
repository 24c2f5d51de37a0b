"""Both grids' walks find exactly brute force's hits where their rounding is hardest: far from
the origin (a cell face rounded to float there can be off by most of a cell: the adaptive grid
once ended a child grid's part of the ray before the cell holding the hit, and the uniform grid
left cells early, missing 175 of 4000 rays in a sphere 1e5 away), and, for the adaptive grid,
where an empty box reaches past a child grid's side (its exit lies beyond the child, where the
parent grid still has cells to visit), found in review of the empty boxes (core/src/empty_box.h);
and for rays from far away, whose float t are too coarse to walk a fine grid with."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import distant
from meshes import uv_sphere


def settings(**kw):
    return gw.RenderSettings(threads=1, **kw)


# Brute force's answers do not depend on the thread count: its references use every core.
BRUTE = gw.RenderSettings(accel="none")


def assert_same_as_brute_force(sc, o, d, accel="adaptive", **kw):
    want = sc.intersect(o, d, settings=BRUTE)
    got = sc.intersect(o, d, settings=settings(accel=accel, **kw))
    assert np.array_equal(np.isfinite(got.t), np.isfinite(want.t)), \
        f"{int(np.sum(np.isfinite(got.t) != np.isfinite(want.t)))} of {len(o)} rays hit in one and miss in the other"
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    occluded = np.asarray(sc.occluded(o, d, settings=settings(accel=accel, **kw)))
    assert np.array_equal(occluded, np.asarray(sc.occluded(o, d, settings=BRUTE)))


@pytest.mark.parametrize("offset, radius, rings", [(1e5, 0.1, 96), (1e6, 0.5, 96), (3e6, 2.0, 24), (1e5, 2.0, 48)])
@pytest.mark.parametrize("skip_empty", [True, False])
@pytest.mark.parametrize("accel", ["adaptive", "grid"])
def test_rays_inside_a_sphere_far_from_the_origin_hit_what_brute_force_hits(offset, radius, rings, skip_empty, accel):
    # Before the cell faces were located in double, 1-3% of these rays missed (16-294 of 4000).
    # The first three spheres span only 16-26 float spacings: "adaptive" builds the uniform grid
    # for them (see the test below). The last one, 500 spacings across, gets a refined adaptive grid.
    rng = np.random.default_rng(int(offset) % 1000 + rings)
    V, F = uv_sphere(rings, 2 * rings, radius=radius, center=np.array([offset, -offset, offset]), seed=1)
    sc = gw.Scene(vertices=V, triangles=F)
    if accel == "adaptive" and radius == 2.0 and offset == 1e5:
        info = sc.grid_info(settings(accel=accel))
        assert info["kind"] == "adaptive grid" and info["grids"] > 1, info
    n = 4000
    o = (V.astype(np.float64).mean(0) + rng.normal(0, 0.2 * radius, (n, 3))).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    assert_same_as_brute_force(sc, o, d, accel, skip_empty=skip_empty)



def test_a_scene_a_few_float_spacings_across_gets_a_grid_that_separates_its_primitives():
    # A 0.2-wide sphere 1e5 from the origin, where floats are 0.0078 apart: the adaptive grid's
    # cells are padded by a few spacings, so no resolution kept its references bounded and its root
    # stayed one cell of all 36,864 triangles (every ray tested every one). The uniform grid is
    # built instead, says so, and still answers as brute force does.
    V, F = uv_sphere(96, 192, radius=0.1, center=np.array([1e5, -1e5, 1e5]), seed=1)
    sc = gw.Scene(vertices=V, triangles=F)
    info = sc.grid_info(settings(accel="adaptive"))
    assert info["kind"] == "uniform grid" and "too few for the adaptive grid" in info["note"], info
    rng = np.random.default_rng(2)
    o = (V.astype(np.float64).mean(0) + rng.normal(0, 0.02, (2000, 3))).astype(np.float32)
    d = rng.normal(size=(2000, 3)).astype(np.float32)
    hits = sc.intersect(o, d, settings=settings(accel="adaptive"))
    assert hits.stats["prim_tests"] / len(o) < 200, hits.stats
    assert_same_as_brute_force(sc, o, d, "adaptive")


def test_a_terrain_a_few_float_spacings_across_gets_the_uniform_grid_even_where_its_root_refines():
    # A 2 m terrain of 20,000 triangles 1e5 from the origin (41 paddings across): the adaptive grid
    # refined its root, so the rule above (then for one-cell roots only) passed it over, and its
    # leaves held hundreds of triangles (270-570 tests a ray in a review probe; at 1e6, thousands).
    k = 100
    x, y = np.meshgrid(np.linspace(-1, 1, k + 1), np.linspace(-1, 1, k + 1))
    z = 0.3 * np.sin(3 * x) * np.cos(4 * y)
    V = (np.stack([x, y, z], -1).reshape(-1, 3) + [1e5, -7e4, 3e4]).astype(np.float32)
    i = np.arange(k * (k + 1)).reshape(k, k + 1)[:, :k].ravel()
    F = np.concatenate([np.stack([i, i + 1, i + k + 2], 1), np.stack([i, i + k + 2, i + k + 1], 1)]).astype(np.int32)
    sc = gw.Scene(vertices=V, triangles=F)
    info = sc.grid_info(settings(accel="adaptive"))
    assert info["kind"] == "uniform grid" and "too few for the adaptive grid" in info["note"], info
    rng = np.random.default_rng(5)
    o = np.tile([1e5, -7e4 - 3.0, 3e4 + 1.5], (2000, 1)).astype(np.float32)
    d = (np.array([0.0, 3.0, -1.5]) + rng.uniform(-1, 1, (2000, 3))).astype(np.float32)
    hits = sc.intersect(o, d, settings=settings(accel="adaptive"))
    assert (hits.kind > 0).mean() > 0.3 and hits.stats["prim_tests"] / len(o) < 60, hits.stats
    assert_same_as_brute_force(sc, o, d, "adaptive")


def test_a_scene_of_a_few_primitives_keeps_its_one_cell_adaptive_grid():
    # One cell is the right structure for a handful of primitives (brute force in all but name),
    # near the origin (Distant) and as narrow in float spacings as the sphere above.
    sc = gw.Scene(**distant())
    info = sc.grid_info(settings(accel="adaptive"))
    assert info["kind"] == "adaptive grid" and info["cells"] == 1, info
    rng = np.random.default_rng(4)
    leaf = gw.RenderSettings().leaf_size
    specks = (np.array([1e5, -1e5, 1e5]) + rng.uniform(-0.1, 0.1, (2 * leaf, 1, 3))
              + rng.normal(0, 0.01, (2 * leaf, 3, 3))).astype(np.float32).reshape(-1, 3)
    sc = gw.Scene(vertices=specks, triangles=np.arange(len(specks), dtype=np.int32).reshape(-1, 3))
    info = sc.grid_info(settings(accel="adaptive"))
    assert info["kind"] == "adaptive grid" and info["cells"] == 1, info

def test_a_box_reaching_past_a_child_grid_does_not_end_the_walk():
    # A tube of tiny triangles along y = z = 20 gets a child grid; rays run down the tube, leave
    # the child through an empty box that reaches its side, and must still find the small
    # triangle across the tube (in the parent's next cell) before the wall that spans the scene.
    # Ending the walk at the box's exit, beyond the child, got 1705 of these 24000 rays wrong.
    rng = np.random.default_rng(0)
    for _ in range(6):
        specks = rng.uniform(0, 40, (1500, 3))
        specks = specks[(np.abs(specks[:, 1] - 20) > 3) | (np.abs(specks[:, 2] - 20) > 3)]
        tris = list(specks[:, None, :] + rng.normal(0, 0.05, (len(specks), 3, 3)))
        cx = rng.uniform(8, 12)
        ang, rad = rng.uniform(0, 2 * np.pi, 3000), rng.uniform(0.3, 0.6, 3000)
        tube = np.stack([cx + rng.uniform(0, 0.8, 3000), 20 + rad * np.cos(ang), 20 + rad * np.sin(ang)], -1)
        tris += list(tube[:, None, :] + rng.normal(0, 0.01, (3000, 3, 3)))
        x1 = cx + rng.uniform(2, 6)
        x2 = cx + rng.uniform(0.9, x1 - cx)
        tris.append([[x1, 0, 0], [x1, 80, 0], [x1, 0, 80]])                   # the wall
        tris.append([[x2, 19, 19], [x2 + 0.01, 21.5, 19], [x2, 19, 21.5]])    # the small triangle
        V = np.asarray(tris, np.float32).reshape(-1, 3)
        sc = gw.Scene(vertices=V, triangles=np.arange(len(V), dtype=np.int32).reshape(-1, 3))
        assert sc.grid_info(settings(accel="adaptive"))["grids"] > 1
        n = 2000
        o = np.stack([np.full(n, cx - 3), 20 + rng.normal(0, 0.05, n), 20 + rng.normal(0, 0.05, n)], -1)
        d = np.stack([np.ones(n), rng.normal(0, 2e-3, n), rng.normal(0, 2e-3, n)], -1)
        assert_same_as_brute_force(sc, o.astype(np.float32), d.astype(np.float32))


@pytest.mark.parametrize("accel", ["adaptive", "grid"])
def test_features_smaller_than_the_coordinates_spacing_are_found(accel):
    # Triangles 5e-5 across around x = 1000, where floats are 6e-5 apart, and rays from 1e-3 away.
    rng = np.random.default_rng(1)
    c = rng.random((200, 3)).astype(np.float32)
    t = ((c[:, None, :] + rng.normal(0, 0.05, (200, 3, 3))) * 1e-3 + 1000).astype(np.float32)
    sc = gw.Scene(vertices=t.reshape(-1, 3), triangles=np.arange(600, dtype=np.int32).reshape(-1, 3))
    target = t.mean(1)[rng.integers(200, size=3000)]
    o = (target + rng.normal(size=(3000, 3)) * 1e-3).astype(np.float32)
    assert_same_as_brute_force(sc, o, (target - o).astype(np.float32), accel)


def distance_in_double(o, d, tri):
    """How far the line o + s d passes from triangle tri (3 x 3), in double: 0 where it crosses
    the triangle, else its distance to the nearest edge."""
    o, d, tri = (np.asarray(x, np.float64) for x in (o, d, tri))
    a, b, c = tri
    e1, e2 = b - a, c - a
    p = np.cross(d, e2)
    det = e1 @ p
    if det != 0:
        u = (o - a) @ p / det
        w = d @ np.cross(o - a, e1) / det
        if u >= 0 and w >= 0 and u + w <= 1:
            return 0.0
    best = np.inf
    for s0, s1 in ((a, b), (b, c), (c, a)):
        e = s1 - s0
        n = np.cross(d, e)
        if n @ n == 0:                        # parallel: the distance from s0 to the line
            r = s0 - o
            best = min(best, np.linalg.norm(r - (r @ d) / (d @ d) * d))
            continue
        # The closest points of the two lines; the segment's clamped to its ends.
        r = s0 - o
        u = np.clip(np.cross(d, r) @ n / -(n @ n), 0.0, 1.0)
        q = s0 + u * e - o
        best = min(best, np.linalg.norm(q - (q @ d) / (d @ d) * d))
    return float(best)


@pytest.fixture(scope="module")
def far_away_case():
    """Specks in a unit cube and 16,000 rays from far away, with brute force's
    answers (computed once for both structures)."""
    rng = np.random.default_rng(5)
    n = 50000
    v = (rng.uniform(0, 1, (n, 1, 3)) + rng.normal(0, 0.005, (n, 3, 3))).reshape(-1, 3).astype(np.float32)
    t = np.arange(3 * n, dtype=np.int32).reshape(-1, 3)
    sc = gw.Scene(vertices=v, triangles=t)
    m = 16000
    w = rng.dirichlet([1, 1, 1], m)
    edge = rng.random(m) < 0.7
    w[edge, rng.integers(0, 3, int(edge.sum()))] = 0
    w /= w.sum(1, keepdims=True)
    target = np.einsum("nk,nkj->nj", w, v[t[rng.integers(0, n, m)]].astype(np.float64))
    away = rng.normal(size=(m, 3))
    away *= 10 ** rng.uniform(4, 4.7, (m, 1)) / np.linalg.norm(away, axis=1, keepdims=True)
    o = (target + away).astype(np.float32)
    d = (target - o).astype(np.float32)
    return v, t, sc, o, d, sc.intersect(o, d, settings=BRUTE), np.asarray(sc.occluded(o, d, settings=BRUTE))


@pytest.mark.parametrize("accel", ["adaptive", "grid"])
def test_rays_from_far_away_find_what_brute_force_finds(accel, far_away_case):
    # Specks in a unit cube, rays from 1e4-5e4 cube sizes away aimed at points on their edges (and
    # inside them). A float t there is coarse: one step moves the ray by 2^-24 of its distance,
    # up to a tenth of a fine cell, far more than the cells' padding, and a walk with float
    # parameters stepped through the wrong cells: 40 of these 16,000 rays got another hit than
    # brute force's (25 of them none), and 25 occlusion queries answered wrongly, in the adaptive
    # grid; the uniform grid's float walk got 666 wrong. Both walks' parameters are doubles.
    # At these distances the triangle test's own rounding, that of the origin's coordinates,
    # reaches a tenth of a speck: brute force itself can report a speck that the ray passes
    # (nearly edge-on) far from, in no cell the ray crosses. Such a ray is excused (one of the
    # 16,000, for the uniform grid; 0-3 with other seeds, for either grid).
    v, t, sc, o, d, want, brute = far_away_case
    m = len(o)
    got = sc.intersect(o, d, settings=settings(accel=accel))
    differ = np.flatnonzero((got.t != want.t) | (got.prim != want.prim))
    assert len(differ) <= 4, f"{len(differ)} of {m} rays got another hit than brute force's"
    # Excused: brute force's triangle lies farther from the ray (in double) than any cell's
    # padding (a thousandth of a cell, cells below 0.03 here), so no walk visits a cell listing it.
    excused = [i for i in differ if want.prim[i] >= 0 and distance_in_double(o[i], d[i], v[t[want.prim[i]]]) > 1e-4]
    assert list(differ) == excused, f"rays {sorted(set(differ) - set(excused))} got another hit than brute force's"
    occluded = np.asarray(sc.occluded(o, d, settings=settings(accel=accel)))
    assert np.array_equal(np.delete(occluded, excused), np.delete(brute, excused))


@pytest.mark.parametrize("offset", [0.0, 1000.0])
@pytest.mark.parametrize("accel", ["adaptive", "grid"])
def test_a_hit_just_before_tmax_near_the_origin_is_found(accel, offset):
    """Rays from 1e-6 - 1e-2 above or below a floor of 2,000 small triangles in a cluster (refined
    cells; the child grids are flat), with tmax just past the hit brute force finds. The float
    triangle test rounds t by an amount relative to the triangle's size, not to t: near the
    origin that puts the hit before the plane's exact crossing, and a child box padded by its
    own thickness ended the walk there (76 of about 10,000 hits were missed). 1000 from the
    origin the floor's box, padded in float, kept no pad (a review: 293 shadow queries)."""
    rng = np.random.default_rng(2)
    k = 2000
    c = rng.uniform(-0.05, 0.05, (k, 1, 2)) + rng.normal(0, 0.01, (k, 3, 2))
    small = np.concatenate([c, np.zeros((k, 3, 1))], 2).reshape(-1, 3)
    big = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    scale = 0.1 if offset else 1.0   # (far out, a smaller floor: its cluster's cells then refine)
    v = (scale * np.concatenate([small, big]) + offset).astype(np.float32)
    sc = gw.Scene(vertices=v, triangles=np.arange(len(v), dtype=np.int32).reshape(-1, 3))
    assert sc.grid_info(gw.RenderSettings(accel="adaptive"))["grids"] > 1    # (refined cells)
    m = 20000
    lowest = -6 if not offset else -4.2   # (1e-6 is below a float spacing at 1000)
    o = np.column_stack([scale * rng.uniform(-0.1, 0.1, (m, 2)), rng.choice([-1, 1], m) * 10 ** rng.uniform(lowest, -2, m)])
    o, d = (o + offset).astype(np.float32), rng.normal(size=(m, 3)).astype(np.float32)
    brute = gw.RenderSettings(accel="none")
    first = sc.intersect(o, d, settings=brute)
    hit = np.isfinite(first.t)
    assert hit.sum() > 5000
    tmax = np.where(hit, first.t * np.float32(1.0001), np.inf).astype(np.float32)
    got = sc.intersect(o, d, tmax=tmax, settings=gw.RenderSettings(accel=accel))
    want = sc.intersect(o, d, tmax=tmax, settings=brute)
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    assert np.array_equal(sc.occluded(o, d, tmax=tmax, settings=gw.RenderSettings(accel=accel)),
                          sc.occluded(o, d, tmax=tmax, settings=brute))
