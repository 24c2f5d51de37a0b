"""Built-in scenes, as keyword arguments for `gridwalk.Scene`.

    scene = gridwalk.Scene(**gridwalk.scenes.SCENES["balls"](size=4))

balls(size)  SPD's "balls" (sphereflake): the same spheres, floor, materials,
             lights and view as SPD's balls generator writes to NFF, so that
             balls(n) matches ../shared/scenes/spd/balls_s<n>.nff.
icosphere()  a closed, outward-wound icosphere mesh (vertices, triangles).
distant()    the seed's "Distant" scene: three spheres at different distances
             on a ground plane, seen through a thin lens focused on the middle
             one; the seed renders it with DISTANT_DOF_SAMPLES samples a pixel.
"""
from __future__ import annotations

import math

import numpy as np

from .io.common import scene_kwargs
from .io.nff import nff_camera, spd_light_intensity
from .model import Camera, Light, Material

SPD_BACKGROUND = (0.078, 0.361, 0.753)      # SPD's "UNC sky blue"
DISTANT_DOF_SAMPLES = 32


def _child_directions() -> np.ndarray:
    """The 9 unit directions from a sphereflake sphere to its children, for a
    sphere whose own axis is +z, in SPD's order: three sectors 120 degrees
    apart, each with one child raised 54.7 degrees (the cube-diagonal angle)
    at azimuth 45 + 120k and two on the equator 30 degrees to either side."""
    rise = math.asin(math.sqrt(2.0 / 3.0))
    directions = []
    for sector in range(3):
        base = math.radians(45.0 + 120.0 * sector)
        for azimuth, elevation in ((base, rise), (base - math.pi / 6, 0.0),
                                   (base + math.pi / 6, 0.0)):
            directions.append((math.cos(elevation) * math.cos(azimuth),
                               math.cos(elevation) * math.sin(azimuth), math.sin(elevation)))
    return np.array(directions)


def _rotate_from_z(axes: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Rotate `vectors` (V, 3) by the shortest rotation taking +z to each unit
    vector in `axes` (P, 3); returns (P, V, 3). An axis at -z is reached by a
    half turn about y, as in SPD."""
    c = axes[:, 2][:, None, None]
    k = np.stack([-axes[:, 1], axes[:, 0], np.zeros(len(axes))], axis=1)[:, None, :]  # z x axis
    u = vectors[None, :, :]
    flipped = u * np.array([-1.0, 1.0, -1.0])
    with np.errstate(divide="ignore", invalid="ignore"):
        rotated = u * c + np.cross(k, u) + k * (k * u).sum(-1, keepdims=True) / (1.0 + c)
    return np.where(c < -0.9999, flipped, rotated)


def _sphereflake(size: int) -> tuple[np.ndarray, np.ndarray]:
    """Centres and radii of a sphereflake of `size` levels, in SPD's
    depth-first order (each sphere followed by its children's subtrees)."""
    total = (9 ** (size + 1) - 1) // 8
    centres, radii = np.empty((total, 3)), np.empty(total)
    directions = _child_directions()
    centre, axis = np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]])
    radius, position = 0.5, np.zeros(1, dtype=np.int64)
    for level in range(size + 1):
        centres[position], radii[position] = centre, radius
        if level == size:
            break
        subtree = (9 ** (size - level) - 1) // 8          # spheres under each child
        axis = _rotate_from_z(axis, directions)            # (parents, 9, 3)
        centre = (centre[:, None, :] + axis * (radius * 4.0 / 3.0)).reshape(-1, 3)
        axis = axis.reshape(-1, 3)
        position = (position[:, None] + 1 + np.arange(9) * subtree).reshape(-1)
        radius /= 3.0
    return centres, radii


def icosphere(subdivisions: int = 2, radius: float = 1.0, center=(0.0, 0.0, 0.0), dtype=np.float32):
    """A closed icosphere of 20 * 4**subdivisions outward-wound triangles:
    (vertices of `dtype`, triangles int32)."""
    t = (1.0 + 5 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        cache, nf = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                cache[key] = len(verts) - 1
            return cache[key]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    V = np.array(verts) * radius + np.asarray(center, float)
    return V.astype(dtype), np.array(f, np.int32)


def balls(size: int = 3) -> dict:
    """SPD "balls" of the given size factor: sum(9**k, k = 0..size) spheres
    (10, 91, 820, 7381 for sizes 1-4) on a square floor (2 triangles)."""
    if not (isinstance(size, int) and size >= 0):
        raise ValueError(f"balls: size must be an integer >= 0, got {size!r}")
    centres, radii = _sphereflake(size)
    gain = spd_light_intensity(3)
    # Materials as SPD writes them to NFF (f lines of balls_s*.nff): a matte
    # beige floor (its Shine is unused since Ks = 0) and shiny mirrored balls.
    floor = Material(color=(1.0, 0.75, 0.33), kd=0.8, ks=0.0, shininess=100000.0,
                     transmittance=0.0, ior=1.0, mirror=0.0)
    ball = Material(color=(1.0, 0.9, 0.7), kd=0.5, ks=0.5, shininess=3.0827,
                    transmittance=0.0, ior=1.0, mirror=0.5)
    return scene_kwargs(
        vertices=[(12.0, 12.0, -0.5), (-12.0, 12.0, -0.5), (-12.0, -12.0, -0.5),
                  (12.0, -12.0, -0.5)],
        triangles=[(0, 1, 2), (0, 2, 3)],
        triangle_materials=[0, 0],
        sphere_centers=centres, sphere_radii=radii,
        sphere_materials=np.ones(len(radii), dtype=np.int32),
        materials=[floor, ball],
        lights=[Light(position=p, color=(gain, gain, gain), kind="point")
                for p in ((4.0, 3.0, 2.0), (1.0, -4.0, 4.0), (-3.0, 1.0, 5.0))],
        camera=nff_camera((2.1, 1.3, 1.7), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 45.0, 512, 512, 0.01),
        background=SPD_BACKGROUND)


def distant() -> dict:
    """Three unit spheres on a ground plane at 6, 12 and 22 units from the
    camera; the lens (aperture radius 0.15) is focused on the middle one, so
    the near and far spheres blur."""
    eye = (0.0, -6.0, 1.6)
    centres = [(-1.4, 0.0, 1.0), (0.4, 6.0, 1.0), (3.2, 16.0, 1.0)]
    g = 60.0
    materials = [Material(color=(0.8, 0.8, 0.8), kd=0.8),                       # ground
                 Material(color=(0.9, 0.2, 0.15), kd=0.7, ks=0.3, shininess=60.0, mirror=0.1),
                 Material(color=(0.2, 0.8, 0.25), kd=0.7, ks=0.3, shininess=60.0, mirror=0.1),
                 Material(color=(0.2, 0.35, 0.9), kd=0.7, ks=0.3, shininess=60.0, mirror=0.1)]
    camera = Camera(eye=eye, target=centres[1], up=(0.0, 0.0, 1.0), fov=40.0,
                    width=512, height=512, aperture=0.15,
                    focus_distance=math.dist(eye, centres[1]))
    return scene_kwargs(
        vertices=[(-g, -g, 0.0), (g, -g, 0.0), (g, g, 0.0), (-g, g, 0.0)],
        triangles=[(0, 1, 2), (0, 2, 3)],
        triangle_materials=[0, 0],
        sphere_centers=centres, sphere_radii=[1.0, 1.0, 1.0], sphere_materials=[1, 2, 3],
        materials=materials,
        lights=[Light(position=(-6.0, -8.0, 10.0), color=(0.7, 0.7, 0.7)),
                Light(position=(8.0, 0.0, 6.0), color=(0.35, 0.35, 0.35))],
        camera=camera, background=SPD_BACKGROUND)


SCENES = {"balls": balls, "distant": distant}


def _rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def scattered_copies(n=400, seed=1, mirrored_every=3, extent=20.0):
    """n copies of an 80-triangle icosphere on a floor (every `mirrored_every`-th one
    mirrored, its corners reversed as Blender's exporter reverses them), turned and
    scaled at random, plus a sphere primitive; the scene's kwargs."""
    rng = np.random.default_rng(seed)
    mesh_v, mesh_t = icosphere(1, dtype=np.float64)
    verts, tris, ranges, meshes, matrices = [], [], [], [], []
    for i in range(n):
        m = np.eye(4)
        size = rng.uniform(0.2, 0.8)
        m[:3, :3] = _rotation(rng) * size
        mirrored = mirrored_every and i % mirrored_every == 0
        if mirrored:
            m[:3, 0] *= -1
        m[:3, 3] = [rng.uniform(-extent, extent), rng.uniform(-extent, extent), size]
        ranges.append((i * len(mesh_t), len(mesh_t)))
        tris.append((mesh_t[:, ::-1] if mirrored else mesh_t) + i * len(mesh_v))
        verts.append((mesh_v @ m[:3, :3].T + m[:3, 3]).astype(np.float32))
        meshes.append(int(mirrored))
        matrices.append(m)
    k = n * len(mesh_v)
    e = 1.5 * extent
    floor = np.array([[-e, -e, 0], [e, -e, 0], [e, e, 0], [-e, e, 0]], np.float32)
    return dict(vertices=np.concatenate(verts + [floor]),
                triangles=np.concatenate(tris + [np.array([[k, k + 1, k + 2], [k, k + 2, k + 3]], np.int32)]),
                sphere_centers=[[0.5, 0.5, 2.0]], sphere_radii=[0.7],
                instance_triangles=np.array(ranges), instance_meshes=np.array(meshes),
                instance_matrices=np.array(matrices))
