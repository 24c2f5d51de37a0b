"""Cross-check Gridwalk's ray/triangle intersections against Embree (embreex).

The same float32 rays go through both engines on the same triangles:

    kwargs = gridwalk.io.load_scene("mount_s6.nff")
    scene = triangle_scene(kwargs)
    rays = ray_sets(kwargs, 100_000, seed=0, scene=scene)
    for kind, (o, d, tmax) in rays.items():
        report = compare(scene.intersect(o, d, tmax=tmax), embree_intersect(embree_scene(...), o, d, tmax))

Embree knows no analytic spheres or cones, so only triangles are compared:
`triangle_scene` drops the other primitives. embreex's tnear is fixed at 0,
so Gridwalk is queried with tmin = 0 too, and shadow-ray origins are offset
off the surface here rather than by either engine.
"""
from __future__ import annotations

import math
import time

import numpy as np

from .scene import Scene
from .settings import RenderSettings

AGREEMENT_REQUIRED = 99.999   # percent of rays on which hit / miss must agree
TIE_TOLERANCE = 1e-5          # two different primitives within this relative t are a tie
RAY_KINDS = ("primary", "shadow", "random")


def triangle_scene(scene_kwargs: dict) -> Scene:
    """A gridwalk.Scene with only the triangles of `scene_kwargs` (camera kept)."""
    if len(scene_kwargs["triangles"]) == 0:
        raise ValueError("the scene has no triangles to compare with Embree")
    return Scene(vertices=scene_kwargs["vertices"], triangles=scene_kwargs["triangles"],
                 camera=scene_kwargs["camera"])


def embree_scene(vertices, triangles):
    """An embreex scene (robust mode, like our watertight test) of one triangle mesh."""
    from embreex.mesh_construction import TriangleMesh
    from embreex.rtcore_scene import EmbreeScene

    scene = EmbreeScene(robust=True)
    TriangleMesh(scene, np.ascontiguousarray(vertices, np.float32),
                 np.ascontiguousarray(triangles, np.int32))
    return scene


def embree_intersect(scene, origins, directions, tmax=None) -> dict:
    """Closest hits from Embree: dict with tfar (inf on a miss), primID (-1 on a miss)."""
    o = np.array(origins, np.float32, order="C")        # embreex wants writable buffers
    d = np.array(directions, np.float32, order="C")
    dists = None if tmax is None else np.array(np.broadcast_to(tmax, (len(o),)), np.float32)
    result = scene.run(o, d, dists=dists, output=1)
    prim = np.asarray(result["primID"], np.int64)
    t = np.where(prim >= 0, np.asarray(result["tfar"], np.float64), np.inf)
    return {"tfar": t, "primID": prim}


def camera_rays(camera, n: int) -> tuple[np.ndarray, np.ndarray]:
    """About n of the camera's own rays (any projection), through a regular
    grid of image positions at the centres of an nx x ny grid."""
    aspect = camera.width / camera.height
    ny = max(1, round(math.sqrt(n / aspect)))
    nx = max(1, round(n / ny))
    gx, gy = np.meshgrid((np.arange(nx) + 0.5) / nx * camera.width, (np.arange(ny) + 0.5) / ny * camera.height)
    o, d, _, _ = camera.rays(gx, gy)
    return o, d


def _light_targets(lights) -> list:
    """(position or None, direction towards the light or None) per light."""
    out = []
    for light in lights:
        if light.kind == "sun":
            out.append((None, -np.asarray(light.direction, np.float64)))
        else:
            out.append((np.asarray(light.position, np.float64), None))
    return out


# What cross_check holds per ray of n, at most: three sets of origins, directions and tmax
# (28 bytes a ray each, float32, with their float64 making), a set's hits from both engines and
# compare()'s temporaries (about 200 bytes): for the CLI's memory check.
BYTES_PER_RAY = 3 * 28 * 2 + 400


def ray_sets(scene_kwargs: dict, n: int, seed: int = 0, scene: Scene | None = None) -> dict:
    """Primary, shadow and random ray sets: {kind: (origins, directions, tmax)}.

    primary: n rays from the camera through a pixel grid.
    shadow:  from the primary rays' hit points, offset off the surface on the
             side the primary ray came from by 1e-4 of the scene's size,
             towards each light (tmax = the light's distance); at most n.
    random:  n rays from uniform points in the bounds, enlarged on every side
             by 5% of their diagonal, in
             uniform random directions.
    All directions are unit length; all float32.
    """
    scene = scene or triangle_scene(scene_kwargs)
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    size = float(np.linalg.norm(hi - lo)) or 1.0
    sets = {}
    o, d = camera_rays(scene_kwargs["camera"], n)
    sets["primary"] = (o, d, np.full(len(o), np.inf, np.float32))

    hits = scene.intersect(o, d)
    hit = np.isfinite(hits.t)
    n_dot_d = np.sum(hits.normal[hit] * d[hit], axis=1, keepdims=True)
    side = -np.sign(n_dot_d) * hits.normal[hit]
    points = (o[hit] + d[hit] * hits.t[hit, None]).astype(np.float64) + 1e-4 * size * side
    origins, directions, tmax = [], [], []
    for position, direction in _light_targets(scene_kwargs["lights"]):
        to_light = (position - points) if position is not None else np.broadcast_to(direction, points.shape)
        dist = np.linalg.norm(to_light, axis=1)
        ok = dist > 0
        origins.append(points[ok])
        directions.append(to_light[ok] / dist[ok, None])
        tmax.append(dist[ok] if position is not None else np.full(ok.sum(), np.inf))
    if origins:
        origins, directions, tmax = (np.concatenate(a) for a in (origins, directions, tmax))
        keep = rng.permutation(len(origins))[:n]
        sets["shadow"] = (origins[keep].astype(np.float32), directions[keep].astype(np.float32),
                          tmax[keep].astype(np.float32))

    pad = 0.05 * size          # per axis, so a flat scene (a floor) gets a box too
    origins = rng.uniform(lo - pad, hi + pad, (n, 3))
    directions = rng.normal(size=(n, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    sets["random"] = (origins.astype(np.float32), directions.astype(np.float32),
                      np.full(n, np.inf, np.float32))
    return sets


def compare(gw_hits, embree_result: dict) -> dict:
    """Agreement of Gridwalk hits (scene.intersect) with embree_intersect's result.

    Among rays both engines hit, two different primitives whose t differ by
    less than TIE_TOLERANCE * t are a tie (an edge or a coplanar overlap), not
    a mismatch. max_rel_t_error is the largest |t - t_embree| / t_embree over
    rays that hit the same primitive (or tie); t_error_over_tolerance counts
    those rays where it exceeds TIE_TOLERANCE (reported, not a failure: both
    engines round t in float32, which is coarse for t much smaller than the
    triangle's distance from the origin of the coordinates). examples lists
    up to 3 failing rays as (index, t, prim, t_embree, prim_embree).
    """
    t_gw = np.asarray(gw_hits.t, np.float64)
    p_gw = np.where(np.isfinite(t_gw), np.asarray(gw_hits.prim, np.int64), -1)
    t_em, p_em = np.asarray(embree_result["tfar"], np.float64), np.asarray(embree_result["primID"], np.int64)
    rays = len(t_gw)
    hit_gw, hit_em = p_gw >= 0, p_em >= 0
    both = hit_gw & hit_em
    same = both & (p_gw == p_em)
    with np.errstate(invalid="ignore"):           # inf - inf on rays both miss
        close = np.abs(t_gw - t_em) <= TIE_TOLERANCE * np.abs(t_em)
    ties = both & ~same & close
    mismatches = both & ~same & ~close
    agree = same | ties
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(t_gw - t_em)[agree] / np.abs(t_em[agree])
    judged = int(both.sum() - ties.sum())
    result = {
        "rays": rays,
        "hit_miss_agreement": 100.0 * float(np.mean(hit_gw == hit_em)) if rays else 100.0,
        "hit_miss_disagreements": int(np.sum(hit_gw != hit_em)),
        "both_hit": int(both.sum()),
        "ties": int(ties.sum()),
        "mismatches": int(mismatches.sum()),
        "same_primitive": 100.0 * float(same.sum()) / judged if judged else 100.0,
        "max_rel_t_error": float(np.max(rel)) if rel.size else 0.0,
        "t_error_over_tolerance": int(np.sum(rel > TIE_TOLERANCE)),
    }
    bad = np.flatnonzero((hit_gw != hit_em) | mismatches)[:3]
    result["examples"] = [(int(i), float(t_gw[i]), int(p_gw[i]), float(t_em[i]), int(p_em[i])) for i in bad]
    result["passed"] = (result["hit_miss_agreement"] >= AGREEMENT_REQUIRED and result["mismatches"] == 0)
    return result


def cross_check(scene_kwargs: dict, n: int, seed: int = 0, threads: int = 1) -> dict:
    """Run every ray set through both engines: {kind: compare(...) + timings}."""
    scene = triangle_scene(scene_kwargs)
    scene.accel()                                   # build the grid before timing
    embree = embree_scene(scene_kwargs["vertices"], scene_kwargs["triangles"])
    embree_intersect(embree, np.zeros((1, 3)), np.ones((1, 3)))   # commit before timing
    results = {}
    for kind, (o, d, tmax) in ray_sets(scene_kwargs, n, seed, scene).items():
        start = time.perf_counter()
        gw_hits = scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=RenderSettings(threads=threads))
        gw_seconds = time.perf_counter() - start
        start = time.perf_counter()
        em = embree_intersect(embree, o, d, tmax)
        em_seconds = time.perf_counter() - start
        results[kind] = {**compare(gw_hits, em), "gridwalk_seconds": gw_seconds,
                         "embree_seconds": em_seconds}
    return results


def format_table(results: dict) -> str:
    """cross_check's results as a table, failing rays, and a PASS / FAIL line."""
    head = ("kind", "rays", "hit/miss %", "same prim %", "ties", "mismatch", "max rel t err", "t err>1e-5",
            "gridwalk s", "embree s")
    lines = ["{:<8} {:>8} {:>11} {:>12} {:>5} {:>8} {:>13} {:>10} {:>10} {:>9}".format(*head)]
    for kind, r in results.items():
        lines.append(f"{kind:<8} {r['rays']:>8} {r['hit_miss_agreement']:>11.4f} {r['same_primitive']:>12.4f} "
                     f"{r['ties']:>5} {r['mismatches']:>8} {r['max_rel_t_error']:>13.2e} "
                     f"{r['t_error_over_tolerance']:>10} {r['gridwalk_seconds']:>10.4f} {r['embree_seconds']:>9.4f}")
    for kind, r in results.items():
        for i, t, prim, t_em, prim_em in r["examples"]:
            lines.append(f"  {kind} ray {i}: gridwalk t={t:.6g} prim {prim}, embree t={t_em:.6g} prim {prim_em}")
    verdict = "PASS" if all(r["passed"] for r in results.values()) else "FAIL"
    lines.append(f"{verdict}: needs hit/miss agreement >= {AGREEMENT_REQUIRED}% and no primitive mismatch "
                 f"outside ties (|t - t_embree| < {TIE_TOLERANCE:g} t)")
    return "\n".join(lines)
