"""A sun's colour is the irradiance on a surface facing it, whatever its angular diameter, as
in Cycles 4.0 and later (whose sun's disc has radiance strength / (pi sin^2 of half the angle)).
Before, the cone's directions were sampled with the colour unscaled, so a facing floor got
colour x (1 + cos(angle / 2)) / 2: 25% less at 120 degrees, half at 180 (found comparing with
Cycles: 0.433 against 0.553 in display values at 180 degrees). A tilted floor gets the cone's
exact cosine integral, and a mirror shows the disc at the matching radiance."""
import math

import numpy as np
import pytest

import gridwalk as gw

N = 16
VERTS = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
CAMERA = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=2.0,
                   width=N, height=N)


def _floor(angle, direction=(0.0, 0.0, -1.0), shadow="random"):
    light = gw.Light(kind="sun", direction=direction, angle=angle, color=(1.0, 1.0, 1.0))
    scene = gw.Scene(VERTS, TRIS, camera=CAMERA, lights=[light],
                     materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)])
    settings = gw.RenderSettings(threads=1, shadow=shadow, shadow_samples=64, aa="jittered", aa_samples=4)
    return float(gw.RenderJob(scene, settings).start().wait()[..., :3].mean())


@pytest.mark.parametrize("degrees", [30, 90, 120, 180])
@pytest.mark.parametrize("shadow", ["random", "hard"])
def test_a_facing_floor_gets_the_same_light_at_any_angle(degrees, shadow):
    # (Hard shadows take the disc's centre: the colour, unscaled; it was scaled as a cone's
    # sample, twice as bright at 180 degrees, found by a review)
    sharp = _floor(0.0)
    assert sharp > 0.1
    assert _floor(math.radians(degrees), shadow=shadow) == pytest.approx(sharp, rel=0.01)


def test_a_sun_wider_than_the_sky_is_refused():
    with pytest.raises(ValueError, match="angular diameter is at most pi"):
        _floor(1.5 * math.pi)


def test_a_tilted_floor_gets_the_cones_cosine_integral():
    # the sun's axis 60 degrees from the floor's normal, a cone of half-angle 30 degrees: wholly above
    # the horizon, so its cosine integral is the axis' cosine times the facing irradiance
    tilt = math.radians(60)
    direction = (math.sin(tilt), 0.0, -math.cos(tilt))
    assert _floor(math.radians(60), direction) == pytest.approx(_floor(0.0) * math.cos(tilt), rel=0.015)
