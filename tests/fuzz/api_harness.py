"""The fuzz target of the Python/C++ API (fuzz_api.py, and the regression test
that replays inputs without atheris).

One input is a byte string read as a small program of operations on the
public API. Every operation starts from a valid call and the bytes mutate it
(all-zero bytes mean no mutation), so most programs get deep into the core
and each byte can push one value, shape or dtype to an extreme:

  settings   RenderSettings with drawn values, converted for the core
  scene      a Scene: a small valid mesh, spheres, a cylinder, materials, a
             light and a camera, with drawn mutations of arrays and records
  rays       intersect / occluded / spawn_origins on the last scene: rays
             aimed at it, or with extreme origins, directions, tmin, tmax
  job        a RenderJob on the last scene (at most 8 x 8 pixels), driven by a
             drawn sequence of start, poll, cancel, wait, progress, stats, wait_for and
             del calls, some from a second thread

ValueError (and RuntimeError for calls out of order, BuildCancelled) is a
clean refusal; anything else escaping, a crash, a hang or a sanitizer report
is a finding. So is a silently wrong answer: every intersect / occluded call
that is answered is asked again with brute force (accel="none", same rays,
limits and flags), and the two must agree exactly (WrongResult).

COUNTS tallies, per entry point, the calls answered and refused; with
GRIDWALK_FUZZ_COUNTS=FILE set, run_bytes writes them there as JSON every 200
inputs (for the counts in docs/robustness.md).
"""
from __future__ import annotations

import dataclasses
import json
import os
import struct
import threading
from collections import Counter

import numpy as np

import gridwalk as gw
from gridwalk.settings import SCHEMA

SPECIAL = (0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 1e-45, -1e-45, 1e-40, 1e-38, 1e-20, 1e-9, 1e9, 1e20, 1e30, -1e30,
           3e38, -3e38, float("inf"), float("-inf"), float("nan"), 179.999999, 180.0, 2**24 + 1, 2**31, -2**31)
INTS = (0, 1, -1, 2, 3, 7, 8, 255, 256, 4096, 2**16, 2**24 + 1, 2**31 - 1, 2**31, 2**32, -2**31 - 1, 2**63, 2**64)
DTYPES = (np.float16, np.uint8, np.int64, np.float64, object, np.complex64, np.bool_)
REFUSALS = (ValueError, RuntimeError, gw.BuildCancelled)
COUNTS: Counter = Counter()
COUNTS_FILE = os.environ.get("GRIDWALK_FUZZ_COUNTS")


COMPARED = "ray queries that agreed with brute force"   # a COUNTS key


class WrongResult(AssertionError):
    """A ray query answered differently by an acceleration structure and by brute force."""


def counted(entry: str, fn, *args, **kwargs):
    """fn(*args, **kwargs), tallied in COUNTS as entry answered / refused."""
    try:
        out = fn(*args, **kwargs)
    except REFUSALS:
        COUNTS[f"{entry}: refused"] += 1
        raise
    COUNTS[f"{entry}: answered"] += 1
    return out


class Input:
    """Values drawn from the bytes, deterministically; zeros once they run out."""

    def __init__(self, data: bytes):
        self.data, self.pos = data, 0

    def byte(self) -> int:
        b = self.data[self.pos] if self.pos < len(self.data) else 0
        self.pos += 1
        return b

    def done(self) -> bool:
        return self.pos >= len(self.data)

    def below(self, n: int) -> int:
        return self.byte() % n if n > 0 else 0

    def pick(self, seq):
        return seq[self.below(len(seq))]

    def real(self) -> float:
        if self.byte() < 200:
            return self.pick(SPECIAL)
        return float(struct.unpack("<f", bytes(self.byte() for _ in range(4)))[0])

    def integer(self) -> int:
        return self.pick(INTS)


# -- settings ---------------------------------------------------------------------

def draw_value(inp: Input, s):
    if s.kind == "enum":
        return inp.pick((*s.ids, "", "GRID", 3, None))
    if s.kind == "bool":
        return inp.pick((True, False, 0, 1, "no", None))
    if s.kind == "region":
        return inp.pick((None, (0, 0, 4, 4), (2, 3, 1, 1), (0, 0, 0, 0), (-1, 0, 2, 2), (0, 0, 2**31, 4),
                         (0, 0, 4), (7, 7, 100, 100)))
    return inp.pick((inp.integer(), inp.real(), s.min, s.max, s.default))


def draw_settings(inp: Input) -> gw.RenderSettings:
    """Defaults (one thread) with up to 3 drawn changes."""
    values = {"threads": 1}
    for _ in range(inp.below(4)):
        s = inp.pick(SCHEMA)
        values[s.name] = draw_value(inp, s)
    # The scenes' declared copies (with_copies) are far below "auto"'s 2^20 triangles:
    # mostly "on", so that the instanced grid is what the queries walk.
    if "instancing" not in values and inp.byte() < 160:
        values["instancing"] = "on"
    # Keep each input fast: few threads, few samples (the limits are the
    # settings test's business).
    for name, most in (("threads", 4), ("aa_samples", 3), ("shadow_samples", 3), ("dof_samples", 3),
                       ("glossy_samples", 3), ("max_depth", 4), ("adaptive_depth", 3)):
        v = values.get(name)
        if isinstance(v, (int, float)) and not isinstance(v, bool) and v == v and v > most:
            values[name] = most
    return gw.RenderSettings(**values)


# -- scenes -----------------------------------------------------------------------

def base_scene() -> dict:
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.5], [0, 0, 1]], np.float32)
    F = np.array([[0, 1, 2], [1, 3, 2], [0, 2, 4], [0, 4, 1]], np.int32)
    return dict(vertices=V, triangles=F, normals=None, triangle_materials=np.array([0, 1, 0, 1], np.int32),
                sphere_centers=np.array([[2, 0, 0.5], [-1, 1, 0.5]], np.float32),
                sphere_radii=np.array([0.5, 0.25], np.float32), sphere_materials=None,
                cylinder_base=np.array([[0, -2, 0]], np.float32), cylinder_apex=np.array([[0, -2, 1]], np.float32),
                cylinder_base_radius=np.array([0.3], np.float32), cylinder_apex_radius=np.array([0.1], np.float32),
                cylinder_materials=None,
                materials=[gw.Material(), gw.Material(color=(1, 0.5, 0.2), mirror=0.3, transmittance=0.2, ior=1.4)],
                lights=[gw.Light(position=(3, -4, 5)), gw.Light(kind="sphere", position=(-2, -3, 4), radius=0.5)],
                camera=gw.Camera(eye=(0.5, -4, 2), target=(0.5, 0.5, 0.3), width=6, height=5),
                background=(0.1, 0.2, 0.3))


ARRAYS = ("vertices", "triangles", "normals", "triangle_materials", "sphere_centers", "sphere_radii",
          "sphere_materials", "cylinder_base", "cylinder_apex", "cylinder_base_radius", "cylinder_apex_radius",
          "cylinder_materials")


def mutate_array(inp: Input, a):
    kind = inp.below(6)
    if a is None:
        return np.zeros((inp.below(4), 3), np.float32) if kind < 3 else None
    a = np.array(a)
    if kind == 0 and a.size:                       # one extreme value
        flat = a.astype(np.float64 if a.dtype.kind == "f" else object).reshape(-1)
        flat[inp.below(flat.size)] = inp.real() if a.dtype.kind == "f" else inp.integer()
        try:
            with np.errstate(all="ignore"):
                return flat.reshape(a.shape).astype(a.dtype)
        except (OverflowError, ValueError, TypeError):
            return flat.reshape(a.shape)
    if kind == 1:                                   # another shape
        return np.resize(a, inp.pick(((0,), (a.shape[0], 4), (a.shape[0], 3, 1), (1,), (a.shape[0] + 1, 3))))
    if kind == 2:                                   # another dtype
        try:
            with np.errstate(all="ignore"):
                return a.astype(inp.pick(DTYPES))
        except (OverflowError, TypeError, ValueError):   # e.g. an object array holding -1, to uint8
            return a
    if kind == 3:                                   # empty
        return a[:0]
    if kind == 4:                                   # a repeated row (coincident primitives)
        return np.concatenate([a, a[:1]]) if a.size else a
    return a.tolist()                               # a list instead of an array


def mutate_record(inp: Input, record):
    fields = dataclasses.fields(record)
    f = inp.pick(fields)
    value = getattr(record, f.name)
    if isinstance(value, tuple):
        new = tuple(inp.real() if inp.byte() < 128 else x for x in value)
        if inp.byte() > 240:
            new = new[:-1]
    elif isinstance(value, bool):
        new = inp.pick((not value, 1, "yes"))
    elif isinstance(value, str):
        new = inp.pick((*gw.model.LIGHT_KINDS, "laser", ""))
    elif isinstance(value, int):
        new = inp.integer() if inp.byte() < 60 else 1 + inp.below(8)
    else:
        new = inp.real() if inp.byte() < 230 else None
    return dataclasses.replace(record, **{f.name: new})


def with_copies(kw: dict, copies: int = 6) -> dict:
    """kw with `copies` copies of its first two triangles, moved along x, declared as instances
    of one mesh (Scene's instance arrays; with the first two, copies of 2 triangles each)."""
    V, F = kw["vertices"], kw["triangles"]
    piece = F[:2]
    used = np.unique(piece)
    verts, tris, matrices = [V], [F], [np.eye(4)]
    for k in range(1, copies + 1):
        m = np.eye(4)
        m[0, 3] = 3.0 * k
        start = sum(len(v) for v in verts)
        verts.append((V[used] + np.float32(3.0 * k)*np.array([1, 0, 0], np.float32)).astype(np.float32))
        tris.append(np.searchsorted(used, piece).astype(np.int32) + start)
        matrices.append(m)
    out = dict(kw, vertices=np.concatenate(verts), triangles=np.concatenate(tris))
    out["triangle_materials"] = None
    out["instance_triangles"] = np.array([[0, 2]] + [[len(F) + 2 * (k - 1), 2] for k in range(1, copies + 1)])
    out["instance_meshes"] = np.zeros(copies + 1, np.int32)
    out["instance_matrices"] = np.array(matrices)
    return out


INSTANCE_ARRAYS = ("instance_triangles", "instance_meshes", "instance_matrices")


def draw_scene(inp: Input) -> gw.Scene:
    kw = base_scene()
    if inp.byte() < 64:                       # copies of a mesh, declared (the instanced grid)
        kw = with_copies(kw, 1 + inp.below(8))
        for _ in range(inp.below(3)):
            name = inp.pick(INSTANCE_ARRAYS)
            kw[name] = mutate_array(inp, kw[name])
    for _ in range(inp.below(4)):
        target = inp.below(len(ARRAYS) + 4)
        if target < len(ARRAYS):
            kw[ARRAYS[target]] = mutate_array(inp, kw[ARRAYS[target]])
        elif target == len(ARRAYS):
            kw["materials"] = [mutate_record(inp, m) for m in kw["materials"]]
        elif target == len(ARRAYS) + 1:
            kw["lights"] = [mutate_record(inp, l) for l in kw["lights"]]
        elif target == len(ARRAYS) + 2:
            kw["camera"] = mutate_record(inp, kw["camera"])
        else:
            kw["background"] = (inp.real(), 0.0, 0.0)
    return gw.Scene(**kw)


# -- rays and jobs ----------------------------------------------------------------

def draw_rays(inp: Input, scene: gw.Scene):
    n = 1 + inp.below(16)
    rng = np.random.default_rng(inp.byte())
    lo, hi = scene.bounds
    o = np.tile(np.asarray(scene.camera.eye, np.float64), (n, 1))
    d = rng.uniform(lo, hi, (n, 3)) - o          # aimed at the scene's box
    for _ in range(inp.below(6)):               # extreme components
        arr = o if inp.byte() < 100 else d
        arr[inp.below(n), inp.below(3)] = inp.real()
    with np.errstate(all="ignore"):
        o32, d32 = o.astype(np.float32), d.astype(np.float32)
    tmin = inp.pick((0.0, 0.0, 0.0, inp.real(), np.full(n, inp.real())))
    tmax = inp.pick((np.inf, np.inf, np.inf, inp.real(), np.full(n, inp.real())))
    settings = draw_settings(inp)
    spawned = inp.byte() > 200
    op = inp.below(3)
    limits = dict(tmin=tmin, tmax=tmax, spawned=spawned)
    if op < 2 and settings.accel != "none" and scene.grid_info(settings)["kind"] == "instanced adaptive grid":
        # Copies are met as their mesh's first copy moved into their place (instanced_grid.h):
        # the same hits to within float rounding, not to the bit. Run, do not compare.
        query = scene.intersect if op == 0 else scene.occluded
        counted("Scene.intersect" if op == 0 else "Scene.occluded", query, o32, d32, settings=settings, **limits)
        COUNTS["instanced queries"] += 1
        return
    if op == 0:
        hits = counted("Scene.intersect", scene.intersect, o32, d32, settings=settings, **limits)
        ref = scene.intersect(o32, d32, settings=settings.replace(accel="none"), **limits)
        if not (np.array_equal(hits.t, ref.t) and np.array_equal(hits.prim, ref.prim)
                and np.array_equal(hits.kind, ref.kind)):
            raise WrongResult(f"{settings.accel} and brute force differ: t {hits.t} vs {ref.t}, "
                              f"prim {hits.prim} vs {ref.prim}; o={o32.tolist()} d={d32.tolist()} {limits}")
        COUNTS[COMPARED] += 1
    elif op == 1:
        occ = counted("Scene.occluded", scene.occluded, o32, d32, settings=settings, **limits)
        ref = scene.occluded(o32, d32, settings=settings.replace(accel="none"), **limits)
        if not np.array_equal(occ, ref):
            raise WrongResult(f"{settings.accel} and brute force differ: occluded {occ} vs {ref}; "
                              f"o={o32.tolist()} d={d32.tolist()} {limits}")
        COUNTS[COMPARED] += 1
    else:
        hits = scene.intersect(o32, d32, settings=gw.RenderSettings(threads=1))
        counted("Scene.spawn_origins", scene.spawn_origins, o32, d32, hits, d32[::-1].copy())


def _quiet(fn):
    def run():
        try:
            fn()
        except REFUSALS:
            pass
    return run


def drive_job(inp: Input, scene: gw.Scene):
    if scene.camera.width * scene.camera.height > 64:   # keep each input fast: small images only
        return
    job = counted("RenderJob()", gw.RenderJob, scene, draw_settings(inp))
    COUNTS["RenderJob call sequences"] += 1
    helper = None
    for _ in range(1 + inp.below(8)):
        op = inp.below(8)
        try:
            if op == 0:
                job.start()
            elif op == 1:
                job.poll()
            elif op == 2:
                job.cancel()
            elif op == 3:
                job.wait()
            elif op == 4:
                _ = job.progress, job.finished, job.cancelled, job.tiles_done
            elif op == 5:
                _ = job.stats
                job.wait_for((-1.0, 0.0, 0.001, float("nan"), float("inf"))[inp.below(5)])
            elif op == 6 and helper is None:   # cancel or wait from another thread
                helper = threading.Thread(target=_quiet(job.cancel if inp.byte() < 128 else job.wait))
                helper.start()
            else:
                _ = job.image, job.depth, job.normal
        except REFUSALS:
            pass
    if helper is not None:
        helper.join()
    if inp.byte() < 128:
        del job


def run_bytes(data: bytes) -> int:
    """Run one input; returns the number of operations refused cleanly."""
    inp = Input(data)
    scene = None
    refused = 0
    for _ in range(6):
        if inp.done():
            break
        op = inp.below(5)
        try:
            if op == 0:
                counted("RenderSettings", lambda: draw_settings(inp).to_core())
            elif op == 1 or scene is None:
                scene = counted("Scene() with Camera/Light/Material", draw_scene, inp)
            elif op in (2, 3):
                draw_rays(inp, scene)
            else:
                drive_job(inp, scene)
        except REFUSALS:
            refused += 1
    COUNTS["inputs"] += 1
    if COUNTS_FILE and COUNTS["inputs"] % 200 == 0:
        with open(COUNTS_FILE, "w") as f:
            json.dump(dict(COUNTS), f, indent=1, sort_keys=True)
    return refused
