"""Section 2: Gridwalk's Scene.intersect / occluded against embreex on the same rays."""
from __future__ import annotations

import time

import numpy as np

from bench_common import Section, alternate, alternate_builds, figure, log, save, table
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


def built_scene(kw):
    """(Scene, its grid_info): the scene and its default structure built."""
    scene = Scene(**kw)
    return scene, scene.grid_info()


def embree_built(vertices, triangles):
    """An embreex scene with its BVH built (committed by a first query)."""
    em = embree_scene(vertices, triangles)
    embree_intersect(em, np.zeros((1, 3)), np.ones((1, 3)))
    return em


def measure(name, kw, n, reps, gw_kw=None):
    """{kind: numbers} for one scene. kw holds triangles only (spheres tessellated) and is what Embree
    and the ray sets use; gw_kw (default kw) is what Gridwalk traces, e.g. the same scene with analytic
    spheres. Gridwalk runs its default structure (the adaptive grid) and, on primary rays, the seed's
    uniform grid beside it."""
    analytic = gw_kw is not None
    gw_kw = gw_kw or kw
    gw_build, (scene, grid), em_build, em_scene = alternate_builds(
        lambda: built_scene(gw_kw), lambda: embree_built(kw["vertices"], kw["triangles"]))
    uniform = scene.grid_info(RenderSettings(accel="grid"))
    tri_scene = Scene(vertices=kw["vertices"], triangles=kw["triangles"], camera=kw["camera"]) if analytic else scene
    rays = ray_sets(kw, n, seed=1, scene=tri_scene)
    o, d, _ = rays["primary"]
    rays["shadow"] = shadow_rays(tri_scene, kw, o, d, n, np.random.default_rng(2))
    one = RenderSettings(threads=1)
    out = {"triangles": len(kw["triangles"]), "primitives": scene.num_primitives, "grid": grid,
           "uniform": uniform, "gw_build": gw_build, "em_build": em_build, "analytic": analytic}
    for kind in KINDS:
        o, d, tmax = rays[kind]
        if kind == "shadow":
            gw_s, gw_occ, em_s, em_ids = alternate(
                lambda: scene.occluded(o, d, tmax=tmax, spawned=True, settings=one),
                lambda: em_scene.run(o.copy(), d.copy(), dists=tmax.copy(), query="OCCLUDED"), reps)
            em_occ = np.asarray(em_ids) != -1
            # Scene.occluded returns no statistics: count them with a closest-hit query on the same rays.
            stats = scene.intersect(o, d, tmax=tmax, spawned=True, settings=one).stats
            agree = {"hit_miss_agreement": 100.0 * float(np.mean(gw_occ == em_occ)), "same_primitive": None,
                     "disagree": int(np.sum(gw_occ != em_occ)), "hits": float(np.mean(em_occ))}
        else:
            gw_s, hits, em_s, em = alternate(lambda: scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=one),
                                             lambda: embree_intersect(em_scene, o, d, tmax), reps)
            stats = hits.stats
            c = compare(hits, em)
            agree = {"hit_miss_agreement": c["hit_miss_agreement"],
                     "same_primitive": None if analytic else c["same_primitive"],
                     "disagree": c["hit_miss_disagreements"] + (0 if analytic else c["mismatches"]),
                     "hits": float(np.mean(em["primID"] >= 0))}
        r = max(stats["rays"], 1)
        out[kind] = {"rays": len(o), "gw": len(o) / gw_s, "em": len(o) / em_s, **agree,
                     "tests": stats["prim_tests"] / r, "cells": stats["cells"] / r}
        if kind == "primary":
            t0 = time.process_time()
            scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=one.replace(accel="grid"))
            out[kind]["uniform"] = len(o) / (time.process_time() - t0)
        log(f"  embree {name} {kind}: gridwalk {out[kind]['gw'] / 1e6:.2f} Mrays/s, "
            f"embree {out[kind]['em'] / 1e6:.2f} Mrays/s")
    return out


def geomean(values) -> float:
    return float(np.exp(np.mean(np.log(values))))


CAUSE = (
    "tests and cells per ray are small (a few of each on primary rays), so the gap is their unit cost. "
    "Per cell the adaptive walk pays a DDA step, a proximity-cloud lookup and, in a refined cell, the "
    "descent into its child grid; Embree's BVH4/8 tests 4-8 boxes per SIMD instruction and culls "
    "subtrees. Shadow rays start on a surface and leave through crowded cells, so they test more "
    "triangles than primary rays; Embree stops at the first occluder found in any order, the grid "
    "walks cells front to back")


def gap_text(name, r):
    """One gap line for a scene whose primary or shadow ratio is below 1 (None if neither is)."""
    kinds = [k for k in ("primary", "shadow") if r[k]["gw"] < r[k]["em"]]
    if not kinds:
        return None
    parts = [f"{k} {r[k]['gw'] / r[k]['em']:.2f} ({1e9 / r[k]['gw']:.0f} ns per ray, {r[k]['tests']:.1f} tests and "
             f"{r[k]['cells']:.1f} cells, against Embree's {1e9 / r[k]['em']:.0f} ns)" for k in kinds]
    return (f"Embree, {LABELS.get(name, name)}: Gridwalk/Embree " + "; ".join(parts) + " - goal >= 1.0 "
            "(see section 2, *Why below 1*).")


def scenes_for(sizes, suzanne):
    """[(name, Embree/ray kwargs, Gridwalk kwargs or None)] for the suite."""
    out = []
    for name in sizes.embree_scenes:
        if name in ("suzanne", "scan_on_plane", "scans_on_floor") and not suzanne:
            continue
        if name.endswith("_analytic"):
            kw = scene_kwargs(name[: -len("_analytic")])
            out.append((name, tessellate_spheres(kw, sizes.sphere_subdiv), kw))
        else:
            out.append((name, tessellate_spheres(scene_kwargs(name, suzanne), sizes.sphere_subdiv), None))
    return out


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
    for name, kw, gw_kw in scenes_for(sizes, suzanne):
        results[name] = measure(name, kw, sizes.embree_rays, sizes.reps, gw_kw)
    rows = []
    for name, r in results.items():
        for kind in KINDS:
            k = r[kind]
            ratio = k["gw"] / k["em"]
            bold = f"**{ratio:.2f}**" if kind != "random" else f"{ratio:.2f}"
            same = "-" if k["same_primitive"] is None else f"{k['same_primitive']:.4f}"
            agree = "-" if r["analytic"] else f"{k['hit_miss_agreement']:.4f}"
            uni = f"{k['uniform'] / k['em']:.3f}" if "uniform" in k else ""
            rows.append([LABELS.get(name, name), kind, f"{k['rays']:,}", f"{100 * k['hits']:.1f}%",
                         f"{k['gw'] / 1e6:.3f}", f"{k['em'] / 1e6:.3f}", bold, uni,
                         agree, same, "-" if r["analytic"] else k["disagree"], f"{k['tests']:.1f}",
                         f"{k['cells']:.1f}"])
            if k["hit_miss_agreement"] < 99.99 and not r["analytic"]:
                sec.gaps.append(f"Embree, {LABELS.get(name, name)}, {kind} rays: hit agreement "
                                f"{k['hit_miss_agreement']:.4f}% (below 99.99%).")
    sec.gaps += [g for g in (gap_text(n, r) for n, r in results.items()) if g]
    names = list(results)
    ratios = {kind: [results[n][kind]["gw"] / results[n][kind]["em"] for n in names] for kind in KINDS}
    goals = {"primary": 1.0, "shadow": 1.0, "random": 0.7}
    summary = []
    for kind in KINDS:
        g, lo = geomean(ratios[kind]), min(ratios[kind])
        worst = names[int(np.argmin(ratios[kind]))]
        summary.append([kind, f"**{g:.2f}**", f"{goals[kind]:.1f}", f"{lo:.2f} ({LABELS.get(worst, worst)})", "0.5",
                        "met" if g >= goals[kind] and lo >= 0.5 else "**not met**"])
        if g < goals[kind] or lo < 0.5:
            sec.gaps.append(f"Embree, {kind} rays: geometric mean Gridwalk/Embree {g:.2f} (goal {goals[kind]:.1f}), "
                            f"lowest {lo:.2f} on {LABELS.get(worst, worst)} (goal 0.5).")
    builds = [[LABELS.get(n, n), f"{r['primitives']:,}",
               f"{r['grid']['grids']:,} grids",
               f"{r['grid']['bytes'] / r['primitives']:.0f}", f"{r['uniform']['bytes'] / r['primitives']:.0f}",
               f"{r['gw_build']:.3f} s", f"{r['em_build']:.3f} s", f"{r['gw_build'] / r['em_build']:.2f}"]
              for n, r in results.items()]
    sec.lines += [
        f"The same float32 rays through both engines. Embree gets triangles only: every sphere is tessellated "
        f"as an icosphere of {sub} triangles (" + ", ".join(
            f"{LABELS.get(n, n)}: {r['triangles']:,} triangles" for n, r in results.items()
            if n.startswith("balls") and not r["analytic"]) + "); the *analytic* row traces the same "
        "rays through Gridwalk's analytic spheres (Embree still has the icospheres, so its hits are not "
        "compared). The two ground-plane scenes are the layout of most Blender scenes: a dense Suzanne "
        "(Blender's, subdivision level 3, 63k triangles) 1 unit across on a 100 x 100 plane, and six of them "
        "on a 40 x 40 floor. Gridwalk: `Scene.intersect` / `Scene.occluded(..., spawned=True)` with "
        "`threads=1` and the default structure (the adaptive grid); the *uniform* column is the seed's "
        "uniform grid (M = 2, mailboxes) on the same primary rays, for comparison. Embree: embreex "
        "`EmbreeScene.run` (Embree 4, robust mode like our watertight test; one call, one thread, `output=1` "
        f"for closest hits, `query='OCCLUDED'` for shadow rays). The two engines take turns, {sizes.reps} "
        "calls each, best kept; rays per second are rays / CPU time of the call (the process's CPU time: both "
        "engines trace on the calling thread only, and CPU time is not inflated when other work shares the "
        "machine).", "",
        f"- **primary**: {sizes.embree_rays:,} rays from the camera through a regular grid of pixel centres.",
        "- **shadow**: from the primary hits to each light, origins from `Scene.spawn_origins` (the "
        "renderer's own offset) moved on by 1e-4 of the light distance (embreex's tnear is fixed at 0 and "
        "would find the surface the ray leaves), kept where the light is on the side the eye sees, tmax "
        f"just short of the light; at most {sizes.embree_rays:,} rays, in pixel order. Agreement = same "
        "occluded / unoccluded answer.",
        "- **random**: uniform origins in the scene bounds (enlarged by 5%), uniform directions "
        "(`gridwalk.validate.ray_sets`).", "",
        "**Against the goals** (Gridwalk / Embree rays per second, one thread; geometric mean over the "
        "scenes, and the lowest scene):", ""]
    sec.lines += table(["rays", "geometric mean", "goal", "lowest scene", "goal", ""], summary)
    sec.lines += [
        "Ratio = Gridwalk rays/s / Embree rays/s. Agreement: hit/miss agreement in %, and among rays both "
        "hit, the % on the same triangle (ties within 1e-5 relative t count as agreement). Tests and cells "
        "per ray are Gridwalk's (cells: every grid cell visited, at any level); for shadow rays they are "
        "counted by a closest-hit query on the same rays (`Scene.occluded` returns no statistics), an upper "
        "bound on what the any-hit query does.", ""]
    sec.lines += table(["scene", "ray kind", "rays", "hit", "Gridwalk Mrays/s", "Embree Mrays/s", "ratio",
                        "uniform grid ratio", "hit/miss agree %", "same prim %", "disagree", "tests/ray",
                        "cells/ray"], rows)
    sec.lines += ["**Why below 1** where a ratio is: " + CAUSE + ". embreex exposes no traversal counters, so "
                  "Embree's side of this is not measured here.", ""]
    sec.lines += ["Acceleration structure builds (not part of the ray timings; both build on all cores: Gridwalk's "
                  "default `RenderSettings.threads` = 0, Embree's own; wall time, the two taking turns, best of up to 3 "
                  "rounds within 2 s, so one round for the largest scenes; goal: at most 2x Embree's build time and "
                  "64 bytes per triangle):", ""]
    sec.lines += table(["scene", "primitives", "adaptive grid", "adaptive bytes/prim", "uniform bytes/prim",
                        "Gridwalk Scene + adaptive grid", "Embree BVH", "time ratio"], builds)
    fig, axes = figure(3, 4.2, 4.4)
    x = np.arange(len(names))
    for ax, kind in zip(axes, KINDS):
        ax.bar(x - 0.2, [results[n][kind]["gw"] / 1e6 for n in names], 0.4, label="Gridwalk")
        ax.bar(x + 0.2, [results[n][kind]["em"] / 1e6 for n in names], 0.4, label="Embree")
        for i, n in enumerate(names):
            ax.text(i, max(results[n][kind]["gw"], results[n][kind]["em"]) / 1e6,
                    f"{results[n][kind]['gw'] / results[n][kind]['em']:.2f}x", ha="center", va="bottom", fontsize=8)
        ax.set_xticks(x, [LABELS.get(n, n) for n in names], fontsize=7, rotation=35, ha="right",
                      rotation_mode="anchor")
        ax.set_title(f"{kind} rays (1 thread)")
        ax.set_ylabel("Mrays/s")
        ax.legend(fontsize=8)
    sec.lines += ["Rays per second, one thread; the label is Gridwalk/Embree:", "", save(fig, out, "embree_rays"), ""]
    sec.headline.append("Gridwalk/Embree rays/s (1 thread), geometric mean over the suite: " + ", ".join(
        f"{kind} {geomean(ratios[kind]):.2f} (lowest {min(ratios[kind]):.2f})" for kind in KINDS)
        + "; on primary rays the uniform grid gave " + ", ".join(
        f"{LABELS.get(n, n)} {results[n]['primary']['uniform'] / results[n]['primary']['em']:.3f}" for n in names)
        + f"; hit agreement >= {min(results[n][k]['hit_miss_agreement'] for n in names for k in KINDS if not results[n]['analytic']):.4f}%")
    return sec
