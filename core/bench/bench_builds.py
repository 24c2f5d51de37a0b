"""Build benchmark (a script, not a test): the acceleration structures on the
distributions that are worst cases for a uniform grid, against Embree's BVH
build on the same triangles; writes docs/build-benchmark.md.

    .venv/bin/python core/bench/bench_builds.py [--out docs/build-benchmark.md] [--quick] [--threads 1,2,4]

Each scene is built by the adaptive grid (the default; on all cores, and
on one thread beside it), by the seed's uniform grid and by Embree (embreex,
all threads), best of REPS builds each, taking
turns. Reported: build seconds (the core's own build clock; Embree's scene
commit), bytes per primitive, and gridwalk.memory's estimate of the structure
against what the core reports it holds. With --threads, a second table gives
the adaptive build's time on each of those thread counts (best of REPS, the
counts taking turns) beside Embree's on all: run it on as many cores as you
can get, since the CI machine has two.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import gridwalk as gw  # noqa: E402
from bench_common import ROOT, machine_info, table  # noqa: E402
from gridwalk import memory  # noqa: E402
from gridwalk.validate import embree_intersect, embree_scene  # noqa: E402

REPS = 2


def soup(tris: np.ndarray) -> dict:
    v = tris.reshape(-1, 3).astype(np.float32)
    return {"vertices": v, "triangles": np.arange(len(v), dtype=np.int32).reshape(-1, 3)}


def plane_with_dense_object(n: int) -> dict:
    """A plane of n triangles 1000 across, and a 12-triangle cube 0.1 across on it (issue 16's scene)."""
    side = int(np.sqrt(n / 2))
    g = np.linspace(-500, 500, side + 1)
    x, y = np.meshgrid(g, g)
    v = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], 1)
    i = (np.arange(side)[:, None] * (side + 1) + np.arange(side)[None, :]).ravel()
    quads = np.stack([i, i + 1, i + side + 2, i + side + 1], 1)
    t = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    cube = np.array([[x, y, z] for x in (0, .1) for y in (0, .1) for z in (0, .1)])
    ct = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
                   [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return {"vertices": np.vstack([v, cube]).astype(np.float32),
            "triangles": np.vstack([t, ct + len(v)]).astype(np.int32)}


def scenes(n: int) -> dict:
    rng = np.random.default_rng(3)
    tiny = rng.uniform(0, 1, (n, 1, 3)) + rng.normal(0, 1e-3, (n, 3, 3))
    big = np.array([[[-1e3, -1e3, 0.5], [1e3, -1e3, 0.5], [0, 1e3, 0.5]]])
    return {
        "plane + tiny dense cube": plane_with_dense_object(n),
        "every triangle at one point": soup(np.zeros((n, 3, 3))),
        "one huge triangle beside tiny ones": soup(np.concatenate([tiny, big])),
        "long thin triangles across the scene": soup(np.stack([rng.uniform(-50, 50, (n, 3)),
                                                               rng.uniform(-50, 50, (n, 3)),
                                                               rng.uniform(-50, 50, (n, 3)) + 1e-3], 1)),
        "tiny cluster, one triangle 1e5 away": soup(np.concatenate([tiny * 1e-3, [[[1e5, 0, 0], [1e5, 1, 0],
                                                                                   [1e5, 0, 1]]]])),
        "random soup (reference)": soup(rng.uniform(0, 1, (n, 1, 3)) + rng.uniform(-0.5, 0.5, (n, 3, 3))
                                        * 0.5 * n ** (-1 / 3)),
    }


def measure(kw: dict) -> dict:
    scene = gw.Scene(**kw)
    out = {"prims": scene.num_primitives}
    best = {"adaptive": None, "adaptive1": None, "grid": None, "embree": float("inf")}
    runs = {"adaptive": gw.RenderSettings(accel="adaptive"),              # all cores (threads = 0)
            "adaptive1": gw.RenderSettings(accel="adaptive", threads=1),
            "grid": gw.RenderSettings(accel="grid")}                       # (builds on one thread)
    for _ in range(REPS):
        for key, settings in runs.items():
            info = gw.Scene(**kw).grid_info(settings)
            if best[key] is None or info["build_seconds"] < best[key]["build_seconds"]:
                best[key] = info
        t0 = time.perf_counter()
        em = embree_scene(kw["vertices"], kw["triangles"])
        embree_intersect(em, np.zeros((1, 3)), np.ones((1, 3)))     # the commit builds the BVH
        best["embree"] = min(best["embree"], time.perf_counter() - t0)
    n = len(kw["triangles"])
    for accel in ("adaptive", "grid"):
        est = memory.estimate(n, len(kw["vertices"]), settings=gw.RenderSettings(accel=accel))
        out[accel] = dict(best[accel], estimate=est.grid)
    out["adaptive1"] = best["adaptive1"]
    out["embree"] = best["embree"]
    return out


def scaling(kw: dict, counts: list) -> dict:
    """The adaptive build's best time on each thread count, the counts taking turns."""
    best = {t: float("inf") for t in counts}
    for _ in range(REPS):
        for t in counts:
            info = gw.Scene(**kw).grid_info(gw.RenderSettings(accel="adaptive", threads=t))
            best[t] = min(best[t], info["build_seconds"])
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "build-benchmark.md")
    ap.add_argument("--quick", action="store_true", help="10k triangles instead of 1M (a smoke run)")
    ap.add_argument("--threads", default="", help="comma-separated thread counts for a build scaling table")
    args = ap.parse_args(argv)
    counts = [int(t) for t in args.threads.split(",")] if args.threads else []
    n = 10_000 if args.quick else 1_000_000
    info = machine_info()
    rows, worst, scaled = [], 0.0, []
    for name, kw in scenes(n).items():
        r = measure(kw)
        if counts:
            b = scaling(kw, counts)
            scaled.append([name] + [f"{b[t]:.3f} s ({b[counts[0]] / b[t]:.2f}x)" for t in counts]
                          + [f"{r['embree']:.3f} s", f"**{b[counts[-1]] / r['embree']:.2f}**"])
        a, g = r["adaptive"], r["grid"]
        ratio = a["build_seconds"] / r["embree"]
        worst = max(worst, ratio)
        a1 = r["adaptive1"]["build_seconds"]
        rows.append([name, f"{r['prims']:,}", f"{a['build_seconds']:.3f} s ({a['build_threads']})",
                     f"{a1:.3f} s ({a1 / a['build_seconds']:.2f}x)", f"{g['build_seconds']:.3f} s",
                     f"{r['embree']:.3f} s", f"**{ratio:.2f}**", f"{a['bytes'] / r['prims']:.0f}",
                     f"{g['bytes'] / r['prims']:.0f}", f"{a['estimate'] / max(a['bytes'], 1):.2f}",
                     f"{g['estimate'] / max(g['bytes'], 1):.2f}"])
        print(f"{name}: adaptive {a['build_seconds']:.3f} s, grid {g['build_seconds']:.3f} s, "
              f"embree {r['embree']:.3f} s", flush=True)
    lines = ["# Build benchmark: worst cases for a uniform grid", "",
             "Generated by `python core/bench/bench_builds.py"
             + "".join(" " + a for a in (argv if argv is not None else sys.argv[1:])) + "` on "
             f"{info['cpu']} (`nproc` = {info['nproc']}, load average {info['load'][0]:.1f} at the start; "
             "other work shared the machine, so compare the columns of one row, which were measured in turns).",
             "", f"Each scene has about {n:,} triangles. The adaptive grid builds on all cores (its default, "
             "`RenderSettings.threads` = 0; the threads it used in brackets) and, beside it, on one thread "
             f"(in brackets: how much longer that takes); the uniform grid builds on one thread, Embree on all; best of {REPS}. "
             "*Estimate / actual* is `gridwalk.memory`'s estimate of the structure divided by the bytes the "
             "core reports it holds (above 1: the estimate is on the safe side). Goal (issues 10 and 16): "
             "builds in time proportional to the scene, at most 2x Embree's, and an estimate that holds.", ""]
    lines += table(["scene", "primitives", "adaptive build (threads)", "adaptive, 1 thread", "uniform build", "Embree BVH", "adaptive / Embree",
                    "adaptive B/prim", "uniform B/prim", "adaptive estimate / actual",
                    "uniform estimate / actual"], rows)
    lines += [f"Largest adaptive / Embree build-time ratio: {worst:.2f}"
              + (" (goal: at most 2)." if worst > 2 else " (goal met: at most 2)."), ""]
    if counts:
        lines += ["## Build thread scaling", "",
                  f"The adaptive build on {', '.join(map(str, counts))} threads (in brackets: the speed-up over "
                  f"{counts[0]}), Embree on all {info['nproc']}; the last column compares the adaptive build on "
                  f"{counts[-1]} threads with Embree's.", ""]
        lines += table(["scene"] + [f"{t} thread{'s' if t > 1 else ''}" for t in counts] + ["Embree BVH", "adaptive / Embree"], scaled)
    args.out.write_text("\n".join(lines))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
