"""Blender's Sky Texture as an equirectangular environment image.

sky_image() bakes the sky that Cycles renders for a Sky Texture node into an
image for World(environment=...): Z up, its centre looking along +X, linear
Rec.709 radiance. The physics is the core's (core/src/sky.h):

- "single": Nishita's single scattering, Blender 3.x-4.x's Nishita type and
  5.0's Single Scattering;
- "multiple": Blender 5.0's Multiple Scattering (its default).

Blender computes a table of the sky over elevations and azimuths from the sun,
then looks each direction up in it; so does this module, with the table's
layout and the lookup of the Blender version asked for (blender_version):

- before 5.0: a 512 x 128 table above the horizon, rows denser towards it;
  below the horizon the horizon's colour fading to black at z = -0.4; inside
  the sun's disc the sun replaces the sky;
- 5.0: a 512 x 256 table over all elevations (Single Scattering's lower half is
  the same fade; Multiple Scattering's the light scattered before the ground);
  the sun is added to the sky, hidden below the horizon as seen from `altitude`;
- 3.6 and later wrap the sun's elevation into [-90, 90] degrees (turning the
  sun round), 3.4 and 3.5 take it as it is.

The sun's disc is darker at its limb (Cycles' 0.6 coefficient) and redder at its
lower edge. Each texel holds the mean of its directions' radiance, the sun's
texels averaged over 16 x 16 directions or more (16 across the disc, weighted
by the solid angle each stands for), so the image carries the sun's light
whatever its resolution.
"""
from __future__ import annotations

import math

import numpy as np

from . import _core

MODELS = ("single", "multiple")

# CIE XYZ (D65) -> linear Rec.709, the matrix Cycles' xyz_to_rgb gets from
# Blender's colour configurations; negative results are clamped to 0 as in Cycles.
XYZ_TO_REC709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                          [-0.9692660, 1.8760108, 0.0415560],
                          [0.0556434, -0.2040259, 1.0572252]])

_TABLE_WIDTH = 512
_EARTH_KM = 6371.0          # the Multiple Scattering model's Earth, and 5.0's horizon dip
_SUN_SUPERSAMPLE = 16


def _wrap(angle: float) -> float:
    angle = math.fmod(angle, 2 * math.pi)
    return angle + 2 * math.pi if angle < 0 else angle


def _sun_angles(elevation: float, rotation: float, blender_version) -> tuple[float, float]:
    """(elevation, rotation) as Cycles uses them: 3.6 and later fold an elevation
    beyond +-90 degrees back (the sun turned half round); the rotation mod 2 pi."""
    if tuple(blender_version) >= (3, 6):
        elevation = math.fmod(elevation, 2 * math.pi)
        if abs(elevation) >= math.pi:
            elevation -= math.copysign(2 * math.pi, elevation)
        if elevation >= math.pi / 2 or elevation <= -math.pi / 2:
            elevation = math.copysign(math.pi, elevation) - elevation
            rotation += math.pi
    return elevation, _wrap(rotation)


def _directions(elevation, azimuth) -> np.ndarray:
    elevation, azimuth = np.broadcast_arrays(np.asarray(elevation, np.float64), np.asarray(azimuth, np.float64))
    c = np.cos(elevation)
    return np.stack([c * np.cos(azimuth), c * np.sin(azimuth), np.sin(elevation)], axis=-1)


def _mirrored(half: np.ndarray) -> np.ndarray:
    """The whole table from its first half: the sky is symmetric about the sun's plane."""
    return np.concatenate([half, half[:, ::-1]], axis=1)


def _table(model: str, new: bool, elevation: float, altitude: float, air: float, dust: float, ozone: float):
    """Cycles' table, XYZ (rows, 512, 3), row 0 the lowest elevation, column 256 facing the sun."""
    half = _TABLE_WIDTH // 2
    x = np.arange(half)
    if model == "multiple":
        u, v = (x + 0.5) / _TABLE_WIDTH, (np.arange(256) + 0.5) / 256
        lat = np.sign(2 * v - 1) * (2 * v - 1) ** 2 * (math.pi / 2)
        views = _directions(lat[:, None], 2 * math.pi * u[None, :])
        km = min(max(altitude, 1.0), 99999.0) / 1000.0
        xyz = _core.sky_table("multiple", np.ascontiguousarray(views.reshape(-1, 3), np.float32), elevation, km,
                              air, dust, ozone)
        return _mirrored(xyz.reshape(256, half, 3))
    metres = min(max(altitude, 1.0), 59999.0)
    rows = 128
    lat = (math.pi / 2 if new else math.pi / 2 + math.pi / (4 * rows)) * (np.arange(rows) / rows) ** 2
    views = _directions(lat[:, None], (2 * math.pi * x / _TABLE_WIDTH - math.pi)[None, :])
    xyz = _mirrored(_core.sky_table("single", np.ascontiguousarray(views.reshape(-1, 3), np.float32), elevation,
                                    metres, air, dust, ozone).reshape(rows, half, 3))
    if not new:
        return xyz
    depth = np.sin((math.pi / 2) * (1 - np.arange(rows) / rows) ** 2)          # rows 0..127: below the horizon
    fade = np.where(depth < 0.4, (1 - 2.5 * depth) ** 3, 0.0)
    return np.concatenate([xyz[:1] * fade[:, None, None], xyz], axis=0)


def _sun_pixels(model: str, new: bool, elevation: float, diameter: float, altitude: float, air, dust, ozone):
    """XYZ radiance of the sun's disc at its lower and upper edges."""
    h = diameter / 2
    solid_angle = 2 * math.pi * (1 - math.cos(h))
    if model == "multiple":
        km = min(max(altitude, 1.0), 99999.0) / 1000.0
        return [np.array(_core.sky_sun("multiple", e, solid_angle, km, air, dust, ozone))
                for e in (elevation - h, elevation + h)]
    if new and elevation + h <= 0:
        return [np.zeros(3), np.zeros(3)]
    metres = min(max(altitude, 1.0), 59999.0)
    return [np.array(_core.sky_sun("single", max(e, 0.0), solid_angle, metres, air, dust, ozone))
            for e in (elevation - h, elevation + h)]


def _texel_weights(coordinate, size: int):
    """Cycles' linear image lookup along one axis, its edges extended (texel centres
    at (i + 0.5) / size): the two texels and the second one's weight."""
    f = np.asarray(coordinate) * size - 0.5
    i = np.floor(f)
    w = f - i
    i = i.astype(np.int64)
    return np.clip(i, 0, size - 1), np.clip(i + 1, 0, size - 1), w[..., None]


def _bilinear(table: np.ndarray, u, v) -> np.ndarray:
    """The table (rows, cols, 3) at (u, v), each direction its own."""
    xa, xb, sx = _texel_weights(u, table.shape[1])
    ya, yb, sy = _texel_weights(v, table.shape[0])
    return ((table[ya, xa] * (1 - sx) + table[ya, xb] * sx) * (1 - sy)
            + (table[yb, xa] * (1 - sx) + table[yb, xb] * sx) * sy)


def _grid_bilinear(table: np.ndarray, v, u) -> np.ndarray:
    """The table at every (v[i], u[j]): (len(v), len(u), 3), a row pass then a column pass."""
    ya, yb, sy = _texel_weights(v, table.shape[0])
    rows = table[ya] * (1 - sy[..., None]) + table[yb] * sy[..., None]
    xa, xb, sx = _texel_weights(u, table.shape[1])
    return rows[:, xa] * (1 - sx) + rows[:, xb] * sx


class _Sky:
    """One Sky Texture's settings, evaluated as Cycles evaluates them."""

    def __init__(self, model, blender_version, sun_elevation, sun_rotation, sun_disc, sun_size, sun_intensity,
                 altitude, air, dust, ozone):
        self.new = tuple(blender_version) >= (5, 0)
        self.model = model
        self.elevation, rotation = _sun_angles(sun_elevation, sun_rotation, blender_version)
        self.sun = _directions(self.elevation, math.pi / 2 - rotation)
        self.sun_azimuth = math.pi / 2 - rotation
        self.diameter = max(sun_size, 0.0005) if sun_disc else -1.0
        self.intensity = sun_intensity
        self.table = _table(model, self.new, self.elevation, altitude, air, dust, ozone)
        self.bottom, self.top = _sun_pixels(model, self.new, self.elevation, max(self.diameter, 0.0005), altitude,
                                            air, dust, ozone)
        # (5.0: the sun hides below the horizon seen from the altitude, whatever the clamps)
        self.horizon_dip = math.pi / 2 - math.asin(_EARTH_KM / (_EARTH_KM + max(altitude, 0.0) / 1000.0))

    def sun_reach(self) -> float:
        """The disc's angular radius (0 without a disc)."""
        return max(self.diameter, 0.0) / 2

    def sky(self, el, lookup) -> np.ndarray:
        """XYZ of the sky without the sun at elevations el, lookup(v) reading the table at
        rows v (before 5.0: the horizon's row, v = -0.5, below it, fading to black)."""
        if self.new:
            return lookup(np.sign(el) * np.sqrt(np.abs(el) * (2 / math.pi)) * 0.5 + 0.5)
        z = np.sin(el)
        fade = np.where(z >= 0, 1.0, np.where(z < -0.4, 0.0, np.clip(1 + 2.5 * z, 0, None) ** 3))
        return lookup(np.where(z >= 0, np.sqrt(np.maximum(el, 0.0) / (math.pi / 2)), -0.5)) * fade[..., None]

    def table_u(self, azimuth):
        """The table's column coordinate of azimuths (0.5: facing the sun)."""
        return np.mod(0.5 + (self.sun_azimuth - azimuth) / (2 * math.pi), 1.0)

    def radiance(self, d: np.ndarray) -> np.ndarray:
        """Linear Rec.709 radiance (..., 3) along unit directions d (..., 3), the sun included."""
        el = np.arcsin(np.clip(d[..., 2], -1.0, 1.0))
        u = self.table_u(np.arctan2(d[..., 1], d[..., 0]))
        xyz = self.sky(el, lambda v: _bilinear(self.table, u, v))
        h = self.diameter / 2
        gamma = 2 * np.arctan2(np.linalg.norm(d - self.sun, axis=-1), np.linalg.norm(d + self.sun, axis=-1))
        disc = (self.diameter >= 0) & (gamma < h)
        limb = (1 - 0.6 * (1 - np.sqrt(np.maximum(0.0, 1 - (gamma / max(h, 1e-30)) ** 2)))) * self.intensity
        e = self.elevation
        if self.new:
            t = (el - e) / self.diameter + 0.5
            shown = disc & (el > -self.horizon_dip)
        else:   # (the sun replaces the sky, above the horizon only)
            t = (el - e) / self.diameter + 0.5 if e - h > 0 else el / (e + h) if e + h > 0 else np.zeros_like(el)
            shown = disc & (el >= 0) & (e + h > 0)
        sun = (self.bottom * (1 - t[..., None]) + self.top * t[..., None]) * limb[..., None]
        if not self.new:
            xyz = np.where(shown[..., None], 0.0, xyz)
        xyz = xyz + np.where(shown[..., None], sun, 0.0)
        return np.maximum(xyz @ XYZ_TO_REC709.T, 0.0)


def _texel_directions(rows, cols, width: int, sub: int = 1) -> np.ndarray:
    """Unit directions (n, sub * sub, 3) through a sub x sub grid of points in each texel
    (rows[i], cols[i]) of a width x width / 2 equirectangular image."""
    offsets = (np.arange(sub) + 0.5) / sub
    px = np.asarray(cols)[:, None, None] + offsets[None, None, :]
    py = np.asarray(rows)[:, None, None] + offsets[None, :, None]
    px, py = (a.reshape(len(rows), sub * sub) for a in np.broadcast_arrays(px, py))
    height = width // 2
    return _directions((0.5 - py / height) * math.pi, (0.5 - px / width) * 2 * math.pi)


def sky_image(model: str = "single", *, blender_version=(4, 5), sun_elevation: float = math.radians(15.0),
              sun_rotation: float = 0.0, sun_disc: bool = True, sun_size: float = math.radians(0.545),
              sun_intensity: float = 1.0, altitude: float = 0.0, air_density: float = 1.0,
              dust_density: float = 1.0, ozone_density: float = 1.0, width: int = 2048) -> np.ndarray:
    """The sky as a float32 (width / 2, width, 3) equirectangular image (row 0 at the
    zenith; linear Rec.709). The arguments are the Sky Texture node's (radians, metres;
    dust_density is 5.0's Aerosol Density); blender_version picks the Blender whose
    Cycles it matches."""
    if model not in MODELS:
        raise ValueError(f"sky model must be one of {list(MODELS)}, got {model!r}")
    values = dict(sun_elevation=sun_elevation, sun_rotation=sun_rotation, sun_size=sun_size,
                  sun_intensity=sun_intensity, altitude=altitude, air_density=air_density,
                  dust_density=dust_density, ozone_density=ozone_density)
    bad = [k for k, v in values.items() if not math.isfinite(v)]
    if bad:
        raise ValueError(f"sky settings must be finite numbers: {', '.join(bad)}")
    width = int(width)
    if width < 8 or width % 2:
        raise ValueError(f"sky image width must be an even number of at least 8, got {width}")
    sky = _Sky(model, blender_version, sun_elevation, sun_rotation, sun_disc, max(sun_size, 0.0),
               max(sun_intensity, 0.0), max(altitude, 0.0), max(air_density, 0.0), max(dust_density, 0.0),
               max(ozone_density, 0.0))
    height = width // 2
    el = (0.5 - (np.arange(height) + 0.5) / height) * math.pi
    u = sky.table_u((0.5 - (np.arange(width) + 0.5) / width) * 2 * math.pi)
    xyz = sky.sky(el[:, None], lambda v: _grid_bilinear(sky.table, v[:, 0], u))
    image = np.maximum(xyz @ XYZ_TO_REC709.T, 0.0).astype(np.float32)
    reach = sky.sun_reach()
    if reach > 0:
        # texels within a texel's diagonal of the disc: the mean over many directions each
        margin = reach + 2.3 * math.pi / height
        band = np.flatnonzero(np.abs(el - sky.elevation) < margin)        # (the rows the disc can reach)
        rows, cols = (a.ravel() for a in np.meshgrid(band, np.arange(width), indexing="ij"))
        near = np.arccos(np.clip(_texel_directions(rows, cols, width)[:, 0] @ sky.sun, -1, 1)) < margin
        r, c = rows[near], cols[near]
        # (at least 16 x 16 points a texel, and 16 across the disc where the disc is smaller than a texel)
        sub = int(min(64, max(_SUN_SUPERSAMPLE, math.ceil(_SUN_SUPERSAMPLE * (math.pi / height) / sky.diameter))))
        for i in range(0, len(r), 1024):
            dirs = _texel_directions(r[i:i + 1024], c[i:i + 1024], width, sub)
            weight = np.sqrt(np.maximum(0.0, 1 - dirs[..., 2] ** 2))[..., None]     # (cos(elevation): solid angle)
            image[r[i:i + 1024], c[i:i + 1024]] = (sky.radiance(dirs) * weight).sum(1) / weight.sum(1)
    return image
