"""Grids whose cells and lists outgrow the caches (8 MiB and more: AdaptiveGridData::kPrefetchBytes)
walk with the next cell's list asked for ahead (adaptive_walk.inc). The walk must still find what
brute force finds, for closest hits and shadow rays, on rays crossing many leaves, and on rays
that end in the grid's last cells (where the next cell would lie outside the node)."""
import numpy as np

import gridwalk as gw


def soup(rng, n):
    a = rng.uniform(-1, 1, (n, 1, 3))
    return (a + rng.normal(0, 0.01, (n, 3, 3))).reshape(-1, 3).astype(np.float32)


def test_a_grid_larger_than_the_caches_agrees_with_brute_force():
    rng = np.random.default_rng(62)
    v = soup(rng, 400_000)
    sc = gw.Scene(vertices=v, triangles=np.arange(len(v), dtype=np.int32).reshape(-1, 3))
    assert sc.grid_info()["bytes"] >= 8 << 20   # (the size where the walk prefetches)
    n = 600
    o = rng.uniform(-1.05, 1.05, (n, 3)).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    # Rays along the box's faces and out through its corners: the next cell beyond the last.
    o[:100] = np.float32([-1.04, -1.04, -1.04]) + rng.uniform(0, 0.02, (100, 3)).astype(np.float32)
    d[:100] = np.float32([1, 1, 1]) + rng.normal(0, 0.01, (100, 3)).astype(np.float32)
    got = sc.intersect(o, d)
    want = sc.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert np.isfinite(want.t).mean() > 0.5
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    tmax = np.where(np.isfinite(want.t), want.t * 1.5, 3.0).astype(np.float32)
    assert np.array_equal(sc.occluded(o, d, tmax=tmax), sc.occluded(o, d, tmax=tmax,
                                                                     settings=gw.RenderSettings(accel="none")))
