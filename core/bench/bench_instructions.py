"""Instructions per ray, Gridwalk against Embree, counted by valgrind's callgrind: the same
rays as the Embree section of benchmarks.md, on the same scenes. Writes docs/instruction-counts.md.

    .venv/bin/python core/bench/bench_instructions.py                       # the Embree suite, 16,384 rays a kind
    .venv/bin/python core/bench/bench_instructions.py --scenes mount_s8 suzanne --rays 4096

Timings on this shared machine move by 10-30% between runs, more than most changes to the walk;
instruction counts do not move at all (the same binary, rays and inputs give the same count). They
leave out what memory costs (cache misses), so they complement the timed ratios, not replace them.

Each scene is built in a child process that runs under callgrind with instrumentation off (so the
builds run at near-native speed); around each query (Gridwalk's Scene.intersect / Scene.occluded
with one thread, embreex's EmbreeScene.run), the parent turns it on with callgrind_control, then
dumps and reads the count. For Embree the count is also split: the whole call (embreex's loop over
the rays, which copies each ray in and each hit out) and the part inside rtcIntersect1 /
rtcOccluded1 (its traversal), which libembree's exported symbols let callgrind_annotate attribute.
Gridwalk's module is stripped, so only its whole call is counted.

Needs valgrind (Debian: apt-get install valgrind) and embreex.
"""
from __future__ import annotations

import argparse
import glob
import json
import os
import pickle
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_common import ROOT, Sizes, log, machine_info, table  # noqa: E402
from bench_meshes import LABELS  # noqa: E402

KINDS = ("primary", "shadow", "random")


# -- the child: builds one scene and answers "go" with one query at a time -----------------------

def child(job: Path) -> None:
    import gridwalk as gw
    from gridwalk.validate import embree_intersect, embree_scene

    spec = pickle.loads(job.read_bytes())
    kw, gw_kw, rays = spec["kw"], spec["gw_kw"], spec["rays"]
    scene = gw.Scene(**gw_kw)
    scene.grid_info()                                             # build the default structure now
    em = embree_scene(kw["vertices"], kw["triangles"])
    embree_intersect(em, np.zeros((1, 3)), np.ones((1, 3)))       # commit (builds the BVH)
    one = gw.RenderSettings(threads=1)
    for engine in ("gridwalk", "embree"):
        for kind, count in ((k, c) for k in KINDS for c in (1, len(rays[k][0]))):
            o, d, tmax = (a[:count] for a in rays[kind])   # one ray first: the call's own cost
            if engine == "gridwalk":
                if kind == "shadow":
                    run = lambda: scene.occluded(o, d, tmax=tmax, spawned=True, settings=one)  # noqa: E731
                else:
                    run = lambda: scene.intersect(o, d, tmin=0.0, tmax=tmax, settings=one)  # noqa: E731
            else:
                oc, dc, tc = o.copy(), d.copy(), tmax.copy()   # embreex wants writable arrays: copied before
                if kind == "shadow":
                    run = lambda: em.run(oc, dc, dists=tc, query="OCCLUDED")  # noqa: E731
                else:
                    run = lambda: em.run(oc, dc, dists=tc, output=1)  # noqa: E731
            if count == 1:
                run()   # a first call, not counted: whatever the first query of a kind sets up
            print(f"ready {engine} {kind} {len(o)}", flush=True)
            sys.stdin.readline()
            run()
            print("done", flush=True)
            sys.stdin.readline()
    print("end", flush=True)


# -- the parent -----------------------------------------------------------------------------------

def geomean(values) -> float:
    return float(np.exp(np.mean(np.log(values))))


def control(pid: int, *args: str) -> None:
    subprocess.run(["callgrind_control", *args, str(pid)], check=True, capture_output=True, timeout=120)


def totals(dump: str) -> tuple[int, dict]:
    """(instructions in the dump, {function: inclusive instructions} for Embree's entry points)."""
    total = 0
    for line in open(dump):
        if line.startswith("totals:"):
            total = int(line.split()[1])
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", dump], capture_output=True,
                         text=True).stdout
    inside = {}
    for line in ann.splitlines():
        for name in ("rtcIntersect1", "rtcOccluded1"):
            if f":{name} " in line or line.rstrip().endswith(f":{name}"):
                inside[name] = int(line.split()[0].replace(",", ""))
    return total, inside


def measure_scene(name: str, kw: dict, gw_kw: dict, rays: dict, tmp: Path) -> dict:
    job = tmp / f"{name}.pkl"
    job.write_bytes(pickle.dumps({"kw": kw, "gw_kw": gw_kw, "rays": rays}))
    out_pattern = str(tmp / f"cg_{name}.%p")
    cmd = ["valgrind", "--tool=callgrind", "--instr-atstart=no", f"--callgrind-out-file={out_pattern}",
           sys.executable, str(Path(__file__).resolve()), "--child", str(job)]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(ROOT / "core" / "bench"))
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    results, single = {}, {}
    try:
        while True:
            line = proc.stdout.readline()
            if not line:
                raise RuntimeError(f"{name}: the child ended early:\n{proc.stderr.read()[-3000:]}")
            words = line.split()
            if words[0] == "end":
                break
            if words[0] != "ready":
                continue
            _, engine, kind, n = words
            n = int(n)
            before = set(glob.glob(str(tmp / f"cg_{name}.*")))
            control(proc.pid, "-i", "on")      # (counters are zero: instrumentation was off since the last dump)
            proc.stdin.write("go\n")
            proc.stdin.flush()
            if proc.stdout.readline().split()[:1] != ["done"]:
                raise RuntimeError(f"{name} {engine} {kind}: no answer from the child")
            control(proc.pid, "-i", "off")
            control(proc.pid, "-d", f"{engine}-{kind}")
            dumps = sorted(set(glob.glob(str(tmp / f"cg_{name}.*"))) - before, key=os.path.getmtime)
            total, inside = totals(dumps[-1])
            inside = sum(inside.values())
            if n == 1:
                single[(engine, kind)] = (total, inside)
            else:   # per ray beyond the first: the call's fixed cost (Python wrappers, arrays) left out
                t1, i1 = single[(engine, kind)]
                results[(engine, kind)] = {"total": (total - t1) / (n - 1),
                                           "inside": (inside - i1) / (n - 1) if inside else None,
                                           "call": t1}
                log(f"  {name} {engine} {kind}: {(total - t1) / (n - 1):.0f} instructions per ray, "
                    f"{t1:,} for a call of one ray")
            proc.stdin.write("next\n")
            proc.stdin.flush()
    finally:
        proc.stdin.close()
        proc.wait(timeout=600)
    return results


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--scenes", nargs="+", default=list(Sizes.make(False).embree_scenes))
    ap.add_argument("--rays", type=int, default=16384, help="rays of each kind (an even sample of the 512 x 512 set)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs")
    args = ap.parse_args(argv)
    if args.child:
        child(args.child)
        return 0
    for tool in ("valgrind", "callgrind_control", "callgrind_annotate"):
        if not shutil.which(tool):
            raise SystemExit(f"{tool} not found: apt-get install valgrind")
    from bench_embree import scenes_for, shadow_rays
    from bench_meshes import export_suzanne
    import gridwalk as gw
    from gridwalk.validate import ray_sets

    t_start = time.perf_counter()
    sizes = Sizes.make(False)
    sizes.embree_scenes = tuple(args.scenes)
    rows, info = [], machine_info()
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        wants_suzanne = any(s in ("suzanne", "scan_on_plane", "scans_on_floor") for s in args.scenes)
        suzanne = export_suzanne(tmp, [1, 3]) if wants_suzanne else None
        for name, kw, gw_kw in scenes_for(sizes, suzanne):
            log(name)
            tri = gw.Scene(vertices=kw["vertices"], triangles=kw["triangles"], camera=kw["camera"])
            full = ray_sets(kw, sizes.embree_rays, seed=1, scene=tri)
            full["shadow"] = shadow_rays(tri, kw, *full["primary"][:2], sizes.embree_rays, np.random.default_rng(2))
            rays = {}
            for kind, (o, d, tmax) in full.items():
                pick = np.linspace(0, len(o) - 1, min(args.rays, len(o))).astype(np.int64)   # an even sample
                rays[kind] = (o[pick], d[pick], tmax[pick])
            geometry = gw_kw or {k: kw[k] for k in ("vertices", "triangles")}
            r = measure_scene(name, {k: kw[k] for k in ("vertices", "triangles")}, geometry, rays, tmp)
            for kind in KINDS:
                g, e = r[("gridwalk", kind)], r[("embree", kind)]
                inside = e["inside"]
                rows.append([LABELS.get(name, name), kind, f"{len(rays[kind][0]):,}", f"{g['total']:.0f}",
                             f"{g['call']:,}", f"{e['total']:.0f}", f"{e['call']:,}",
                             "-" if inside is None else f"{inside:.0f}",
                             f"**{g['total'] / e['total']:.2f}**",
                             "-" if not inside else f"{g['total'] / inside:.2f}"])
    minutes = (time.perf_counter() - t_start) / 60
    summary = []
    for kind in KINDS:
        whole = [float(r[8].strip("*")) for r in rows if r[1] == kind]
        traversal = [float(r[9]) for r in rows if r[1] == kind and r[9] != "-"]
        summary.append([kind, f"**{geomean(whole):.2f}**", f"{min(whole):.2f}-{max(whole):.2f}",
                        f"{geomean(traversal):.2f}" if traversal else "-"])
    lines = [
        "# Instructions per ray: Gridwalk and Embree", "",
        f"Generated by `.venv/bin/python core/bench/bench_instructions.py` in {minutes:.1f} minutes "
        f"(gridwalk {info['gridwalk']}, embreex {info['embreex']}, {info['cpu']}). Counted by valgrind's callgrind "
        "around each query, on an even sample of the rays of [benchmarks.md](benchmarks.md)'s Embree section "
        "(the same scenes, rays and queries: Gridwalk's `Scene.intersect` / `Scene.occluded(..., spawned=True)` "
        "with one thread and the default structure, embreex's `EmbreeScene.run`). Counts are exact and repeat "
        "from run to run; they leave out what memory costs, which the timed ratios include.", "",
        "*Per ray* is the count of a call of all the rays less that of a call of one ray, over the rays "
        "beyond the first: the calls' fixed costs (Python wrappers, output arrays), also listed, are left out. "
        "Embree's per ray counts embreex's loop too (it copies each ray in and each hit out); *inside "
        "rtcIntersect1 / rtcOccluded1* is Embree's own traversal. Gridwalk's per ray is its batch loop, walk "
        "and hit record (its module is stripped, so it is not split further). Ratios above 1: Gridwalk "
        "executes more instructions per ray.", "",
    ]
    lines += ["Geometric means over the scenes (Gridwalk's instructions per ray over Embree's):", ""]
    lines += table(["ray kind", "over Embree's whole call", "range", "over Embree's traversal"], summary)
    lines += table(["scene", "ray kind", "rays", "Gridwalk per ray", "Gridwalk, a call of one ray", "Embree per ray",
                    "Embree, a call of one ray", "Embree per ray inside rtcIntersect1 / rtcOccluded1",
                    "Gridwalk / Embree", "Gridwalk / Embree's traversal"], rows)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "instruction-counts.md").write_text("\n".join(lines))
    log(f"wrote {args.out / 'instruction-counts.md'} ({minutes:.1f} min)")
    print(json.dumps({"rows": rows}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
