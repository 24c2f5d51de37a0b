"""A rectangular, disk or elliptic area light near a surface (Blender's area
light a few centimetres above a floor) is sampled by the solid angle it
subtends (near_area_light.h; a disk or an ellipse through its bounding
rectangle's, the points outside it weighing 0): each light sample weighs radiance x
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
SIZE = 3.0          # the light: SIZE x SIZE (a rect) or SIZE across (a disk), centred over the origin, facing down


def _light(shape, height, size):
    """The light, of radiance 1 (colour / area)."""
    if shape == "rect":
        return gw.Light(kind="rect", position=(0, 0, height), size=(size, size), axis_u=(1, 0, 0), axis_v=(0, 1, 0),
                        direction=(0, 0, -1), color=(size * size,) * 3, inverse_square=True)
    if shape == "ellipse":   # SIZE across along x, twice that along y
        return gw.Light(kind="ellipse", position=(0, 0, height), size=(size, 2 * size), axis_u=(1, 0, 0),
                        axis_v=(0, 1, 0), direction=(0, 0, -1), color=(np.pi * size * size / 2,) * 3,
                        inverse_square=True)
    area = np.pi * (size / 2) ** 2
    return gw.Light(kind="disk", position=(0, 0, height), radius=size / 2, axis_u=(1, 0, 0), axis_v=(0, 1, 0),
                    direction=(0, 0, -1), color=(area,) * 3, inverse_square=True)


def _outline(shape, height, size):
    """The light's outline as a polygon (the disk's and the ellipse's: 128 sides of the same area)."""
    h = size / 2
    if shape == "rect":
        return np.array([[-h, -h, height], [h, -h, height], [h, h, height], [-h, h, height]], float)
    a = np.arange(128) * (2 * np.pi / 128)
    r = h * np.sqrt(2 * np.pi / (128 * np.sin(2 * np.pi / 128)))
    squash = 2.0 if shape == "ellipse" else 1.0
    return np.stack([r * np.cos(a), squash * r * np.sin(a), np.full(128, height)], axis=1)


def _render(height, settings, shape="rect", size=SIZE):
    """A white diffuse floor (kd 1) under the light at `height`; an orthographic camera looks
    straight down at x in [0.7, 2.3] (across the light's edge at x = 1.5), y in [-0.8, 0.8]."""
    floor = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
    light = _light(shape, height, size)
    cam = gw.Camera(eye=(1.5, 0, 5), target=(1.5, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=1.6, width=N, height=N)
    scene = gw.Scene(floor, np.array([[0, 1, 2], [0, 2, 3]]), materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)],
                     lights=[light], camera=cam)
    return gw.render(scene, gw.RenderSettings(**settings))[..., 0].reshape(-1)


def _expected(height, shape="rect", sub=16, size=SIZE):
    """Each pixel's irradiance from the light's radiance (colour / area = 1), averaged over the
    pixel (sub x sub points: near the light's edge it changes within a pixel, and the render's
    box filter averages it)."""
    c = (np.arange(N * sub) + 0.5) / (N * sub) * 1.6 - 0.8
    x, y = np.meshgrid(1.5 + c, c[::-1])
    points = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    e = polygon_irradiance(points, _outline(shape, height, size)).reshape(N, sub, N, sub)
    return e.mean(axis=(1, 3)).reshape(-1)


def _scale():
    """The core's diffuse radiance per unit irradiance: from a far light (uniform points on
    it: beyond twice its diagonal), where nothing new applies."""
    got = _render(12.0, dict(aa="jittered", aa_samples=4, filter="box", shadow="area", shadow_samples=16, threads=2))
    return float(np.mean(got / _expected(12.0)))


@pytest.mark.parametrize("shape", ["rect", "disk", "ellipse"])
@pytest.mark.parametrize("height", [0.5, 0.05, 0.002])
def test_a_near_area_light_lights_the_floor_as_its_irradiance_says(height, shape):
    k = _scale()
    expected = _expected(height, shape) * k
    # (the disk's points outside it weigh 0: more of them for the same noise)
    many = _render(height, dict(aa="jittered", aa_samples=4, filter="box", shadow="area",
                                shadow_samples=16 if shape == "rect" else 64, threads=2), shape)
    # Per pixel, away from the light's edge (x = 1.5 on the rect, a circle of radius 1.5: there the
    # light steps within a pixel, which 4 x 4 pixel samples resolve coarsely) and where there is light
    # to speak of; in all, everywhere.
    c = (np.arange(N) + 0.5) / N * 1.6 - 0.8
    x, y = np.tile(1.5 + c, N), np.repeat(c[::-1], N)
    edge = np.abs(x - 1.5) if shape == "rect" else np.abs(np.hypot(x, y / (2 if shape == "ellipse" else 1)) - 1.5)
    judged = (expected > 0.01 * expected.max()) & (edge > 1.6 / N)
    assert judged.mean() > 0.4 and np.abs(many / expected - 1)[judged].mean() < 0.01
    assert abs(many.sum() / expected.sum() - 1) < 0.01
    # one light sample a pixel (Blender's defaults): noisy, but no pixel far above the light's
    # own bound (radiance x 2 pi x the diffuse scale), and the mean right
    one = _render(height, dict(aa="jittered", aa_samples=1, filter="box", shadow="random", shadow_samples=1, threads=2),
                  shape)
    assert one.max() <= 2 * np.pi * k * (1 + 1e-5)
    assert abs(one.mean() / expected.mean() - 1) < 0.05


@pytest.mark.parametrize("shape", ["rect", "disk", "ellipse"])
def test_a_light_filling_the_view_is_sampled_by_the_cosine(shape):
    """A 40 m light 1 m above the floor covers about 0.99 of the cosine's weight at the points seen.
    Sampled by its solid angle alone, one light sample a pixel deviates from the irradiance by about
    half of it (the cosine's spread over the hemisphere); mixed with cosine-weighted directions
    (near_area_light.h), by a few percent. The mean stays the irradiance."""
    k = _scale()
    expected = _expected(1.0, shape, sub=4, size=40.0) * k
    one = _render(1.0, dict(aa="jittered", aa_samples=1, filter="box", shadow="random", shadow_samples=1, threads=2),
                  shape, 40.0)
    assert abs(one.mean() / expected.mean() - 1) < 0.02
    assert np.sqrt(np.mean((one / expected - 1) ** 2)) < 0.1
