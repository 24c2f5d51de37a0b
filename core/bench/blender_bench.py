"""Blender benchmark (a script, not a test): export speed and GRIDWALK vs Cycles.

    .venv-bpy45/bin/python core/bench/blender_bench.py [--out docs/blender-benchmark.md]

1. Export time of a ~1M-triangle scene (Suzanne, Subdivision level 5, smooth):
   the first export (Blender computes its triangulation and normals lazily)
   and the best of 3 repeats. Goal: 0.5 s or less.
2. Render time of the demo scene (blender_addon/demo.py) with GRIDWALK and with
   Cycles (CPU) at comparable settings: the same samples per pixel (GRIDWALK's
   n x n anti-aliasing samples = Cycles samples), bounces = max depth - 1, no
   denoising, same threads. Both measured side by side in one run; the ratio is
   what to quote.
"""
from __future__ import annotations

import argparse
import os
import platform
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [ROOT, os.path.join(ROOT, "blender_addon")]


def export_timing(levels=5):
    import bpy

    import demo
    from blender_addon.export import export_scene
    demo.build_demo_scene(64, 36)
    for obj in list(bpy.data.objects):
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.object
    for poly in monkey.data.polygons:
        poly.use_smooth = True
    mod = monkey.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = levels
    depsgraph = bpy.context.evaluated_depsgraph_get()
    times = []
    for _ in range(4):
        t0 = time.perf_counter()
        kwargs, _ = export_scene(depsgraph)
        times.append(time.perf_counter() - t0)
    return len(kwargs["triangles"]), times[0], min(times[1:])


def render_seconds(engine, width, height, samples, threads, max_depth):
    import bpy

    import demo
    scene = demo.build_demo_scene(width, height)
    scene.render.engine = engine
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    settings = scene.gridwalk
    settings.aa, settings.aa_samples, settings.threads, settings.max_depth = "JITTERED", samples, threads, max_depth
    settings.shadow, settings.shadow_samples = "RANDOM", 1
    settings.dof_samples = settings.glossy_samples = 1
    if engine == "CYCLES":
        scene.cycles.device, scene.cycles.samples = "CPU", samples * samples
        scene.cycles.use_adaptive_sampling = scene.cycles.use_denoising = False
        scene.cycles.max_bounces = max_depth - 1
    t0 = time.perf_counter()
    bpy.ops.render.render()
    return time.perf_counter() - t0


def main(argv):
    import bpy
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "blender-benchmark.md"))
    parser.add_argument("--size", type=int, nargs=2, default=(640, 360))
    parser.add_argument("--samples", type=int, default=4, help="n: n x n samples per pixel")
    args = parser.parse_args(argv)
    threads = os.cpu_count() or 1
    tris, first, repeat = export_timing()
    gw = render_seconds("GRIDWALK", *args.size, args.samples, threads, 5)
    cy = render_seconds("CYCLES", *args.size, args.samples, threads, 5)
    lines = [
        "# Blender benchmark", "",
        f"Blender {bpy.app.version_string}, {platform.processor() or platform.machine()}, "
        f"{threads} threads. Regenerate: `.venv-bpy45/bin/python core/bench/blender_bench.py`.", "",
        "| measure | value |", "|---|---|",
        f"| export, {tris:,} triangles, first (incl. Blender's lazy triangulation) | {first:.3f} s |",
        f"| export, {tris:,} triangles, best repeat | {repeat:.3f} s |",
        f"| demo scene {args.size[0]}x{args.size[1]}, {args.samples ** 2} spp: GRIDWALK | {gw:.2f} s |",
        f"| same scene and spp: Cycles (CPU, path tracing, no denoising) | {cy:.2f} s |",
        f"| Cycles / GRIDWALK time ratio | {cy / gw:.2f} |", "",
        "Cycles traces global illumination (a path per sample); GRIDWALK traces "
        "Whitted rays with direct light only, so the ratio compares cost, not images.", ""]
    with open(args.out, "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
