"""A bump map (Material.bump_texture, Blender's Bump node) may be any texture: a procedural one
(Checker, Gradient, Noise) or an image at Generated or Object coordinates bends the normal by its
pattern's slope along the surface, taken by central differences of the pattern, as an image at
the UV map bends it by its texels' slopes. Checked against the slope worked out by hand (a
linear Gradient), against numpy's differences of Cycles' noise (test76's evaluation) pixel by
pixel, and for the Bump node's Distance and Strength. Blender's side: tests/blender/test_b39."""
from dataclasses import replace

import numpy as np
import pytest

import gridwalk as gw
from test76_noise_texture_is_perlin_noise_as_cycles_computes_it import fractal

N = 24
VERTS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
SUN = np.array([0.4, 0.2, 1.0]) / np.linalg.norm([0.4, 0.2, 1.0])   # towards the light
# Object coordinates x 0.25 + 0.5: a linear Gradient's value 0.25 x + 0.5, never clamped on the square
QUARTER = (0.25, 0, 0, 0.5, 0, 0.25, 0, 0.5, 0, 0, 0.25, 0.5)


def _render(texture=None, distance=1.0, strength=1.0):
    bump = {} if texture is None else dict(bump_texture=0, bump_distance=distance, bump_strength=strength)
    s = gw.Scene(VERTS, TRIS, object_coords=VERTS[TRIS], textures=[texture] if texture else None,
                 lights=[gw.Light(kind="sun", direction=tuple(-SUN), color=(0.8, 0.8, 0.8))],
                 camera=gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                                  ortho_height=2.0, width=N, height=N),
                 materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0, **bump)])
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., 0]


def _lit(normals):
    """The sun's light on unit normals (..., 3) relative to the flat square's: its cosine, times
    the shadowing the renderer gives bumps (Chiang et al. 2019, as Cycles: G1 of slopes of
    roughness^2 tan^2(d) / 8 for the angle d the bump turned the normal through)."""
    cos_d = np.minimum(np.abs(normals[..., 2]), 1.0)
    alpha2 = np.clip((1 - cos_d ** 2) / np.maximum(cos_d ** 2, 1e-12) / 8, 0, 1)
    shadowing = 2 / (1 + np.sqrt(1 + alpha2 * (1 - SUN[2] ** 2) / SUN[2] ** 2))
    return np.clip(normals @ SUN, 0, None) / SUN[2] * shadowing


def test_a_linear_gradient_tilts_every_normal_by_its_slope():
    flat = _render()
    assert flat.std() < 1e-6 and flat.mean() > 0.1
    for distance in (1.0, 2.5, -1.5):
        image = _render(gw.Texture(kind="gradient", coordinates="object", vector_transform=QUARTER), distance)
        # the height rises 0.25 per unit of x: the normal leans to -x by atan(0.25 distance)
        n = np.array([-0.25 * distance, 0.0, 1.0]) / np.hypot(0.25 * distance, 1.0)
        np.testing.assert_allclose(image / flat, _lit(n), rtol=2e-3)


def test_strength_blends_the_bent_normal_with_the_surfaces():
    flat = _render()
    texture = gw.Texture(kind="gradient", coordinates="object", vector_transform=QUARTER)
    bent = np.array([-0.5, 0.0, 1.0]) / np.hypot(0.5, 1.0)
    blend = 0.4 * bent + 0.6 * np.array([0, 0, 1.0])
    np.testing.assert_allclose(_render(texture, 2.0, 0.4) / flat, _lit(blend / np.linalg.norm(blend)), rtol=2e-3)


def test_a_noise_bump_follows_the_noises_slope_pixel_by_pixel():
    flat = _render()
    texture = gw.Texture(kind="noise", coordinates="object", scale=1.5, detail=1.0, use_alpha=True)
    image = _render(texture, distance=0.4)
    c = -1 + 2 * (np.arange(N) + 0.5) / N
    x, y = np.meshgrid(c, c[::-1])
    h, scale = 1e-3, np.float32(1.5)
    height = lambda px, py: fractal([np.float32(px) * scale, np.float32(py) * scale,
                                     np.zeros(px.shape, np.float32)], "fbm", 1.0, 0.5, 2.0).astype(np.float64)
    gx = (height(x + h, y) - height(x - h, y)) / (2 * h)
    gy = (height(x, y + h) - height(x, y - h)) / (2 * h)
    n = np.stack([-0.4 * gx, -0.4 * gy, np.ones_like(gx)], axis=-1)
    want = _lit(n / np.linalg.norm(n, axis=-1, keepdims=True))
    assert want.std() > 0.02                                          # the bumps show
    np.testing.assert_allclose(image / flat, want, atol=3e-3)


def test_a_checker_bump_is_flat_inside_its_squares():
    flat = _render()
    image = _render(gw.Texture(kind="checker", coordinates="object", scale=2.0), distance=1.0)
    # (a step has no slope: only a pixel centre within the difference's step of an edge could
    # show one, and none lies there)
    np.testing.assert_allclose(image, flat, rtol=1e-5)


def test_a_bump_at_position_coordinates_bends_as_at_equal_object_coordinates():
    # the square's Object coordinates here are its world corners: the same slopes
    texture = gw.Texture(kind="noise", coordinates="position", scale=3.0, detail=2.0)
    bumped = _render(texture)
    assert bumped.std() > 0.02                              # the noise's slopes show
    np.testing.assert_array_equal(bumped, _render(replace(texture, coordinates="object")))


def test_a_bump_at_object_coordinates_without_them_is_refused():
    with pytest.raises(ValueError, match=r"texture at object coordinates.*Scene\(object_coords=...\)"):
        gw.Scene(VERTS, TRIS, textures=[gw.Texture(kind="noise", coordinates="object")],
                 materials=[gw.Material(bump_texture=0)])
