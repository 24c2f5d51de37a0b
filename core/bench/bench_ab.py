"""Two builds of the core side by side in one process: rays per second of a base git revision
against the working tree (or a second revision), on the Embree section's scenes and rays, with
the two builds called in turn. Writes docs/build-comparison.md.

    .venv/bin/python core/bench/bench_ab.py --base HEAD~1                  # base revision vs working tree
    .venv/bin/python core/bench/bench_ab.py --base v1 --new v2 --scenes mount_s8 --rounds 7

Separate runs of one build on this shared machine differ by 10-30%, more than most changes
move a ratio; in one process, calls taking turns, load hits both builds alike. Each build gets
its own nanobind domain (NB_DOMAIN), so that both `_core` modules can load in one interpreter;
the build happens in a temporary folder (cmake and ninja from the test extras).
"""
from __future__ import annotations

import argparse
import importlib
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import gridwalk as gw  # noqa: E402
from bench_common import ROOT, Sizes, log, machine_info, table  # noqa: E402
from bench_embree import KINDS, geomean, scenes_for, shadow_rays  # noqa: E402
from bench_meshes import LABELS, export_suzanne  # noqa: E402
from gridwalk.validate import ray_sets  # noqa: E402

GEOMETRY = ("vertices", "triangles", "sphere_centers", "sphere_radii", "cylinder_base", "cylinder_apex",
            "cylinder_base_radius", "cylinder_apex_radius")
MARK = "nanobind_add_module(_core NB_STATIC"


def build_package(rev: str | None, name: str, tmp: Path) -> Path:
    """Builds the core of git revision rev (None: the working tree) as package gw_<name> under tmp/pkgs."""
    src = tmp / f"src_{name}"
    src.mkdir()
    if rev is None:
        shutil.copytree(ROOT / "core", src / "core")
    else:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "core"], check=True, capture_output=True)
        subprocess.run(["tar", "-x", "-C", str(src)], input=archive.stdout, check=True)
    cmake_file = src / "core" / "CMakeLists.txt"
    text = cmake_file.read_text()
    if MARK not in text:
        raise SystemExit(f"{rev or 'working tree'}: core/CMakeLists.txt has no '{MARK}' line to give a domain")
    cmake_file.write_text(text.replace(MARK, f"{MARK} NB_DOMAIN gw_{name}"))
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    build = tmp / f"build_{name}"
    subprocess.run(["cmake", "-S", str(src / "core"), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                    f"-DPython_EXECUTABLE={sys.executable}"], check=True, env=env, capture_output=True)
    subprocess.run(["cmake", "--build", str(build), "-j", str(os.cpu_count() or 1)], check=True, env=env,
                   capture_output=True)
    package = tmp / "pkgs" / f"gw_{name}"
    shutil.copytree(src / "core" / "python" / "gridwalk", package)
    for so in build.glob("_core*.so"):
        shutil.copy(so, package)
    return package


def timed(fn) -> float:
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def compare(mods, kw, rays, rounds) -> dict:
    """{kind: {"rate": [Mrays/s per build], "cells": [...], "tests": [...]}, "build": [s per build]}."""
    geometry = {k: kw[k] for k in GEOMETRY if k in kw}
    scenes, builds = [], []
    for m in mods:
        t0 = time.perf_counter()
        s = m.Scene(**geometry)
        s.grid_info()
        builds.append(time.perf_counter() - t0)
        scenes.append(s)
    out = {"build": builds}
    for kind in KINDS:
        o, d, tmax = rays[kind]
        best = [np.inf] * len(mods)
        stats = []
        for m, s in zip(mods, scenes):   # statistics once per build, closest-hit query (as bench_embree)
            h = s.intersect(o, d, tmin=0.0, tmax=tmax, spawned=kind == "shadow", settings=m.RenderSettings(threads=1))
            stats.append((h.stats["cells"] / len(o), h.stats["prim_tests"] / len(o)))
        for _ in range(rounds):
            for i, (m, s) in enumerate(zip(mods, scenes)):
                one = m.RenderSettings(threads=1)
                if kind == "shadow":
                    best[i] = min(best[i], timed(lambda: s.occluded(o, d, tmax=tmax, spawned=True, settings=one)))
                else:
                    best[i] = min(best[i], timed(lambda: s.intersect(o, d, tmin=0.0, tmax=tmax, settings=one)))
        out[kind] = {"rate": [len(o) / b / 1e6 for b in best], "cells": [c for c, _ in stats],
                     "tests": [t for _, t in stats]}
        log(f"  {kind}: " + " / ".join(f"{r:.2f}" for r in out[kind]["rate"]) + " Mrays/s")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", required=True, help="git revision of the base build")
    ap.add_argument("--new", default=None, help="git revision of the new build (default: the working tree)")
    ap.add_argument("--scenes", nargs="+", default=["scan_on_plane", "balls_s4", "mount_s6", "mount_s8"])
    ap.add_argument("--rays", type=int, default=512 * 512)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--out", default=str(ROOT / "docs"))
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    names = ("base", "new")
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        (tmp / "pkgs").mkdir()
        for rev, name in zip((args.base, args.new), names):
            log(f"building {rev or 'the working tree'}")
            build_package(rev, name, tmp)
        sys.path.insert(0, str(tmp / "pkgs"))
        mods = [importlib.import_module(f"gw_{n}") for n in names]
        sizes = Sizes.make(False)
        sizes.embree_scenes = tuple(args.scenes)
        wants_suzanne = any(s in ("suzanne", "scan_on_plane", "scans_on_floor") for s in args.scenes)
        suzanne = export_suzanne(tmp, [1, 3]) if wants_suzanne else None
        rows, ratios = [], {k: [] for k in KINDS}
        for name, kw, gw_kw in scenes_for(sizes, suzanne):   # (gw_kw: an analytic variant's own primitives)
            log(name)
            tri_scene = gw.Scene(vertices=kw["vertices"], triangles=kw["triangles"], camera=kw["camera"])
            rays = ray_sets(kw, args.rays, seed=1, scene=tri_scene)
            rays["shadow"] = shadow_rays(tri_scene, kw, *rays["primary"][:2], args.rays, np.random.default_rng(2))
            r = compare(mods, gw_kw or kw, rays, args.rounds)
            for kind in KINDS:
                k = r[kind]
                ratio = k["rate"][1] / k["rate"][0]
                ratios[kind].append(ratio)
                rows.append([LABELS.get(name, name), kind, f"{k['rate'][0]:.2f}", f"{k['rate'][1]:.2f}",
                             f"**{ratio:.2f}**", f"{k['cells'][0]:.1f} / {k['cells'][1]:.1f}",
                             f"{k['tests'][0]:.1f} / {k['tests'][1]:.1f}"])
            rows.append([LABELS.get(name, name), "build", f"{r['build'][0]:.3f} s", f"{r['build'][1]:.3f} s",
                         f"{r['build'][0] / r['build'][1]:.2f}", "", ""])
    revs = [subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", rev], capture_output=True, text=True,
                           check=True).stdout.strip() if rev else "working tree" for rev in (args.base, args.new)]
    info = machine_info()
    lines = ["# Build comparison", "",
             f"Generated by `.venv/bin/python core/bench/bench_ab.py --base {args.base}"
             f"{' --new ' + args.new if args.new else ''}` in {(time.perf_counter() - t_start) / 60:.1f} minutes: "
             f"base = {revs[0]}, new = {revs[1]}. Both builds are loaded in one process and called in turn, "
             f"{args.rounds} rounds, best kept; rays per second are rays / process CPU time of one call, one thread, "
             "the Embree section's rays (benchmarks.md, section 2). Ratio = new / base (above 1: new is faster; "
             "for the build row, base time / new time). Cells and tests per ray: base / new (shadow rays counted "
             "by a closest-hit query).", "",
             f"**Machine:** {info.get('cpu', '')}, Python {info.get('python', '')}; load average at the end "
             f"{os.getloadavg()[0]:.2f}.", "",
             "**Geometric mean of new / base:** " + ", ".join(f"{k} {geomean(v):.2f}" for k, v in ratios.items()), ""]
    lines += table(["scene", "rays", "base Mrays/s", "new Mrays/s", "new / base", "cells per ray", "tests per ray"],
                   rows)
    out = Path(args.out) / "build-comparison.md"
    out.write_text("\n".join(lines))
    log(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
