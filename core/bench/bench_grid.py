"""Grid benchmark: brute force vs grid vs grid + mailboxes, 1 thread vs all.

Renders SPD balls (sizes 2-4) and mount (sizes 4-8) from ../shared/scenes/spd
with the SPD protocol (Whitted, depth 5) and prints a markdown table. Brute
force ("none") is timed on a regular subset of image rows and scaled up to the
whole image (marked with *). A script, not a test:

    .venv/bin/python core/bench/bench_grid.py [--res 512] [--scenes balls_s2 ...]
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import gridwalk as gw
from gridwalk.io import load_nff

SPD = Path(__file__).resolve().parents[2].parent / "shared" / "scenes" / "spd"
SCENES = ["balls_s2", "balls_s3", "balls_s4", "mount_s4", "mount_s6", "mount_s8"]


def timed_render(scene, settings):
    job = gw.RenderJob(scene, settings)   # builds the grid first: build time is not render time
    t0 = time.perf_counter()
    job.start()
    job.wait()
    return time.perf_counter() - t0, job.stats


def brute_force_estimate(scene, settings, res, budget_rays):
    """Time brute force on evenly spaced full-width rows and scale to the image."""
    per_row = res
    rows = max(1, min(res, budget_rays // per_row))
    step = res / rows
    total = 0.0
    for k in range(rows):
        y = int(k * step)
        dt, _ = timed_render(scene, settings.replace(region=(0, y, res, 1)))
        total += dt
    return total * res / rows, rows < res


def run(names, res, budget):
    threads = os.cpu_count() or 1
    base = gw.RenderSettings(max_depth=5, tile_size=16)
    rows = []
    for name in names:
        kw = load_nff(SPD / f"{name}.nff")
        kw["camera"].width = kw["camera"].height = res
        scene = gw.Scene(**kw)
        t_none, scaled = brute_force_estimate(scene, base.replace(accel="none", threads=threads), res, budget)
        t_none *= threads   # the subset ran on all cores; report single-core time like the other columns
        t_grid, st = timed_render(scene, base.replace(mailboxes=False, threads=1))
        t_mb, st_mb = timed_render(scene, base.replace(mailboxes=True, threads=1))
        t_par, _ = timed_render(scene, base.replace(mailboxes=False, threads=threads))
        t_mbpar, _ = timed_render(scene, base.replace(mailboxes=True, threads=threads))
        g = st["grid"]
        rows.append((name, scene.num_primitives, t_none, scaled, t_grid, t_mb, t_par, t_mbpar, st, st_mb, g))
        print(f"{name}: done", flush=True)
    print(f"\n{res}x{res}, SPD protocol (depth 5, 1 eye ray per pixel), {threads} threads for the parallel columns\n")
    print("| scene | prims | none (1 core) | grid | grid + mailboxes | grid + parallel | grid + mailboxes + parallel"
          " | none/grid | tests/ray (no mb / mb) | cells/ray | grid cells |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, n, tn, sc, tg, tm, tp, tmp, st, stm, g in rows:
        star = "*" if sc else ""
        print(f"| {name} | {n} | {tn:.2f}s{star} | {tg:.2f}s | {tm:.2f}s | {tp:.2f}s | {tmp:.2f}s | {tn / tg:.0f}x"
              f" | {st['tests_per_ray']:.1f} / {stm['tests_per_ray']:.1f} | {st['cells_per_ray']:.1f}"
              f" | {'x'.join(map(str, g['resolution']))} |")
    print("\n* brute force timed on a regular subset of rows (all cores) and scaled to the whole image and one core.")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--res", type=int, default=512)
    ap.add_argument("--scenes", nargs="*", default=SCENES)
    ap.add_argument("--none-rays", type=int, default=8192, help="eye rays to time brute force on")
    a = ap.parse_args()
    run(a.scenes, a.res, a.none_rays)


if __name__ == "__main__":
    main()
