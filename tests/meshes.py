"""Small mesh generators shared by the tests (closed meshes, soups)."""
import numpy as np

from gridwalk.scenes import icosphere, scattered_copies  # noqa: F401  (re-exported for the tests)


def triangle_soup(n, seed=0, extent=10.0, size=1.0):
    """n random triangles in a cube of side `extent`."""
    rng = np.random.default_rng(seed)
    centers = rng.uniform(0, extent, (n, 1, 3))
    V = (centers + rng.normal(0, size, (n, 3, 3))).reshape(-1, 3).astype(np.float32)
    return V, np.arange(3 * n, dtype=np.int32).reshape(n, 3)


def random_rays(n, lo, hi, seed=0):
    """Origins uniform in the box [lo, hi] (slightly enlarged), unit directions uniform on the sphere."""
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    pad = 0.1 * (hi - lo)
    o = rng.uniform(lo - pad, hi + pad, (n, 3))
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return o.astype(np.float32), d.astype(np.float32)


def camera_rays(eye, target, n_side, fov_deg=40.0):
    """A coherent n_side x n_side pinhole bundle from eye towards target."""
    eye, target = np.asarray(eye, float), np.asarray(target, float)
    fwd = (target - eye) / np.linalg.norm(target - eye)
    up = np.array([0.0, 0.0, 1.0]) if abs(fwd[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    right = np.cross(fwd, up); right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    h = np.tan(np.radians(fov_deg) / 2)
    s = np.linspace(-h, h, n_side)
    x, y = np.meshgrid(s, s)
    d = fwd + x[..., None] * right + y[..., None] * up
    d = d.reshape(-1, 3)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    o = np.broadcast_to(eye, d.shape)
    return np.ascontiguousarray(o, np.float32), d.astype(np.float32)


def uv_sphere(rings=24, segments=48, radius=1.0, jitter=0.05, center=(0.0, 0.0, 0.0), seed=0):
    """A closed UV sphere with jittered radii, a seam of duplicated vertices and
    coincident (duplicated) pole vertices, one per segment. Duplicates share
    bit-identical coordinates, so the surface is closed while the topology is not."""
    rng = np.random.default_rng(seed)
    radii = radius * (1 + jitter * rng.uniform(-1, 1, (rings + 1, segments)))
    radii[:, -1] = radii[:, 0] * 1.0
    radii = np.concatenate([radii, radii[:, :1]], axis=1)     # the seam column repeats column 0
    radii[0, :] = radius
    radii[-1, :] = radius
    theta = np.linspace(0, np.pi, rings + 1)[:, None]
    phi = np.linspace(0, 2 * np.pi, segments + 1)[None, :]
    phi = np.broadcast_to(phi, (rings + 1, segments + 1)).copy()
    phi[:, -1] = 0.0                                           # seam: same angle as column 0
    x = radii * np.sin(theta) * np.cos(phi)
    y = radii * np.sin(theta) * np.sin(phi)
    z = radii * np.cos(theta) * np.ones_like(phi)
    x[0, :] = y[0, :] = 0.0
    x[-1, :] = y[-1, :] = 0.0                                  # coincident poles
    V = (np.stack([x, y, z], -1).reshape(-1, 3) + np.asarray(center, float)).astype(np.float32)
    idx = np.arange((rings + 1) * (segments + 1)).reshape(rings + 1, segments + 1)
    a, b = idx[:-1, :-1], idx[:-1, 1:]
    c, d = idx[1:, :-1], idx[1:, 1:]
    F = np.concatenate([np.stack([a, c, d], -1).reshape(-1, 3), np.stack([a, d, b], -1).reshape(-1, 3)])
    return V, F.astype(np.int32)
