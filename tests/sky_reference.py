"""A numpy transcription of Nishita's single-scattering sky, in double precision: the
reference that test81 holds the core's float table (core/src/sky.cpp) to.

Blender's Sky Texture (its Nishita type, 5.0's Single Scattering) precomputes a
table of the sky's colour over directions (Nishita et al. 1993, "Display of the
Earth taking into account atmospheric scattering"; the constants are Cycles'
`intern/sky`):

- an Earth of radius 6360 km under 60 km of atmosphere, the camera at
  `altitude` metres;
- Rayleigh scattering by air (scale height 8 km), Mie scattering by dust
  (1.2 km, anisotropy 0.76, extinction 1.11 x its scattering) and absorption by
  ozone (a tent between 10 and 40 km), each times its density factor;
- 21 wavelengths from 380 to 780 nm, the sun's spectrum at the top of the
  atmosphere, turned into CIE XYZ by the 1931 colour-matching functions;
- each view ray marched in 32 segments to the top of the atmosphere, each
  segment lit by the sun through the atmosphere above it (unless the Earth is
  in the way), that path's optical depth by an 8-point Gauss-Laguerre rule.

single_scattering() gives XYZ radiance along view directions, sun_radiance() the
sun disc's.
"""
from __future__ import annotations

import numpy as np

EARTH_RADIUS = 6360e3
ATMOSPHERE_RADIUS = 6420e3
RAYLEIGH_SCALE = 8e3
MIE_SCALE = 1.2e3
MIE_COEFF = 2e-5
MIE_G = 0.76
MIE_EXTINCTION = 1.11          # Mie extinction / Mie scattering
STEPS = 32
STEP_LAMBDA = 20.0             # nm, 380..780 in 21 wavelengths

# Per wavelength (380, 400, ..., 780 nm): the sun's irradiance at the top of the
# atmosphere (W m^-2 nm^-1), Rayleigh scattering and ozone absorption (m^-1) at
# sea-level density, and the CIE 1931 colour-matching functions.
SUN_IRRADIANCE = np.array([
    1.45756829855592995315, 1.56596305559738380175, 1.65148449067670455293, 1.71496242737209314555,
    1.75797983805020541226, 1.78256407885924539336, 1.79095108475838560302, 1.78541550133410664714,
    1.76815554864306845317, 1.74122069647250410362, 1.70647127164943679389, 1.66556087452739887134,
    1.61993437242451854274, 1.57083597368892080581, 1.51932335059305478886, 1.46628494965214395407,
    1.41245852740172450623, 1.35844961970384092709, 1.30474913844739281998, 1.25174963272610817455,
    1.19975998755420620867])
RAYLEIGH = np.array([
    5.424820087636473e-05, 4.418549866505454e-05, 3.635151910165377e-05, 3.017929012024763e-05,
    2.526320226989157e-05, 2.130859310621843e-05, 1.809838025320633e-05, 1.547057129129042e-05,
    1.330284977336850e-05, 1.150184784075764e-05, 9.99557429990163e-06, 8.72799973630707e-06,
    7.65513700977967e-06, 6.74217203751443e-06, 5.96134125832052e-06, 5.29034598065810e-06,
    4.71115687557433e-06, 4.20910481110487e-06, 3.77218381260133e-06, 3.39051255477280e-06,
    3.05591531679811e-06])
OZONE = np.array([
    3.25126849861e-09, 5.85395365047e-09, 1.977191155085e-08, 7.309568762914e-08, 2.0084561514287e-07,
    4.0383958096161e-07, 6.3551335912363e-07, 9.6707041180970e-07, 1.54797400424410e-06,
    2.09038647223331e-06, 2.46128056164565e-06, 2.73551299461512e-06, 2.15125863128643e-06,
    1.59051840791988e-06, 1.12356197979857e-06, 7.3527551487574e-07, 4.6450130357806e-07,
    3.3096079921048e-07, 2.2512612292678e-07, 1.4879129266490e-07, 1.6828623364192e-07])
CMF_XYZ = np.array([
    (0.00136800000, 0.00003900000, 0.00645000100), (0.01431000000, 0.00039600000, 0.06785001000),
    (0.13438000000, 0.00400000000, 0.64560000000), (0.34828000000, 0.02300000000, 1.74706000000),
    (0.29080000000, 0.06000000000, 1.66920000000), (0.09564000000, 0.13902000000, 0.81295010000),
    (0.00490000000, 0.32300000000, 0.27200000000), (0.06327000000, 0.71000000000, 0.07824999000),
    (0.29040000000, 0.95400000000, 0.02030000000), (0.59450000000, 0.99500000000, 0.00390000000),
    (0.91630000000, 0.87000000000, 0.00165000100), (1.06220000000, 0.63100000000, 0.00080000000),
    (0.85444990000, 0.38100000000, 0.00019000000), (0.44790000000, 0.17500000000, 0.00002000000),
    (0.16490000000, 0.06100000000, 0.00000000000), (0.04677000000, 0.01700000000, 0.00000000000),
    (0.01135916000, 0.00410200000, 0.00000000000), (0.00289932700, 0.00104700000, 0.00000000000),
    (0.00069007860, 0.00024920000, 0.00000000000), (0.00016615050, 0.00006000000, 0.00000000000),
    (0.00004150994, 0.00001499000, 0.00000000000)])

# Gauss-Laguerre, 8 points, for the optical depth towards the sun: the nodes as
# fractions of the path to the top of the atmosphere (the last within it), the
# weights with exp(node) folded in (so that they integrate the density itself).
_LAGUERRE_NODES = np.array([0.006811185292, 0.03614807107, 0.09004346519, 0.1706680068,
                            0.2818362161, 0.4303406404, 0.6296271457, 0.9145252695])
_LAGUERRE_WEIGHTS = np.array([0.01750893642, 0.04135477391, 0.06678839063, 0.09507698807,
                              0.1283416365, 0.1707430204, 0.2327233347, 0.3562490486])


def direction(elevation, azimuth) -> np.ndarray:
    """Unit vectors (..., 3) at these elevations and azimuths (radians; azimuth 0 along +X)."""
    elevation, azimuth = np.broadcast_arrays(np.asarray(elevation, float), np.asarray(azimuth, float))
    return np.stack([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                     np.sin(elevation)], axis=-1)


def _densities(height) -> np.ndarray:
    """(..., 3): air, dust and ozone density factors at heights above the ground (m)."""
    ozone = np.where((height >= 10e3) & (height < 25e3), height / 15e3 - 2 / 3,
                     np.where((height >= 25e3) & (height < 40e3), 8 / 3 - height / 15e3, 0.0))
    return np.stack([np.exp(-height / RAYLEIGH_SCALE), np.exp(-height / MIE_SCALE), ozone], axis=-1)


def _to_atmosphere_top(p, d) -> np.ndarray:
    """Distance from points p (..., 3) inside the atmosphere along d to its top."""
    b = (p * d).sum(-1)
    c = (p * p).sum(-1) - ATMOSPHERE_RADIUS ** 2
    return -b + np.sqrt(np.maximum(b * b - c, 0.0))


def _optical_depth(p, d) -> np.ndarray:
    """(..., 3) integrals of the three densities from p along d to the top of the atmosphere."""
    length = _to_atmosphere_top(p, d)
    points = p[..., None, :] + (_LAGUERRE_NODES[:, None] * d) * length[..., None, None]
    heights = np.linalg.norm(points, axis=-1) - EARTH_RADIUS
    return (_densities(heights) * _LAGUERRE_WEIGHTS[:, None]).sum(-2) * length[..., None]


def _hits_ground(p, d) -> np.ndarray:
    """Whether the ray from p along d (a constant direction) meets the Earth."""
    if d[2] >= 0:
        return np.zeros(p.shape[:-1], bool)
    b = (p * d).sum(-1)
    return b * b - ((p * p).sum(-1) - EARTH_RADIUS ** 2) >= 0


def _phases(mu) -> np.ndarray:
    """(..., 2): Rayleigh's and the Cornette-Shanks Mie phase functions at cos(angle) mu."""
    g2 = MIE_G * MIE_G
    rayleigh = 3 / (16 * np.pi) * (1 + mu * mu)
    mie = 3 * (1 - g2) * (1 + mu * mu) / (8 * np.pi * (2 + g2) * (1 + g2 - 2 * MIE_G * mu) ** 1.5)
    return np.stack([rayleigh, mie], axis=-1)


def _spectrum_to_xyz(spectrum) -> np.ndarray:
    return spectrum @ CMF_XYZ * STEP_LAMBDA


def single_scattering(view, sun_direction, altitude, densities) -> np.ndarray:
    """XYZ radiance (N, 3) seen along unit directions view (N, 3) from `altitude`
    metres, lit by a sun in unit direction sun_direction; densities: the air,
    dust and ozone factors (1 = Earth's)."""
    view = np.asarray(view, float)
    sun_direction = np.asarray(sun_direction, float)
    scale = np.asarray(densities, float)
    origin = np.array([0.0, 0.0, EARTH_RADIUS + altitude])
    segment = _to_atmosphere_top(np.broadcast_to(origin, view.shape), view) / STEPS
    phase = _phases(view @ sun_direction)                                     # (N, 2)
    depth = np.zeros(view.shape[:-1] + (3,))
    spectrum = np.zeros(view.shape[:-1] + (len(SUN_IRRADIANCE),))
    extinction = np.stack([RAYLEIGH, np.full_like(RAYLEIGH, MIE_EXTINCTION * MIE_COEFF), OZONE])   # (3, 21)
    for i in range(STEPS):
        point = origin + view * (segment * (i + 0.5))[..., None]
        density = scale * _densities(np.linalg.norm(point, axis=-1) - EARTH_RADIUS)
        depth += segment[..., None] * density
        lit = ~_hits_ground(point, sun_direction)
        total = depth + scale * _optical_depth(point, sun_direction)
        scattering = (density[..., :2] * phase) @ np.stack([RAYLEIGH, np.full_like(RAYLEIGH, MIE_COEFF)])
        spectrum += np.where(lit[..., None], np.exp(-total @ extinction) * scattering, 0.0) \
            * (SUN_IRRADIANCE * segment[..., None])
    return _spectrum_to_xyz(spectrum)


def sun_radiance(elevation, angular_diameter, altitude, densities) -> np.ndarray:
    """XYZ radiance of the sun's disc seen at `elevation` (its light through the
    atmosphere, spread over the disc's solid angle; the Earth not considered)."""
    scale = np.asarray(densities, float)
    origin = np.array([0.0, 0.0, EARTH_RADIUS + altitude])
    depth = _optical_depth(origin, direction(elevation, 0.0))
    transmittance = np.exp(-(RAYLEIGH * depth[0] * scale[0] + MIE_EXTINCTION * MIE_COEFF * depth[1] * scale[1]))
    solid_angle = 2 * np.pi * (1 - np.cos(angular_diameter / 2))
    return _spectrum_to_xyz(SUN_IRRADIANCE * transmittance / solid_angle)

