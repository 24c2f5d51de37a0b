"""Glossy surfaces (roughness > 0) reflect lamps and what surrounds them by a GGX microfacet lobe
(core/src/microfacet.h), as Cycles' Principled and Glossy BSDFs do: the highlight against the
formula, integrated here independently; the energy a white metal returns from a uniform world,
with and without Multiscatter GGX; a lobe far narrower than the light reflecting it as a mirror
does, without noise. Before, glossy surfaces took a normalised Blinn-Phong lobe whose rough
metals were 0.7-1.9x Cycles' brightness."""
import numpy as np
import pytest

import gridwalk as gw
from microfacet_math import dielectric_fresnel, ggx_albedo, ggx_brdf

RES = 41                                       # odd: the middle pixel's ray goes through the target


def floor_pixel(material, light_at, eye=(0.0, -3.0, 2.0)):
    """The middle pixel of a floor (z = 0) seen from `eye`, lit by a point light at `light_at`."""
    verts = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
    cam = gw.Camera(eye=eye, target=(0, 0, 0), fov=30, width=RES, height=RES)
    scene = gw.Scene(vertices=verts, triangles=[[0, 1, 2], [0, 2, 3]], materials=[material], camera=cam,
                     lights=[gw.Light(position=light_at, color=(5, 5, 5))], background=(0, 0, 0))
    return gw.render(scene, gw.RenderSettings())[RES // 2, RES // 2, :3]


@pytest.mark.parametrize("roughness", [0.2, 0.45, 0.8])
def test_a_lamps_highlight_is_the_ggx_formula(roughness):
    light_at, eye = np.array([0.6, 2.5, 2.2]), np.array([0.0, -3.0, 2.0])
    # ks = f0 x (shininess + 8) / 8: with shininess 0 the reflectance at normal incidence is ks
    glossy = gw.Material(color=(1, 1, 1), kd=0.0, ks=0.5, shininess=0.0, roughness=roughness)
    diffuse = gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)
    ratio = floor_pixel(glossy, tuple(light_at)) / floor_pixel(diffuse, tuple(light_at))
    wi, wo = light_at / np.linalg.norm(light_at), eye / np.linalg.norm(eye)
    h = (wi + wo) / np.linalg.norm(wi + wo)
    fresnel = dielectric_fresnel(wi @ h, 0.5)    # (a non-metal: the exact Fresnel of the IOR of f0 0.5)
    # a lamp lights a diffuse point by kd cos_i / pi (the lamps' intensities carry the 1 / pi)
    expected = ggx_brdf(wi, wo, roughness ** 2, fresnel) * np.pi
    assert ratio == pytest.approx([expected] * 3, rel=2e-3)


def white_metal_in_white_world(roughness, multiscatter, res=24):
    """The middle of a white metal sphere in a world of radiance 1, seen head on (cos_o about 1)."""
    metal = gw.Material(color=(1, 1, 1), kd=0.0, mirror=1.0, metallic=1.0, roughness=roughness,
                        multiscatter=multiscatter)
    cam = gw.Camera(eye=(0, -6, 0), target=(0, 0, 0), fov=25, width=res, height=res)
    scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], sphere_materials=[0], materials=[metal],
                     camera=cam, background=(1, 1, 1))
    image = gw.render(scene, gw.RenderSettings(aa="jittered", aa_samples=4, glossy_samples=64, max_depth=2))
    return image[res // 2 - 2:res // 2 + 2, res // 2 - 2:res // 2 + 2, :3].mean()


@pytest.mark.parametrize("roughness", [0.5, 0.8, 1.0])
def test_single_scattering_returns_the_lobes_albedo(roughness):
    # (the middle patch sees the sphere within about 4 degrees of head on)
    assert white_metal_in_white_world(roughness, False) == pytest.approx(ggx_albedo(0.999, roughness ** 2), rel=0.02)


@pytest.mark.parametrize("roughness", [0.5, 0.8, 1.0])
def test_multiscatter_returns_all_of_a_white_worlds_light(roughness):
    assert white_metal_in_white_world(roughness, True) == pytest.approx(1.0, abs=0.02)


def sphere_under_sun(roughness, mirror, seed):
    """The sum of the pixels of a white metal sphere under a sun 0.4 radians wide, in a black world,
    at 16 pixel samples x 4 light samples."""
    metal = gw.Material(color=(1, 1, 1), kd=0.0, ks=1.0, shininess=0.0, mirror=mirror, metallic=1.0,
                        roughness=roughness)
    cam = gw.Camera(eye=(0, -60, 0), target=(0, 0, 0), fov=2.5, width=64, height=64)
    sun = gw.Light(kind="sun", direction=(0.3, -1.0, 0.5), angle=0.4)
    scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], sphere_materials=[0], materials=[metal],
                     camera=cam, lights=[sun], background=(0, 0, 0))
    settings = gw.RenderSettings(aa="jittered", aa_samples=4, shadow="random", shadow_samples=4, seed=seed)
    return float(gw.render(scene, settings)[..., :3].sum())


def test_a_lobe_far_narrower_than_the_light_keeps_its_highlights_energy():
    # The sharp mirror shows the sun's disk (its rays see the light's shape); a roughness of
    # 0.01 is a lobe a thousandth of the sun's width: met by the light's samples alone, its
    # highlight summed to 0.5-2.3% of the mirror's at these samples (and 0.33-1.24x at
    # roughness 0.03, by seed). It is the light seen in the mirror direction now.
    mirror = sphere_under_sun(0.0, 1.0, 0)
    for seed in (1, 2, 3):
        assert sphere_under_sun(0.01, 0.0, seed) == pytest.approx(mirror, rel=0.03)


def floor_under_rect(roughness, mirror, res=5):
    """A floor pixel whose mirror direction meets a 1 x 1 rect light (with falloff) inside its
    edges, 3 units away."""
    verts = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
    floor = gw.Material(color=(1, 1, 1), kd=0.0, ks=0.5, shininess=0.0, roughness=roughness, mirror=mirror)
    light = gw.Light(kind="rect", position=(0.1, 2.6, 1.8), size=(1, 1), axis_u=(1, 0, 0), axis_v=(0, -1, 0),
                     direction=(0, 0, -1), color=(5, 5, 5), inverse_square=True)
    cam = gw.Camera(eye=(0, -3, 2), target=(0, 0, 0), fov=30, width=res, height=res)
    scene = gw.Scene(vertices=verts, triangles=[[0, 1, 2], [0, 2, 3]], materials=[floor], camera=cam,
                     lights=[light], background=(0, 0, 0))
    return gw.render(scene, gw.RenderSettings(shadow="random", shadow_samples=16))[res // 2, res // 2, 0]


@pytest.mark.parametrize("roughness", [0.03, 0.08])
def test_a_narrow_lobe_reflects_a_rect_light_as_bright_as_a_mirror_does(roughness):
    # Inside the light's reflection a narrow lobe returns the light's radiance times Fresnel
    # (a dielectric's of f0 0.5 at the view's angle; the albedo is about 1). Widening such lobes to a
    # fifth of the light's radius instead (the commit before) dimmed such reflections to
    # 0.61-0.78 of it in a review's measurements; sampling the light alone is noise.
    wo = np.array([0.0, -3.0, 2.0]) / np.linalg.norm([0.0, -3.0, 2.0])
    fresnel = dielectric_fresnel(wo[2], 0.5)
    assert floor_under_rect(roughness, 0.0) == pytest.approx(floor_under_rect(0.0, 1.0) * fresnel, rel=0.03)



def floor_under_emitter(material):
    """A glossy floor lit only by an emissive 1 x 1 panel 1.5 above it, seen near the panel's
    reflection (the panel itself out of view), as an image."""
    verts = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0],
                      [-0.5, 1.5, 1.5], [0.5, 1.5, 1.5], [0.5, 2.5, 1.5], [-0.5, 2.5, 1.5]], np.float32)
    panel = gw.Material(color=(1, 1, 1), kd=0.0, emission=4.0, emits_light=True)
    cam = gw.Camera(eye=(0, -2, 1.2), target=(0, 1.2, 0), fov=30, width=24, height=24)
    scene = gw.Scene(vertices=verts, triangles=[[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]],
                     triangle_materials=[0, 0, 1, 1], materials=[material, panel], camera=cam,
                     background=(0, 0, 0))
    settings = gw.RenderSettings(aa="jittered", aa_samples=4, shadow="random", shadow_samples=8, glossy_samples=8)
    return gw.render(scene, settings)[..., :3]


def test_a_half_metal_reflects_emitters_as_the_mean_of_metal_and_dielectric():
    # Every term of the material is linear in its metallic share (the Principled mapping: half
    # the diffuse, Fresnel from the mean reflectance, half the mirror reflection), so its image is
    # the mean of the metal's and the dielectric's. Emitters are seen by the glossy rays (the
    # mirror share) and sampled (the rest): sampled with f0 x (1 - mirror) before, the half metal
    # took 0.25 of the metal's highlight twice over.
    copper, r = (0.9, 0.6, 0.3), 0.3
    metal = gw.Material(color=copper, kd=0.0, ks=1.0, shininess=0.0, mirror=1.0, metallic=1.0, roughness=r)
    dielectric = gw.Material(color=copper, kd=0.6, ks=0.04, shininess=0.0, roughness=r)
    half = gw.Material(color=copper, kd=0.3, ks=0.52, shininess=0.0, mirror=0.5, metallic=0.5, roughness=r)
    mean = (floor_under_emitter(metal) + floor_under_emitter(dielectric)) / 2
    assert floor_under_emitter(half).sum() == pytest.approx(mean.sum(), rel=0.03)
