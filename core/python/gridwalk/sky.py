"""Blender's Sky Texture as an equirectangular environment image.

sky_image() bakes the sky that Cycles renders for a Sky Texture node into an
image for World(environment=...): Z up, its centre looking along +X, linear
Rec.709 radiance. The physics is the core's (core/src/sky.h):

- "single": Nishita's single scattering, Blender 3.x-4.x's Nishita type and
  5.0's Single Scattering;
- "multiple": Blender 5.0's Multiple Scattering (its default);
- "preetham": Preetham, Shirley & Smits' analytic sky (1999), Blender's Preetham
  type: Perez et al.'s sky-luminance formula for Y and the chromaticities x and y,
  its coefficients linear in the turbidity, towards a sun_direction vector; it
  has no sun disc, and below the horizon it repeats the horizon.

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
lower edge. Each texel holds the radiance at its centre, the sun's texels the
mean over their solid angle: a disc under 8 texels across is 65,536 points of
equal solid angle, each adding its share of the light to its texel (exact at
any resolution, at the poles too); a larger disc's texels take their centre's
radiance inside it and the mean of 16 x 16 directions on its edge. Such a
small disc is a blur of a few texels to a ray that sees it, so sky_inset()
also draws it 48 texels across, for World(inset=...).
"""
from __future__ import annotations

import math

import numpy as np

from . import _core

MODELS = ("single", "multiple", "preetham")

# CIE XYZ (D65) -> linear Rec.709, the matrix Cycles' xyz_to_rgb gets from
# Blender's colour configurations; negative results are clamped to 0 as in Cycles.
XYZ_TO_REC709 = np.array([[3.2404542, -1.5371385, -0.4985314],
                          [-0.9692660, 1.8760108, 0.0415560],
                          [0.0556434, -0.2040259, 1.0572252]])

# The brightest texel an image gets: a Sun Intensity of 1000 makes the sun about 2e9; a Preetham
# sun below the horizon makes Perez's formula explode (Cycles renders 1e30 there).
RADIANCE_LIMIT = 1e20
_TABLE_WIDTH = 512
_EARTH_KM = 6371.0          # the Multiple Scattering model's Earth, and 5.0's horizon dip
_SUN_SUPERSAMPLE = 16


_F32_2PI, _F32_PI = np.float32(2 * math.pi), np.float32(math.pi)


def _wrap(angle) -> np.float32:
    """The angle mod 2 pi in [0, 2 pi), in float as Cycles takes it (far from 0 the float
    modulus and a double one part by degrees)."""
    angle = np.fmod(np.float32(angle), _F32_2PI)
    return angle + _F32_2PI if angle < 0 else angle


def _sun_angles(elevation: float, rotation: float, blender_version) -> tuple[float, float]:
    """(elevation, rotation) as Cycles uses them: 3.6 and later fold an elevation
    beyond +-90 degrees back (the sun turned half round); the rotation mod 2 pi."""
    rotation = np.float32(rotation)
    if tuple(blender_version) >= (3, 6):
        e = np.fmod(np.float32(elevation), _F32_2PI)
        if abs(e) >= _F32_PI:
            e = e - np.float32(math.copysign(2.0, e)) * _F32_PI
        if e >= _F32_PI / 2 or e <= -_F32_PI / 2:
            e = np.float32(math.copysign(_F32_PI, e)) - e
            rotation = rotation + _F32_PI
        elevation = e
    return float(elevation), float(_wrap(rotation))


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
    """The table at every (v[i], u[j]): (len(v), len(u), 3), float32 (as Cycles reads its
    float image): a column pass over the table's rows, then a row pass, which gathers whole rows."""
    table = np.asarray(table, np.float32)
    xa, xb, sx = _texel_weights(u, table.shape[1])
    sx = sx.astype(np.float32)
    columns = table[:, xa] * (1 - sx) + table[:, xb] * sx
    ya, yb, sy = _texel_weights(v, table.shape[0])
    sy = sy[..., None].astype(np.float32)
    return columns[ya] * (1 - sy) + columns[yb] * sy


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
        xyz = lookup(np.where(z >= 0, np.sqrt(np.maximum(el, 0.0) / (math.pi / 2)), -0.5))
        return xyz * fade[..., None].astype(xyz.dtype)

    def table_u(self, azimuth):
        """The table's column coordinate of azimuths (0.5: facing the sun)."""
        return np.mod(0.5 + (self.sun_azimuth - azimuth) / (2 * math.pi), 1.0)

    def sky_xyz(self, d: np.ndarray) -> np.ndarray:
        """XYZ of the sky without the sun along unit directions d (..., 3)."""
        el = np.arcsin(np.clip(d[..., 2], -1.0, 1.0))
        u = self.table_u(np.arctan2(d[..., 1], d[..., 0]))
        return self.sky(el, lambda v: _bilinear(self.table, u, v))

    def sun_xyz(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(XYZ of the sun's disc along unit directions d (..., 3), where it shows: a mask)."""
        el = np.arcsin(np.clip(d[..., 2], -1.0, 1.0))
        h = self.diameter / 2
        gamma = 2 * np.arctan2(np.linalg.norm(d - self.sun, axis=-1), np.linalg.norm(d + self.sun, axis=-1))
        disc = (self.diameter >= 0) & (gamma < h)
        limb = (1 - 0.6 * (1 - np.sqrt(np.maximum(0.0, 1 - (gamma / max(h, 1e-30)) ** 2)))) * self.intensity
        e = self.elevation
        if self.new:
            t = (el - e) / self.diameter + 0.5
            shown = disc & (el > -self.horizon_dip)
        else:   # (above the horizon only)
            t = (el - e) / self.diameter + 0.5 if e - h > 0 else el / (e + h) if e + h > 0 else np.zeros_like(el)
            shown = disc & (el >= 0) & (e + h > 0)
        sun = (self.bottom * (1 - t[..., None]) + self.top * t[..., None]) * limb[..., None]
        return np.where(shown[..., None], sun, 0.0), shown

    def radiance(self, d: np.ndarray) -> np.ndarray:
        """Linear Rec.709 radiance (..., 3) along unit directions d (..., 3), the sun included
        (before 5.0 it replaces the sky it covers, from 5.0 on it adds to it)."""
        sun, shown = self.sun_xyz(d)
        sky = self.sky_xyz(d)
        if not self.new:
            sky = np.where(shown[..., None], 0.0, sky)
        return _to_rgb(sky + sun)


def _to_rgb(xyz) -> np.ndarray:
    """Linear Rec.709 of CIE XYZ, clamped to [0, RADIANCE_LIMIT] (Cycles clamps at 0); in
    float32 for float32 XYZ."""
    with np.errstate(over="ignore", invalid="ignore"):
        rgb = xyz @ (XYZ_TO_REC709.T.astype(np.float32) if xyz.dtype == np.float32 else XYZ_TO_REC709.T)
        rgb = np.nan_to_num(rgb, copy=False, nan=0.0, posinf=RADIANCE_LIMIT, neginf=0.0)
    return np.clip(rgb, 0.0, RADIANCE_LIMIT, out=rgb)


def _perez(coefficients, theta, gamma):
    """Perez et al.'s sky distribution at zenith angle theta, angle gamma from the sun."""
    a, b, c, d, e = coefficients
    return (1 + a * np.exp(b / np.cos(theta))) * (1 + c * np.exp(d * gamma) + e * np.cos(gamma) ** 2)


class _Preetham:
    """Blender's Preetham sky: xyY from three Perez distributions, each scaled to its zenith value."""

    def __init__(self, sun_direction, turbidity):
        x, y, z = (float(v) for v in sun_direction)
        length = math.sqrt(x * x + y * y + z * z)                  # (Blender hands Cycles the vector normalised)
        self.black = not length > 0                                 # (a zero vector: Cycles renders black)
        if length > 0:
            x, y, z = x / length, y / length, z / length
        self.sun_theta = math.acos(min(1.0, max(-1.0, z)))
        self.sun_phi = math.atan2(x, y)
        t, th = float(turbidity), self.sun_theta
        chi = (4 / 9 - t / 120) * (math.pi - 2 * th)
        zenith_y = ((4.0453 * t - 4.9710) * math.tan(chi) - 0.2155 * t + 2.4192) * 0.06
        cubic = np.array([th ** 3, th ** 2, th, 1.0])
        zenith_x = (np.array([0.00166, -0.00375, 0.00209, 0.0]) @ cubic * t * t
                    + np.array([-0.02903, 0.06377, -0.03202, 0.00394]) @ cubic * t
                    + np.array([0.11693, -0.21196, 0.06052, 0.25886]) @ cubic)
        zenith_yc = (np.array([0.00275, -0.00610, 0.00317, 0.0]) @ cubic * t * t
                     + np.array([-0.04214, 0.08970, -0.04153, 0.00516]) @ cubic * t
                     + np.array([0.15346, -0.26756, 0.06670, 0.26688]) @ cubic)
        self.coefficients = [
            (0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771, -0.0670 * t + 0.3703),
            (-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989, -0.0033 * t + 0.0452),
            (-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537, -0.0109 * t + 0.0529)]
        # (each distribution divided by its value at the zenith, where the formulas above hold)
        self.zenith = [v / _perez(c, 0.0, th) for v, c in zip((zenith_y, zenith_x, zenith_yc), self.coefficients)]

    def radiance(self, d: np.ndarray) -> np.ndarray:
        """Linear Rec.709 radiance along unit directions d (..., 3), at most RADIANCE_LIMIT."""
        return self.radiance_at(np.arccos(np.clip(d[..., 2], -1.0, 1.0)), np.arctan2(d[..., 0], d[..., 1]))

    def radiance_at(self, theta, phi) -> np.ndarray:
        """radiance() at zenith angles theta and azimuths phi (atan2(x, y)), broadcast together
        (an image's rows and columns: the factors of one row or column are computed once)."""
        if self.black:
            return np.zeros(np.broadcast_shapes(np.shape(theta), np.shape(phi)) + (3,))
        cos_gamma = (np.sin(theta) * math.sin(self.sun_theta) * np.cos(self.sun_phi - phi)
                     + np.cos(theta) * math.cos(self.sun_theta))
        gamma = np.arccos(np.clip(cos_gamma, -1.0, 1.0))
        theta = np.minimum(theta, math.pi / 2 - 0.001)              # (below the horizon: the horizon)
        big_y, x, y = (z * _perez(c, theta, gamma) for z, c in zip(self.zenith, self.coefficients))
        with np.errstate(divide="ignore", invalid="ignore"):
            xyz = np.stack([np.where(y != 0, x / y * big_y, 0.0), big_y,
                            np.where(y != 0, (1 - x - y) / y * big_y, 0.0)], axis=-1)
        return _to_rgb(xyz)


def _texel_directions(rows, cols, width: int, sub: int = 1) -> np.ndarray:
    """Unit directions (n, sub * sub, 3) through a sub x sub grid of points in each texel
    (rows[i], cols[i]) of a width x width / 2 equirectangular image."""
    offsets = (np.arange(sub) + 0.5) / sub
    px = np.asarray(cols)[:, None, None] + offsets[None, None, :]
    py = np.asarray(rows)[:, None, None] + offsets[None, :, None]
    px, py = (a.reshape(len(rows), sub * sub) for a in np.broadcast_arrays(px, py))
    height = width // 2
    return _directions((0.5 - py / height) * math.pi, (0.5 - px / width) * 2 * math.pi)


def _texel_solid_angles(rows, width: int) -> np.ndarray:
    """The solid angle of a texel in each of these rows of a width x width / 2 image."""
    height = width // 2
    top, bottom = (0.5 - np.asarray(rows) / height) * math.pi, (0.5 - (np.asarray(rows) + 1) / height) * math.pi
    return (2 * math.pi / width) * (np.sin(top) - np.sin(bottom))


def _splat_sun(image, sky: _Sky, width: int):
    """A disc under 8 texels across: 65,536 points spread evenly over its solid angle (rings of
    equal area), each carrying its share of the disc's light into the texel it falls in, so
    the light is exact at any resolution and near the poles; before 5.0 the covered share of
    the texel's sky is taken out."""
    height = width // 2
    rings = sectors = 256
    h = sky.diameter / 2
    cos_g = 1 - (1 - math.cos(h)) * (np.arange(rings) + 0.5) / rings
    sin_g = np.sqrt(1 - cos_g ** 2)
    phase = (np.arange(sectors)[None, :] + 0.5) * (2 * math.pi / sectors) + np.arange(rings)[:, None] * 2.399963
    axis = sky.sun
    t1 = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(axis, t1)
    d = ((sin_g[:, None] * np.cos(phase))[..., None] * t1 + (sin_g[:, None] * np.sin(phase))[..., None] * t2
         + cos_g[:, None, None] * axis).reshape(-1, 3)
    share = 2 * math.pi * (1 - math.cos(h)) / len(d)
    sun, shown = sky.sun_xyz(d)
    el = np.arcsin(np.clip(d[:, 2], -1.0, 1.0))
    row = np.clip(np.floor((0.5 - el / math.pi) * height), 0, height - 1).astype(np.int64)
    col = np.mod(np.floor((0.5 - np.arctan2(d[:, 1], d[:, 0]) / (2 * math.pi)) * width), width).astype(np.int64)
    index = row * width + col
    texels, inverse = np.unique(index, return_inverse=True)
    energy = np.stack([np.bincount(inverse, sun[:, k] * share) for k in range(3)], axis=-1)
    covered = np.bincount(inverse, shown * share)
    r, c = texels // width, texels % width
    solid = _texel_solid_angles(r, width)
    xyz = sky.sky_xyz(_texel_directions(r, c, width)[:, 0])
    if not sky.new:
        xyz = xyz * np.clip(1 - covered / solid, 0.0, 1.0)[:, None]
    image[r, c] = _to_rgb(xyz + energy / solid[:, None])


def _edge_sun(image, sky: _Sky, width: int):
    """A disc 8 texels across or more: texels wholly inside it take their centre's radiance,
    texels on its edge the mean over 16 x 16 directions (weighted by solid angle)."""
    height = width // 2
    h = sky.sun_reach()
    el = (0.5 - (np.arange(height) + 0.5) / height) * math.pi
    sun_el = math.asin(max(-1.0, min(1.0, float(sky.sun[2]))))
    band = np.flatnonzero(np.abs(el - sun_el) < h + 2 * math.pi / height)       # (the rows the disc reaches)
    # (half a texel's diagonal, along its row's widest edge)
    widest = np.cos(np.maximum(np.abs(el[band]) - 0.5 * math.pi / height, 0.0))
    half = 0.5 * np.hypot(math.pi / height, 2 * math.pi / width * widest)
    rows, cols = (a.ravel() for a in np.meshgrid(band, np.arange(width), indexing="ij"))
    half = np.repeat(half, width)
    angle = np.arccos(np.clip(_texel_directions(rows, cols, width)[:, 0] @ sky.sun, -1, 1))
    inside, edge = angle + half < h, np.abs(angle - h) <= half
    r, c = rows[inside], cols[inside]
    for i in range(0, len(r), 65536):
        image[r[i:i + 65536], c[i:i + 65536]] = sky.radiance(_texel_directions(r[i:i + 65536], c[i:i + 65536],
                                                                               width)[:, 0])
    r, c = rows[edge], cols[edge]
    for i in range(0, len(r), 1024):
        dirs = _texel_directions(r[i:i + 1024], c[i:i + 1024], width, _SUN_SUPERSAMPLE)
        weight = np.sqrt(np.maximum(0.0, 1 - dirs[..., 2] ** 2))[..., None]     # (cos(elevation): solid angle)
        image[r[i:i + 1024], c[i:i + 1024]] = (sky.radiance(dirs) * weight).sum(1) / weight.sum(1)


def _preetham_image(sky: _Preetham, width: int) -> np.ndarray:
    """The sky at the texels' centres: a row's zenith angle and a column's azimuth (the texel
    directions' atan2(x, y), which does not depend on the row) broadcast over the image."""
    height = width // 2
    image = np.empty((height, width, 3), np.float32)
    el = (0.5 - (np.arange(height) + 0.5) / height) * math.pi
    az = (0.5 - (np.arange(width) + 0.5) / width) * 2 * math.pi
    theta = np.arccos(np.clip(np.sin(el), -1.0, 1.0))[:, None]
    phi = np.arctan2(np.cos(az), np.sin(az))[None, :]
    for r0 in range(0, height, 64):                         # (bands of rows: bounded memory)
        image[r0:r0 + 64] = sky.radiance_at(theta[r0:r0 + 64], phi)
    return image


def _settings(model, blender_version, sun_elevation, sun_rotation, sun_disc, sun_size, sun_intensity, altitude,
              air_density, dust_density, ozone_density, sun_direction, turbidity, width):
    """The sky these settings describe (_Sky or _Preetham), and the image width; ValueError for bad ones."""
    if model not in MODELS:
        raise ValueError(f"sky model must be one of {list(MODELS)}, got {model!r}")
    values = dict(sun_elevation=sun_elevation, sun_rotation=sun_rotation, sun_size=sun_size,
                  sun_intensity=sun_intensity, altitude=altitude, air_density=air_density,
                  dust_density=dust_density, ozone_density=ozone_density, turbidity=turbidity)
    values.update({f"sun_direction[{i}]": v for i, v in enumerate(np.asarray(sun_direction, float).reshape(3))})
    bad = [k for k, v in values.items() if not math.isfinite(v)]
    if bad:
        raise ValueError(f"sky settings must be finite numbers: {', '.join(bad)}")
    width = int(width)
    if width < 8 or width % 2:
        raise ValueError(f"sky image width must be an even number of at least 8, got {width}")
    if model == "preetham":
        return _Preetham(sun_direction, turbidity), width
    return _Sky(model, blender_version, sun_elevation, sun_rotation, sun_disc, max(sun_size, 0.0),
                max(sun_intensity, 0.0), max(altitude, 0.0), max(air_density, 0.0), max(dust_density, 0.0),
                max(ozone_density, 0.0)), width


_DEFAULTS = dict(blender_version=(4, 5), sun_elevation=math.radians(15.0), sun_rotation=0.0, sun_disc=True,
                 sun_size=math.radians(0.545), sun_intensity=1.0, altitude=0.0, air_density=1.0, dust_density=1.0,
                 ozone_density=1.0, sun_direction=(0.0, 0.0, 1.0), turbidity=2.2, width=2048)


def sky_image(model: str = "single", **settings) -> np.ndarray:
    """The sky as a float32 (width / 2, width, 3) equirectangular image (row 0 at the
    zenith; linear Rec.709). settings (keywords, defaults as Blender adds the node):
    the Sky Texture node's sun_elevation, sun_rotation, sun_disc, sun_size,
    sun_intensity, altitude, air_density, dust_density (5.0's Aerosol Density) and
    ozone_density (radians, metres), the Preetham model's sun_direction and
    turbidity; blender_version, the Blender whose Cycles it matches; width."""
    return _image(*_settings(model, **{**_DEFAULTS, **settings}))


def sky_environment(model: str = "single", **settings):
    """(sky_image(model, **settings), sky_inset(model, **settings)) from one table."""
    sky, width = _settings(model, **{**_DEFAULTS, **settings})
    return _image(sky, width), _inset(sky, width)


def _image(sky, width: int) -> np.ndarray:
    if isinstance(sky, _Preetham):
        return _preetham_image(sky, width)
    height = width // 2
    el = (0.5 - (np.arange(height) + 0.5) / height) * math.pi
    u = sky.table_u((0.5 - (np.arange(width) + 0.5) / width) * 2 * math.pi)
    xyz = sky.sky(el[:, None], lambda v: _grid_bilinear(sky.table, v[:, 0], u))
    image = _to_rgb(xyz).astype(np.float32)
    if sky.sun_reach() > 0:
        (_splat_sun if _small_disc(sky, width) else _edge_sun)(image, sky, width)
    return image


def _small_disc(sky, width: int) -> bool:
    """Whether the sun's disc is under 8 texels of a width x width / 2 image across."""
    return sky.diameter < 8 * math.pi / (width // 2)


_INSET_TEXELS = 48      # across the sun's disc


def sky_inset(model: str = "single", **settings):
    """The sun as sky_image(model, **settings) blurs it, in detail: (pixels, frame, extent)
    for World.inset / inset_frame / inset_extent, or None (no disc, or a disc the image
    already shows 8 texels wide or more). The inset is the square of half-angle the
    disc's radius + 3 texels about the sun, the disc 48 texels across (at most 512
    texels in all), each the radiance at its centre (the sky and sun of sky_image)."""
    return _inset(*_settings(model, **{**_DEFAULTS, **settings}))


def _inset(sky, width: int):
    if isinstance(sky, _Preetham) or sky.sun_reach() <= 0 or not _small_disc(sky, width):
        return None
    h = sky.sun_reach()
    half = h + 3 * math.pi / (width // 2)
    n = int(min(512, max(16, math.ceil(_INSET_TEXELS * half / h))))
    axis = sky.sun
    x_axis = np.cross([0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0], axis)
    x_axis /= np.linalg.norm(x_axis)
    y_axis = np.cross(axis, x_axis)
    extent = math.tan(half)
    t = (2 * (np.arange(n) + 0.5) / n - 1) * extent
    x, y = t[None, :], -t[:, None]                               # (row 0 at the top: v = 1)
    d = x[..., None] * x_axis + y[..., None] * y_axis + axis
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    pixels = sky.radiance(d).astype(np.float32)
    frame = tuple(float(v) for v in np.concatenate([x_axis, y_axis, axis]))
    return pixels, frame, extent
