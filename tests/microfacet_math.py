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


def ggx_glass_split(cos_o, alpha, n1, n2, n=1000):
    """(R, T): what a rough dielectric interface (GGX, Smith height-correlated G2, exact Fresnel)
    seen from cos_o on the side of index n1 reflects and lets through of a white world, single
    scattering, by a midpoint rule over directions: R integrates F D G2 / (4 cos_o) (the BRDF times cos_i) over the upper
    hemisphere, T Walter et al.'s (2007) BTDF times |cos_t| over the lower one, without its
    (n1 / n2)^2 compression of radiance (as the renderers' rays carry it)."""
    theta = (np.arange(n) + 0.5) / n * np.pi / 2
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    d_omega = np.sin(t) * (np.pi / 2 / n) * (np.pi / n)
    up = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    wo = np.array([np.sqrt(1 - cos_o ** 2), 0.0, cos_o])
    a2 = alpha ** 2
    lam = lambda c: 0.5 * (np.sqrt(1 + a2 * (1 - c * c) / (c * c)) - 1)
    ggx_d = lambda hz: a2 / (np.pi * (hz ** 2 * (a2 - 1) + 1) ** 2)
    eta = n2 / n1

    def fresnel(c):
        g2 = eta ** 2 - 1 + c * c
        g = np.sqrt(np.maximum(g2, 0))
        a, b = (g - c) / (g + c), (c * (g + c) - 1) / (c * (g - c) + 1)
        return np.where(g2 > 0, 0.5 * a * a * (1 + b * b), 1.0)

    h = up + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    reflect = fresnel((wo * h).sum(-1)) * ggx_d(h[..., 2]) / (1 + lam(cos_o) + lam(up[..., 2])) / (4 * cos_o)
    wt = up * np.array([1.0, 1.0, -1.0])                   # the lower hemisphere
    ht = -(n2 * wt + n1 * wo)
    ht /= np.linalg.norm(ht, axis=-1, keepdims=True)
    ht *= np.sign(ht[..., 2])[..., None]                   # towards the viewer's side
    co_h, ct_h = (wo * ht).sum(-1), (wt * ht).sum(-1)
    valid = (co_h > 0) & (ct_h < 0)                         # each direction on its own side of the microfacet
    g2 = 1 / (1 + lam(cos_o) + lam(-wt[..., 2]))
    btdf = (np.abs(ct_h) * co_h / (np.abs(wt[..., 2]) * cos_o) * n1 ** 2 * (1 - fresnel(co_h)) * ggx_d(ht[..., 2]) * g2
            / (n2 * ct_h + n1 * co_h) ** 2)
    through = np.where(valid, btdf, 0.0) * np.abs(wt[..., 2]) * eta ** 2
    return float((reflect * d_omega).sum()), float((through * d_omega).sum())
