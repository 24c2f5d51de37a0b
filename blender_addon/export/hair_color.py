"""The colour a hair BSDF shows, for the Whitted material of hair curves.

Cycles' Principled Hair BSDF (Chiang et al. 2016's model, and Huang et al.
2022's in Blender 4.0+) takes an absorption coefficient sigma_a inside the
fibre, given directly (Absorption Coefficient), from melanin concentrations
(Melanin, Melanin Redness, Tint), or from a colour (Direct Coloring). The
colour a fibre shows is the inverse of Chiang et al.'s mapping from a
colour to sigma_a (their eq. for the azimuthal roughness beta_n, the node's
Radial Roughness):

    sigma_a = (ln(colour) / f(beta_n))^2,
    f(b) = 5.969 - 0.215 b + 2.532 b^2 - 10.73 b^3 + 5.574 b^4 + 0.245 b^5,

so colour = exp(-sqrt(sigma_a) f(beta_n)). Melanin gives sigma_a as the sum
of eumelanin's and pheomelanin's absorption (the coefficients Cycles uses)
times their concentrations; Melanin in [0, 1] maps to the
concentration -ln(1 - Melanin), split by Melanin Redness; Tint adds its own
sigma_a by the same mapping. The older Hair BSDF gives its Color as is.
"""
from __future__ import annotations

import numpy as np

EUMELANIN = np.array([0.506, 0.841, 1.653])    # absorption per unit concentration, as Cycles sets them
PHEOMELANIN = np.array([0.343, 0.733, 1.924])


def _roughness_factor(beta: float) -> float:
    b = min(max(float(beta), 0.0), 1.0)
    return ((((0.245 * b + 5.574) * b - 10.73) * b + 2.532) * b - 0.215) * b + 5.969


def sigma_from_color(color, beta: float) -> np.ndarray:
    c = np.clip(np.asarray(color, np.float64)[:3], 1e-4, 1.0)
    return (np.log(c) / _roughness_factor(beta)) ** 2


def color_from_sigma(sigma, beta: float) -> tuple:
    s = np.maximum(np.asarray(sigma, np.float64), 0.0)
    return tuple(float(x) for x in np.exp(-np.sqrt(s) * _roughness_factor(beta)))


def sigma_from_melanin(melanin: float, redness: float) -> np.ndarray:
    amount = -np.log(max(1.0 - min(max(float(melanin), 0.0), 1.0), 1e-4))
    red = min(max(float(redness), 0.0), 1.0)
    return amount * (1.0 - red) * EUMELANIN + amount * red * PHEOMELANIN


def hair_color(parametrization: str, value) -> tuple:
    """The colour of a Principled Hair BSDF; value(name, default) reads an input."""
    beta = value("Radial Roughness", 0.3)
    if parametrization == "COLOR":
        return tuple(float(c) for c in value("Color", (0.017513, 0.005763, 0.002059))[:3])
    if parametrization == "ABSORPTION":
        sigma = np.asarray(value("Absorption Coefficient", (0.245531, 0.52, 1.365))[:3], np.float64)
    else:
        sigma = sigma_from_melanin(value("Melanin", 0.8), value("Melanin Redness", 1.0)) \
            + sigma_from_color(value("Tint", (1.0, 1.0, 1.0)), beta)
    return color_from_sigma(sigma, beta)
