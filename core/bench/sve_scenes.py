"""The four effect scenes of bench_speed_vs_error.py, and their strategies.

Each scene isolates one effect, built from the public API:

  edges     self-lit shapes with hard edges on black (a big triangle, a
            sphere, a fan of thin wedges whose tips are sub-pixel): anti-aliasing;
            "edges-plain" is the same without the fan (only smooth edges).
  penumbra  a camera between a floor and two occluders looks straight down at
            the floor, lit by a rect area light: only the soft shadow varies,
            no geometric edge is in view.
  dof       gridwalk.scenes.distant(), the seed's "Distant" scene.
  glossy    gridwalk.scenes.balls(1) with rough (roughness 0.3) mirror balls
            and a rough mirror floor.

A strategy is label -> {n: RenderSettings changes}; n is the sample-count
parameter shown in the tables (n of n x n for the n x n modes, k for k rays,
d for the adaptive depth).
"""
from __future__ import annotations

import math

import gridwalk as gw
from gridwalk import scenes


def _camera(cam, res):
    cam.width = cam.height = res
    return cam


EDGE_COLOURS = ((0, 0, 0), (1, 1, 1), (1, 0.25, 0.1), (0.2, 0.5, 1.0))   # background + 3 emitters


def edges(res, fan=True):
    """Self-lit flat colours on black: every pixel value is a coverage fraction."""
    white, red, blue = (gw.Material(color=c, kd=0.0, emission=1.0) for c in EDGE_COLOURS[1:])
    V = [(-2.2, 0, -1.9), (0.4, 0, -0.9), (-1.2, 0, 0.6)]          # a tilted triangle
    F, M = [(0, 1, 2)], [0]
    cx, cz, r, k = 0.9, 0.9, 1.1, 18                                  # a fan of k thin wedges
    for i in range(k if fan else 0):
        a0, a1 = 2 * math.pi * i / k, 2 * math.pi * (i + 0.5) / k
        base = len(V)
        V += [(cx, 0, cz), (cx + r * math.cos(a0), 0, cz + r * math.sin(a0)),
              (cx + r * math.cos(a1), 0, cz + r * math.sin(a1))]
        F.append((base, base + 1, base + 2))
        M.append(2)
    cam = gw.Camera(eye=(0, -6, 0), target=(0, 0, 0), up=(0, 0, 1), fov=40, width=res, height=res)
    return gw.Scene(vertices=V, triangles=F, triangle_materials=M, sphere_centers=[(1.0, 0.5, -1.1)],
                    sphere_radii=[0.75], sphere_materials=[1], materials=[white, red, blue], camera=cam)


def penumbra(res):
    floor = [(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)]
    c, s = math.cos(0.5), math.sin(0.5)                                # a square card turned 0.5 rad
    card = [(-0.8 + 0.7 * (c * x - s * y), 0.4 + 0.7 * (s * x + c * y), 1.8)
            for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    light = gw.Light(kind="rect", position=(0.3, -0.2, 5.0), size=(1.6, 0.8), axis_u=(1, 0, 0),
                     axis_v=(0, 1, 0), direction=(0, 0, -1), color=(1.0, 0.95, 0.85))
    cam = gw.Camera(eye=(0, 0, 1.5), target=(0, 0, 0), up=(0, 1, 0), fov=100, width=res, height=res)
    return gw.Scene(vertices=floor + card, triangles=[(0, 1, 2), (0, 2, 3), (4, 5, 6), (4, 6, 7)],
                    sphere_centers=[(0.9, -0.6, 2.1)], sphere_radii=[0.45],
                    materials=[gw.Material(color=(0.9, 0.9, 0.9), kd=1.0)], lights=[light], camera=cam)


def dof(res):
    kw = scenes.distant()
    _camera(kw["camera"], res)
    return gw.Scene(**kw)


def glossy(res):
    kw = scenes.balls(1)
    floor, ball = kw["materials"]
    floor.mirror, floor.roughness = 0.4, 0.3
    ball.roughness = 0.3
    _camera(kw["camera"], res)
    return gw.Scene(**kw)


def effects(quick=False):
    """name -> (title, scene builder, reference settings, baseline strategy, strategies)."""
    def pick(full, short):
        return short if quick else full
    pow2 = pick([1, 2, 4, 8, 16, 32, 64], [1, 4, 16])
    nn = pick([1, 2, 3, 4, 6, 8], [1, 2, 4])
    few = pick([1, 2, 4, 8, 16], [1, 4])
    depths = pick((1, 2, 3, 4, 5), (1, 2, 3))
    S = gw.RenderSettings
    aa = {"center (1 spp)": {1: dict(aa="center")},
          **{f"{m} n x n": {n: dict(aa=m, aa_samples=n) for n in nn} for m in ("jittered", "random", "sobol")}}
    # Every edge here has a contrast of at least 0.9 in some channel, so any threshold below 0.9 gives
    # the same image: one threshold, depths 1-5.
    aa["adaptive thr 0.1, depth d"] = {d: dict(aa="adaptive", adaptive_threshold=0.1, adaptive_depth=d)
                                       for d in depths}
    rnd = dict(shadow="random")
    shadow = {
        "random k (centre AA)": {k: dict(rnd, shadow_samples=k) for k in pow2},
        "area n x n (centre AA)": {n: dict(shadow="area", shadow_samples=n) for n in nn},
        "jittered n x n + random 1": {n: dict(rnd, aa="jittered", aa_samples=n) for n in nn},
        "jittered n x n + area n x n": {n: dict(aa="jittered", aa_samples=n, shadow="area", shadow_samples=n)
                                        for n in nn},
    }
    for thr in pick((0.05, 0.3), (0.05,)):
        shadow[f"adaptive thr {thr} + random 1, depth d"] = {
            d: dict(rnd, aa="adaptive", adaptive_threshold=thr, adaptive_depth=d) for d in depths[:4]}
    lens = {
        "lens k (centre AA)": {k: dict(dof_samples=k) for k in pow2},
        "jittered n x n, lens 1": {n: dict(aa="jittered", aa_samples=n) for n in nn},
        "sobol n x n, lens 1": {n: dict(aa="sobol", aa_samples=n) for n in nn},
        "jittered 2 x 2, lens k": {k: dict(aa="jittered", aa_samples=2, dof_samples=k) for k in few},
    }
    gloss = {
        "glossy k (centre AA)": {k: dict(glossy_samples=k) for k in pow2},
        "jittered n x n, glossy 1": {n: dict(aa="jittered", aa_samples=n) for n in nn},
        "jittered 2 x 2, glossy k": {k: dict(aa="jittered", aa_samples=2, glossy_samples=k) for k in few},
    }
    ref_aa = S(aa="jittered", aa_samples=pick(48, 16))
    return {
        "edges": ("Anti-aliasing on hard edges (with a fan of thin wedges)", edges, ref_aa,
                  "jittered n x n", aa),
        "edges-plain": ("Anti-aliasing on hard edges (no thin features)", lambda res: edges(res, fan=False),
                        ref_aa, "jittered n x n", aa),
        "penumbra": ("Soft-shadow penumbra (rect light)", penumbra,
                     S(aa="jittered", aa_samples=pick(8, 4), shadow="area", shadow_samples=pick(48, 16)),
                     "random k (centre AA)", shadow),
        "dof": ("Depth of field (the seed's Distant scene)", dof,
                S(aa="jittered", aa_samples=pick(16, 6), dof_samples=pick(8, 4)), "jittered n x n, lens 1", lens),
        "glossy": ("Glossy reflection (balls(1), roughness 0.3)", glossy,
                   S(aa="jittered", aa_samples=pick(12, 6), glossy_samples=pick(16, 4)),
                   "jittered n x n, glossy 1", gloss),
    }
