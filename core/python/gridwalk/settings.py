"""Render settings: one dataclass, converted to the core's struct in one place."""
from __future__ import annotations

from dataclasses import asdict, dataclass, fields

from . import _core

ACCELS = {"none": 0, "grid": 1}
AA_MODES = ("center", "jittered", "random", "adaptive", "sobol")
SHADOW_MODES = ("hard", "random", "area")
FILTERS = ("box", "gaussian")


@dataclass
class RenderSettings:
    """Every setting of a render.

    accel: "grid" (uniform grid, Amanatides & Woo DDA) or "none" (brute force).
    grid_density: the seed's M in N_ax = floor(M * dim_ax / cbrt(V / N)) + 1.
    max_cells: cap on grid cells; past it M is reduced (reported in stats).
    mailboxes: skip primitives already tested by the same ray (per-thread stamps).
    skip_empty: jump across blocks of empty grid cells (proximity clouds); off
        walks every cell, as in Havran & Sixta's cell counts.
    threads: worker threads, 0 = all cores. tile_size: tile edge in pixels.
    max_depth: ray generations (primary rays are generation 1).
    seed: random seed; the image is a pure function of the seed.
    aa: "center" (1 ray through the pixel centre), "jittered" (stratified n x n),
        "random" (n x n uniform), "sobol" (n x n Owen-scrambled Sobol),
        "adaptive" (Whitted: corners, subdivide where they differ).
    aa_samples: n for the n x n modes.
    adaptive_threshold, adaptive_depth: adaptive subdivision controls.
    filter: "box" or "gaussian" (filter_width = standard deviation in pixels).
    shadow: "hard" (light centre), "random" (random point per shadow ray),
        "area" (n x n jittered light grid shuffled per pixel).
    shadow_samples: random: rays per light; area: n of the n x n grid.
    dof_samples: lens samples per pixel sample (used when the camera has an aperture).
    glossy_samples: rays at the first glossy bounce.
    min_weight: secondary rays whose path weight falls below this are skipped.
    region: (x, y, w, h) in pixels (row 0 at the top) to render only part of
        the image; None renders all of it. Pixels outside stay 0.
    """
    accel: str = "grid"
    grid_density: float = 2.0
    max_cells: int = 1 << 24
    mailboxes: bool = True
    skip_empty: bool = True
    threads: int = 0
    tile_size: int = 32
    max_depth: int = 5
    seed: int = 0
    aa: str = "center"
    aa_samples: int = 1
    adaptive_threshold: float = 0.05
    adaptive_depth: int = 3
    filter: str = "box"
    filter_width: float = 0.5
    shadow: str = "hard"
    shadow_samples: int = 1
    dof_samples: int = 1
    glossy_samples: int = 1
    min_weight: float = 1e-3
    region: tuple | None = None

    def replace(self, **changes) -> "RenderSettings":
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            raise ValueError(f"unknown render settings: {sorted(unknown)}")
        return RenderSettings(**{**asdict(self), **changes})

    def to_core(self) -> "_core.RenderSettings":
        def pick(name, value, choices):
            if value not in choices:
                raise ValueError(f"RenderSettings.{name} must be one of {list(choices)}, got {value!r}")
            return value

        c = _core.RenderSettings()
        c.accel = ACCELS[pick("accel", self.accel, ACCELS)]
        c.grid_density = float(self.grid_density)
        if int(self.max_cells) < 1:
            raise ValueError("RenderSettings.max_cells must be >= 1")
        c.max_cells = int(self.max_cells)
        c.mailboxes = bool(self.mailboxes)
        c.skip_empty = bool(self.skip_empty)
        c.threads = int(self.threads)
        c.tile_size = int(self.tile_size)
        c.max_depth = int(self.max_depth)
        if not 0 <= int(self.seed) < 2**32:
            raise ValueError("RenderSettings.seed must be in [0, 2^32)")
        c.seed = int(self.seed)
        c.aa = getattr(_core.AAMode, pick("aa", self.aa, AA_MODES))
        c.aa_samples = int(self.aa_samples)
        c.adaptive_threshold = float(self.adaptive_threshold)
        c.adaptive_depth = int(self.adaptive_depth)
        c.filter = getattr(_core.PixelFilter, pick("filter", self.filter, FILTERS))
        c.filter_width = float(self.filter_width)
        c.shadow = getattr(_core.ShadowMode, pick("shadow", self.shadow, SHADOW_MODES))
        c.shadow_samples = int(self.shadow_samples)
        c.dof_samples = int(self.dof_samples)
        c.glossy_samples = int(self.glossy_samples)
        c.min_weight = float(self.min_weight)
        if self.region is not None:
            r = tuple(int(v) for v in self.region)
            if len(r) != 4 or min(r) < 0 or r[2] < 1 or r[3] < 1:
                raise ValueError(f"RenderSettings.region must be (x, y, w, h) with w, h >= 1, got {self.region!r}")
            c.region = r
        c.validate()
        return c
