"""A glossy lobe wider than the environment's sun (its bright cells, which world shadows already
sample as a light) samples that sun as a light, and its rays leave the sun's cells out: rays alone
met a sun of 200x the sky's radiance with a small chance and its whole weight, fireflies over
every rough metal and, since dielectrics reflect their surroundings, every Principled surface
under an HDRI with a sun (Suzanne's row of docs/materials.md fell from NCC 0.992 to 0.812)."""
import numpy as np
import pytest

import gridwalk as gw
from microfacet_math import ggx_brdf

RES = 41
EYE = np.array([0.0, -3.0, 2.0])
H, W = 128, 256


def sky_with_sun():
    """A sky of 0.3 with a 3 x 3-texel sun of 5000 near the floor's mirror direction (+Y, 34
    degrees up) and a darker ground half."""
    sky = np.full((H, W, 3), 0.3, np.float32)
    sky[H // 2:] = 0.05
    sky[38:41, 62:65] = 5000.0
    return sky


def texel_directions_and_solid_angles():
    u, v = (np.arange(W) + 0.5) / W, 1 - (np.arange(H) + 0.5) / H
    phi, e = (0.5 - u) * 2 * np.pi, (v - 0.5) * np.pi
    d = np.stack([np.cos(e)[:, None] * np.cos(phi)[None, :], np.cos(e)[:, None] * np.sin(phi)[None, :],
                  np.broadcast_to(np.sin(e)[:, None], (H, W))], axis=-1)
    edges = (0.5 - np.arange(H + 1) / H) * np.pi
    omega = np.broadcast_to((2 * np.pi / W * (np.sin(edges[:-1]) - np.sin(edges[1:])))[:, None], (H, W))
    return d, omega


def render_floor(roughness, seed=0):
    verts = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
    metal = gw.Material(color=(1, 1, 1), kd=0.0, ks=1.0, shininess=0.0, mirror=1.0, metallic=1.0,
                        roughness=roughness)
    cam = gw.Camera(eye=tuple(EYE), target=(0, 0, 0), fov=30, width=RES, height=RES)
    scene = gw.Scene(vertices=verts, triangles=[[0, 1, 2], [0, 2, 3]], materials=[metal], camera=cam,
                     textures=[gw.Texture(gw.Image(sky_with_sun()))],
                     world=gw.World(environment=0, environment_light=True))
    settings = gw.RenderSettings(aa="jittered", aa_samples=8, glossy_samples=2, max_depth=2, seed=seed)
    return gw.render(scene, settings)[..., :3].mean(axis=2)


@pytest.mark.parametrize("roughness", [0.4, 0.7])
def test_a_rough_metal_reflects_the_sky_and_its_sun_without_fireflies(roughness):
    image = render_floor(roughness)
    d, omega = texel_directions_and_solid_angles()
    up = d[..., 2] > 0
    wo = EYE / np.linalg.norm(EYE)
    # a white metal (F = 1): the middle pixel's value is the GGX lobe over the sky's texels
    expected = float((ggx_brdf(d[up], wo, roughness ** 2) * d[up][:, 2] * sky_with_sun()[up][:, 0]
                      * omega[up]).sum())
    middle = image[RES // 2 - 1:RES // 2 + 2, RES // 2 - 1:RES // 2 + 2].mean()
    assert middle == pytest.approx(expected, rel=0.03)
    assert expected > 2 * 0.3                                  # (the sun is most of it)
    # no fireflies: neighbouring pixels differ by little (rays meeting the sun gave single pixels
    # of many times their neighbours)
    patch = image[RES // 2 - 4:RES // 2 + 5, RES // 2 - 4:RES // 2 + 5]
    assert patch.max() < 1.5 * np.median(patch), (patch.max(), np.median(patch))
