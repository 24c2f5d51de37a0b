"""A rectangular area light near a surface (Blender's area light a few
centimetres above a floor) is sampled by the solid angle it subtends
(lights.h, sample_rect_solid_angle): each light sample weighs radiance x
cos x solid angle, so the floor under it is lit as Lambert's polygon formula
says, without the fireflies of uniform points on the light (their cos /
distance^2 weight made single pixels thousands of times the mean). Checked
against the formula per pixel at several heights, with one light sample per
pixel and with many."""
import numpy as np
import pytest

import gridwalk as gw
from polygon_irradiance import polygon_irradiance

N = 32
SIZE = 3.0          # the light: SIZE x SIZE, centred over the origin, facing down


def _render(height, settings):
    """A white diffuse floor (kd 1) under the light at `height`; an orthographic camera looks
    straight down at x in [0.7, 2.3] (across the light's edge at x = 1.5), y in [-0.8, 0.8]."""
    floor = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
    light = gw.Light(kind="rect", position=(0, 0, height), size=(SIZE, SIZE), axis_u=(1, 0, 0), axis_v=(0, 1, 0),
                     direction=(0, 0, -1), color=(SIZE * SIZE, SIZE * SIZE, SIZE * SIZE), inverse_square=True)
    cam = gw.Camera(eye=(1.5, 0, 5), target=(1.5, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=1.6, width=N, height=N)
    scene = gw.Scene(floor, np.array([[0, 1, 2], [0, 2, 3]]), materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)],
                     lights=[light], camera=cam)
    return gw.render(scene, gw.RenderSettings(**settings))[..., 0].reshape(-1)


def _expected(height, sub=16):
    """Each pixel's irradiance from the light's radiance (colour / area = 1), averaged over the
    pixel (sub x sub points: near the light's edge it changes within a pixel, and the render's
    box filter averages it)."""
    c = (np.arange(N * sub) + 0.5) / (N * sub) * 1.6 - 0.8
    x, y = np.meshgrid(1.5 + c, c[::-1])
    points = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    h = SIZE / 2
    corners = np.array([[-h, -h, height], [h, -h, height], [h, h, height], [-h, h, height]], float)
    e = polygon_irradiance(points, corners).reshape(N, sub, N, sub)
    return e.mean(axis=(1, 3)).reshape(-1)


def _scale():
    """The core's diffuse radiance per unit irradiance: from a far light (uniform points on
    it: beyond twice its diagonal), where nothing new applies."""
    got = _render(12.0, dict(aa="jittered", aa_samples=4, filter="box", shadow="area", shadow_samples=16, threads=2))
    return float(np.mean(got / _expected(12.0)))


@pytest.mark.parametrize("height", [0.5, 0.05, 0.002])
def test_a_near_area_light_lights_the_floor_as_its_irradiance_says(height):
    k = _scale()
    expected = _expected(height) * k
    many = _render(height, dict(aa="jittered", aa_samples=4, filter="box", shadow="area", shadow_samples=16, threads=2))
    # Per pixel, away from the light's edge (x = 1.5: there the light steps within a pixel, which
    # 4 x 4 pixel samples resolve coarsely) and where there is light to speak of; in all, everywhere.
    x = np.tile(1.5 + ((np.arange(N) + 0.5) / N * 1.6 - 0.8), N)
    judged = (expected > 0.01 * expected.max()) & (np.abs(x - 1.5) > 1.6 / N)
    assert judged.mean() > 0.4 and np.abs(many / expected - 1)[judged].mean() < 0.01
    assert abs(many.sum() / expected.sum() - 1) < 0.01
    # one light sample a pixel (Blender's defaults): noisy, but no pixel far above the light's
    # own bound (radiance x 2 pi x the diffuse scale), and the mean right
    one = _render(height, dict(aa="jittered", aa_samples=1, filter="box", shadow="random", shadow_samples=1, threads=2))
    assert one.max() <= 2 * np.pi * k * (1 + 1e-5)
    assert abs(one.mean() / expected.mean() - 1) < 0.05
