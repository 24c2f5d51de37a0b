"""The GGX lobe and a dielectric's Fresnel in numpy (float64), written independently of the core
for the tests of glossy and dielectric surfaces."""
import numpy as np


def ggx_albedo(cos_o, alpha, n=1200, f0=None):
    """The GGX lobe's directional albedo at F = 1 (Smith height-correlated G2), by a midpoint rule
    over the hemisphere of light directions; with f0, weighted by the Fresnel of the dielectric of
    that reflectance at normal incidence."""
    theta = (np.arange(n) + 0.5) / n * np.pi / 2
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    wi = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    wo = np.array([np.sqrt(1 - cos_o ** 2), 0.0, cos_o])
    if f0 is None:
        brdf = ggx_brdf(wi, wo, alpha)
    else:
        h = (wi + wo) / np.linalg.norm(wi + wo, axis=-1, keepdims=True)
        brdf = ggx_brdf(wi, wo, alpha, dielectric_fresnel((wi * h).sum(-1), f0))
    return float((brdf * wi[..., 2] * np.sin(t)).sum() * (np.pi / 2 / n) * (np.pi / n))


def ggx_brdf(wi, wo, alpha, f=1.0):
    """F D G2 / (4 cos_i cos_o) in the frame whose z is the normal (numpy, float64)."""
    h = wi + wo
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    a2 = alpha ** 2
    d = a2 / (np.pi * (h[..., 2] ** 2 * (a2 - 1) + 1) ** 2)
    lam = lambda c: 0.5 * (np.sqrt(1 + a2 * (1 - c * c) / (c * c)) - 1)
    g2 = 1 / (1 + lam(wo[..., 2]) + lam(wi[..., 2]))
    return f * d * g2 / (4 * wi[..., 2] * wo[..., 2])


def dielectric_fresnel(c, f0):
    """The unpolarised Fresnel reflectance at cosine c of the dielectric whose reflectance at
    normal incidence is f0 (the mean of the s and p reflectances)."""
    eta = (1 + np.sqrt(f0)) / (1 - np.sqrt(f0))
    ct = np.sqrt(1 - (1 - c * c) / eta ** 2)
    rs, rp = (c - eta * ct) / (c + eta * ct), (eta * c - ct) / (eta * c + ct)
    return (rs * rs + rp * rp) / 2
