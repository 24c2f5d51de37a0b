"""Cycles' panoramic cameras, checked against their formulas (no Blender):
the core's rays (Camera.rays) for the three fisheyes, the mirror ball, the
equiangular cube map face and the central cylindrical panorama; the lens shift
and the window that move a panorama's unit square; image positions beyond a
fisheye's circle, which get no ray and render black and opaque (as
Cycles renders them, also on a transparent film) over a bright world; and a render whose silhouette and depth follow the rays.

The image's (u, v) run from 0 to 1 left to right and bottom to top; in the
camera's frame "forward" is the view axis (eye to target: +y here), "right"
+x and "up" +z.
"""
import dataclasses
import math

import numpy as np
import pytest

import gridwalk as gw

EYE = dict(eye=(0, 0, 0), target=(0, 1, 0))
W, H = 80, 60


def rays_at(cam, u, v):
    """The camera's rays at unit-square positions (u, v) (no shift, the whole window)."""
    u, v = np.atleast_1d(u).astype(np.float64), np.atleast_1d(v).astype(np.float64)
    return cam.rays(u * cam.width, (1 - v) * cam.height)


def angle_from_axis(d):
    return np.arccos(np.clip(d[:, 1] / np.linalg.norm(d, axis=1), -1, 1))


def grid(n=9):
    u, v = np.meshgrid(np.linspace(0.02, 0.98, n), np.linspace(0.03, 0.97, n))
    return u.reshape(-1), v.reshape(-1)


def test_the_equidistant_fisheye_turns_by_half_its_field_of_view_per_unit_radius():
    fov = 3.4
    cam = gw.Camera(projection="fisheye_equidistant", fisheye_fov=fov, width=W, height=H, **EYE)
    u, v = grid()
    _, d, _, tmax = rays_at(cam, u, v)
    x, y = 2 * u - 1, 2 * v - 1
    r = np.hypot(x, y)
    inside = r <= 1
    assert 0.2 < inside.mean() < 0.95
    np.testing.assert_allclose(angle_from_axis(d[inside]), r[inside] * fov / 2, atol=2e-6)
    # the side the ray leans to is the image position's: right of centre leans right, above leans up
    off = inside & (r > 0)
    lean = d[off][:, [0, 2]]
    np.testing.assert_allclose(lean / np.linalg.norm(lean, axis=1, keepdims=True),
                               np.stack([x, y], 1)[off] / r[off, None], atol=1e-5)
    assert np.all(d[~inside] == 0) and np.all(tmax[~inside] == 0)     # no ray beyond the circle


def test_the_equisolid_fisheye_maps_the_angle_to_twice_the_lens_times_its_half_sine_on_the_sensor():
    lens, fov, sensor = 8.0, 2.6, (36.0, 27.0)
    cam = gw.Camera(projection="fisheye_equisolid", fisheye_lens=lens, fisheye_fov=fov, sensor=sensor,
                    width=W, height=H, **EYE)
    u, v = grid(13)
    _, d, _, _ = rays_at(cam, u, v)
    r = np.hypot((u - 0.5) * sensor[0], (v - 0.5) * sensor[1])             # mm on the sensor
    inside = r <= 2 * lens * math.sin(fov / 4)
    assert 0.2 < inside.mean() < 0.95
    np.testing.assert_allclose(angle_from_axis(d[inside]), 2 * np.arcsin(r[inside] / (2 * lens)), atol=3e-6)
    assert np.all(d[~inside] == 0)


def test_the_polynomial_fisheye_follows_its_polynomial_and_stops_at_its_field_of_view():
    k = (0.0, -0.03, 1e-5, -2e-6, 1e-8)
    fov = 1.0
    cam = gw.Camera(projection="fisheye_polynomial", polynomial=k, fisheye_fov=fov, sensor=(36.0, 27.0),
                    width=W, height=H, **EYE)
    u, v = grid(13)
    _, d, _, _ = rays_at(cam, u, v)
    r = np.hypot((u - 0.5) * 36.0, (v - 0.5) * 27.0)
    theta = -(k[0] + k[1] * r + k[2] * r ** 2 + k[3] * r ** 3 + k[4] * r ** 4)
    inside = np.abs(theta) <= fov / 2
    assert 0.2 < inside.mean() < 0.95
    np.testing.assert_allclose(angle_from_axis(d[inside]), theta[inside], atol=3e-6)
    assert np.all(d[~inside] == 0)


def test_the_mirror_ball_reflects_the_view_about_the_balls_normal():
    """Cycles' mirror ball shows what lies ahead at its centre and what lies
    behind at its rim: a ball seen from behind, its normal n pointing away
    from the camera, reflecting rays that travel back towards it."""
    cam = gw.Camera(projection="mirror_ball", width=W, height=W, **EYE)
    u, v = grid(11)
    _, d, _, _ = rays_at(cam, u, v)
    nx, nz = 2 * u - 1, 2 * v - 1
    inside = nx ** 2 + nz ** 2 <= 1
    n = np.stack([nx, np.sqrt(np.maximum(1 - nx ** 2 - nz ** 2, 0)), nz], 1)
    i = np.array([0.0, -1.0, 0.0])
    expected = i - 2 * (n @ i)[:, None] * n
    np.testing.assert_allclose(d[inside], expected[inside], atol=2e-5)
    assert np.all(d[~inside] == 0)
    _, centre, _, _ = rays_at(cam, 0.5, 0.5)
    np.testing.assert_allclose(centre[0], [0, 1, 0], atol=1e-6)                    # the centre looks ahead
    _, rim, _, _ = rays_at(cam, 0.5, 0.999)
    assert rim[0, 1] < -0.99                                                        # the rim looks back


def test_the_cube_map_face_spans_90_degrees_with_equal_angles_per_pixel():
    cam = gw.Camera(projection="cubemap_face", width=W, height=W, **EYE)
    u, v = grid(7)
    _, d, _, _ = rays_at(cam, u, v)
    # the angle across x and across z are linear in u and v, 90 degrees over the face
    np.testing.assert_allclose(np.arctan2(d[:, 0], d[:, 1]), (u - 0.5) * math.pi / 2, atol=2e-6)
    np.testing.assert_allclose(np.arctan2(d[:, 2], d[:, 1]), (v - 0.5) * math.pi / 2, atol=2e-6)


def test_the_central_cylinder_spans_its_longitude_and_heights():
    cam = gw.Camera(projection="central_cylindrical", longitude=(-2.0, 1.0), cylinder_height=(-0.5, 1.5),
                    width=W, height=H, **EYE)
    u, v = grid(7)
    _, d, _, _ = rays_at(cam, u, v)
    np.testing.assert_allclose(np.arctan2(d[:, 0], d[:, 1]), -2.0 + 3.0 * u, atol=2e-6)
    np.testing.assert_allclose(d[:, 2] / np.hypot(d[:, 0], d[:, 1]), -0.5 + 2.0 * v, atol=2e-6)


@pytest.mark.parametrize("projection", ["fisheye_equidistant", "mirror_ball", "cubemap_face", "equirectangular"])
def test_shift_and_window_move_the_unit_square(projection):
    """A panorama's shift is in units of its unit square, as Cycles shifts it;
    the window picks the part of the square the image spans (the viewport's stretch)."""
    base = dict(projection=projection, width=W, height=H, **EYE)
    u, v = grid(5)
    u, v = 0.25 + 0.5 * u, 0.25 + 0.5 * v
    shifted = gw.Camera(**base, shift=(0.1, -0.2))
    np.testing.assert_allclose(rays_at(shifted, u, v)[1], rays_at(gw.Camera(**base), u + 0.1, v - 0.2)[1], atol=2e-6)
    windowed = gw.Camera(**base, window=(0.2, 0.6, -0.1, 1.3))
    np.testing.assert_allclose(rays_at(windowed, u, v)[1],
                               rays_at(gw.Camera(**base), 0.2 + 0.4 * u, -0.1 + 1.4 * v)[1], atol=2e-6)


def sphere_render(camera, center, radius, background=(0.6, 0.7, 0.8), transparent=False):
    scene = gw.Scene(sphere_centers=[center], sphere_radii=[radius], sphere_materials=[0],
                     lights=[gw.Light(position=(0, -10, 10))], camera=camera, background=background,
                     world=gw.World(transparent=transparent))
    job = gw.RenderJob(scene, gw.RenderSettings(aa="center", threads=2)).start()
    return job.wait(), job


@pytest.mark.parametrize("projection", ["fisheye_equidistant", "fisheye_equisolid", "mirror_ball"])
def test_a_fisheye_render_follows_its_rays_and_is_black_beyond_its_circle(projection):
    cam = gw.Camera(projection=projection, fisheye_fov=3.6, fisheye_lens=9.0, width=W, height=H, **EYE)
    center, radius = (1.5, 3.0, 1.0), 1.0
    rgba, job = sphere_render(cam, center, radius)
    gx, gy = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    o, d, _, _ = cam.rays(gx.reshape(-1), gy.reshape(-1))
    none = np.all(d == 0, axis=1).reshape(H, W)
    assert 0.05 < none.mean() < 0.6
    # no ray: black and opaque, though the world behind is bright
    assert np.all(rgba[none] == (0, 0, 0, 1))
    # elsewhere the world shows, and the sphere exactly where its rays meet it
    oc = -np.asarray(center, np.float64)
    dd = d.astype(np.float64)
    b = dd @ oc
    expected = ((b * b - (dd * dd).sum(1) * (oc @ oc - radius ** 2)) >= 0) & (b < 0)
    expected = expected.reshape(H, W) & ~none
    assert expected.sum() > 30
    assert np.mean((rgba[..., 3] > 0.5)[~none] != expected[~none]) < 0.003
    world = ~none & ~expected
    assert np.allclose(rgba[world][:, :3], (0.6, 0.7, 0.8), atol=1e-6)
    # on a transparent film too (the world's pixels turn transparent)
    clear, _ = sphere_render(cam, center, radius, transparent=True)
    assert np.all(clear[none] == (0, 0, 0, 1)) and np.all(clear[world] == 0)
    # the Depth pass of a panorama is the distance along the ray
    hit = expected & (rgba[..., 3] > 0.5)
    depth = job.depth[hit]
    distance = np.linalg.norm(center)
    assert np.all((depth >= distance - radius - 1e-3) & (depth <= distance + 1e-3))


def test_a_position_whose_direction_overflows_gets_no_ray():
    """A window far outside the unit square (from a script) never gives a NaN
    direction: the fisheyes, whose radius and angle overflow there, give no ray."""
    for projection in ("fisheye_polynomial", "fisheye_equisolid", "fisheye_equidistant", "mirror_ball",
                       "central_cylindrical", "cubemap_face", "equirectangular"):
        cam = gw.Camera(projection=projection, polynomial=(0, -0.02, 0, 0, 0), fisheye_fov=3.0,
                        window=(0, 1e30, 0, 1e30), width=W, height=H, **EYE)
        _, d, _, _ = cam.rays(np.arange(W) + 0.5, np.full(W, 10.5))
        assert np.isfinite(d).all(), projection
        if projection.startswith("fisheye") or projection == "mirror_ball":
            assert np.all(d == 0), projection


@pytest.mark.parametrize("projection", ["fisheye_equisolid", "fisheye_polynomial"])
def test_a_sensor_fisheye_resized_to_another_aspect_stays_round(projection):
    """Camera.resized, which gridwalk.io and the farm use for a new image size:
    the sensor's width follows the new aspect, so pixels equally far from the
    centre across and upwards see equal angles (keeping the sensor in mm
    stretched the circle into an ellipse)."""
    from gridwalk.renderfarm.core_job import load_scene
    cam = gw.Camera(projection=projection, fisheye_lens=8.0, fisheye_fov=3.0, sensor=(36.0, 24.0),
                    polynomial=(0.0, -0.09, 0.0, 0.0, 0.0), width=90, height=60, **EYE)
    wide = cam.resized(200, 60)
    assert wide.sensor == pytest.approx((80.0, 24.0)) and (wide.width, wide.height) == (200, 60)
    assert cam.resized(90, 60) == cam                                    # the same size: the same camera
    square = dataclasses.replace(cam, sensor=(30.0, 30.0))               # (a sensor not of the image's aspect)
    assert square.resized(90, 60) == square and square.resized(60, 60).sensor == pytest.approx((20.0, 30.0))
    assert load_scene({"camera": cam}, 200, 60)[0]["camera"] == wide
    for c in (cam, wide):
        px = c.width / 2 + np.array([10.0, 0.0])
        py = c.height / 2 - np.array([0.0, 10.0])
        _, d, _, _ = c.rays(px, py)
        a = angle_from_axis(d)
        assert a[0] > 0.1 and a[0] == pytest.approx(a[1], abs=1e-5)
    # what the old resize made of it: the same sensor over a wider image stretches the circle
    _, d, _, _ = dataclasses.replace(cam, width=200).rays(100 + np.array([10.0, 0.0]), 30 - np.array([0.0, 10.0]))
    assert abs(angle_from_axis(d)[0] - angle_from_axis(d)[1]) > 0.05
    with pytest.raises(ValueError, match="at least 1 x 1"):
        cam.resized(0, 60)
