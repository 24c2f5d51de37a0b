"""Whitted shading against analytic values, energy conservation of the Fresnel
split, bit-identical output for any thread count and tile size, and a render
regression against a stored reference (GRIDWALK_REGEN=1 rewrites it)."""
import os
from pathlib import Path

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls
from meshes import icosphere

REF = Path(__file__).parent / "references" / "balls1_96.npz"
FLOOR_V = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
FLOOR_F = np.array([[0, 1, 2], [0, 2, 3]], np.int32)


def top_down_camera(n=65, height=10.0, fov=60.0):
    return gw.Camera(eye=(0, 0, height), target=(0, 0, 0), up=(0, 1, 0), fov=fov, width=n, height=n)


def floor_directions(cam, h):
    """At each pixel's floor point under top_down_camera: the unit direction to
    a light at height h above the origin, and the half vector with the eye's."""
    n = cam.width
    t = np.tan(np.radians(cam.fov) / 2)
    c = (np.arange(n) + 0.5) / n
    X, Y = np.meshgrid((2 * c - 1) * t * 10, (1 - 2 * c) * t * 10)
    P = np.stack([X, Y, np.zeros_like(X)], -1)
    wi = np.array([0, 0, h]) - P
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    wo = np.array([0, 0, 10.0]) - P
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    H = wi + wo
    return wi, H / np.linalg.norm(H, axis=-1, keepdims=True)


def test_blinn_phong_and_mirror_match_analytic_values():
    kd, ks, shine, mirror, I, h = 0.5, 0.3, 20.0, 0.25, 2.0, 5.0
    color, bg = np.array([1.0, 0.5, 0.25]), np.array([0.2, 0.3, 0.4])
    mat = gw.Material(color=tuple(color), kd=kd, ks=ks, shininess=shine, mirror=mirror)
    cam = top_down_camera()
    sc = gw.Scene(vertices=FLOOR_V, triangles=FLOOR_F, materials=[mat],
                  lights=[gw.Light(position=(0, 0, h), color=(I, I, I))], camera=cam, background=tuple(bg))
    img = gw.render(sc, gw.RenderSettings(threads=2))
    wi, H = floor_directions(cam, h)
    expected = (kd * color * wi[..., 2:3] + ks * H[..., 2:3] ** shine) * I + mirror * bg
    assert np.allclose(img[..., :3], expected, rtol=2e-5, atol=2e-6)
    assert np.all(img[..., 3] == 1.0)


@pytest.mark.parametrize("metallic", [0.0, 0.6, 1.0])
def test_a_metal_tints_its_highlight_and_reflection_with_its_colour(metallic):
    """The analytic floor above, now partly metal: the metal's share of the
    highlight (metallic * (shine + 8) / (8 ks)) and of the mirror term takes
    the base colour (a gold Principled BSDF rendered a grey mirror)."""
    shine, I, h, mirror = 20.0, 2.0, 5.0, metallic
    ks = ((1 - metallic) * 0.04 + metallic) * (shine + 8) / 8
    color, bg = np.array([1.0, 0.5, 0.25]), np.array([0.2, 0.3, 0.4])
    mat = gw.Material(color=tuple(color), kd=0.0, ks=ks, shininess=shine, mirror=mirror, metallic=metallic)
    cam = top_down_camera()
    sc = gw.Scene(vertices=FLOOR_V, triangles=FLOOR_F, materials=[mat],
                  lights=[gw.Light(position=(0, 0, h), color=(I, I, I))], camera=cam, background=tuple(bg))
    img = gw.render(sc, gw.RenderSettings(threads=2))
    wi, H = floor_directions(cam, h)
    metal = min(1.0, metallic * (shine + 8) / (8 * ks))
    tint = 1 + (color - 1) * metal
    expected = ks * H[..., 2:3] ** shine * I * tint + mirror * bg * color
    np.testing.assert_allclose(img[..., :3], expected, rtol=2e-5, atol=2e-6)


def test_shadowed_floor_gets_only_the_mirror_term():
    mat = gw.Material(color=(1, 1, 1), kd=0.8, mirror=0.1)
    sc = gw.Scene(vertices=FLOOR_V, triangles=FLOOR_F, sphere_centers=[[0, 0, 2]], sphere_radii=[1.0],
                  materials=[mat], lights=[gw.Light(position=(0, 0, 4))], camera=top_down_camera(n=33, height=30, fov=20),
                  background=(0.5, 0.5, 0.5))
    depth = gw.RenderJob(sc).start()
    depth.wait()
    img, z = depth.image, depth.depth
    floor = np.abs(z - 30.0) < 1e-3
    r2 = np.sum(np.stack(np.meshgrid(np.arange(33) - 16, np.arange(33) - 16), -1) ** 2, -1)
    # A unit sphere at height 2 under a light at height 4 subtends 30 degrees:
    # its shadow on the floor has radius 4 tan(30deg); the camera sees the
    # floor outside the sphere's own silhouette (radius ~1.1).
    px = 30 * np.tan(np.radians(10)) / 16.5
    r = np.sqrt(r2) * px
    umbra = floor & (r > 1.2) & (r < 0.9 * 4 * np.tan(np.radians(30)))
    lit = floor & (r > 1.1 * 4 * np.tan(np.radians(30)))
    assert umbra.sum() > 0 and lit.sum() > 0
    # In the umbra only the mirror reflection remains: it sees the sphere's underside (dark) or background.
    assert np.all(img[umbra, 0] < 0.1)
    assert np.all(img[lit, 0] > 0.3)


def test_a_light_that_casts_no_shadows_lights_the_floor_under_an_occluder():
    # Blender's Cast Shadow off: the floor under the sphere gets exactly what it
    # gets with no sphere at all (a Lambertian floor, so the light alone decides)
    mat = gw.Material(color=(1, 1, 1), kd=0.8)
    cam = top_down_camera(n=33, height=30, fov=20)
    ball = dict(sphere_centers=[[0, 0, 2]], sphere_radii=[1.0])
    images = {}
    for name, extra, shadows in (("shadowless", ball, False), ("shadowed", ball, True), ("no ball", {}, True)):
        light = gw.Light(position=(0, 0, 4), color=(3, 3, 3), casts_shadows=shadows)
        sc = gw.Scene(vertices=FLOOR_V, triangles=FLOOR_F, materials=[mat], lights=[light], camera=cam, **extra)
        job = gw.RenderJob(sc).start()
        job.wait()
        images[name] = (job.image, job.depth)
    img, z = images["shadowless"]
    floor = np.abs(z - 30.0) < 1e-3
    shadow = floor & (images["shadowed"][0][..., 0] < 0.5 * images["no ball"][0][..., 0])
    assert shadow.sum() > 20 and floor.sum() > shadow.sum() + 100
    np.testing.assert_array_equal(img[floor], images["no ball"][0][floor])


@pytest.mark.parametrize("shape", ["sphere", "cube"])
def test_clear_glass_in_a_white_world_is_invisible(shape):
    """Fresnel reflection + refraction (and total internal reflection in the
    cube) split the energy exactly: with a uniform white background every
    pixel stays 1 up to the truncated path depth."""
    glass = gw.Material(color=(1, 1, 1), kd=0.0, transmittance=1.0, ior=1.5)
    if shape == "sphere":
        geo = dict(sphere_centers=[[0, 0, 0]], sphere_radii=[2.0])
    else:
        V = np.array([[x, y, z] for x in (-1.5, 1.5) for y in (-1.5, 1.5) for z in (-1.5, 1.5)], np.float32)
        F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], np.int32)
        geo = dict(vertices=V, triangles=F)
    cam = gw.Camera(eye=(6, -7, 5), target=(0, 0, 0), fov=40, width=48, height=48)
    sc = gw.Scene(**geo, materials=[glass], camera=cam, background=(1, 1, 1))
    img = gw.render(sc, gw.RenderSettings(max_depth=24, min_weight=0.0))
    assert img[..., 3].sum() > 100   # the object covers pixels
    assert img[..., :3].max() <= 1.0 + 1e-5
    assert img[..., :3].min() >= 0.995


def small_settings(**kw):
    base = dict(aa="jittered", aa_samples=2, shadow="area", shadow_samples=2, max_depth=4)
    base.update(kw)
    return gw.RenderSettings(**base)


def small_scene():
    kw = balls(1)
    kw["camera"].width = kw["camera"].height = 96
    kw["lights"] = [gw.Light(position=l.position, color=l.color, kind="sphere", radius=0.3) for l in kw["lights"]]
    return gw.Scene(**kw)


def test_any_thread_count_and_tile_size_gives_identical_bits():
    sc = small_scene()
    ref = gw.render(sc, small_settings(threads=1, tile_size=32))
    for threads, tile in [(2, 32), (5, 7), (3, 96), (8, 1)]:
        img = gw.render(sc, small_settings(threads=threads, tile_size=tile))
        assert np.array_equal(img, ref), (threads, tile)


def test_render_matches_stored_reference():
    img = gw.render(small_scene(), small_settings())
    if os.environ.get("GRIDWALK_REGEN") == "1" or not REF.exists():
        if os.environ.get("GRIDWALK_REGEN") != "1":
            pytest.fail(f"missing reference {REF}; run with GRIDWALK_REGEN=1 to create it")
        np.savez_compressed(REF, rgba=img.astype(np.float16))
    ref = np.load(REF)["rgba"].astype(np.float32)
    assert img.shape == ref.shape
    err = np.abs(img - ref)
    assert np.mean(err) < 2e-3 and np.percentile(err, 99.9) < 0.02
