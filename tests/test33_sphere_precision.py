"""Spheres at hard scales against a double-precision reference: a tiny sphere
far away, a huge sphere used as ground, and rays starting on the surface."""
import numpy as np

import gridwalk as gw
from test03_intersections_match_embree import sphere_reference


def check(C, R, o, d, rel=1e-5):
    sc = gw.Scene(sphere_centers=C, sphere_radii=R)
    ours = sc.intersect(o, d)
    ref, _ = sphere_reference(np.asarray(C, np.float32), np.asarray(R, np.float32), o, d)
    hit_o, hit_r = np.isfinite(ours.t), np.isfinite(ref)
    mismatch = hit_o != hit_r
    assert mismatch.mean() <= 1e-3, f"{mismatch.sum()} hit/miss mismatches"
    both = hit_o & hit_r
    err = np.abs(ours.t[both] - ref[both]) / ref[both]
    assert err.max() <= rel, err.max()
    return both.sum()


def test_tiny_sphere_far_away():
    rng = np.random.default_rng(1)
    C, R = np.array([[1e4, 0, 0]], np.float32), np.array([1e-3], np.float32)
    n = 20000
    # Aim at random points within 1.5 radii of the centre, from the origin.
    target = C[0] + rng.uniform(-1.5e-3, 1.5e-3, (n, 3))
    o = np.zeros((n, 3), np.float32)
    assert check(C, R, o, (target - o).astype(np.float32)) > 5000


def test_huge_ground_sphere():
    rng = np.random.default_rng(2)
    C, R = np.array([[0, 0, -1e6]], np.float32), np.array([1e6], np.float32)
    n = 20000
    o = np.column_stack([rng.uniform(-50, 50, (n, 2)), rng.uniform(0.5, 20, n)]).astype(np.float32)
    d = np.column_stack([rng.normal(size=(n, 2)), -rng.uniform(0.05, 1, n)]).astype(np.float32)
    assert check(C, R, o, d) > 15000


def test_ray_origin_on_the_surface():
    """Origins on the surface (up to float rounding), rays inward and outward:
    whatever root the double-precision reference finds, we find."""
    rng = np.random.default_rng(3)
    C, R = np.array([[1.5, -2.0, 0.5]], np.float32), np.array([2.0], np.float32)
    n = 20000
    nrm = rng.normal(size=(n, 3)); nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    o = (C[0] + nrm * R[0]).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    assert check(C, R, o, d) > 5000
