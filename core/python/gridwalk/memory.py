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
                mount and balls), plus the build's per-primitive boxes (24).
                The uniform grid (accel "grid"): per cell 4 (offsets) + 1
                (empty-space distance) + 4 (the count array of the build);
                per primitive reference 4. Cells follow the resolution formula
                (about M^3 per primitive, capped at settings.max_cells);
                references are estimated at 1 + M^2 per primitive (measured:
                1.7 - 3.3 for M = 1, 2.7 - 7.5 for M = 2 on tessellated
                spheres and triangle soups) and capped at the core's 2^27.
  mailboxes     one 4-byte stamp per primitive per worker thread (uniform
                grid with mailboxes on).
  textures      the images textures sample, each once (1 byte per channel
                for 8-bit images, 4 for float ones: the caller passes their
                total), and the corner UVs (24 bytes per triangle, x2) and
                colours (36, x2) when a material uses them.
  images        the core's RGBA, depth, normal and albedo buffers (44 per pixel), the
                copies read back at the end (36) and the host's render result
                (Combined + Depth + Normal, 32): 112 per pixel.
Checked against the resident memory of renders of 0.16M - 1.3M-triangle
spheres (tests/test16_memory_estimate.py): the estimate is 1.25 - 1.35 times
the measured figure, on the safe side. Long thin triangles spanning many cells
can need more references, up to the 2^27 cap (512 MiB).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

MAX_REFS = 1 << 27            # the core's cap on grid references (GridParams.max_refs)
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
ADAPTIVE_BUILD_BYTES = 24     # the build's box per primitive
ADAPTIVE_MAX_CELLS = 1 << 26  # the core's caps (AdaptiveParams)
ADAPTIVE_MAX_REFS = 1 << 28
STAMP_BYTES = 4
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


def grid_cells(primitives: int, density: float, max_cells: int) -> int:
    """Cells of the uniform grid: about (M * cbrt(N) + 1)^3, capped at max_cells."""
    if primitives <= 0:
        return 0
    cells = math.ceil((density * primitives ** (1.0 / 3.0) + 1.0) ** 3)
    return max(1, min(int(max_cells), cells))


def grid_refs(primitives: int, density: float) -> int:
    """Primitive references stored in the grid (estimate). The core caps them at
    max(MAX_REFS, primitives): every primitive keeps at least one reference."""
    if primitives <= 0:
        return 0
    return max(primitives, min(MAX_REFS, math.ceil(primitives * (1.0 + density * density))))


def estimate(triangles: int, vertices: int | None = None, spheres: int = 0, cylinders: int = 0,
             width: int = 1, height: int = 1, settings=None, normals: bool = True,
             texture_bytes: int = 0, uvs: bool = False, colors: bool = False) -> MemoryEstimate:
    """Bytes needed to render a scene with these counts (see the module docstring).

    vertices defaults to 3 per triangle (unshared corners, the worst case).
    settings is a gridwalk.RenderSettings (defaults when None); its accel,
    grid_density, max_cells, mailboxes and threads are used.
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
    grid = mailboxes = 0
    if settings.accel == "adaptive" and prims:
        cells = min(ADAPTIVE_MAX_CELLS, math.ceil(ADAPTIVE_CELLS * prims))
        refs = min(ADAPTIVE_MAX_REFS, math.ceil(ADAPTIVE_REFS * prims))
        grid = cells * ADAPTIVE_CELL_BYTES + refs * REF_BYTES + prims * ADAPTIVE_BUILD_BYTES
    elif settings.accel == "grid" and prims:
        density = float(settings.grid_density)
        cells = grid_cells(prims, density, int(settings.max_cells))
        grid = cells * CELL_BYTES + 4 + grid_refs(prims, density) * REF_BYTES
        if settings.mailboxes:
            threads = int(settings.threads) or (os.cpu_count() or 1)
            mailboxes = prims * STAMP_BYTES * threads
    images = int(width) * int(height) * PIXEL_BYTES
    textures = int(texture_bytes) + triangles * 2 * ((24 if uvs else 0) + (36 if colors else 0))
    return MemoryEstimate(scene_arrays, grid, mailboxes, images, textures)


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
