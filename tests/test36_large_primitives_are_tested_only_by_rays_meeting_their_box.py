"""The adaptive grid's large primitives (a floor, the glass spheres over SPD's mountain: those
covering many cells of a grid, kept in a list the walk tests when a ray enters the grid) sit
behind their box: shadow rays that miss it, and closest-hit rays where the list is costly to test
(a quadric or more than 4 triangles in a box small beside the grid), skip them. The skip must lose
no hit (brute force decides) and must happen (the test counts say so). Where many primitives are
that large and alike (a building's floors and walls: the 16 widest cover less than half of what
they all cover), the list keeps only those covering a sixteenth of the grid or more, not 16 picked
among them that every ray would test."""
import functools
import sys
from pathlib import Path

import numpy as np
import pytest

import gridwalk as gw

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core" / "bench"))
from layout_scenes import building, camera_test  # noqa: E402  (the building of docs/layouts.md)


def settings(**kw):
    return gw.RenderSettings(threads=1, **kw)


def specks(rng, n, lo, hi, size=0.02):
    """n tiny triangles in the box [lo, hi]."""
    c = rng.uniform(lo, hi, (n, 1, 3))
    return (c + rng.normal(0, size, (n, 3, 3))).reshape(-1, 3)


def floor_scene(rng, spheres=True):
    """A 40 x 40 floor at z = 0 (2 triangles), a cluster of 3000 tiny triangles over one corner,
    and (optionally) four spheres close together over the other corner."""
    f = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
    v = np.vstack([f, specks(rng, 3000, (-19, -19, 0.2), (-15, -15, 3))]).astype(np.float32)
    t = np.vstack([[[0, 1, 2], [0, 2, 3]], 4 + np.arange(9000).reshape(-1, 3)])
    kw = dict(vertices=v, triangles=t)
    if spheres:
        kw.update(sphere_centers=[(15, 15, 1), (16, 15, 1.2), (15, 16, 1.1), (16, 16, 0.9)],
                  sphere_radii=[0.8, 0.7, 0.75, 0.6])
    return kw


def brute_force_agrees(sc, o, d, tmax=np.inf, spawned=False):
    want = sc.intersect(o, d, tmax=tmax, spawned=spawned, settings=gw.RenderSettings(accel="none"))
    got = sc.intersect(o, d, tmax=tmax, spawned=spawned, settings=settings())
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim) and np.array_equal(got.kind, want.kind)
    occ = sc.occluded(o, d, tmax=tmax, spawned=spawned, settings=settings())
    assert np.array_equal(occ, sc.occluded(o, d, tmax=tmax, spawned=spawned, settings=gw.RenderSettings(accel="none")))
    return got


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_rays_from_the_floor_and_around_the_boxes_find_brute_force_hits(seed):
    rng = np.random.default_rng(seed)
    sc = gw.Scene(**floor_scene(rng))
    n = 3000
    # Rays leaving the floor upwards, downwards, and grazing it; from the spheres' box faces and
    # corners; and random rays through the whole scene.
    on_floor = np.c_[rng.uniform(-20, 20, (n, 2)), np.zeros(n)]
    up = rng.normal(size=(n, 3)) * [1, 1, 0.3]
    box_lo, box_hi = np.array([14.2, 14.2, 0.2]), np.array([16.7, 16.8, 1.9])
    corners = np.where(rng.random((n, 3)) < 0.5, box_lo, box_hi) + rng.normal(0, 1e-3, (n, 3)) * (rng.random((n, 1)) < 0.5)
    towards = rng.uniform(box_lo, box_hi, (n, 3)) - corners
    flat = np.c_[rng.uniform(-25, 25, (n, 2)), np.where(rng.random(n) < 0.5, 0.0, rng.normal(0, 1e-6, n))]
    along = np.c_[rng.normal(size=(n, 2)), np.zeros(n)]
    anywhere = rng.uniform(-22, 22, (n, 3)) * [1, 1, 0.15]
    o = np.vstack([on_floor, on_floor, corners, flat, anywhere]).astype(np.float32)
    d = np.vstack([up, -up, towards, along, rng.normal(size=(n, 3))]).astype(np.float32)
    brute_force_agrees(sc, o, d)
    brute_force_agrees(sc, o, d, tmax=np.float32(rng.uniform(0.01, 30, len(o))))
    # As the renderer's shadow rays leave the floor: spawned, to points above it.
    hits = sc.intersect(o[:n], d[:n])
    keep = hits.kind > 0
    w = (rng.uniform(-20, 20, (n, 3)) * [1, 1, 0.2] + [0, 0, 4]) - (o[:n] + d[:n] * np.where(keep, hits.t, 0)[:, None])
    w = (w / np.linalg.norm(w, axis=1)[:, None]).astype(np.float32)
    spawned = sc.spawn_origins(o[:n], d[:n], hits, w)
    brute_force_agrees(sc, spawned[keep], w[keep], spawned=True)


def test_shadow_rays_leaving_the_floor_upwards_skip_it():
    # The camera sees only floor; the light is straight above it. Each pixel's camera ray tests
    # the floor's 2 triangles (a closest-hit ray over a list of 2 triangles does not check the
    # box); its shadow ray leaves the floor upwards, misses the floor's flat box and tests nothing.
    rng = np.random.default_rng(4)
    kw = floor_scene(rng, spheres=False)
    cam = gw.Camera(eye=(5, 0, 6), target=(5, 0, 0), up=(0, 1, 0), fov=30, width=32, height=32)
    sc = gw.Scene(**kw, lights=[gw.Light(position=(5, 0, 8))], camera=cam)
    job = gw.RenderJob(sc, settings(max_depth=1))
    job.start()
    job.wait()
    st = job.stats
    assert st["primary_rays"] == 32 * 32 and st["shadow_rays"] == 32 * 32
    assert st["prim_tests"] == 2 * st["primary_rays"]


def test_closest_hit_rays_skip_a_costly_list_in_a_small_box():
    # SPD's mountain in small: a terrain of 20000 tiny triangles and four large spheres close
    # together over one corner, each covering over 64 root cells (a list of quadrics in a box
    # small beside the grid). Rays over the other side test none of the four spheres.
    rng = np.random.default_rng(5)
    v = specks(rng, 20000, (-20, -20, 0), (20, 20, 0.5))
    centres = [(14, 14, 2.5), (17, 14, 2.8), (14, 17, 2.6), (17, 17, 2.4)]
    sc = gw.Scene(vertices=v.astype(np.float32), triangles=np.arange(len(v)).reshape(-1, 3),
                  sphere_centers=centres, sphere_radii=[1.5, 1.4, 1.6, 1.3])
    n = 2000
    o = np.c_[rng.uniform(-10, 5, n), np.full(n, -19.0), rng.uniform(1.5, 4, n)].astype(np.float32)
    d = np.c_[rng.uniform(-0.05, 0.05, n), np.ones(n), np.zeros(n)].astype(np.float32)   # above the terrain
    hits = brute_force_agrees(sc, o, d)
    assert hits.stats["prim_tests"] == 0   # (4 n with the spheres tested by every ray)
    # Rays aimed at the spheres still hit them, and rays leaving them (spawned) find what brute
    # force finds, the other spheres included.
    target = np.array(centres)[rng.integers(0, 4, n)]
    hits = brute_force_agrees(sc, o, (target - o).astype(np.float32))
    assert np.mean(hits.kind == 2) > 0.9
    w = rng.normal(size=(n, 3)).astype(np.float32)
    w /= np.linalg.norm(w, axis=1)[:, None]
    spawned = sc.spawn_origins(o, (target - o).astype(np.float32), hits, w)
    brute_force_agrees(sc, spawned, w, spawned=True)


def test_many_large_floors_and_walls_are_not_a_list_every_ray_tests():
    # The building's root grid finds 468 primitives over the size that makes
    # one large (about 100 with two floors); testing 16 of them on every ray
    # cost 18 tests per camera ray (20 with two floors).
    for floors, most in [(10, 8), (2, 8)]:
        sc, o, d = camera_test(functools.partial(building, floors=floors), 4000, 0.5, seed=12)
        got = sc.intersect(o, d, settings=settings())
        assert np.isfinite(got.t).mean() > 0.9
        tests = got.stats["prim_tests"] / len(o)
        assert tests < most, (floors, tests)
        few = slice(0, 4000, 20)   # (brute force tests every triangle on every ray)
        want = sc.intersect(o[few], d[few], settings=settings(accel="none"))
        assert np.array_equal(got.t[few], want.t) and np.array_equal(got.prim[few], want.prim)
