"""How much memory a render will need, estimated from counts alone.

Used to refuse a scene that would not fit in memory before any large array is
built (the Blender add-on counts triangles from the evaluated meshes, then
calls `estimate` and `check` before it exports anything):

    est = estimate(triangles=12_000_000, vertices=6_000_000, width=1920, height=1080,
                   settings=RenderSettings())
    check(est, limit=default_limit())      # raises SceneTooLarge with both figures

What is counted (bytes):
  scene arrays  the float32 / int32 arrays handed to gridwalk.Scene, once, plus
                the core's copies: vertices and normals 12 + 12 per vertex (x2),
                triangles 12 + 4 (material) per triangle (x2) and the core's
                packed corner positions (36 per triangle); spheres 20 (x2);
                cylinders 36 (x2) + the core's 76-byte record.
  grid          The adaptive grid (accel "adaptive"): 8 bytes per cell and 4
                per primitive reference, at ADAPTIVE_CELLS and ADAPTIVE_REFS
                per primitive (measured: 1.2 - 1.7 cells and 2.7 - 5.3
                references on tessellated spheres, scans on a floor, SPD
                mount and balls), plus the build's per-primitive boxes (24)
                and, for the empty boxes (empty_box.h), a summed-area table,
                the boxes and two distance passes over the root grid, about
                one cell per primitive (12).
                A crowded root (a fan, a tilted stack: adaptive_grid.cpp) may
                list up to ADAPTIVE_CROWDED_REFS_PER_PRIM references per
                primitive, within ADAPTIVE_CROWDED_REFS in all, and its cells
                refine as usual: ADAPTIVE_CROWDED_BYTES per such reference,
                about twice the 6 - 34 bytes measured over the whole structure
                (4 for the reference, the rest the refining grids below it) on
                fans, cones of thin triangles around one point, tilted stacks,
                big overlapping and long thin triangles (layout_scenes.py); at
                most 16 MiB. (With a smaller leaf_size or more grid_levels than
                the defaults every figure here can be exceeded.)
                The uniform grid (accel "grid"): per cell 4 (offsets) + 1
                (empty-space distance) + 4 (the count array of the build);
                per primitive reference 4. Cells and references are the
                budget the core's build keeps by lowering M (grid_budget,
                uniform_grid.h): 2 (M cbrt N + 1)^3 + 64 cells and
                N (M + 1)^3 + 4 (M cbrt N + 1)^2 + 64 references, capped at
                max_cells and 2^27. It is an upper bound for every
                distribution (long thin triangles across the scene, a box
                thin along one axis), 1.7 - 70 times the actual structure
                (core/bench/bench_builds.py).
                The instanced grid (copies of a mesh declared, accel
                "adaptive" with instancing): the adaptive grid's figure for
                the primitives that are not copies, twice (the meshes' own
                grids are over some of them), and COPY_BYTES per copy.
  mailboxes     one 4-byte stamp per primitive per worker thread (uniform
                grid with mailboxes on).
  textures      the images textures sample, each once (1 byte per channel
                for 8-bit images, 4 for float ones: the caller passes their
                total), and the corner UVs (24 bytes per triangle, x2) and
                colours (36, x2) when a material uses them.
  images        the core's RGBA, depth, normal and albedo buffers (44 per pixel), the
                copies read back at the end (36) and the host's render result
                (Combined + Depth + Normal, 32): 112 per pixel; with
                RenderSettings.matte_ranks, per rank and layer of matte keys
                (matte_layers), 8 (a key and its coverage) and as much again
                for the host's Cryptomatte passes.
Checked against the resident memory of a render of a 1M-triangle sphere
(tests/test16_memory_estimate.py): with the adaptive grid the estimate is
within 0.8 - 1.75 of the measured figure (1.6 before the crowded roots'
allowance, which a sphere does not take); with the uniform grid, whose budget
is an upper bound, about 2.5 times.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from . import _core

DEFAULT_FRACTION = 0.75       # default limit: this fraction of physical memory

VERTEX_BYTES = 2 * 24         # position + normal, float32, ours and the core's
TRIANGLE_BYTES = 2 * 16 + 36  # indices + material, ours and the core's; the core's corner positions
SPHERE_BYTES = 2 * 20
CYLINDER_BYTES = 2 * 36 + 76    # the arrays, the core's input copies and its records
CELL_BYTES = 4 + 1 + 4
REF_BYTES = 4
ADAPTIVE_CELL_BYTES = 8
ADAPTIVE_CELLS = 2.0          # cells per primitive, all levels
ADAPTIVE_REFS = 6.0           # references per primitive, all levels
ADAPTIVE_BUILD_BYTES = 36     # the build's box per primitive (24), and its empty-box temporaries (12 per root cell)
ADAPTIVE_MAX_CELLS = _core.ADAPTIVE_MAX_CELLS   # the core's caps (AdaptiveParams)
ADAPTIVE_MAX_REFS = _core.ADAPTIVE_MAX_REFS
ADAPTIVE_CROWDED_REFS = _core.ADAPTIVE_CROWDED_REFS   # a crowded root's allowance (AdaptiveParams)
ADAPTIVE_CROWDED_REFS_PER_PRIM = _core.ADAPTIVE_CROWDED_REFS_PER_PRIM
ADAPTIVE_CROWDED_BYTES = 64   # per reference of a crowded root's allowance
STAMP_BYTES = 4
INSTANCING_AUTO_TRIANGLES = _core.INSTANCING_AUTO_TRIANGLES   # instancing "auto": the fewest copied triangles
COPY_BYTES = 320              # the instanced grid, per copy: its record (map, box) and its cells' lists (245 measured)
TANGENT_BYTES = 180           # normal maps: the core's tangents (3 corners x 4 floats), and 132 more while they are built
PIXEL_BYTES = 44 + 36 + 32


class SceneTooLarge(MemoryError):
    """The estimate exceeds the limit; the message states both."""


@dataclass(frozen=True)
class MemoryEstimate:
    scene_arrays: int
    grid: int
    mailboxes: int
    images: int
    textures: int = 0

    @property
    def total(self) -> int:
        return self.scene_arrays + self.grid + self.mailboxes + self.images + self.textures

    def breakdown(self) -> str:
        parts = (("scene arrays", self.scene_arrays), ("grid", self.grid),
                 ("mailboxes", self.mailboxes), ("images", self.images), ("textures", self.textures))
        return ", ".join(f"{name} {format_bytes(n)}" for name, n in parts if n)


def format_bytes(n: float) -> str:
    """1536 -> '1.5 KiB'; binary units, 3 significant figures."""
    n = float(n)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if abs(n) < 1024 or unit == "TiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.3g} {unit}"
        n /= 1024
    raise AssertionError("unreachable")


def grid_budget(primitives: int, density: float, max_cells: int) -> tuple[int, int]:
    """(cells, references) the uniform grid holds at most: the core's own
    budget (uniform_grid.h), which its build keeps by lowering M."""
    if primitives <= 0:
        return 0, 0
    cells, refs = _core.uniform_grid_budget(int(primitives), float(density), int(max_cells))
    return int(cells), int(refs)


def estimate(triangles: int, vertices: int | None = None, spheres: int = 0, cylinders: int = 0,
             width: int = 1, height: int = 1, settings=None, normals: bool = True,
             texture_bytes: int = 0, uvs: bool = False, colors: bool = False,
             tangents: bool = False, corner_points: int = 0, matte_layers: int = 1, copies: int = 0,
             copied_triangles: int = 0) -> MemoryEstimate:
    """Bytes needed to render a scene with these counts (see the module docstring).

    vertices defaults to 3 per triangle (unshared corners, the worst case).
    settings is a gridwalk.RenderSettings (defaults when None); its accel,
    grid_density, max_cells, mailboxes and threads are used. uvs, colors:
    the triangles have corner UVs / colours; corner_points: how many arrays
    of corner points they have (Generated and Object coordinates, object normals); tangents: a material has a
    normal map (the core keeps a tangent per corner, 48 bytes a triangle,
    and needs 132 more while it builds them); matte_layers: the layers of
    matte keys (Scene(matte_keys=...)) when settings.matte_ranks > 0;
    copies, copied_triangles: instances of a mesh beyond its first (Scene's
    instance arrays) and their triangles. Where the instanced grid is built
    (settings.instancing "on" with a copy, or "auto" with copies making at
    least half of the primitives and INSTANCING_AUTO_TRIANGLES) its grid is
    the adaptive grid's for the other primitives, as much again for the
    meshes' own grids (at most those primitives), and COPY_BYTES per copy.
    """
    if settings is None:
        from .settings import RenderSettings
        settings = RenderSettings()
    for name, value in (("triangles", triangles), ("spheres", spheres), ("cylinders", cylinders),
                        ("width", width), ("height", height), ("texture_bytes", texture_bytes)):
        if int(value) < 0:
            raise ValueError(f"{name} must be >= 0, got {value}")
    triangles, spheres, cylinders = int(triangles), int(spheres), int(cylinders)
    vertices = 3 * triangles if vertices is None else int(vertices)
    vertex_bytes = VERTEX_BYTES if normals else VERTEX_BYTES // 2
    scene_arrays = (vertices * vertex_bytes + triangles * TRIANGLE_BYTES + spheres * SPHERE_BYTES
                    + cylinders * CYLINDER_BYTES)
    prims = triangles + spheres + cylinders
    if settings.matte_ranks:
        scene_arrays += 4 * prims * max(1, int(matte_layers))
    grid = mailboxes = 0
    copied_triangles = min(max(int(copied_triangles), 0), triangles)
    instanced = copies > 0 and (settings.instancing == "on" or settings.instancing == "auto" and (
        2 * copied_triangles >= prims and copied_triangles >= INSTANCING_AUTO_TRIANGLES))
    if settings.accel == "adaptive" and prims and instanced:
        grid = 2 * _adaptive_grid(prims - copied_triangles) + int(copies) * COPY_BYTES + 4 * prims
    elif settings.accel == "adaptive" and prims:
        grid = _adaptive_grid(prims)
    elif settings.accel == "grid" and prims:
        density = float(settings.grid_density)
        cells, refs = grid_budget(prims, density, int(settings.max_cells))
        grid = (cells + 1) * CELL_BYTES + refs * REF_BYTES
        if settings.mailboxes:
            threads = int(settings.threads) or (os.cpu_count() or 1)
            mailboxes = prims * STAMP_BYTES * threads
    images = int(width) * int(height) * (PIXEL_BYTES + 16 * int(settings.matte_ranks) * max(1, int(matte_layers)))
    textures = (int(texture_bytes)
                + triangles * 2 * ((24 if uvs else 0) + (36 if colors else 0) + 36 * int(corner_points))
                + (triangles * TANGENT_BYTES if uvs and tangents else 0))
    return MemoryEstimate(scene_arrays, grid, mailboxes, images, textures)


def declared_copies(scene_kwargs: dict) -> dict:
    """estimate()'s copies and copied_triangles for gridwalk.Scene keyword
    arguments: each declared instance after its mesh's first."""
    meshes = scene_kwargs.get("instance_meshes")
    if meshes is None or len(meshes) == 0:
        return {"copies": 0, "copied_triangles": 0}
    meshes = np.asarray(meshes)
    counts = np.asarray(scene_kwargs["instance_triangles"])[:, 1]
    _, first = np.unique(meshes, return_index=True)
    later = np.ones(len(meshes), bool)
    later[first] = False
    return {"copies": int(later.sum()), "copied_triangles": int(counts[later].sum())}


def _adaptive_grid(prims: int) -> int:
    """The adaptive grid's bytes over `prims` primitives (its build's included)."""
    cells = min(ADAPTIVE_MAX_CELLS, math.ceil(ADAPTIVE_CELLS * prims))
    refs = min(ADAPTIVE_MAX_REFS, math.ceil(ADAPTIVE_REFS * prims))
    crowded = min(ADAPTIVE_CROWDED_REFS, math.ceil(ADAPTIVE_CROWDED_REFS_PER_PRIM * prims))
    return (cells * ADAPTIVE_CELL_BYTES + refs * REF_BYTES + prims * ADAPTIVE_BUILD_BYTES
            + crowded * ADAPTIVE_CROWDED_BYTES)


def physical_memory() -> int | None:
    """Bytes of physical memory (os.sysconf), or None where it cannot be read."""
    try:
        pages, page_size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None
    return pages * page_size if pages > 0 and page_size > 0 else None


def default_limit(fraction: float = DEFAULT_FRACTION) -> int | None:
    """`fraction` of physical memory, or None (no limit) where it is unknown."""
    total = physical_memory()
    return int(total * fraction) if total else None


def check(est: MemoryEstimate, limit: int | None, what: str = "This scene", limit_source: str = "") -> None:
    """Raise SceneTooLarge when est.total exceeds `limit` (None: no limit)."""
    if limit is not None and est.total > limit:
        source = f" ({limit_source})" if limit_source else ""
        raise SceneTooLarge(f"{what} needs an estimated {format_bytes(est.total)} of memory "
                            f"({est.breakdown()}), more than the limit of {format_bytes(limit)}{source}")
