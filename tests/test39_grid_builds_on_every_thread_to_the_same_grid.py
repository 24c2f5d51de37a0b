"""The adaptive grid builds the root's refined cells on several threads
(RenderSettings.threads, at most the machine's cores), each as a structure of
its own copied into the whole in cell order, and finds the cells of a large
root's primitives in parts on those threads: the grid is the same for any
number of threads. Checked on layouts whose refined cells differ a lot in
size (a dense cluster on a large floor, many small clusters, one primitive
far away): the same counts of grids, cells and references, and every ray
visits the same cells, runs the same tests and finds the same hit."""
import os

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls

CORES = os.cpu_count() or 1


def cluster_on_floor(rng):
    floor = np.array([[[-50, -50, 0], [50, -50, 0], [50, 50, 0]], [[-50, -50, 0], [50, 50, 0], [-50, 50, 0]]])
    blob = rng.normal(0, 0.3, (20000, 1, 3)) + rng.normal(0, 0.01, (20000, 3, 3)) + [0, 0, 1]
    return np.concatenate([floor, blob])


def many_clusters(rng):
    # (40,000 triangles: enough for the root's cells to be found by several threads too)
    centres = rng.uniform(0, 20, (40, 1, 1, 3))
    return (centres + rng.normal(0, 0.2, (40, 1000, 1, 3)) + rng.normal(0, 0.02, (40, 1000, 3, 3))).reshape(-1, 3, 3)


def far_primitive(rng):
    near = rng.normal(0, 0.1, (8000, 1, 3)) + rng.normal(0, 0.005, (8000, 3, 3))
    return np.concatenate([near, [[[1e4, 0, 0], [1e4, 1, 0], [1e4, 0, 1]]]])


def triangle_scene(tris):
    V = np.asarray(tris, np.float64).reshape(-1, 3).astype(np.float32)
    return {"vertices": V, "triangles": np.arange(len(V), dtype=np.int32).reshape(-1, 3)}


def aim_points(kw, rng, n):
    """n points of the scene's primitives (triangles' centroids, spheres' centres), to aim rays at."""
    points = [np.asarray(kw["vertices"], np.float32)[np.asarray(kw["triangles"])].mean(1)]
    if kw.get("sphere_centers") is not None:
        points.append(np.asarray(kw["sphere_centers"], np.float32))
    points = np.concatenate(points)
    return points[rng.integers(0, len(points), n)]


LAYOUTS = {
    "cluster on a floor": lambda rng: triangle_scene(cluster_on_floor(rng)),
    "many clusters": lambda rng: triangle_scene(many_clusters(rng)),
    "one primitive far away": lambda rng: triangle_scene(far_primitive(rng)),
    "SPD balls, analytic spheres": lambda rng: balls(3),
}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_grid_does_not_depend_on_the_threads_that_build_it(layout):
    rng = np.random.default_rng(7)
    kw = LAYOUTS[layout](rng)
    threads = [1, 2, 4]
    scenes = [gw.Scene(**kw) for _ in threads]   # (one structure per Scene: its cache ignores threads)
    infos = [sc.grid_info(gw.RenderSettings(threads=t)) for sc, t in zip(scenes, threads)]
    for t, info in zip(threads, infos):
        # (at most the threads asked for and the cores; fewer where there are fewer cells to share)
        assert 1 <= info["build_threads"] <= min(t, CORES), (t, info)
        assert info["build_threads"] >= min(t, CORES, 2), (t, info)   # several threads took part
        for key in ("grids", "cells", "refs", "bytes", "resolution"):
            assert info[key] == infos[0][key], (layout, t, key, info[key], infos[0][key])
    assert infos[0]["grids"] >= 4, infos[0]   # refined: the threads had cells to share
    lo, hi = scenes[0].bounds
    pad = 0.1 * (hi - lo) + 1e-3
    o = rng.uniform(lo - pad, hi + pad, (20000, 3)).astype(np.float32)
    d = (aim_points(kw, rng, 20000) - o).astype(np.float32)   # most rays hit something
    one = gw.RenderSettings(threads=1)
    hits = [sc.intersect(o, d, settings=one) for sc in scenes]
    assert np.isfinite(hits[0].t).sum() > 1000, layout
    for h in hits[1:]:
        assert np.array_equal(h.t, hits[0].t) and np.array_equal(h.prim, hits[0].prim), layout
        assert h.stats["cells"] == hits[0].stats["cells"], layout
        assert h.stats["prim_tests"] == hits[0].stats["prim_tests"], layout


def test_a_parallel_build_agrees_with_brute_force():
    rng = np.random.default_rng(8)
    sc = gw.Scene(**triangle_scene(cluster_on_floor(rng)))
    assert min(CORES, 2) <= sc.grid_info(gw.RenderSettings(threads=0))["build_threads"] <= CORES
    o = rng.uniform([-5, -5, 0.01], [5, 5, 4], (5000, 3)).astype(np.float32)
    d = rng.normal(size=(5000, 3)).astype(np.float32)
    got = sc.intersect(o, d, settings=gw.RenderSettings(threads=1))
    want = sc.intersect(o, d, settings=gw.RenderSettings(accel="none", threads=1))
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    assert np.isfinite(got.t).sum() > 1000
