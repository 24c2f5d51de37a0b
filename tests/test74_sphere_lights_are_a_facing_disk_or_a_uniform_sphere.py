"""A sphere light (Blender's point light with a radius, and a spot with one) takes one of the two
forms Cycles gives it (core/src/sphere_light.h): with soft_falloff (Blender's default) a
Lambertian disk of its radius facing the lit point, without it a sphere of uniform radiance. Both
have the same radiance; the disk's cone is a little narrower than the sphere's. Near the lamp
that matters: straight below a lamp of radius 0.5 at 0.6 m the disk gives 0.59 of a point
light's light and the sphere all of it. Gridwalk took the disk without its cosine for both
(0.67 there), which no Blender renders."""
import numpy as np
import pytest

import gridwalk as gw
from microfacet_math import ggx_brdf
from panel_floor import CENTRE, EYE, white_metal

RADIUS = 0.5


def lamp(centre, soft, kind="sphere"):
    """Colour pi r^2: radiance pi (the colour over r^2, sphere_light.h), so that a white
    Lambertian floor (BRDF 1 / pi) returns the cosine-weighted solid angle of the lamp's cone."""
    spot = dict(direction=(0, 0, -1), spot_size=3.0, spot_blend=0.0) if kind == "spot" else {}
    return gw.Light(kind=kind, position=tuple(centre), radius=RADIUS, color=(np.pi * RADIUS ** 2,) * 3,
                    inverse_square=True, soft_falloff=soft, **spot)


def floor_pixel(light, x, floor=None, eye=None, seeds=(1,), **settings):
    """The floor (white, Lambertian unless given) at (x, 0, 0), seen through one pixel from just
    above it (or from `eye`), lit by `light` alone."""
    verts = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
    if eye is None:
        camera = gw.Camera(eye=(x, 0, 0.01), target=(x, 0, 0), up=(0, 1, 0), projection="orthographic",
                           ortho_height=1e-4, width=1, height=1, hither=1e-3)
    else:
        camera = gw.Camera(eye=tuple(eye), target=(x, 0, 0), up=(0, 0, 1), fov=1e-3, width=1, height=1)
    scene = gw.Scene(verts, np.array([[0, 1, 2], [0, 2, 3]]), lights=[light], camera=camera,
                     materials=[floor or gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)], background=(0, 0, 0))
    defaults = dict(shadow="area", shadow_samples=32)
    return np.mean([gw.render(scene, gw.RenderSettings(seed=seed, **{**defaults, **settings}))[0, 0, 0]
                    for seed in seeds])


def over_cone(p, centre, half_angle, f, n=600):
    """The integral of f(wi) (unit directions, shape (..., 3)) over the cone of half-angle
    `half_angle` from p around the direction to `centre`, by a midpoint rule in (1 - cos, phi)."""
    axis = (np.asarray(centre) - p) / np.linalg.norm(np.asarray(centre) - p)
    t = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    t /= np.linalg.norm(t)
    b = np.cross(axis, t)
    width = 1 - np.cos(half_angle)
    below, phi = np.meshgrid((np.arange(n) + 0.5) / n * width, (np.arange(n) + 0.5) / n * 2 * np.pi)
    ct = 1 - below
    st = np.sqrt(below * (2 - below))
    wi = (axis * ct[..., None] + t * (st * np.cos(phi))[..., None] + b * (st * np.sin(phi))[..., None])
    return float(f(wi).sum() * width * 2 * np.pi / n ** 2)


def cone_of(p, centre, soft):
    """The disk's cone (soft) or the sphere's."""
    d = np.linalg.norm(np.asarray(centre) - p)
    return np.arctan(RADIUS / d) if soft else (np.pi / 2 if d <= RADIUS else np.arcsin(RADIUS / d))


def irradiance(x, centre, soft):
    """A white Lambertian floor point's value under the lamp: the cosine-weighted solid angle
    of its cone, cos_i clipped at the horizon."""
    p = np.array([x, 0.0, 0.0])
    if soft or np.linalg.norm(np.asarray(centre) - p) > RADIUS:
        return over_cone(p, centre, cone_of(p, centre, soft), lambda wi: np.maximum(wi[..., 2], 0))
    return np.pi   # inside the uniform sphere: every direction above


@pytest.mark.parametrize("soft", [True, False])
def test_straight_below_the_lamp_the_floor_gets_the_closed_form(soft):
    # The disk: pi r^2 / (d^2 + r^2) (its form factor); the sphere: pi r^2 / d^2, a point
    # light's (the shell theorem).
    for height in (0.55, 0.6, 1.0, 3.0):
        expected = np.pi * RADIUS ** 2 / (height ** 2 + (RADIUS ** 2 if soft else 0))
        assert floor_pixel(lamp((0, 0, height), soft), 0.0) == pytest.approx(expected, rel=0.005), height


@pytest.mark.parametrize("soft", [True, False])
@pytest.mark.parametrize("height, x", [(0.6, 0.8), (0.6, 1.5), (0.3, 0.7), (0.3, 1.2), (0.2, 0.1)])
def test_beside_the_lamp_and_where_it_cuts_the_floor_the_floor_gets_the_cones_light(soft, height, x):
    # (height 0.3: the lamp dips below the floor, whose horizon cuts its cone; (0.2, 0.1): a
    # point inside the sphere, lit from the whole sky by the uniform sphere)
    centre = (0, 0, height)
    expected = irradiance(x, centre, soft)
    assert floor_pixel(lamp(centre, soft), x) == pytest.approx(expected, rel=0.01)


def test_a_spot_with_a_radius_takes_the_same_forms():
    # A cone wide enough to hold every direction here: the spot is its sphere.
    for soft in (True, False):
        expected = irradiance(0.8, (0, 0, 0.6), soft)
        assert floor_pixel(lamp((0, 0, 0.6), soft, "spot"), 0.8) == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("soft", [True, False])
def test_a_spots_cone_weighs_each_direction_from_its_lamp(soft):
    # A cone of half-angle 30 degrees pointing down; the floor point 0.5 m aside sees the lamp's
    # centre 40 degrees off its axis, and only the part of the lamp whose light leaves within the
    # cone lights it (blend 0: a sharp edge): about a third of what the lamp would give.
    centre = (0, 0, 0.6)
    light = gw.Light(kind="spot", position=centre, radius=RADIUS, color=(np.pi * RADIUS ** 2,) * 3,
                     inverse_square=True, soft_falloff=soft, direction=(0, 0, -1), spot_size=np.radians(60),
                     spot_blend=0.0)
    p = np.array([0.5, 0.0, 0.0])
    expected = over_cone(p, centre, cone_of(p, centre, soft),
                         lambda wi: np.maximum(wi[..., 2], 0) * (wi[..., 2] >= np.cos(np.radians(30))))
    assert 0.2 * irradiance(0.5, centre, soft) < expected < 0.5 * irradiance(0.5, centre, soft)
    assert floor_pixel(light, 0.5) == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("soft", [True, False])
@pytest.mark.parametrize("height, x", [(0.6, 0.8), (0.2, 0.1)])
def test_hard_shadows_take_the_lamps_centre_as_a_point_light(soft, height, x):
    # (0.2, 0.1): the point lies inside the lamp; the centre still lights it.
    d2 = height ** 2 + x ** 2
    expected = np.pi * RADIUS ** 2 * height / d2 ** 1.5   # colour x cos / d^2
    assert floor_pixel(lamp((0, 0, height), soft), x, shadow="hard") == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("soft", [True, False])
def test_a_sphere_light_of_radius_zero_is_a_point_light(soft):
    light = gw.Light(kind="sphere", position=(0, 0, 0.6), radius=0.0, color=(1, 1, 1), inverse_square=True,
                     soft_falloff=soft)
    assert floor_pixel(light, 0.8) == pytest.approx(0.6 / 1.0 ** 3, rel=1e-4)   # cos / d^2 at d = 1


def test_inside_a_uniform_sphere_a_diffuse_floor_gets_its_light_without_noise():
    # The lamp fills the whole sky there: its light points are cosine-weighted about the normal,
    # so each brings the same light (spread over all directions, half of them below the floor,
    # one light point a pixel varied by 1.4x the mean from seed to seed).
    light = lamp((0, 0, 0.2), False)
    values = [floor_pixel(light, 0.1, seeds=(seed,), shadow="random", shadow_samples=1) for seed in range(8)]
    assert np.mean(values) == pytest.approx(np.pi, rel=1e-4)
    assert np.std(values) < 1e-4 * np.pi
