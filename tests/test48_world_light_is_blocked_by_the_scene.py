"""RenderSettings.world_shadows: the scene blocks the world's light (the
ambient colour and the environment's irradiance), as Cycles' world light is
blocked. Checked on a white floor under a unit sphere 2 above it, seen from
above beside the sphere, against the exact light at each pixel: for a uniform
world, 1 - (R/d)^2 cos(beta) of it (the cosine-weighted share of a spherical
cap); for a sky of degree 2 in the direction, the integral over every texel
of L cos V with V the ray's analytic miss of the sphere."""
import numpy as np
import pytest

import gridwalk as gw

N = 20
SETTINGS = dict(aa="jittered", aa_samples=4, shadow="area", shadow_samples=16, threads=2, world_shadows=True)
CENTRE, R = np.array([0.0, 0.0, 2.0]), 1.0


def _scene(world, textures=None):
    floor = np.array([[-30, -30, 0], [30, -30, 0], [30, 30, 0], [-30, 30, 0]], np.float32)
    cam = gw.Camera(eye=(2.5, 0, 10), target=(2.5, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=2.0, width=N, height=N)
    return gw.Scene(floor, [[0, 1, 2], [0, 2, 3]], sphere_centers=[CENTRE], sphere_radii=[R],
                    materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)], camera=cam, world=world,
                    textures=textures)


def _floor_points():
    c = (np.arange(N) + 0.5) / N * 2.0 - 1.0
    x, y = np.meshgrid(2.5 + c, c[::-1])
    return np.stack([x.ravel(), y.ravel(), np.zeros(N * N)], axis=1)


def test_a_sphere_blocks_a_uniform_worlds_light_as_its_cap_says():
    rgba = gw.render(_scene(gw.World(ambient=(0.5, 1.0, 2.0))), gw.RenderSettings(**SETTINGS))
    to = CENTRE[None, :] - _floor_points()
    d = np.linalg.norm(to, axis=1)
    seen = 1 - (R / d) ** 2 * (to[:, 2] / d)
    expected = seen[:, None] * [0.5, 1.0, 2.0]
    got = rgba[..., :3].reshape(-1, 3)
    assert seen.min() < 0.97                                          # the shadow is there to find
    assert np.abs(got / expected - 1).mean() < 0.01
    assert np.abs(got / expected - 1).max() < 0.04
    unblocked = gw.render(_scene(gw.World(ambient=(0.5, 1.0, 2.0))),
                          gw.RenderSettings(**dict(SETTINGS, world_shadows=False)))
    np.testing.assert_allclose(unblocked[..., :3].reshape(-1, 3), np.broadcast_to([0.5, 1.0, 2.0], got.shape),
                               rtol=1e-6)


def _sky(h=64, w=128):
    """A smooth sky of degree 2 in the direction, bright overhead."""
    u = (np.arange(w) + 0.5) / w
    v = 1 - (np.arange(h) + 0.5) / h
    phi, e = (0.5 - u) * 2 * np.pi, (v - 0.5) * np.pi
    x = np.cos(e)[:, None] * np.cos(phi)[None, :]
    z = np.broadcast_to(np.sin(e)[:, None], (h, w))
    sky = np.stack([1.2 + 0.9 * z + 0.3 * x, 1.0 + 0.8 * z, 0.8 + 0.7 * z + 0.4 * z * z], axis=-1)
    return sky.astype(np.float32), x, np.cos(e)[:, None] * np.sin(phi)[None, :], z, e


def _exact_blocked(sky, dirs):
    """The light each floor point gets from the sky, the sphere blocking it: the
    integral over every texel of L cos V / pi, V the ray's analytic miss of the sphere."""
    h, w = sky.shape[:2]
    edges = (0.5 - np.arange(h + 1) / h) * np.pi
    omega = np.broadcast_to(((np.sin(edges[:-1]) - np.sin(edges[1:])) * 2 * np.pi / w)[:, None], (h, w))
    weight = (omega.reshape(-1, 1) * sky.reshape(-1, 3)).astype(np.float64)
    out = []
    for p in _floor_points():
        oc = p - CENTRE
        b = dirs @ oc
        hits = (b * b - (oc @ oc - R * R) > 0) & (b < 0)              # the ray from p meets the sphere
        out.append((np.clip(dirs[:, 2], 0, None) * ~hits) @ weight / np.pi)
    return np.array(out), np.clip(dirs[:, 2], 0, None) @ weight / np.pi


def test_a_sphere_blocks_an_environments_light_where_its_rays_meet_it():
    sky, dx, dy, dz, e = _sky()
    world = gw.World(environment=0, environment_light=True)
    rgba = gw.render(_scene(world, textures=[gw.Texture(gw.Image(sky))]), gw.RenderSettings(**SETTINGS))
    expected, open_sky = _exact_blocked(sky, np.stack([dx, dy, dz], axis=-1).reshape(-1, 3))
    got = rgba[..., :3].reshape(-1, 3)
    assert (expected / open_sky).min() < 0.95                         # the sphere's shadow is in view
    assert np.abs(got / expected - 1).mean() < 0.01
    assert np.abs(got / expected - 1).max() < 0.04


def test_a_sphere_in_front_of_a_sun_casts_its_shadow():
    # A sun 2,000 times its sky, in the west (-X): the sphere's shadow falls on the view. (Texels of
    # 0.7 degrees: the reference's V, taken at their centres, must resolve the sun's 3 degrees.)
    sky, dx, dy, dz, e = _sky(256, 512)
    sky = np.full_like(sky, 0.2)
    sun = np.array([-0.62, 0.0, 0.78]) / np.hypot(0.62, 0.78)          # from the view's middle past the sphere
    dirs = np.stack([dx, dy, dz], axis=-1)
    sky[(dirs @ sun) > np.cos(np.radians(3.0))] = 400.0
    world = gw.World(environment=0, environment_light=True)
    rgba = gw.render(_scene(world, textures=[gw.Texture(gw.Image(sky))]), gw.RenderSettings(**SETTINGS))
    expected, open_sky = _exact_blocked(sky, dirs.reshape(-1, 3))
    got = rgba[..., :3].reshape(-1, 3)[:, 0]
    expected = expected[:, 0]
    shadow = expected < 0.5 * open_sky[0]
    assert 0.05 < shadow.mean() < 0.7                                 # umbra and lit floor both in view
    assert np.abs(got - expected).mean() < 0.01 * open_sky[0]
    assert abs(got[shadow].mean() / expected[shadow].mean() - 1) < 0.03
    # Blender's defaults (2 x 2 pixel samples, one shadow ray each): noisier, not brighter. (Estimating
    # the sun's blocked part instead of sampling it as a light made the umbra 1.5x too bright here.)
    quick = gw.render(_scene(world, textures=[gw.Texture(gw.Image(sky))]),
                      gw.RenderSettings(aa="jittered", aa_samples=2, shadow="area", shadow_samples=2, threads=2,
                                        world_shadows=True))[..., 0].ravel()
    assert abs(quick[shadow].mean() / expected[shadow].mean() - 1) < 0.06
    assert abs(quick[~shadow].mean() / expected[~shadow].mean() - 1) < 0.02


@pytest.mark.parametrize("shadow", ["area", "random", "hard"])
def test_world_shadows_are_the_same_for_any_thread_count_and_tile_size(shadow):
    sky = _sky()[0]
    scene = _scene(gw.World(ambient=(0.2, 0.2, 0.2), environment=0, environment_light=True),
                   textures=[gw.Texture(gw.Image(sky))])
    one = gw.render(scene, gw.RenderSettings(**dict(SETTINGS, shadow=shadow, threads=1, tile_size=7)))
    two = gw.render(scene, gw.RenderSettings(**dict(SETTINGS, shadow=shadow, threads=2, tile_size=16)))
    np.testing.assert_array_equal(one, two)
