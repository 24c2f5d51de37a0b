"""Geometry for the benchmarks: scenes by name, tessellated spheres (for Embree,
which has no analytic spheres), random triangle soups, and Suzanne exported
from Blender as binary PLY files."""
from __future__ import annotations

import numpy as np

from bench_common import SPD, bpy_missing, run_bpy
from gridwalk import scenes
from gridwalk.io import load_nff, load_ply


def tessellate_spheres(kw: dict, subdiv: int) -> dict:
    """Scene kwargs with every sphere replaced by an icosphere (triangles only, lights and camera kept)."""
    centres, radii = np.asarray(kw["sphere_centers"], float), np.asarray(kw["sphere_radii"], float)
    unit_v, unit_t = scenes.icosphere(subdiv, dtype=np.float64)
    verts = (centres[:, None, :] + radii[:, None, None] * unit_v[None]).reshape(-1, 3)
    tris = (unit_t[None] + (np.arange(len(radii)) * len(unit_v))[:, None, None]).reshape(-1, 3)
    base_v, base_t = np.asarray(kw["vertices"], float).reshape(-1, 3), np.asarray(kw["triangles"]).reshape(-1, 3)
    return {"vertices": np.vstack([base_v, verts]).astype(np.float32),
            "triangles": np.vstack([base_t, tris + len(base_v)]).astype(np.int32),
            "camera": kw["camera"], "lights": kw["lights"]}


def random_soup(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """n random triangles in the unit cube, each about 0.5 * n**(-1/3) across (a triangle
    spans about one grid cell at M = 2, as in a tessellated surface)."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.0, 1.0, (n, 1, 3))
    h = 0.25 * n ** (-1.0 / 3.0)
    verts = (centres + rng.uniform(-h, h, (n, 3, 3))).reshape(-1, 3).astype(np.float32)
    return verts, np.arange(3 * n, dtype=np.int32).reshape(n, 3)


def export_suzanne(out_dir, levels) -> dict:
    """{level: path} of Suzanne PLY files written by Blender (bpy 4.5) in a subprocess."""
    reason = bpy_missing()
    if reason:
        raise RuntimeError(reason)
    run_bpy("suzanne", out_dir, *levels, timeout=300)
    return {level: out_dir / f"suzanne_L{level}.ply" for level in levels}


def scene_kwargs(name: str, suzanne: dict | None = None, res: int | None = None) -> dict:
    """gridwalk.Scene keyword arguments for an SPD file name, "suzanne" (the level-1 PLY) or "distant"."""
    if name == "distant":
        kw = scenes.distant()
    elif name == "suzanne":
        kw = load_ply(suzanne[1])
    else:
        kw = load_nff(SPD / f"{name}.nff")
    if res:
        kw["camera"].width = kw["camera"].height = res
    return kw


LABELS = {"balls_s4": "Balls (size 4)", "mount_s8": "Mount (size 8)", "mount_s6": "Mount (size 6)",
          "suzanne": "Suzanne PLY (subdiv 1)", "distant": "Distant (DoF)", "balls_s2": "Balls (size 2)",
          "balls_s3": "Balls (size 3)", "mount_s4": "Mount (size 4)", "balls_s1": "Balls (size 1)"}
