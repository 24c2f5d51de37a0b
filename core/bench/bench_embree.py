"""Section 2: Gridwalk's Scene.intersect / occluded against embreex on the same rays."""
from __future__ import annotations

import time

import numpy as np

from bench_common import Section, alternate, figure, log, save, table
from bench_meshes import LABELS, scene_kwargs, tessellate_spheres
from gridwalk import RenderSettings, Scene
from gridwalk.validate import compare, embree_intersect, embree_scene, ray_sets

KINDS = ("primary", "shadow", "random")


def shadow_rays(scene, kw, o, d, n, rng):
    """Rays from the primary hits to each point light, leaving the surface where the renderer would
    (Scene.spawn_origins), only where the light is on the side the eye sees; at most n of them."""
    hits = scene.intersect(o, d)
    hit = hits.kind > 0
    p = o.astype(np.float64) + d * np.where(hit, hits.t, 0.0)[:, None]
    facing = np.sign(np.sum(hits.normal * -d, axis=1))
    origins, directions, tmax = [], [], []
    for light in kw["lights"]:
        if light.kind == "sun":
            continue
        to_light = np.asarray(light.position, np.float64) - p
        keep = hit & (np.sign(np.sum(hits.normal * to_light, axis=1)) == facing) & (facing != 0)
        spawned = scene.spawn_origins(o, d, hits, (to_light / np.linalg.norm(to_light, axis=1)[:, None]))
        v = np.asarray(light.position, np.float64) - spawned[keep].astype(np.float64)
        dist = np.linalg.norm(v, axis=1)
        w = v / dist[:, None]
        # embreex fixes tnear at 0: a shadow ray starting exactly on a surface
        # (an axis-aligned floor, whose points need no offset) would hit it
        # there. Both engines get origins moved 1e-4 of the light distance
        # along the ray.
        origins.append(spawned[keep] + w * (1e-4 * dist[:, None]))
        directions.append(w)
        tmax.append(dist * (1 - 2e-4))
    o2, d2, t2 = (np.concatenate(a) for a in (origins, directions, tmax))
    pick = np.sort(rng.permutation(len(o2))[:n])   # a subset, kept in pixel order (per light) as a renderer makes them
    return o2[pick].astype(np.float32), d2[pick].astype(np.float32), t2[pick].astype(np.float32)


def measure(name, kw, n, reps):
    """{kind: numbers} for one scene; kw holds triangles only (spheres tessellated)."""
    t0 = time.perf_counter()
    scene = Scene(vertices=kw["vertices"], triangles=kw["triangles"], camera=kw["camera"])
    grid = scene.grid_info()
    gw_build = time.perf_counter() - t0
    t0 = time.perf_counter()
    em_scene = embree_scene(kw["vertices"], kw["triangles"])
    embree_intersect(em_scene, np.zeros((1, 3)), np.ones((1, 3)))      # commit (builds the BVH)
    em_build = time.perf_counter() - t0
    rays = ray_sets(kw, n, seed=1, scene=scene)
    o, d, _ = rays["primary"]
    rays["shadow"] = shadow_rays(scene, kw, o, d, n, np.random.default_rng(2))
    out = {"triangles": len(kw["triangles"]), "grid": grid, "gw_build": gw_build, "em_build": em_build}
    for kind in KINDS:
        o, d, tmax = rays[kind]
        if kind == "shadow":
            gw_s, gw_occ, em_s, em_ids = alternate(
                lambda: scene.occluded(o, d, tmax=tmax, spawned=True, settings=RenderSettings(threads=1)),
                lambda: em_scene.run(o.copy(), d.copy(), dists=tmax.copy(), query="OCCLUDED"), reps)
            em_occ = np.asarray(em_ids) != -1
            # Scene.occluded returns no statistics: count them with a closest-hit query on the same rays.
            stats = scene.intersect(o, d, tmax=tmax, spawned=True, settings=RenderSettings(threads=1)).stats
            agree = {"hit_miss_agreement": 100.0 * float(np.mean(gw_occ == em_occ)), "same_primitive": None,
                     "disagree": int(np.sum(gw_occ != em_occ)), "hits": float(np.mean(em_occ))}
        else:
            gw_s, hits, em_s, em = alternate(lambda: scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=RenderSettings(threads=1)),
                                             lambda: embree_intersect(em_scene, o, d, tmax), reps)
            stats = hits.stats
            c = compare(hits, em)
            agree = {"hit_miss_agreement": c["hit_miss_agreement"], "same_primitive": c["same_primitive"],
                     "disagree": c["hit_miss_disagreements"] + c["mismatches"],
                     "hits": float(np.mean(em["primID"] >= 0))}
        r = max(stats["rays"], 1)
        out[kind] = {"rays": len(o), "gw": len(o) / gw_s, "em": len(o) / em_s, **agree,
                     "tests": stats["prim_tests"] / r, "cells": stats["cells"] / r}
        log(f"  embree {name} {kind}: gridwalk {out[kind]['gw'] / 1e6:.2f} Mrays/s, "
            f"embree {out[kind]['em'] / 1e6:.2f} Mrays/s")
    return out


CAUSE_DENSITY = (
    "the uniform grid spans the whole scene, whose box is set by the 24 x 24 floor, while the sphere "
    "triangles crowd into a small part of it, so the cells a ray crosses near the balls hold hundreds of "
    "triangles; raising M is capped by max_cells. A BVH adapts its depth to that density; a uniform grid "
    "cannot (a nested grid in the dense cells, or a grid over the small primitives with the floor kept "
    "apart, would)")
CAUSE_UNIT = (
    "tests and cells per ray are already small, so the gap is their unit cost: Gridwalk tests one triangle "
    "at a time in scalar code (the watertight test plus its error bound) and steps cells one by one, while "
    "Embree tests 4-8 boxes or triangles per SIMD instruction (AVX2/AVX-512 on this CPU) and culls whole "
    "subtrees; for shadow rays Embree also stops at the first occluder found in any order, while the grid "
    "walks cells front to back")


def gap_text(name, r):
    """One gap line for a scene whose primary or shadow ratio is below 1 (None if neither is)."""
    kinds = [k for k in ("primary", "shadow") if r[k]["gw"] < r[k]["em"]]
    if not kinds:
        return None
    parts = [f"{k} {r[k]['gw'] / r[k]['em']:.2f} ({1e9 / r[k]['gw']:.0f} ns per ray, {r[k]['tests']:.1f} tests and "
             f"{r[k]['cells']:.1f} cells, against Embree's {1e9 / r[k]['em']:.0f} ns)" for k in kinds]
    dense = name.startswith("balls") and max(r[k]["tests"] for k in kinds) > 50
    cause = (f"crowded cells: the grid ({'x'.join(map(str, r['grid']['resolution']))}) spans the floor, the "
             "sphere triangles fill a small part of it" if dense else
             "unit cost: scalar one-triangle tests and one-cell DDA steps against Embree's SIMD BVH")
    return (f"Embree, {LABELS.get(name, name)}: Gridwalk/Embree " + "; ".join(parts) + " - goal >= 1.0. Cause: "
            + cause + " (see section 2, *Why below 1*).")


def run(sizes, suzanne, out) -> Section:
    sec = Section("2. Embree")
    try:
        import embreex  # noqa: F401
    except ImportError:
        sec.lines += ["Skipped: embreex is not installed (`pip install embreex`).", ""]
        sec.gaps.append("Embree comparison not run: embreex is not installed.")
        return sec
    results = {}
    sub = 20 * 4 ** sizes.sphere_subdiv
    for name in sizes.embree_scenes:
        if name == "suzanne" and not suzanne:
            continue
        kw = tessellate_spheres(scene_kwargs(name, suzanne), sizes.sphere_subdiv)
        results[name] = measure(name, kw, sizes.embree_rays, sizes.reps)
    rows = []
    for name, r in results.items():
        for kind in KINDS:
            k = r[kind]
            ratio = k["gw"] / k["em"]
            bold = f"**{ratio:.2f}**" if kind != "random" else f"{ratio:.2f}"
            same = "-" if k["same_primitive"] is None else f"{k['same_primitive']:.4f}"
            rows.append([LABELS.get(name, name), kind, f"{k['rays']:,}", f"{100 * k['hits']:.1f}%",
                         f"{k['gw'] / 1e6:.3f}", f"{k['em'] / 1e6:.3f}", bold,
                         f"{k['hit_miss_agreement']:.4f}", same, k["disagree"], f"{k['tests']:.1f}",
                         f"{k['cells']:.1f}"])
            if k["hit_miss_agreement"] < 99.99:
                sec.gaps.append(f"Embree, {LABELS.get(name, name)}, {kind} rays: hit agreement "
                                f"{k['hit_miss_agreement']:.4f}% (below 99.99%).")
    sec.gaps += [g for g in (gap_text(n, r) for n, r in results.items()) if g]
    builds = [[LABELS.get(n, n), f"{r['triangles']:,}", "x".join(map(str, r["grid"]["resolution"])),
               f"{r['grid']['density_used']:.2f}", f"{r['gw_build']:.3f} s", f"{r['em_build']:.3f} s"]
              for n, r in results.items()]
    sec.lines += [
        f"The same float32 rays through both engines, on the same triangles: every sphere is tessellated as an "
        f"icosphere of {sub} triangles (Embree has no analytic spheres), so Balls size 4 has "
        f"{results.get('balls_s4', {}).get('triangles', 0):,} triangles. Gridwalk: `Scene.intersect` / "
        "`Scene.occluded(..., spawned=True)` with `threads=1` (default grid, M = 2, mailboxes on). Embree: "
        "embreex `EmbreeScene.run` (Embree 4, robust mode like our watertight test; one call, one thread, "
        "`output=1` for closest hits, `query='OCCLUDED'` for shadow rays). The two engines "
        f"take turns, {sizes.reps} calls each, best kept; rays per second are rays / wall time of the call.", "",
        f"- **primary**: {sizes.embree_rays:,} rays from the camera through a regular grid of pixel centres.",
        "- **shadow**: from the primary hits to each light, origins from `Scene.spawn_origins` (the "
        "renderer's own offset), kept where the light is on the side the eye sees, tmax = distance to the "
        "light; embreex's tnear is fixed at 0, so Embree starts at the same offset origin. At most "
        f"{sizes.embree_rays:,} rays (random subset). Agreement = same occluded / unoccluded answer.",
        "- **random**: uniform origins in the scene bounds (enlarged by 5%), uniform directions "
        "(`gridwalk.validate.ray_sets`).", "",
        "Ratio = Gridwalk rays/s / Embree rays/s (goal: >= 1.0 on primary and shadow). Agreement: hit/miss "
        "agreement in %, and among rays both hit, the % on the same triangle (ties within 1e-5 relative t "
        "count as agreement). Tests and cells per ray are Gridwalk's; for shadow rays they are counted by "
        "a closest-hit query on the same rays (`Scene.occluded` returns no statistics), an upper bound on "
        "what the any-hit query does.", ""]
    sec.lines += table(["scene", "ray kind", "rays", "hit", "Gridwalk Mrays/s", "Embree Mrays/s", "ratio",
                        "hit/miss agree %", "same prim %", "disagree", "tests/ray", "cells/ray"], rows)
    sec.lines += ["**Why below 1** where a ratio is. Crowded cells (Balls): " + CAUSE_DENSITY + ". Unit cost "
                  "(the other scenes): " + CAUSE_UNIT + ". embreex exposes no traversal counters, so Embree's "
                  "side of this is not measured here.", ""]
    sec.lines += ["Acceleration structure builds (not part of the ray timings):", ""]
    sec.lines += table(["scene", "triangles", "grid", "M used", "Gridwalk Scene + grid", "Embree BVH (all threads)"],
                       builds)
    fig, axes = figure(3, 4.2, 3.6)
    names = list(results)
    x = np.arange(len(names))
    for ax, kind in zip(axes, KINDS):
        ax.bar(x - 0.2, [results[n][kind]["gw"] / 1e6 for n in names], 0.4, label="Gridwalk")
        ax.bar(x + 0.2, [results[n][kind]["em"] / 1e6 for n in names], 0.4, label="Embree")
        for i, n in enumerate(names):
            ax.text(i, max(results[n][kind]["gw"], results[n][kind]["em"]) / 1e6,
                    f"{results[n][kind]['gw'] / results[n][kind]['em']:.2f}x", ha="center", va="bottom", fontsize=8)
        ax.set_xticks(x, [LABELS.get(n, n).replace(" (", "\n(") for n in names], fontsize=7)
        ax.set_title(f"{kind} rays (1 thread)")
        ax.set_ylabel("Mrays/s")
        ax.legend(fontsize=8)
    sec.lines += ["Rays per second, one thread; the label is Gridwalk/Embree:", "", save(fig, out, "embree_rays"), ""]
    ratios = {kind: [results[n][kind]["gw"] / results[n][kind]["em"] for n in names] for kind in KINDS}
    sec.headline.append("Gridwalk/Embree rays/s (1 thread): " + "; ".join(
        f"{kind} " + ", ".join(f"{LABELS.get(n, n)} {q:.2f}" for n, q in zip(names, ratios[kind])) for kind in KINDS)
        + f"; hit agreement >= {min(results[n][k]['hit_miss_agreement'] for n in names for k in KINDS):.4f}%")
    return sec
