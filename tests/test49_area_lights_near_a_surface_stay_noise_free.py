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

from area_light_floor import N, VIEW, expected, light, outline, render, scale


@pytest.mark.parametrize("shape", ["rect", "disk", "ellipse"])
@pytest.mark.parametrize("height", [0.5, 0.05, 0.002])
def test_a_near_area_light_lights_the_floor_as_its_irradiance_says(height, shape):
    k = scale()
    want = expected(outline(shape, height)) * k
    # (the disk's points outside it weigh 0: more of them for the same noise)
    many = render(light(shape, height), dict(aa="jittered", aa_samples=4, filter="box", shadow="area",
                                             shadow_samples=16 if shape == "rect" else 64, threads=2))
    # Per pixel, away from the light's edge (x = 1.5 on the rect, a circle of radius 1.5: there the
    # light steps within a pixel, which 4 x 4 pixel samples resolve coarsely) and where there is light
    # to speak of; in all, everywhere.
    c = (np.arange(N) + 0.5) / N * VIEW - VIEW / 2
    x, y = np.tile(1.5 + c, N), np.repeat(c[::-1], N)
    edge = np.abs(x - 1.5) if shape == "rect" else np.abs(np.hypot(x, y / (2 if shape == "ellipse" else 1)) - 1.5)
    judged = (want > 0.01 * want.max()) & (edge > VIEW / N)
    assert judged.mean() > 0.4 and np.abs(many / want - 1)[judged].mean() < 0.01
    assert abs(many.sum() / want.sum() - 1) < 0.01
    # one light sample a pixel (Blender's defaults): noisy, but no pixel far above the light's
    # own bound (radiance x 2 pi x the diffuse scale), and the mean right
    one = render(light(shape, height), dict(aa="jittered", aa_samples=1, filter="box", shadow="random",
                                            shadow_samples=1, threads=2))
    assert one.max() <= 2 * np.pi * k * (1 + 1e-5)
    assert abs(one.mean() / want.mean() - 1) < 0.05


