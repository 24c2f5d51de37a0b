"""A floor at z = 0 seen by a pixel at its origin from EYE, a square panel of light facing down
above it, and the GGX lobe integrated over the panel in numpy: shared by the tests of glossy
rays and light points sharing a light's highlight (test71: emissive triangles, test73: lamps)."""
import numpy as np

import gridwalk as gw
from microfacet_math import dielectric_fresnel, ggx_brdf

EYE = np.array([0.0, -3.0, 2.0])
CENTRE = np.array([0.0, 3.0, 2.0])              # on the reflection of the ray from EYE to the origin


# What may stand halfway between the floor's origin and the light (blocker_quad).
BLOCKERS = {"opaque": gw.Material(color=(0, 0, 0), kd=0.0, ks=0.0),
            "cut-out": gw.Material(color=(0, 0, 0), kd=0.0, ks=0.0, alpha=0.0),
            "clear pane": gw.Material(color=(1, 1, 1), kd=0.0, ks=0.0, transmittance=1.0, ior=1.0)}


def blocker_quad(centre=CENTRE):
    """The corners of a 2 x 2 horizontal quad halfway between the floor's origin and `centre`."""
    mid = np.asarray(centre) / 2
    return [list(mid + [dx, dy, 0]) for dx, dy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]


def shininess(roughness):
    return min(2 / max(roughness ** 2, 1e-3) ** 2 - 2, 1000.0)


def white_metal(roughness):
    s = shininess(roughness)
    return gw.Material(color=(1, 1, 1), kd=0.0, ks=(s + 8) / 8, shininess=s, roughness=roughness, mirror=1.0,
                       metallic=1.0)


def dielectric_layer(roughness, f0):
    s = shininess(roughness)
    return gw.Material(color=(1, 1, 1), kd=0.0, ks=f0 * (s + 8) / 8, shininess=s, roughness=roughness,
                       dielectric_reflection=True)


def lobe_over_panel(roughness, size, radiance, f0=None, centre=CENTRE, n=400):
    """The floor's origin lit by a size x size panel of the radiance centred at `centre`, facing
    down: the GGX BRDF (F = 1, or a dielectric's Fresnel of f0) x radiance x cos_i over the
    panel's solid angle, by a midpoint rule over its area."""
    g = ((np.arange(n) + 0.5) / n - 0.5) * size
    x, y = np.meshgrid(g, g)
    q = np.stack([x + centre[0], y + centre[1], np.full_like(x, centre[2])], -1)
    d2 = (q ** 2).sum(-1)
    wi = q / np.sqrt(d2)[..., None]
    wo = EYE / np.linalg.norm(EYE)
    f = 1.0
    if f0 is not None:
        h = (wi + wo) / np.linalg.norm(wi + wo, axis=-1, keepdims=True)
        f = dielectric_fresnel((wi * h).sum(-1), f0)
    brdf = ggx_brdf(wi, wo, roughness ** 2, f)
    # dw = cos_l dA / d^2, the panel facing along z (cos_l = wi.z, as cos_i)
    return float((brdf * wi[..., 2] * wi[..., 2] / d2).sum() * (size / n) ** 2 * radiance)
