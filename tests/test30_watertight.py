"""Watertightness: rays from inside closed meshes never escape, including rays
aimed exactly at vertices and edges, near the origin and 1e5 away from it,
with the grid on and off."""
import numpy as np
import pytest

import gridwalk as gw
from meshes import icosphere, uv_sphere

OFFSETS = [(0.0, 0.0, 0.0), (1e5, -1e5, 1e5)]


def inside_rays(V, F, origin, n_random, seed):
    """Directions at every vertex, every edge midpoint, and random ones."""
    o = np.asarray(origin, np.float64)
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    mids = (V[edges[:, 0]].astype(np.float64) + V[edges[:, 1]]) / 2
    rng = np.random.default_rng(seed)
    rand = rng.normal(size=(n_random, 3))
    d = np.concatenate([V - o, mids - o, rand])
    return np.broadcast_to(o, d.shape).astype(np.float32), d.astype(np.float32), len(V), len(mids)


def meshes():
    for off in OFFSETS:
        V, F = icosphere(3, radius=2.0)
        yield f"icosphere@{off[0]:g}", (V + np.float32(off)).astype(np.float32), F, off
        V, F = uv_sphere(radius=2.0, center=off, seed=1)
        yield f"uvsphere@{off[0]:g}", V, F, off


CASES = list(meshes())


@pytest.mark.parametrize("name, V, F, center", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("accel", ["adaptive", "grid", "none"])
def test_rays_from_inside_never_escape(name, V, F, center, accel):
    # Every vertex and edge midpoint, and random directions: a million through the grids, a
    # tenth as many through brute force (the same triangle test; its million took 20-40 s a
    # mesh of CI's 2-core time, the grids' 1-2 s).
    n_random = 100_000 if accel == "none" else 1_000_000
    sc = gw.Scene(vertices=V, triangles=F)
    # The centre itself is not representable 1e5 away from the origin; use the float32 centre.
    origin = np.asarray(center, np.float32)
    o, d, nv, ne = inside_rays(V, F, origin, n_random, seed=len(name))
    hits = sc.intersect(o, d, settings=gw.RenderSettings(accel=accel))
    misses = ~np.isfinite(hits.t)
    assert misses.sum() == 0, f"{misses.sum()} escapes: {misses[:nv].sum()} at vertices, " \
                              f"{misses[nv:nv + ne].sum()} at edges, {misses[nv + ne:].sum()} random"


def test_uv_sphere_really_has_seam_and_pole_duplicates():
    V, F = uv_sphere()
    uniq = np.unique(V, axis=0)
    assert len(uniq) < len(V) - 40            # poles and seam are duplicated vertices
    area = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    assert np.sum(area == 0) >= 48            # zero-area triangles at the poles


@pytest.mark.parametrize("scale", [1e-20, 1e-12, 1e13, 1e21, 4e29])
@pytest.mark.parametrize("accel", ["adaptive", "grid", "none"])
def test_meshes_far_above_and_below_unit_scale_stay_watertight_and_at_their_distance(scale, accel):
    # The float test's T, a cubic in the corners' coordinates, overflowed from
    # about 5e12 and lost its digits below about 1e-9: those triangles were
    # never hit (an empty image). They are tested in double there.
    V, F = icosphere(3, radius=2.0)
    V = (V.astype(np.float64) * scale).astype(np.float32)
    sc = gw.Scene(vertices=V, triangles=F)
    o, d, nv, ne = inside_rays(V, F, np.zeros(3, np.float32), 20_000, seed=7)
    hits = sc.intersect(o, d, settings=gw.RenderSettings(accel=accel))
    assert np.isfinite(hits.t).all(), f"{(~np.isfinite(hits.t)).sum()} escapes"
    reach = hits.t.astype(np.float64) * np.linalg.norm(d.astype(np.float64), axis=1) / (2.0 * scale)
    assert reach.min() > 0.99 and reach.max() < 1.0 + 1e-5   # the inscribed faces: within 1% of the radius
    # and from outside, shadow rays towards the centre are blocked by the shell
    far = np.float32(3.0 * scale) * d[nv + ne:] / np.linalg.norm(d[nv + ne:], axis=1, keepdims=True)
    assert sc.occluded(far, -far, tmax=np.ones(len(far), np.float32), settings=gw.RenderSettings(accel=accel)).all()


@pytest.mark.parametrize("accel", ["adaptive", "grid", "none"])
def test_a_triangle_whose_det_overflows_float_is_still_hit(accel):
    # Spanning +-1e19 in z = 0: the edge functions' sum overflows float while
    # T stays finite, so the float t was 0 (a miss); it is found in double.
    V = np.array([[-1e19, -1e19, 0], [1e19, -1e19, 0], [0, 1e19, 0]], np.float32)
    sc = gw.Scene(vertices=V, triangles=np.array([[0, 1, 2]], np.int32))
    o = np.array([[0, 0, 0.5], [1e18, 1e17, 3.0]], np.float32)
    d = np.array([[0, 0, -1], [0, 0, -1]], np.float32)
    hits = sc.intersect(o, d, settings=gw.RenderSettings(accel=accel))
    np.testing.assert_allclose(hits.t, [0.5, 3.0], rtol=1e-6)
