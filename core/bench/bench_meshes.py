"""Geometry for the benchmarks: scenes by name, tessellated spheres (for Embree,
which has no analytic spheres), random triangle soups, and Suzanne exported
from Blender as binary PLY files."""
from __future__ import annotations

import numpy as np

from bench_common import SPD, bpy_missing, run_bpy
import gridwalk as gw
from gridwalk import scenes
from gridwalk.io import load_nff, load_ply


def tessellate_spheres(kw: dict, subdiv: int) -> dict:
    """Scene kwargs with every sphere replaced by an icosphere (triangles only, lights and camera kept)."""
    centres = np.asarray(kw.get("sphere_centers", np.zeros((0, 3))), float).reshape(-1, 3)
    radii = np.asarray(kw.get("sphere_radii", ()), float)
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


def placed_suzanne(path, size: float, at=(0.0, 0.0), turn: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Suzanne from its PLY, scaled to `size` across, turned by `turn` radians
    about z and standing on z = 0 at `at`."""
    mesh = load_ply(path)
    v = mesh["vertices"].astype(np.float64)
    v = (v - v.mean(0)) / np.ptp(v, axis=0).max() * size
    c, s = np.cos(turn), np.sin(turn)
    v = v @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T
    v[:, 2] -= v[:, 2].min()
    return v + (at[0], at[1], 0.0), np.asarray(mesh["triangles"])


def ground_plane_scene(meshes, plane_size: float, eye, target) -> dict:
    """Meshes standing on a square plane of two triangles (the layout most
    Blender scenes have: detail in a small part of a large box), two lights."""
    h = plane_size / 2
    parts = meshes + [(np.array([[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]], float),
                       np.array([[0, 1, 2], [0, 2, 3]]))]
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    camera = gw.Camera(eye=eye, target=target, up=(0, 0, 1), fov=40, width=512, height=512)
    lights = [gw.Light(position=(3.0, -4.0, 6.0)), gw.Light(position=(-5.0, -2.0, 4.0))]
    return {"vertices": np.vstack([v for v, _ in parts]).astype(np.float32),
            "triangles": np.vstack([t + o for (_, t), o in zip(parts, offsets)]).astype(np.int32),
            "camera": camera, "lights": lights}


def scene_kwargs(name: str, suzanne: dict | None = None, res: int | None = None) -> dict:
    """gridwalk.Scene keyword arguments for an SPD file name, "suzanne" (the level-1 PLY), "distant",
    "scan_on_plane" (Suzanne at subdivision level 3, 63k triangles, 1 across, on a 100 x 100 plane) or
    "scans_on_floor" (six of them on a 40 x 40 floor); --quick runs use the densest level exported."""
    if name == "distant":
        kw = scenes.distant()
    elif name == "suzanne":
        kw = load_ply(suzanne[1])
    elif name == "scan_on_plane":
        kw = ground_plane_scene([placed_suzanne(suzanne[min(3, max(suzanne))], 1.0)], 100.0, (0.3, -2.5, 1.0),
                                (0.0, 0.0, 0.4))
    elif name == "scans_on_floor":
        level = min(3, max(suzanne))
        spots = [(-3, 0), (0, 0), (3, 0), (-1.5, 3), (1.5, 3), (0, -3)]
        kw = ground_plane_scene([placed_suzanne(suzanne[level], 1.0, xy, 0.7 * xy[0]) for xy in spots], 40.0,
                                (0.0, -9.0, 4.0), (0.0, 0.0, 0.5))
    else:
        kw = load_nff(SPD / f"{name}.nff")
    if res:
        kw["camera"].width = kw["camera"].height = res
    return kw


LABELS = {"scan_on_plane": "Suzanne on a 100x plane", "scans_on_floor": "6 Suzannes on a floor",
          "balls_s4_analytic": "Balls (size 4), analytic spheres", "balls_s4": "Balls (size 4)", "mount_s8": "Mount (size 8)", "mount_s6": "Mount (size 6)",
          "suzanne": "Suzanne PLY (subdiv 1)", "distant": "Distant (DoF)", "balls_s2": "Balls (size 2)",
          "balls_s3": "Balls (size 3)", "balls_s2_analytic": "Balls (size 2), analytic spheres", "mount_s4": "Mount (size 4)", "balls_s1": "Balls (size 1)"}
