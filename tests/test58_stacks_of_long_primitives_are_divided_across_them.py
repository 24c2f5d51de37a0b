"""Primitives long along some axes and stacked along another (a building's floors, shelves, the
slats of a blind, a row of walls) keep the adaptive grid fine: where cubic cells would list each
of them in a whole layer of cells, and the reference budget held the grid back to a few cells
(a stack of 1,000 floor quads was one cell of 2,000 triangles, 0.01x Embree's speed), the node is
divided only across the stack. The grid still agrees with brute force everywhere, and a terrain,
whose triangles cross any such layers, is not divided so."""
import sys
from pathlib import Path

import numpy as np
import pytest

import gridwalk as gw

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core" / "bench"))
from layout_scenes import camera_test, terrain  # noqa: E402  (the 300 x 300 terrain of docs/layouts.md)

ONE = gw.RenderSettings(threads=1)


def quads(corners):
    """Triangles of quads given as (n, 4, 3) corners."""
    n = len(corners)
    v = np.asarray(corners, np.float32).reshape(-1, 3)
    k = 4 * np.arange(n)[:, None]
    t = np.concatenate([k + [0, 1, 2], k + [0, 2, 3]])
    return v, t.astype(np.int32)


def floors(rng, n, tilt=0.0):
    """n 2 x 2 quads at random heights in [-1, 1], tilted by about `tilt`."""
    z = rng.uniform(-1, 1, n)
    s = rng.normal(0, tilt, (n, 2))
    xy = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)
    c = np.zeros((n, 4, 3))
    c[:, :, :2] = xy
    c[:, :, 2] = z[:, None] + xy[None, :, 0] * s[:, :1] + xy[None, :, 1] * s[:, 1:]
    return quads(c)


def walls(rng, n):
    """n quads x = const spanning y and z (a row of walls)."""
    x = rng.uniform(-1, 1, n)
    c = np.zeros((n, 4, 3))
    c[:, :, 0] = x[:, None]
    c[:, :, 1:] = [[-1, -1], [1, -1], [1, 1], [-1, 1]]
    return quads(c)


def slats(rng, n):
    """n thin boxes 2 long along x, stacked in z (a blind): long along one axis only."""
    z = np.sort(rng.uniform(-1, 1, n))
    lo = np.stack([np.full(n, -1.0), np.full(n, -0.05), z], 1)
    hi = np.stack([np.full(n, 1.0), np.full(n, 0.05), z + 0.002], 1)
    cube = np.array([[x, y, w] for w in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    v = (lo[:, None] + cube[None] * (hi - lo)[:, None]).reshape(-1, 3)
    f = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4], [2, 6, 3], [3, 6, 7],
                  [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    t = (f[None] + 8 * np.arange(n)[:, None, None]).reshape(-1, 3)
    return v.astype(np.float32), t.astype(np.int32)


def rays(rng, n, spread=1.2):
    o = rng.uniform(-spread, spread, (n, 3)).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    return o, d


def agrees_with_brute_force(sc, o, d):
    got = sc.intersect(o, d, settings=ONE)
    want = sc.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    assert np.array_equal(sc.occluded(o, d, tmax=np.full(len(o), 0.5, np.float32), settings=ONE),
                          sc.occluded(o, d, tmax=np.full(len(o), 0.5, np.float32),
                                      settings=gw.RenderSettings(accel="none")))
    assert np.isfinite(got.t).mean() > 0.15   # (the rays meet the primitives)
    return got.stats["prim_tests"] / len(o)


@pytest.mark.parametrize("layout, across", [("floors", 2), ("walls", 0), ("slats", 2)])
def test_a_stack_is_divided_across_it_and_agrees_with_brute_force(layout, across):
    rng = np.random.default_rng(7)
    v, t = {"floors": lambda: floors(rng, 1000), "walls": lambda: walls(rng, 1000),
            "slats": lambda: slats(rng, 300)}[layout]()
    sc = gw.Scene(vertices=v, triangles=t)
    res = sc.grid_info()["resolution"]
    assert res[across] >= 256, res
    long_axes = [a for a in range(3) if a != across and not (layout == "slats" and a == 1)]
    assert all(res[a] == 1 for a in long_axes), res
    o, d = rays(rng, 4000)
    tests = agrees_with_brute_force(sc, o, d)
    assert tests < 20, tests   # (one cell of every primitive before: 2,000 / 3,600 tests per ray)


def test_a_tilted_stack_tests_a_fraction_of_it_per_ray_and_agrees_with_brute_force():
    rng = np.random.default_rng(8)
    v, t = floors(rng, 500, tilt=0.05)
    sc = gw.Scene(vertices=v, triangles=t)
    o, d = rays(rng, 4000)
    tests = agrees_with_brute_force(sc, o, d)
    assert tests < 0.2 * len(t), tests   # (every one of the 1,000 triangles before)


def test_a_terrain_is_not_divided_into_layers_its_triangles_cross():
    # The small grids refining a heightfield are thin boxes its triangles
    # cross from bottom to top: layers across them would list each triangle in
    # every layer.
    sc, o, d = camera_test(terrain, 4000, 0.6, seed=10)
    got = sc.intersect(o, d, settings=ONE)
    assert np.isfinite(got.t).mean() > 0.7
    tests = got.stats["prim_tests"] / len(o)
    assert tests < 60, tests   # (31 here; 651 with layers taken)
    few = slice(0, 4000, 16)   # (brute force tests all 180,000 triangles per ray)
    want = sc.intersect(o[few], d[few], settings=gw.RenderSettings(accel="none"))
    assert np.array_equal(got.t[few], want.t) and np.array_equal(got.prim[few], want.prim)


def test_floors_in_one_thin_band_amid_clutter_are_not_layered():
    # 2,000 overlapping quads within 0.1% of the box's height among 20,000
    # small triangles filling it: layers would hold the band in one or two of
    # them while rays crossed hundreds of layers of clutter (249 cells per ray).
    rng = np.random.default_rng(11)
    k, m = 2000, 20000
    size = rng.uniform(0.6, 2, (k, 1, 1))
    centre = rng.uniform(-1, 1, (k, 1, 2)) * (2 - size) / 2
    c = np.zeros((k, 4, 3))
    c[:, :, :2] = centre + np.array([[-.5, -.5], [.5, -.5], [.5, .5], [-.5, .5]]) * size
    c[:, :, 2] = rng.uniform(-0.001, 0.001, (k, 1))
    v1, t1 = quads(c)
    a = rng.uniform(-1, 1, (m, 1, 3)) + rng.normal(0, 0.003, (m, 3, 3))
    v = np.concatenate([v1, a.reshape(-1, 3)]).astype(np.float32)
    t = np.concatenate([t1, np.arange(3 * m).reshape(m, 3) + len(v1)]).astype(np.int32)
    sc = gw.Scene(vertices=v, triangles=t)
    res = sc.grid_info()["resolution"]
    assert min(res) > 1, res
    o, d = rays(rng, 2000)
    agrees_with_brute_force(sc, o, d)
    cells = sc.intersect(o, d, settings=ONE).stats["cells"] / len(o)
    assert cells < 180, cells   # (109: the band's own cells are layered, not the clutter's)
