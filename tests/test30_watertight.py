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
    n_random = 1_000_000
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
