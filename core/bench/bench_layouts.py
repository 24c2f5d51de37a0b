"""Gridwalk against Embree on layouts that are hard for grids (layout_scenes.py): writes
docs/layouts.md.

    .venv/bin/python core/bench/bench_layouts.py [--quick] [--layouts building,blind] [--out docs]

The suite of benchmarks.md holds SPD scenes and meshes on ground planes. These are the other
layouts a user builds, and the ones a grid can handle worst: long primitives stacked across one
axis (floors, shelves, a blind's slats), a heightfield, thin blades on a plane, a soup, clusters
far apart, long thin slivers in every direction. For each: the build times (Gridwalk's Scene and
default structure, the adaptive grid, on all cores; Embree's BVH; wall time, taking turns, best
of up to 3 rounds within 2 s), then primary rays (256 x 256
through the camera) and random rays (65,536, gridwalk.validate.ray_sets), one thread each, the two
engines taking turns (best of 3, process CPU time), as section 2 of benchmarks.md measures them;
Gridwalk's tests and cells per ray; and the seed's uniform grid on the primary rays, for
comparison. Embree gets the same triangles (robust mode). A picture of each layout, as its
camera sees it, goes into docs/images/layouts.png.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_common import ROOT, alternate, alternate_builds, log, machine_info, table  # noqa: E402
from bench_embree import built_scene, embree_built  # noqa: E402
from layout_scenes import LAYOUTS  # noqa: E402

import gridwalk as gw  # noqa: E402
from gridwalk.validate import embree_intersect, ray_sets  # noqa: E402


def measure(make, scale, rays, reps):
    v, t, eye, target = make(np.random.default_rng(0), scale)
    side = int(np.sqrt(rays))
    kw = {"vertices": np.asarray(v, np.float32), "triangles": np.asarray(t, np.int32),
          "camera": gw.Camera(eye=eye, target=target, up=(0, 0, 1), fov=50, width=side, height=side),
          "lights": [gw.Light(position=(5.0, -5.0, 10.0))]}
    gw_build, (scene, info), em_build, em = alternate_builds(
        lambda: built_scene(kw), lambda: embree_built(kw["vertices"], kw["triangles"]))
    sets = ray_sets(kw, side * side, seed=1, scene=scene)
    # (the sheet in layouts.md: what the camera sees, lit from the camera)
    picture = gw.render(gw.Scene(**dict(kw, lights=[gw.Light(position=eye)])), gw.RenderSettings())
    one = gw.RenderSettings(threads=1)
    uniform = one.replace(accel="grid")
    scene.grid_info(uniform)   # (built now: the timings below are of tracing alone)
    out = {"triangles": len(t), "gw_build": gw_build, "em_build": em_build, "grids": info["grids"],
           "bytes": info["bytes"] / len(t), "picture": picture}
    for kind in ("primary", "random"):
        o, d, tmax = sets[kind]
        gw_s, hits, em_s, em_hits = alternate(lambda: scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=one),
                                              lambda: embree_intersect(em, o, d, tmax), reps)
        n = len(o)
        out[kind] = {"ratio": em_s / gw_s, "gw": n / gw_s, "em": n / em_s,
                     "tests": hits.stats["prim_tests"] / n, "cells": hits.stats["cells"] / n,
                     "agree": 100.0 * float(np.mean(np.isfinite(hits.t) == (em_hits["primID"] >= 0)))}
        if kind == "primary":
            grid_s, _, _, _ = alternate(lambda: scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=uniform),
                                        lambda: None, reps)
            out[kind]["uniform"] = em_s / grid_s
    return out


def write_sheet(results: dict, path: Path, columns: int = 4) -> None:
    """The layouts as their cameras see them (Gridwalk's default render, lit from the camera),
    labelled, in one PNG."""
    from PIL import Image, ImageDraw

    from gridwalk.cli import to_srgb8

    size, pad, head = 192, 8, 16
    names = list(results)
    rows = (len(names) + columns - 1) // columns
    sheet = Image.new("RGB", (columns * (size + pad) + pad, rows * (size + head + pad) + pad), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for k, name in enumerate(names):
        x, y = pad + (k % columns) * (size + pad), pad + (k // columns) * (size + head + pad)
        rgb = to_srgb8(results[name]["picture"][..., :3])
        sheet.paste(Image.fromarray(rgb).resize((size, size), Image.LANCZOS), (x, y + head))
        draw.text((x, y), LAYOUTS[name][0][:34], fill=(0, 0, 0))
    sheet.save(path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="tiny sizes (a smoke run)")
    ap.add_argument("--layouts", default=",".join(LAYOUTS), help="comma-separated: " + ", ".join(LAYOUTS))
    ap.add_argument("--out", default=str(ROOT / "docs"))
    args = ap.parse_args(argv)
    names = [n for n in args.layouts.split(",") if n]
    unknown = [n for n in names if n not in LAYOUTS]
    if unknown:
        ap.error(f"unknown layouts {unknown}; known: {', '.join(LAYOUTS)}")
    scale, rays, reps = (0.02, 32 * 32, 1) if args.quick else (1.0, 256 * 256, 3)
    start = time.perf_counter()
    info = machine_info()
    results = {}
    for name in names:
        log(f"layouts: {name}")
        results[name] = measure(LAYOUTS[name][1], scale, rays, reps)
    rows = []
    for name, r in results.items():
        for kind in ("primary", "random"):
            k = r[kind]
            rows.append([LAYOUTS[name][0], kind, f"{r['triangles']:,}" if kind == "primary" else "",
                         f"{k['gw'] / 1e6:.2f}", f"{k['em'] / 1e6:.2f}", f"**{k['ratio']:.2f}**",
                         f"{k['uniform']:.3f}" if "uniform" in k else "", f"{k['agree']:.3f}",
                         f"{k['tests']:.1f}", f"{k['cells']:.1f}"])
    builds = [[LAYOUTS[n][0], f"{r['triangles']:,}", f"{r['grids']:,}", f"{r['bytes']:.0f}",
               f"{r['gw_build']:.3f} s", f"{r['em_build']:.3f} s", f"{r['gw_build'] / r['em_build']:.2f}"]
              for n, r in results.items()]
    lines = ["# Layouts that are hard for grids", "",
             f"Generated by `.venv/bin/python core/bench/bench_layouts.py`{' --quick' if args.quick else ''} "
             f"in {time.perf_counter() - start:.0f} s; do not edit by hand. The script's docstring describes the "
             "method, `core/bench/layout_scenes.py` builds the scenes.", "",
             f"**Machine:** {info['cpu']}, `nproc` = {info['nproc']}; gridwalk {info['gridwalk']}, "
             f"embreex {info['embreex']}. Ratios are measured side by side in this one run; quote them, "
             "not the absolute rates.", "",
             "Rays per second, one thread; ratio = Gridwalk / Embree (above 1: Gridwalk is faster). *Uniform* "
             "is the seed's uniform grid (M = 2, mailboxes) on the same primary rays, over Embree. *Agree*: "
             "hit/miss agreement with Embree in % (the two watertight tests can differ on rays through the "
             "edges of needle-thin triangles; Gridwalk's answers equal its brute force's, which the tests "
             "check).", ""]
    lines += table(["layout", "rays", "triangles", "Gridwalk Mrays/s", "Embree Mrays/s", "ratio", "uniform",
                    "agree %", "tests/ray", "cells/ray"], rows)
    lines += ["Builds (all cores; Gridwalk: Scene and adaptive grid):", ""]
    lines += table(["layout", "triangles", "grids", "bytes/triangle", "Gridwalk", "Embree", "time ratio"], builds)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "images").mkdir(exist_ok=True)
    write_sheet(results, out / "images" / "layouts.png")
    lines += ["The layouts as their cameras see them (the primary rays above; Gridwalk's default render, "
              "lit by a point light at the camera):", "", "![the layouts](images/layouts.png)", ""]
    (out / "layouts.md").write_text("\n".join(lines))
    log(f"layouts: wrote {out / 'layouts.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
