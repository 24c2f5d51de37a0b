"""Material.emits_light: emissive triangles light other surfaces as area
lights do (Cycles' mesh lights), sampled by area times emission, from both
sides, their textures read at each sampled point. Checked on a diffuse floor
seen from above beside an emissive square 1 unit over it, against the
irradiance Lambert's polygon formula gives at each pixel (exact), and with
a two-coloured textured emitter against the formula over each half."""
import numpy as np
import pytest

import gridwalk as gw
from polygon_irradiance import polygon_irradiance

N = 24
SETTINGS = dict(aa="jittered", aa_samples=4, shadow="area", shadow_samples=16, threads=2)


def _scene(emitter_material, textures=None, uvs=None):
    """A 40 x 40 floor at z = 0 and an emissive square [-0.5, 0.5]^2 at z = 1;
    an orthographic camera looks down on x in [0.7, 2.3], y in [-0.8, 0.8]."""
    floor = [[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]]
    lamp = [[-0.5, -0.5, 1], [0.5, -0.5, 1], [0.5, 0.5, 1], [-0.5, 0.5, 1]]
    verts = np.array(floor + lamp, np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    cam = gw.Camera(eye=(1.5, 0, 5), target=(1.5, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=1.6, width=N, height=N)
    materials = [gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0), emitter_material]
    kwargs = dict(textures=textures, uvs=uvs) if textures else {}
    return gw.Scene(verts, tris, triangle_materials=[0, 0, 1, 1], materials=materials, camera=cam, **kwargs)


def _floor_points():
    c = (np.arange(N) + 0.5) / N * 1.6 - 0.8
    x, y = np.meshgrid(1.5 + c, c[::-1])        # row 0 at the top of the image: +y
    return np.stack([x.ravel(), y.ravel(), np.zeros(N * N)], axis=1)


def test_an_emissive_square_lights_the_floor_as_its_irradiance_says():
    rgba = gw.render(_scene(gw.Material(color=(1, 1, 1), kd=0, emission_color=(2.0, 1.0, 0.5), emits_light=True)),
                     gw.RenderSettings(**SETTINGS))
    lamp = np.array([[-0.5, -0.5, 1], [0.5, -0.5, 1], [0.5, 0.5, 1], [-0.5, 0.5, 1]], float)
    expected = polygon_irradiance(_floor_points(), lamp)[:, None] / np.pi * np.array([2.0, 1.0, 0.5])
    got = rgba[..., :3].reshape(-1, 3)
    assert expected[:, 0].max() > 3 * expected[:, 0].min()            # it falls off across the view
    assert np.abs(got / expected - 1).mean() < 0.01
    assert np.abs(got / expected - 1).max() < 0.06


def test_without_emits_light_emission_is_only_seen():
    rgba = gw.render(_scene(gw.Material(color=(1, 1, 1), kd=0, emission_color=(2.0, 1.0, 0.5))),
                     gw.RenderSettings(**SETTINGS))
    assert np.all(rgba[..., :3] == 0)


def test_a_textured_emitter_lights_with_the_texel_under_each_sampled_point():
    texels = np.zeros((1, 2, 3), np.float32)
    texels[0, 0] = (1.0, 0.0, 0.0)                                   # u < 0.5 (x < 0): red
    texels[0, 1] = (0.0, 0.0, 1.0)                                   # x > 0: blue
    uv = np.array([[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]], np.float32)
    uvs = np.concatenate([np.zeros((2, 3, 2), np.float32), uv])
    emitter = gw.Material(color=(1, 1, 1), kd=0, emission=3.0, color_texture=0, emits_light=True)
    rgba = gw.render(_scene(emitter, textures=[gw.Texture(gw.Image(texels), interpolation="closest")], uvs=uvs),
                     gw.RenderSettings(**SETTINGS))
    points = _floor_points()
    red = polygon_irradiance(points, np.array([[-0.5, -0.5, 1], [0, -0.5, 1], [0, 0.5, 1], [-0.5, 0.5, 1]]))
    blue = polygon_irradiance(points, np.array([[0, -0.5, 1], [0.5, -0.5, 1], [0.5, 0.5, 1], [0, 0.5, 1]]))
    got = rgba[..., :3].reshape(-1, 3)
    np.testing.assert_allclose(got[:, 0].mean(), 3 * red.mean() / np.pi, rtol=0.02)
    np.testing.assert_allclose(got[:, 2].mean(), 3 * blue.mean() / np.pi, rtol=0.02)
    assert np.all(got[:, 1] == 0)
    assert got[:, 2].mean() > 1.5 * got[:, 0].mean()                  # the blue half is the nearer


def test_emitter_light_is_the_same_for_any_thread_count_and_tile_size():
    scene = _scene(gw.Material(color=(1, 1, 1), kd=0, emission_color=(1.0, 1.0, 1.0), emits_light=True))
    one = gw.render(scene, gw.RenderSettings(**dict(SETTINGS, threads=1, tile_size=8)))
    two = gw.render(scene, gw.RenderSettings(**dict(SETTINGS, threads=2, tile_size=5)))
    np.testing.assert_array_equal(one, two)
