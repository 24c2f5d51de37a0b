"""World.environment_light: a diffuse surface gets the irradiance an
environment image sends on its normal (a table over 64 x 32 normals of the
image's exact cosine integral, core/src/irradiance.h), not one average
colour. Checked on a matte analytic sphere seen by an orthographic camera,
whose every pixel faces another direction, against values computed here:
for skies that are polynomials of degree 2 in the direction (known in closed
form), and against the cosine-weighted integral over every texel for a sky
over coloured ground and for a sun."""
import numpy as np
import pytest

import gridwalk as gw

N = 48


def _directions(h, w):
    """Unit directions of the texel centres of an equirectangular image (row 0 =
    top), as Blender maps it: the centre column along +X, a quarter left of it +Y."""
    u = (np.arange(w) + 0.5) / w
    v = 1 - (np.arange(h) + 0.5) / h
    phi = (0.5 - u) * 2 * np.pi
    e = (v - 0.5) * np.pi
    ce = np.cos(e)[:, None]
    return np.stack([ce * np.cos(phi)[None, :], ce * np.sin(phi)[None, :],
                     np.broadcast_to(np.sin(e)[:, None], (h, w))], axis=-1)


def _solid_angles(h, w):
    edges = (0.5 - np.arange(h + 1) / h) * np.pi                       # elevation of row edges, top first
    band = np.sin(edges[:-1]) - np.sin(edges[1:])
    return np.broadcast_to((2 * np.pi / w * band)[:, None], (h, w))


def _render_sphere(sky, strength=1.0, light=True, ambient=(0.0, 0.0, 0.0), image=None):
    """(rgb, normals, hit mask) of a white matte unit sphere in the sky."""
    cam = gw.Camera(eye=(0.3, -5, 0.4), target=(0, 0, 0), up=(0, 0, 1), projection="orthographic",
                    ortho_height=2.2, width=N, height=N)
    texture = gw.Texture(image if image is not None else gw.Image(np.asarray(sky, np.float32)))
    scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], camera=cam,
                     materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)], textures=[texture],
                     world=gw.World(ambient=ambient, environment=0, environment_strength=strength,
                                    environment_light=light))
    job = gw.RenderJob(scene, gw.RenderSettings(threads=2)).start()
    rgba = job.wait()
    hit = rgba[..., 3] == 1
    return rgba[..., :3], job.normal, hit


def test_a_degree_two_sky_lights_each_normal_exactly():
    # L(d) = a + b.d + q(d) per colour: its irradiance / pi is a + (2/3) b.n + (1/4) q(n) for the
    # traceless quadratic q, which the order-2 harmonics hold exactly.
    h, w = 256, 512
    d = _directions(h, w)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    quad = [x * y, 3 * z * z - 1, x * x - y * y]
    sky = np.stack([1.0 + 0.6 * z + 0.3 * quad[0],
                    0.8 - 0.4 * x + 0.2 * quad[1],
                    0.9 + 0.5 * y + 0.25 * quad[2]], axis=-1)
    rgb, n, hit = _render_sphere(sky)
    assert hit.sum() > 0.5 * N * N
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]
    expected = np.stack([1.0 + 2 / 3 * 0.6 * nz + 0.25 * 0.3 * nx * ny,
                         0.8 - 2 / 3 * 0.4 * nx + 0.25 * 0.2 * (3 * nz * nz - 1),
                         0.9 + 2 / 3 * 0.5 * ny + 0.25 * 0.25 * (nx * nx - ny * ny)], axis=-1)
    np.testing.assert_allclose(rgb[hit], expected[hit], atol=2e-3)
    assert np.ptp(rgb[hit][:, 0]) > 0.7                              # top and bottom 2 x 2/3 x 0.6 apart where n = +-z


def test_a_uniform_sky_gives_its_radiance_as_the_ambient_term_does():
    sky = np.full((32, 64, 3), (0.5, 1.0, 2.0), np.float32)
    lit, _, hit = _render_sphere(sky, strength=3.0)
    np.testing.assert_allclose(lit[hit], np.broadcast_to([1.5, 3.0, 6.0], lit[hit].shape), rtol=1e-4)
    ambient, _, _ = _render_sphere(sky, light=False, ambient=(1.5, 3.0, 6.0))
    np.testing.assert_allclose(lit[hit], ambient[hit], rtol=1e-4)
    dark, _, _ = _render_sphere(sky, light=False)                     # the flag off: no light from the image
    assert np.all(dark[hit] == 0)


@pytest.mark.parametrize("shape", [(1, 1), (1, 64), (2, 8), (3, 5)])
def test_a_uniform_sky_of_a_few_texels_lights_every_normal(shape):
    # An image one texel tall (a strip, or the 1 x 1 stand-in for a missing image) once
    # gave every normal off the horizon no light: its cells all sat on the horizon.
    sky = np.full(shape + (3,), (0.5, 1.0, 2.0), np.float32)
    lit, n, hit = _render_sphere(sky, strength=2.0)
    assert hit.sum() > 0.5 * N * N and np.ptp(n[hit][:, 2]) > 1.5     # normals from down to up
    np.testing.assert_allclose(lit[hit], np.broadcast_to([1.0, 2.0, 4.0], lit[hit].shape), rtol=1e-3)
    # A floor, whose normal is exactly +z (the sphere's normals are never quite vertical).
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=1.0, width=8, height=8)
    floor = gw.Scene(vertices=[[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], triangles=[[0, 1, 2], [0, 2, 3]],
                     camera=cam, materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)],
                     textures=[gw.Texture(gw.Image(sky))],
                     world=gw.World(environment=0, environment_strength=2.0, environment_light=True))
    rgba = gw.RenderJob(floor, gw.RenderSettings(threads=1)).start().wait()
    np.testing.assert_allclose(rgba[..., :3].reshape(-1, 3), np.broadcast_to([1.0, 2.0, 4.0], (64, 3)), rtol=1e-3)


def _sky_with_ground(h=128, w=256):
    """A bright bluish sky, a green-brown ground, brighter towards +X."""
    d = _directions(h, w)
    up = np.clip(d[..., 2], 0, 1)[..., None]
    sky = np.where(up > 0, (0.6, 0.8, 1.4) * (0.3 + up), (0.10, 0.08, 0.03))
    return (sky * (1.2 + 0.5 * d[..., :1])).astype(np.float32)


def _cosine_integral(sky, normals):
    """E(n) / pi summed over every texel, max(0, n.d) weighted."""
    h, w = sky.shape[:2]
    d = _directions(h, w).reshape(-1, 3)
    weights = _solid_angles(h, w).reshape(-1, 1) * sky.reshape(-1, 3)
    cos = np.clip(normals.reshape(-1, 3) @ d.T, 0, None)
    return (cos @ weights / np.pi).reshape(normals.shape)


def test_a_sky_over_dark_ground_lights_tops_not_undersides():
    sky = _sky_with_ground()
    rgb, n, hit = _render_sphere(sky)
    exact = _cosine_integral(sky.astype(np.float64), n[hit])
    assert np.abs(rgb[hit] - exact).max() < 0.01 * exact.max()
    up, down = n[hit][:, 2] > 0.8, n[hit][:, 2] < -0.8
    assert rgb[hit][up, 2].mean() > 5 * rgb[hit][down, 2].mean()     # tops lit by the sky, undersides by ground
    mean = (_solid_angles(*sky.shape[:2])[..., None] * sky).sum(axis=(0, 1)) / (4 * np.pi)
    assert np.abs(rgb[hit][up].mean(axis=0) / mean - 1).max() > 0.4  # what one average colour would get wrong


def test_a_small_sun_lights_the_side_facing_it_and_not_the_far_side():
    # (Nine spherical-harmonic coefficients, tried first, gave faces turned away from a sun 6% of
    # its irradiance and rang around its terminator.)
    h, w = 128, 256
    sky = np.full((h, w, 3), 0.3, np.float32)
    sky[:h // 2] += 0.5                                              # a brighter upper half
    sky[20:23, 100:103] = 5000.0                                     # a sun high above, 200x the sky
    rgb, n, hit = _render_sphere(sky)
    exact = _cosine_integral(sky.astype(np.float64), n[hit])
    assert np.abs(rgb[hit] - exact).max() < 0.02 * exact.max()
    assert np.abs(rgb[hit] / exact - 1).mean() < 0.01
    sun = _directions(h, w)[21, 101]
    away = n[hit] @ sun < -0.2                                       # the sun below their horizon
    assert away.sum() > 50
    np.testing.assert_allclose(rgb[hit][away], exact[away], rtol=0.005)
    assert exact[~away].max() > 5 * exact[away].max()                 # (SH: +0.27 on these 0.3-0.6)


def test_strength_scales_and_8_bit_srgb_skies_are_decoded():
    sky = _sky_with_ground(32, 64)
    one, _, hit = _render_sphere(sky)
    two, _, _ = _render_sphere(sky, strength=2.0)
    np.testing.assert_allclose(two[hit], 2 * one[hit], rtol=1e-5)
    linear = np.clip(sky / sky.max(), 0, 1)
    encoded = np.where(linear <= 0.0031308, linear * 12.92, 1.055 * linear ** (1 / 2.4) - 0.055)
    bytes_ = np.rint(encoded * 255).astype(np.uint8)
    srgb, _, _ = _render_sphere(None, image=gw.Image(bytes_, colorspace="srgb"))
    decoded = bytes_ / 255.0
    decoded = np.where(decoded <= 0.04045, decoded / 12.92, ((decoded + 0.055) / 1.055) ** 2.4)
    as_float, _, _ = _render_sphere(decoded.astype(np.float32))
    np.testing.assert_allclose(srgb[hit], as_float[hit], rtol=1e-4, atol=1e-6)


def test_a_premultiplied_8_bit_sky_lights_with_its_associated_colour():
    # Cycles' Environment Texture gives associated colour: premultiplied in bytes, then decoded.
    px = np.zeros((16, 32, 4), np.uint8)
    px[...] = (200, 100, 50, 64)
    srgb, _, hit = _render_sphere(None, image=gw.Image(px, colorspace="srgb"))
    cam = gw.Camera(eye=(0, -5, 0), target=(0, 0, 0), up=(0, 0, 1), projection="orthographic",
                    ortho_height=2.2, width=8, height=8)
    scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], camera=cam,
                     materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)],
                     textures=[gw.Texture(gw.Image(px, colorspace="srgb"), premultiply=True)],
                     world=gw.World(environment=0, environment_light=True))
    rgba = gw.render(scene)
    associated = np.array([200, 100, 50]) * 64 // 255 / 255.0
    associated = np.where(associated <= 0.04045, associated / 12.92, ((associated + 0.055) / 1.055) ** 2.4)
    straight = np.array([200, 100, 50]) / 255.0
    straight = ((straight + 0.055) / 1.055) ** 2.4
    centre = rgba[rgba[..., 3] == 1][:, :3]
    np.testing.assert_allclose(centre, np.broadcast_to(associated, centre.shape), rtol=1e-4)
    np.testing.assert_allclose(srgb[hit], np.broadcast_to(straight, srgb[hit].shape), rtol=1e-4)


def test_a_rotated_environment_lights_and_shows_as_the_rotated_image():
    # environment_rotation R looks the image up along R d: a quarter turn about +Z is the image's
    # columns rolled by a quarter (u - 0.25), in what rays see and in the light surfaces get.
    sky = _sky_with_ground(32, 64)
    sky[..., 1] *= (1.0 + 0.8 * np.sin(np.linspace(0, 2 * np.pi, 64, endpoint=False)))[None, :]
    quarter = (0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)          # R d: d turned +90 degrees about +Z

    def render(image, rotation):
        cam = gw.Camera(eye=(0.3, -5, 0.4), target=(0, 0, 0), up=(0, 0, 1), fov=40.0, width=N, height=N)
        scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], camera=cam,
                         materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)],
                         textures=[gw.Texture(gw.Image(image), interpolation="closest")],
                         world=gw.World(environment=0, environment_light=True, environment_rotation=rotation))
        return gw.render(scene, gw.RenderSettings(threads=2, world_shadows=True))

    turned = render(sky, quarter)
    rolled = render(np.roll(sky, 16, axis=1), tuple(np.eye(3).ravel()))
    plain = render(sky, tuple(np.eye(3).ravel()))
    np.testing.assert_allclose(turned, rolled, rtol=2e-4, atol=1e-6)
    assert np.abs(turned - plain).max() > 0.1                        # the turn is visible
