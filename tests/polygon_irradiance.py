"""Lambert's polygon formula: the exact irradiance a polygon of uniform radiance gives."""
import numpy as np


def polygon_irradiance(points, corners):
    """Irradiance / radiance at floor points (normal +z) from a polygon of unit
    radiance seen whole (Lambert: E = 1/2 sum over edges of theta_e (N . n_e))."""
    total = np.zeros(len(points))
    for a, b in zip(corners, np.roll(corners, -1, axis=0)):
        ra, rb = a[None, :] - points, b[None, :] - points
        ra /= np.linalg.norm(ra, axis=1)[:, None]
        rb /= np.linalg.norm(rb, axis=1)[:, None]
        theta = np.arccos(np.clip((ra * rb).sum(axis=1), -1, 1))
        n = np.cross(ra, rb)
        n /= np.linalg.norm(n, axis=1)[:, None]
        total += theta * n[:, 2]
    return np.abs(total) / 2
